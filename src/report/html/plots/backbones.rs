//! The charts of backbones of several jobs side by side
//! ([`crate::analysis::backbones`]), against the amplitude X on a log axis, one colour
//! per job: its measured points (a free decay's windows, a table's levels) as markers,
//! its fitted law as a line of the same colour with a ±1.96σ band where the job has
//! standard deviations.

use plotters::prelude::*;

use super::{
    Group, Mark, SIZE, Ticks, chart_svg_of_height, colour, draw_group, frame, legend_below,
    legend_strip, padded, plot_error, px,
};
use crate::error::Result;

/// One job's series on a chart: (X, y) measured, and the fitted (X, y, sd of y).
pub(crate) struct JobSeries {
    /// The legend's name of the job.
    pub name: String,
    /// Measured points.
    pub measured: Vec<(f64, f64)>,
    /// The fitted curve, by increasing X.
    pub fitted: Vec<(f64, f64, Option<f64>)>,
}

/// The chart of `jobs` (module doc) under `caption`, y described by `y_desc`.
pub(crate) fn by_job(caption: &str, y_desc: &str, jobs: &[JobSeries]) -> Result<String> {
    let log_x = |x: f64, y: f64| (x > 0.0 && y.is_finite()).then(|| (x.log10(), y));
    let groups: Vec<Group> = jobs
        .iter()
        .map(|j| Group {
            name: format!("{}: measured", j.name),
            points: j
                .measured
                .iter()
                .filter_map(|&(x, y)| log_x(x, y))
                .collect(),
            rest: false,
        })
        .collect();
    let lines: Vec<Vec<(f64, f64)>> = jobs
        .iter()
        .map(|j| {
            j.fitted
                .iter()
                .filter_map(|&(x, y, _)| log_x(x, y))
                .collect()
        })
        .collect();
    let bands: Vec<Vec<(f64, f64, f64)>> = jobs
        .iter()
        .map(|j| {
            j.fitted
                .iter()
                .filter_map(|&(x, y, s)| {
                    let s = s.filter(|s| s.is_finite())?;
                    let (x, _) = log_x(x, y)?;
                    Some((x, y - 1.96 * s, y + 1.96 * s))
                })
                .collect()
        })
        .collect();
    let mut entries = Vec::new();
    for (k, job) in jobs.iter().enumerate() {
        entries.push((Mark::Group(k), groups[k].name.clone()));
        if !lines[k].is_empty() {
            entries.push((
                Mark::Line(colour(k).stroke_width(px(2))),
                format!("{}: fitted law", job.name),
            ));
        }
        if !bands[k].is_empty() {
            entries.push((Mark::Band(colour(k)), format!("{}: ±1.96σ", job.name)));
        }
    }
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let xs = lines
            .iter()
            .flatten()
            .map(|p| p.0)
            .chain(groups.iter().flat_map(|g| g.points.iter().map(|p| p.0)));
        let ys = lines
            .iter()
            .flatten()
            .map(|p| p.1)
            .chain(bands.iter().flatten().flat_map(|b| [b.1, b.2]))
            .chain(groups.iter().flat_map(|g| g.points.iter().map(|p| p.1)));
        let mut chart = frame(
            &plot,
            caption,
            padded(xs),
            padded(ys),
            ("displacement amplitude X (log scale)", y_desc),
            (Ticks::Decades, Ticks::Plain),
        )?;
        for (k, band) in bands.iter().enumerate().filter(|(_, b)| !b.is_empty()) {
            let upper = band.iter().map(|b| (b.0, b.2));
            let lower = band.iter().rev().map(|b| (b.0, b.1));
            chart
                .draw_series(std::iter::once(Polygon::new(
                    upper.chain(lower).collect::<Vec<_>>(),
                    colour(k).mix(0.2),
                )))
                .map_err(plot_error)?;
        }
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        for (k, line) in lines.iter().enumerate() {
            chart
                .draw_series(LineSeries::new(
                    line.iter().copied(),
                    colour(k).stroke_width(px(2)),
                ))
                .map_err(plot_error)?;
        }
        legend_below(&below, &entries)
    })
}
