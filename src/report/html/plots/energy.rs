//! The charts of a one-mode stepped-sine table's equivalent damping, against the
//! response amplitude X on a log axis, the measured points coloured by sweep:
//!
//! - energy per cycle (log-log): each point's input work E_p = π a X sin φ and the
//!   fitted law's dissipation E_d(X) at ω_n, in all and per term;
//! - the equivalent viscous damping ratio ζ_eq(X) = E_d(X)/(2π k X²) with its ±1.96σ
//!   band, and each point's own ζ_p = E_p/(2π k X_p²) where the caller says it compares
//!   (near resonance).
//!
//! The curves are black (the whole law solid, its terms in dash patterns) so that the
//! colours stay the sweeps'; the legends sit below the plots.

use plotters::prelude::*;

use super::{
    Curve, Group, LEVEL_SQUARE, Mark, SIZE, Ticks, chart_svg_of_height, draw_group, frame,
    group_entries, legend_below, legend_strip, padded, plot_error, px,
};
use crate::error::Result;

/// The dash (length, gap) in shown pixels of term curve `k`.
fn dashes(k: usize) -> (u32, u32) {
    [(10, 5), (3, 4), (16, 4), (6, 9)][k % 4]
}

/// `(x, y)` on log-log axes, when both are positive.
fn log_log((x, y): (f64, f64)) -> Option<(f64, f64)> {
    (x > 0.0 && y > 0.0).then(|| (x.log10(), y.log10()))
}

/// Dissipated energy per cycle against amplitude on log-log axes (module doc): the
/// measured (X_p, E_p) of every point in `measured` (one group per sweep; positive
/// values only), and the fitted `curves`, the first the whole law, the others its terms,
/// each over the measured amplitude range only.
pub(crate) fn energy_per_cycle(measured: &[Group], curves: &[Curve]) -> Result<String> {
    let groups: Vec<Group> = measured
        .iter()
        .map(|g| Group {
            name: g.name.clone(),
            points: g.points.iter().copied().filter_map(log_log).collect(),
            rest: g.rest,
        })
        .collect();
    let lines: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| c.points.iter().copied().filter_map(log_log).collect())
        .collect();
    let whole = BLACK.stroke_width(px(2));
    let term = BLACK.mix(0.7).stroke_width(px(2));
    let mut entries: Vec<(Mark, String)> = curves
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mark = match k {
                0 => Mark::Line(whole),
                _ => {
                    let (dash, gap) = dashes(k - 1);
                    Mark::Dash(term, dash, gap)
                }
            };
            (mark, c.name.clone())
        })
        .collect();
    if !groups.is_empty() {
        entries.push((
            Mark::Note,
            "markers: each point's measured input work π a X sin φ, by sweep:".into(),
        ));
        entries.extend(group_entries(&groups));
    }
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let all = || {
            groups
                .iter()
                .flat_map(|g| g.points.iter())
                .chain(lines.iter().flatten())
        };
        let mut chart = frame(
            &plot,
            "Dissipated energy per cycle",
            padded(all().map(|p| p.0)),
            padded(all().map(|p| p.1)),
            (
                "response amplitude X (log scale)",
                "energy per cycle (log scale)",
            ),
            (Ticks::Decades, Ticks::Decades),
        )?;
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        for (k, line) in lines.iter().enumerate() {
            if k == 0 {
                chart
                    .draw_series(LineSeries::new(line.iter().copied(), whole))
                    .map_err(plot_error)?;
            } else {
                let (dash, gap) = dashes(k - 1);
                chart
                    .draw_series(DashedLineSeries::new(
                        line.iter().copied(),
                        px(dash),
                        px(gap),
                        term,
                    ))
                    .map_err(plot_error)?;
            }
        }
        legend_below(&below, &entries)
    })
}

