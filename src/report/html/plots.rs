//! SVG charts for the HTML report, drawn with plotters' SVG backend. Text is written as
//! SVG `<text>` elements with estimated metrics, so no font library is needed.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{Error, Result};

const SIZE: (u32, u32) = (640, 400);

/// A named curve with an optional band (lower, upper) at each point.
pub(crate) struct Curve {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub band: Option<Vec<(f64, f64, f64)>>,
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Numerical {
        stage: "plot".into(),
        detail: e.to_string(),
    }
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// How an axis's tick labels read.
#[derive(Debug, Clone, Copy)]
enum Ticks {
    /// plotters' own numbers.
    Plain,
    /// An index axis: labels at whole numbers only, at most this many.
    Integers(usize),
    /// The axis holds log10 of the value: labels 1e k at whole k only.
    Decades,
}

/// The label of a whole-number tick; other ticks go unlabelled.
fn integer_label(value: &f64) -> String {
    whole(*value).map_or_else(String::new, |k| format!("{k}"))
}

/// The label of a whole decade of a log10 axis; other ticks go unlabelled.
fn decade_label(value: &f64) -> String {
    match whole(*value) {
        Some(0) => "1".into(),
        Some(k) => format!("1e{k}"),
        None => String::new(),
    }
}

/// `value` as a whole number, if it is one (up to round-off).
fn whole(value: f64) -> Option<i64> {
    let rounded = value.round();
    ((value - rounded).abs() < 1e-9 && rounded.abs() < 1e15).then_some(rounded as i64)
}

/// The common frame: caption, margins, axes with their descriptions.
fn frame<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    descriptions: (&str, &str),
) -> Result<Chart<'a, 'b>> {
    frame_with_ticks(
        root,
        caption,
        x,
        y,
        descriptions,
        (Ticks::Plain, Ticks::Plain),
    )
}

/// The common frame with the tick labels `ticks` (x, y).
fn frame_with_ticks<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    (x_desc, y_desc): (&str, &str),
    (x_ticks, y_ticks): (Ticks, Ticks),
) -> Result<Chart<'a, 'b>> {
    root.fill(&WHITE).map_err(plot_error)?;
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc).y_desc(y_desc);
    match x_ticks {
        Ticks::Plain => {}
        Ticks::Integers(most) => {
            mesh.x_labels(most.max(1)).x_label_formatter(&integer_label);
        }
        Ticks::Decades => {
            mesh.x_label_formatter(&decade_label);
        }
    }
    match y_ticks {
        Ticks::Plain => {}
        Ticks::Integers(most) => {
            mesh.y_labels(most.max(1)).y_label_formatter(&integer_label);
        }
        Ticks::Decades => {
            mesh.y_label_formatter(&decade_label);
        }
    }
    mesh.draw().map_err(plot_error)?;
    Ok(chart)
}

/// Draws the legend box at `position`.
fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, position: SeriesLabelPosition) -> Result<()> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(plot_error)
}

/// A range that contains every value, padded by 5%, never empty.
fn padded(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return -1.0..1.0;
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad)..(hi + pad)
}

