//! The energy balance of every equation and its residuals, one colour per group of
//! equations (a record's windows, or a stepped-sine table's sweep):
//!
//! - the balance: measured input work b_r against identified work (Aθ)_r with the line
//!   of equality, on linear axes, or on log-log axes for a table, whose energies span
//!   decades (points with a value ≤ 0 are then counted, not drawn);
//! - the residuals b_r − (Aθ)_r against the equation's index (records) or the point's
//!   frequency (a table), with the zero line and the mean residual.
//!
//! Both legends sit below the plot, where they cover no point.

use plotters::prelude::*;

use super::{
    Group, Mark, SIZE, Ticks, chart_svg_of_height, draw_group, frame, group_entries, legend_below,
    legend_strip, padded, plot_error, px,
};
use crate::error::Result;
use crate::report::units::with_unit;

/// The words and scale of an energy-balance chart.
pub(crate) struct BalanceAxes<'a> {
    /// The chart's title.
    pub title: &'a str,
    /// The measured input work's axis.
    pub input: &'a str,
    /// The identified work's axis.
    pub identified: &'a str,
    /// Log-log axes (the positive points only).
    pub log: bool,
    /// The work's unit, when known.
    pub unit: Option<&'a str>,
}

/// Measured input work against identified work per equation (module doc): `groups`
/// hold (input, identified) points.
pub(crate) fn work_balance(groups: &[Group], axes: &BalanceAxes<'_>) -> Result<String> {
    let drawn: Vec<Group> = groups
        .iter()
        .map(|g| Group {
            name: g.name.clone(),
            points: if axes.log {
                g.points
                    .iter()
                    .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                    .map(|p| (p.0.log10(), p.1.log10()))
                    .collect()
            } else {
                g.points.clone()
            },
            rest: g.rest,
        })
        .collect();
    let hidden: usize = groups.iter().map(|g| g.points.len()).sum::<usize>()
        - drawn.iter().map(|g| g.points.len()).sum::<usize>();
    let reference = BLACK.mix(0.5).stroke_width(px(1));
    let mut entries = vec![(
        Mark::Line(reference),
        "equality (input = identified)".to_string(),
    )];
    entries.extend(group_entries(&drawn));
    if hidden > 0 {
        entries.push((
            Mark::Note,
            format!("{hidden} not drawn: a value ≤ 0 has no place on log axes"),
        ));
    }
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let range = padded(
            drawn
                .iter()
                .flat_map(|g| g.points.iter().flat_map(|p| [p.0, p.1])),
        );
        let scale = if axes.log { " (log scale)" } else { "" };
        let x = with_unit(&format!("{}{scale}", axes.input), axes.unit);
        let y = with_unit(&format!("{}{scale}", axes.identified), axes.unit);
        let ticks = if axes.log {
            (Ticks::Decades, Ticks::Decades)
        } else {
            (Ticks::Plain, Ticks::Plain)
        };
        let mut chart = frame(
            &plot,
            axes.title,
            range.clone(),
            range.clone(),
            (&x, &y),
            ticks,
        )?;
        chart
            .draw_series(LineSeries::new(
                [(range.start, range.start), (range.end, range.end)],
                reference,
            ))
            .map_err(plot_error)?;
        for (k, group) in drawn.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        legend_below(&below, &entries)
    })
}

/// The words and abscissa of a residual chart.
pub(crate) struct ResidualAxes<'a> {
    /// The chart's title.
    pub title: &'a str,
    /// The abscissa's description.
    pub x: &'a str,
    /// `Some(n)`: the abscissa is the equation's index 1..=n (whole-number ticks);
    /// `None`: a value (a frequency).
    pub index: Option<usize>,
    /// The work's unit, when known.
    pub unit: Option<&'a str>,
}

/// Residual per equation (module doc), with the zero line and the mean residual,
/// labelled as the residual bias (mean residual / mean |input work|) the report's
/// header gives.
pub(crate) fn residuals(groups: &[Group], axes: &ResidualAxes<'_>, bias: f64) -> Result<String> {
    let all: Vec<f64> = groups
        .iter()
        .flat_map(|g| g.points.iter().map(|p| p.1))
        .collect();
    let mean = all.iter().sum::<f64>() / all.len().max(1) as f64;
    let mean_style = BLACK.stroke_width(px(2));
    let mut entries = vec![(
        Mark::Line(mean_style),
        format!("mean residual {mean:+.3e} = residual bias {bias:+.3e} × mean |input work|"),
    )];
    entries.extend(group_entries(groups));
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let (x, ticks) = match axes.index {
            Some(n) => (
                0.5..(n.max(1) as f64 + 0.5),
                Ticks::Integers(n.clamp(1, 12)),
            ),
            None => (
                padded(groups.iter().flat_map(|g| g.points.iter().map(|p| p.0))),
                Ticks::Plain,
            ),
        };
        let y = padded(all.iter().copied().chain([0.0, mean]));
        let y_desc = with_unit("residual work b − Aθ", axes.unit);
        let mut chart = frame(
            &plot,
            axes.title,
            x.clone(),
            y,
            (axes.x, &y_desc),
            (ticks, Ticks::Plain),
        )?;
        chart
            .draw_series(LineSeries::new(
                [(x.start, 0.0), (x.end, 0.0)],
                BLACK.mix(0.5).stroke_width(px(1)),
            ))
            .map_err(plot_error)?;
        chart
            .draw_series(LineSeries::new(
                [(x.start, mean), (x.end, mean)],
                mean_style,
            ))
            .map_err(plot_error)?;
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        legend_below(&below, &entries)
    })
}
