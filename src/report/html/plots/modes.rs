//! The proper orthogonal modes' charts: the retained mode shapes and every mode's
//! energy share.

use plotters::prelude::*;

use super::{Curve, Ticks, chart_svg, colour, frame, legend, legend_line, padded, plot_error, px};
use crate::error::Result;

/// Index axes label at most this many whole numbers.
const MOST_INDEX_LABELS: usize = 12;

/// Points are marked on the mode shapes up to this many DOFs (beyond, lines only).
const MOST_MARKED_DOFS: usize = 64;

/// Energy shares below 10^this are round-off: their bars start at the axis bottom.
const LOWEST_DECADE: f64 = -16.0;

/// Mode shapes: each curve's points are (DOF index, amplitude), drawn as one line per
/// mode (marked at every DOF when there are few), with the zero line.
pub(crate) fn mode_shapes(title: &str, modes: &[Curve]) -> Result<String> {
    let finite = |points: &[(f64, f64)]| -> Vec<(f64, f64)> {
        points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect()
    };
    let modes: Vec<(&str, Vec<(f64, f64)>)> = modes
        .iter()
        .map(|m| (m.name.as_str(), finite(&m.points)))
        .collect();
    let dofs = modes.iter().map(|m| m.1.len()).max().unwrap_or(0);
    chart_svg(|root| {
        let x = padded(modes.iter().flat_map(|m| m.1.iter().map(|p| p.0)));
        let y = padded(
            modes
                .iter()
                .flat_map(|m| m.1.iter().map(|p| p.1))
                .chain([0.0]),
        );
        let axes = ("DOF (sensor)", "unit mode amplitude");
        let ticks = (Ticks::Integers(dofs.min(MOST_INDEX_LABELS)), Ticks::Plain);
        let mut chart = frame(root, title, x.clone(), y, axes, ticks)?;
        chart
            .draw_series(LineSeries::new(
                [(x.start, 0.0), (x.end, 0.0)],
                BLACK.mix(0.5).stroke_width(px(1)),
            ))
            .map_err(plot_error)?;
        for (k, (name, points)) in modes.iter().enumerate() {
            let color = colour(k);
            let style = color.stroke_width(px(2));
            chart
                .draw_series(LineSeries::new(points.iter().copied(), style))
                .map_err(plot_error)?
                .label(*name)
                .legend(move |(x, y)| legend_line(x, y, style));
            if dofs <= MOST_MARKED_DOFS {
                chart
                    .draw_series(
                        points
                            .iter()
                            .map(|&p| Circle::new(p, px(4) as i32, color.filled())),
                    )
                    .map_err(plot_error)?;
            }
        }
        if !modes.is_empty() {
            legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    })
}

/// The energy share of every mode (1-based, in order) as bars on a log scale, the
/// `retained` leading ones filled and the rest grey, with a line after the last retained.
/// Shares that are zero, negative or not finite draw no bar.
pub(crate) fn energy_shares(title: &str, shares: &[f64], retained: usize) -> Result<String> {
    let retained = retained.min(shares.len());
    let decades: Vec<Option<f64>> = shares
        .iter()
        .map(|&s| (s > 0.0 && s.is_finite()).then(|| s.log10().max(LOWEST_DECADE)))
        .collect();
    let (low, high) = decades
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
            (lo.min(d), hi.max(d))
        });
    let (low, high) = if low.is_finite() {
        (low.floor(), high.ceil().max(low.floor() + 1.0))
    } else {
        (-1.0, 0.0)
    };
    let bottom = low - 0.2;
    let count = shares.len().max(1) as f64;
    let retained_share: f64 = shares[..retained].iter().filter(|s| s.is_finite()).sum();
    chart_svg(|root| {
        let axes = ("mode", "energy share λ_k / Σλ (log scale)");
        let ticks = (
            Ticks::Integers(shares.len().min(MOST_INDEX_LABELS)),
            Ticks::Decades,
        );
        let x = 0.5..(count + 0.5);
        let mut chart = frame(root, title, x, bottom..(high + 0.2), axes, ticks)?;
        let bar = |k: usize, top: f64, style: ShapeStyle| {
            let centre = (k + 1) as f64;
            Rectangle::new([(centre - 0.35, bottom), (centre + 0.35, top)], style)
        };
        let bars = |range: std::ops::Range<usize>, style: ShapeStyle| {
            decades[range.clone()]
                .iter()
                .zip(range)
                .filter_map(move |(d, k)| d.map(|top| bar(k, top, style)))
                .collect::<Vec<_>>()
        };
        let kept = colour(0).filled();
        chart
            .draw_series(bars(0..retained, kept))
            .map_err(plot_error)?
            .label(format!(
                "retained: {retained} mode(s), {:.4}% of the energy",
                100.0 * retained_share
            ))
            .legend(move |(x, y)| {
                Rectangle::new(
                    [(x, y - px(6) as i32), (x + px(14) as i32, y + px(6) as i32)],
                    kept,
                )
            });
        if retained < shares.len() {
            let dropped = BLACK.mix(0.3).filled();
            chart
                .draw_series(bars(retained..shares.len(), dropped))
                .map_err(plot_error)?
                .label(format!("discarded: {} mode(s)", shares.len() - retained))
                .legend(move |(x, y)| {
                    Rectangle::new(
                        [(x, y - px(6) as i32), (x + px(14) as i32, y + px(6) as i32)],
                        dropped,
                    )
                });
            if retained > 0 {
                let cut = retained as f64 + 0.5;
                chart
                    .draw_series(LineSeries::new(
                        [(cut, bottom), (cut, high + 0.2)],
                        colour(1).stroke_width(px(2)),
                    ))
                    .map_err(plot_error)?;
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::html::plots::tests::has_text;

    fn curve(name: &str, shape: &[f64]) -> Curve {
        Curve {
            name: name.into(),
            points: shape
                .iter()
                .enumerate()
                .map(|(i, &a)| ((i + 1) as f64, a))
                .collect(),
            band: None,
            measured: None,
        }
    }

    #[test]
    fn mode_shapes_draw_one_labelled_line_per_mode() {
        let modes = [
            curve("POM 1 (97.01%)", &[0.2, 0.4, 0.6, 0.7]),
            curve("POM 2 (2.90%)", &[-0.5, -0.5, 0.1, 0.7]),
        ];
        let svg = mode_shapes("shapes", &modes).unwrap();
        assert!(svg.starts_with("<svg"));
        for needle in ["shapes", "POM 1 (97.01%)", "POM 2 (2.90%)", "DOF (sensor)"] {
            assert!(svg.contains(needle), "missing {needle}");
        }
        // Index ticks are whole numbers: no "1.5" on the DOF axis.
        assert!(has_text(&svg, "1") && has_text(&svg, "4"));
        assert!(!has_text(&svg, "1.5") && !has_text(&svg, "1.0"));
    }

    #[test]
    fn mode_shapes_survive_odd_input() {
        // No modes, one DOF, a non-finite amplitude: a frame, no panic.
        for modes in [
            vec![],
            vec![curve("one DOF", &[1.0])],
            vec![curve("bad", &[f64::NAN, 1.0, f64::INFINITY])],
        ] {
            assert!(mode_shapes("odd", &modes).unwrap().contains("</svg>"));
        }
    }

    #[test]
    fn energy_shares_mark_retained_and_discarded_modes() {
        let svg = energy_shares("energy", &[0.97, 0.029, 9e-4, 1e-4], 2).unwrap();
        assert!(svg.contains("retained: 2 mode(s), 99.9000% of the energy"));
        assert!(svg.contains("discarded: 2 mode(s)"));
        // Decade labels on the log axis.
        for decade in ["1", "1e-1", "1e-2", "1e-3", "1e-4"] {
            assert!(has_text(&svg, decade), "no label {decade}");
        }
        assert!(!has_text(&svg, "-0.5"));
    }

    #[test]
    fn energy_shares_survive_odd_input() {
        for (shares, retained) in [
            (vec![], 0),
            (vec![1.0], 1),
            (vec![1.0, 0.0, -1e-20, f64::NAN], 1),
            (vec![0.5, 0.5], 5),
            (vec![0.0, 0.0], 0),
        ] {
            let svg = energy_shares("odd", &shares, retained).unwrap();
            assert!(svg.contains("</svg>"));
        }
        // Everything retained: no discarded entry.
        let all = energy_shares("all", &[0.6, 0.4], 2).unwrap();
        assert!(!all.contains("discarded"));
    }
}