/// Measured input work against identified dissipated work per window, with y = x; with
/// `stored`, the identified work also holds the change of stored energy and the work of
/// constant forces (the non-periodic balance).
pub(crate) fn work_balance(input: &[f64], dissipated: &[f64], stored: bool) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let range = padded(input.iter().chain(dissipated).copied());
        let axes = if stored {
            (
                "input work ∫ vᵀr dt",
                "identified dissipated + stored work Σ θ_k A_k",
            )
        } else {
            (
                "input work ∮ vᵀr dt",
                "identified dissipated work Σ θ_k A_k",
            )
        };
        let mut chart = frame(
            &root,
            "Energy balance per window",
            range.clone(),
            range.clone(),
            axes,
        )?;
        chart
            .draw_series(LineSeries::new(
                [(range.start, range.start), (range.end, range.end)],
                BLACK.mix(0.4),
            ))
            .map_err(plot_error)?
            .label("equality")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.mix(0.4)));
        chart
            .draw_series(
                input
                    .iter()
                    .zip(dissipated)
                    .map(|(&x, &y)| Circle::new((x, y), 4, BLUE.filled())),
            )
            .map_err(plot_error)?
            .label("windows")
            .legend(|(x, y)| Circle::new((x + 8, y), 4, BLUE.filled()));
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Residual per equation with the zero line and the mean (the bias).
pub(crate) fn residuals(residuals: &[f64]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let n = residuals.len().max(1) as f64;
        let mean = residuals.iter().sum::<f64>() / n;
        let y = padded(residuals.iter().copied().chain([0.0, mean]));
        let axes = ("equation (window)", "residual work");
        let mut chart = frame(
            &root,
            "Residuals b − Aθ per equation",
            -0.5..(n - 0.5),
            y,
            axes,
        )?;
        chart
            .draw_series(LineSeries::new(
                [(-0.5, 0.0), (n - 0.5, 0.0)],
                BLACK.mix(0.4),
            ))
            .map_err(plot_error)?;
        chart
            .draw_series(LineSeries::new(
                [(-0.5, mean), (n - 0.5, mean)],
                RED.stroke_width(2),
            ))
            .map_err(plot_error)?
            .label(format!("mean (bias) {mean:.3e}"))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], RED.stroke_width(2)));
        chart
            .draw_series(
                residuals
                    .iter()
                    .enumerate()
                    .map(|(i, &r)| Circle::new((i as f64, r), 4, BLUE.filled())),
            )
            .map_err(plot_error)?
            .label("residuals")
            .legend(|(x, y)| Circle::new((x + 8, y), 4, BLUE.filled()));
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Identified force laws against relative velocity, each with its uncertainty band.
pub(crate) fn force_laws(title: &str, curves: &[Curve]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let x = padded(curves.iter().flat_map(|c| c.points.iter().map(|p| p.0)));
        let y = padded(curves.iter().flat_map(|c| {
            let band = c.band.iter().flatten().flat_map(|b| [b.1, b.2]);
            c.points.iter().map(|p| p.1).chain(band)
        }));
        let axes = ("relative velocity v", "damping force θ f(v)");
        let mut chart = frame(&root, title, x, y, axes)?;
        for (k, curve) in curves.iter().enumerate() {
            let color = Palette99::pick(k).to_rgba();
            if let Some(band) = &curve.band {
                let upper = band.iter().map(|b| (b.0, b.2));
                let lower = band.iter().rev().map(|b| (b.0, b.1));
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        upper.chain(lower).collect::<Vec<_>>(),
                        color.mix(0.2),
                    )))
                    .map_err(plot_error)?;
            }
            chart
                .draw_series(LineSeries::new(
                    curve.points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(curve.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let x = padded(modes.iter().flat_map(|m| m.1.iter().map(|p| p.0)));
        let y = padded(
            modes
                .iter()
                .flat_map(|m| m.1.iter().map(|p| p.1))
                .chain([0.0]),
        );
        let axes = ("DOF (sensor)", "unit mode amplitude");
        let ticks = (Ticks::Integers(dofs.min(MOST_INDEX_LABELS)), Ticks::Plain);
        let mut chart = frame_with_ticks(&root, title, x.clone(), y, axes, ticks)?;
        chart
            .draw_series(LineSeries::new(
                [(x.start, 0.0), (x.end, 0.0)],
                BLACK.mix(0.4),
            ))
            .map_err(plot_error)?;
        for (k, (name, points)) in modes.iter().enumerate() {
            let color = Palette99::pick(k).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(*name)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2))
                });
            if dofs <= MOST_MARKED_DOFS {
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
                    .map_err(plot_error)?;
            }
        }
        if !modes.is_empty() {
            legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let axes = ("mode", "energy share λ_k / Σλ (log scale)");
        let ticks = (
            Ticks::Integers(shares.len().min(MOST_INDEX_LABELS)),
            Ticks::Decades,
        );
        let x = 0.5..(count + 0.5);
        let mut chart = frame_with_ticks(&root, title, x, bottom..(high + 0.2), axes, ticks)?;
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
        let kept = BLUE.filled();
        chart
            .draw_series(bars(0..retained, kept))
            .map_err(plot_error)?
            .label(format!(
                "retained: {retained} mode(s), {:.4}% of the energy",
                100.0 * retained_share
            ))
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], kept));
        if retained < shares.len() {
            let dropped = BLACK.mix(0.3).filled();
            chart
                .draw_series(bars(retained..shares.len(), dropped))
                .map_err(plot_error)?
                .label(format!("discarded: {} mode(s)", shares.len() - retained))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], dropped));
            if retained > 0 {
                let cut = retained as f64 + 0.5;
                chart
                    .draw_series(LineSeries::new(
                        [(cut, bottom), (cut, high + 0.2)],
                        RED.stroke_width(2),
                    ))
                    .map_err(plot_error)?;
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Dissipated energy per cycle against amplitude on log-log axes: the measured input
/// work of each point (`measured`, positive values only) and the fitted `curves`, each
/// over the measured amplitude range only.
pub(crate) fn energy_per_cycle(measured: &[(f64, f64)], curves: &[Curve]) -> Result<String> {
    let log = |(x, y): (f64, f64)| (x > 0.0 && y > 0.0).then(|| (x.log10(), y.log10()));
    let points: Vec<(f64, f64)> = measured.iter().copied().filter_map(log).collect();
    let lines: Vec<(String, Vec<(f64, f64)>)> = curves
        .iter()
        .map(|c| {
            (
                c.name.clone(),
                c.points.iter().copied().filter_map(log).collect(),
            )
        })
        .collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let all = || {
            points
                .iter()
                .chain(lines.iter().flat_map(|(_, l)| l.iter()))
        };
        let mut chart = frame_with_ticks(
            &root,
            "Dissipated energy per cycle",
            padded(all().map(|p| p.0)),
            padded(all().map(|p| p.1)),
            ("response amplitude X (log10)", "energy per cycle (log10)"),
            (Ticks::Decades, Ticks::Decades),
        )?;
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 3, BLUE.filled())))
            .map_err(plot_error)?
            .label("measured π a X sin φ")
            .legend(|(x, y)| Circle::new((x + 8, y), 3, BLUE.filled()));
        for (k, (name, line)) in lines.iter().enumerate() {
            let colour = Palette99::pick(k + 1).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    line.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(name.as_str())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(name: &str, shape: &[f64]) -> Curve {
        Curve {
            name: name.into(),
            points: shape
                .iter()
                .enumerate()
                .map(|(i, &a)| ((i + 1) as f64, a))
                .collect(),
            band: None,
        }
    }

    /// Whether the SVG has a text element reading exactly `text`.
    fn has_text(svg: &str, text: &str) -> bool {
        svg.contains(&format!(">\n{text}\n</text>"))
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