/// The fitted ζ_eq(X) of [`damping_ratio`]: (X, ζ_eq, its standard deviation when
/// known) from the smallest to the largest amplitude.
pub(crate) struct ZetaCurve {
    /// The legend's name of the curve.
    pub name: String,
    /// The points.
    pub points: Vec<(f64, f64, Option<f64>)>,
}

/// ζ_eq against amplitude X on a log axis (module doc): the `fitted` curve with its
/// ±1.96σ band where it has standard deviations, and the points of `measured` (X_p,
/// ζ_p) one group per sweep, described in the legend by `measured_note`.
pub(crate) fn damping_ratio(
    fitted: &ZetaCurve,
    measured: &[Group],
    measured_note: &str,
    levels: &[(f64, f64)],
) -> Result<String> {
    let log_x = |x: f64, y: f64| (x > 0.0 && y.is_finite()).then(|| (x.log10(), y));
    let curve: Vec<(f64, f64)> = fitted
        .points
        .iter()
        .filter_map(|&(x, z, _)| log_x(x, z))
        .collect();
    let band: Vec<(f64, f64, f64)> = fitted
        .points
        .iter()
        .filter_map(|&(x, z, s)| {
            let s = s.filter(|s| s.is_finite())?;
            let (x, _) = log_x(x, z)?;
            Some((x, z - 1.96 * s, z + 1.96 * s))
        })
        .collect();
    let groups: Vec<Group> = measured
        .iter()
        .map(|g| Group {
            name: g.name.clone(),
            points: g.points.iter().filter_map(|&(x, z)| log_x(x, z)).collect(),
            rest: g.rest,
        })
        .collect();
    let line = BLACK.stroke_width(px(2));
    let mut entries = vec![(Mark::Line(line), fitted.name.clone())];
    if !band.is_empty() {
        entries.push((Mark::Band(BLACK), "±1.96σ of the fitted ζ_eq".into()));
    }
    if groups.iter().any(|g| !g.points.is_empty()) {
        entries.push((Mark::Note, measured_note.to_string()));
        entries.extend(group_entries(&groups));
    }
    let levels: Vec<(f64, f64)> = levels.iter().filter_map(|&(x, z)| log_x(x, z)).collect();
    if !levels.is_empty() {
        entries.push((
            Mark::Level,
            "ζ measured at each sweep's level (phase slope at its π/2 crossing)".into(),
        ));
    }
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let xs = curve
            .iter()
            .map(|p| p.0)
            .chain(groups.iter().flat_map(|g| g.points.iter().map(|p| p.0)))
            .chain(levels.iter().map(|p| p.0));
        let ys = curve
            .iter()
            .map(|p| p.1)
            .chain(band.iter().flat_map(|b| [b.1, b.2]))
            .chain(groups.iter().flat_map(|g| g.points.iter().map(|p| p.1)))
            .chain(levels.iter().map(|p| p.1));
        let mut chart = frame(
            &plot,
            "Equivalent viscous damping ratio ζ_eq(X)",
            padded(xs),
            padded(ys),
            (
                "response amplitude X (log scale)",
                "damping ratio ζ_eq = E_d / (2π k X²)",
            ),
            (Ticks::Decades, Ticks::Plain),
        )?;
        if !band.is_empty() {
            let upper = band.iter().map(|b| (b.0, b.2));
            let lower = band.iter().rev().map(|b| (b.0, b.1));
            chart
                .draw_series(std::iter::once(Polygon::new(
                    upper.chain(lower).collect::<Vec<_>>(),
                    BLACK.mix(0.2),
                )))
                .map_err(plot_error)?;
        }
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        chart
            .draw_series(LineSeries::new(curve.iter().copied(), line))
            .map_err(plot_error)?;
        chart
            .draw_series(levels.iter().map(|&p| {
                EmptyElement::at(p) + Rectangle::new(LEVEL_SQUARE, BLACK.stroke_width(px(2)))
            }))
            .map_err(plot_error)?;
        legend_below(&below, &entries)
    })
}
