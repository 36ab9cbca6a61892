//! Identified damping laws θ f(v) against relative velocity.

use plotters::prelude::*;

use super::{
    Curve, Mark, SIZE, Ticks, chart_svg_of_height, colour, frame, legend_below, legend_strip,
    padded, plot_error, px,
};
use crate::error::Result;
use crate::report::units::with_unit;

/// Identified force laws against relative velocity: each solid, with its uncertainty
/// band, over the velocity range its elements were measured at (`Curve::measured`),
/// and dashed beyond it, as a legend entry (below the plot) says.
pub(crate) fn force_laws(
    title: &str,
    curves: &[Curve],
    units: (Option<&str>, Option<&str>),
) -> Result<String> {
    let inside = |c: &Curve, x: f64| c.measured.is_none_or(|(lo, hi)| lo <= x && x <= hi);
    let extrapolated = curves
        .iter()
        .any(|c| c.points.iter().any(|p| !inside(c, p.0)));
    let mut entries: Vec<(Mark, String)> = curves
        .iter()
        .enumerate()
        .map(|(k, curve)| {
            let style = colour(k).stroke_width(px(2));
            if curve.points.iter().any(|p| inside(curve, p.0)) {
                (Mark::Line(style), curve.name.clone())
            } else {
                (
                    Mark::Dashed(style),
                    format!("{} (outside the measured range only)", curve.name),
                )
            }
        })
        .collect();
    if extrapolated {
        entries.push((
            Mark::Dashed(BLACK.mix(0.6).stroke_width(px(2))),
            "dashed: beyond the measured range of relative velocity (extrapolated)".into(),
        ));
    }
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let x = padded(
            curves
                .iter()
                .flat_map(|c| c.points.iter().map(|p| p.0))
                .chain([0.0]),
        );
        let y = padded(curves.iter().flat_map(|c| {
            let band = c.band.iter().flatten().flat_map(|b| [b.1, b.2]);
            c.points.iter().map(|p| p.1).chain(band)
        }));
        let x_desc = with_unit("relative velocity v", units.0);
        let y_desc = with_unit("damping force θ f(v)", units.1);
        let mut chart = frame(
            &plot,
            title,
            x,
            y,
            (&x_desc, &y_desc),
            (Ticks::Plain, Ticks::Plain),
        )?;
        for (k, curve) in curves.iter().enumerate() {
            let color = colour(k);
            if let Some(band) = &curve.band {
                let band: Vec<_> = band.iter().filter(|b| inside(curve, b.0)).collect();
                let upper = band.iter().map(|b| (b.0, b.2));
                let lower = band.iter().rev().map(|b| (b.0, b.1));
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        upper.chain(lower).collect::<Vec<_>>(),
                        color.mix(0.2),
                    )))
                    .map_err(plot_error)?;
            }
            let style = color.stroke_width(px(2));
            // Runs of points inside or outside the measured range, each joined to the
            // next run's first point so the line is unbroken where it changes style.
            let mut start = 0;
            while start < curve.points.len() {
                let measured = inside(curve, curve.points[start].0);
                let mut end = start + 1;
                while end < curve.points.len() && inside(curve, curve.points[end].0) == measured {
                    end += 1;
                }
                let run = curve.points[start..(end + 1).min(curve.points.len())].to_vec();
                if measured {
                    chart
                        .draw_series(LineSeries::new(run, style))
                        .map_err(plot_error)?;
                } else {
                    chart
                        .draw_series(DashedLineSeries::new(run, px(8), px(6), style))
                        .map_err(plot_error)?;
                }
                start = end;
            }
        }
        legend_below(&below, &entries)
    })
}
