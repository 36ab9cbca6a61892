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

/// The common frame: caption, margins, axes with their descriptions.
fn frame<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    (x_desc, y_desc): (&str, &str),
) -> Result<Chart<'a, 'b>> {
    root.fill(&WHITE).map_err(plot_error)?;
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .draw()
        .map_err(plot_error)?;
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

/// Measured input work against identified dissipated work per window, with y = x.
pub(crate) fn work_balance(input: &[f64], dissipated: &[f64]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        let range = padded(input.iter().chain(dissipated).copied());
        let axes = (
            "input work ∮ vᵀr dt",
            "identified dissipated work Σ θ_k A_k",
        );
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
