//! SVG charts for the HTML report, drawn with plotters' SVG backend. Text is written as
//! SVG `<text>` elements with estimated metrics, so no font library is needed.
//!
//! plotters writes whole-pixel coordinates; every chart is drawn at [`OVERSAMPLE`] times
//! its size and shown at its size (the root's `viewBox` keeps the drawn size, `width` and
//! `height` the shown one), so lines land on quarter pixels instead of stair-stepping.
//! Every length below (fonts, margins, markers, strokes) is in shown pixels and
//! multiplied by [`OVERSAMPLE`] where it is drawn. Text is at least 13 px as shown at
//! [`SIZE`] (plotters writes `font-size` = size / 1.24). Colours are the Okabe–Ito
//! palette, safe for the common colour-vision deficiencies.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{Error, Result};

/// The shown size of a chart, in CSS pixels (the page stretches it to its width).
pub(crate) const SIZE: (u32, u32) = (960, 480);

/// Drawn pixels per shown pixel.
pub(crate) const OVERSAMPLE: u32 = 4;

/// `px` shown pixels in drawn pixels.
const fn px(px: u32) -> u32 {
    px * OVERSAMPLE
}

/// Font sizes (plotters' size, shown pixels ×1.24 = the written font-size ≥ 13 px).
const CAPTION_FONT: f64 = 22.0 * 1.24;
const LABEL_FONT: f64 = 14.0 * 1.24;
const DESC_FONT: f64 = 15.0 * 1.24;

/// The Okabe–Ito palette without yellow (hard to see on white) and black (the reference
/// lines): blue, vermillion, bluish green, orange, sky blue, reddish purple.
pub(crate) const PALETTE: [RGBColor; 6] = [
    RGBColor(0x00, 0x72, 0xB2),
    RGBColor(0xD5, 0x5E, 0x00),
    RGBColor(0x00, 0x9E, 0x73),
    RGBColor(0xE6, 0x9F, 0x00),
    RGBColor(0x56, 0xB4, 0xE9),
    RGBColor(0xCC, 0x79, 0xA7),
];

/// The colour of series `k`.
pub(crate) fn colour(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// A named curve with an optional band (lower, upper) at each point. With `measured`
/// = (lo, hi), the curve was measured over lo ≤ x ≤ hi only: [`force_laws`] draws it
/// solid (with its band) there and dashed beyond.
pub(crate) struct Curve {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub band: Option<Vec<(f64, f64, f64)>>,
    pub measured: Option<(f64, f64)>,
}

/// Points of one group (a record) in a scatter: its legend name and (x, y) points.
pub(crate) struct Group {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Numerical {
        stage: "plot".into(),
        detail: e.to_string(),
    }
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws one chart with `draw` on an oversampled canvas and returns the SVG shown at
/// [`SIZE`].
fn chart_svg(
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<String> {
    chart_svg_of_height(SIZE.1, draw)
}

/// [`chart_svg`] at `height` shown pixels (a chart with its legend below the plot).
fn chart_svg_of_height(
    height: u32,
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (px(SIZE.0), px(height))).into_drawing_area();
        draw(&root)?;
        root.present().map_err(plot_error)?;
    }
    let drawn = format!("width=\"{}\" height=\"{}\"", px(SIZE.0), px(height));
    let shown = format!("width=\"{}\" height=\"{}\"", SIZE.0, height);
    Ok(svg.replacen(&drawn, &shown, 1))
}

/// Shown pixels per legend entry (plotters' `legend_area_size` plus its spacing).
const LEGEND_ROW: u32 = 30;

/// Shown pixels below the plot for a legend of `entries` entries (with its margins).
fn legend_strip(entries: usize) -> u32 {
    LEGEND_ROW * entries as u32 + 30
}

/// How an axis's tick labels read.
#[derive(Debug, Clone, Copy)]
enum Ticks {
    /// Numbers at a round step, never "-0".
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

/// The label of tick `value` on an axis spanning `span`: as many decimals as a tenth of
/// the span needs, exponent form for very large or small numbers, and "0" for a tick at
/// zero up to round-off (never "-0.0").
pub(crate) fn tick_label(value: f64, span: f64) -> String {
    let step = (span.abs() / 10.0).max(f64::MIN_POSITIVE);
    if value.abs() < 1e-6 * step {
        return "0".into();
    }
    let magnitude = value.abs().max(step);
    if !(1e-3..1e5).contains(&magnitude) || step < 1e-4 {
        let digits = ((magnitude / step).log10().ceil().max(0.0) as usize).min(6);
        return format!("{value:.digits$e}");
    }
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let text = format!("{value:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        text
    }
}

/// The common frame: caption, margins, axes with their descriptions, tick labels
/// `ticks` (x, y).
fn frame<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    (x_desc, y_desc): (&str, &str),
    (x_ticks, y_ticks): (Ticks, Ticks),
) -> Result<Chart<'a, 'b>> {
    root.fill(&WHITE).map_err(plot_error)?;
    let (x_span, y_span) = (x.end - x.start, y.end - y.start);
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", CAPTION_FONT * OVERSAMPLE as f64))
        .margin(px(14))
        .x_label_area_size(px(52))
        .y_label_area_size(px(96))
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    let x_plain = move |v: &f64| tick_label(*v, x_span);
    let y_plain = move |v: &f64| tick_label(*v, y_span);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", LABEL_FONT * OVERSAMPLE as f64))
        .axis_desc_style(("sans-serif", DESC_FONT * OVERSAMPLE as f64))
        .bold_line_style(BLACK.mix(0.12).stroke_width(OVERSAMPLE))
        .light_line_style(BLACK.mix(0.04).stroke_width(OVERSAMPLE))
        .axis_style(BLACK.stroke_width(OVERSAMPLE))
        .set_all_tick_mark_size(px(5))
        .x_label_formatter(&x_plain)
        .y_label_formatter(&y_plain);
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
        .label_font(("sans-serif", LABEL_FONT * OVERSAMPLE as f64))
        .margin(px(10))
        .legend_area_size(px(28))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3).stroke_width(OVERSAMPLE))
        .draw()
        .map_err(plot_error)
}

/// What a legend entry shows beside its text.
#[derive(Clone, Copy)]
enum Mark {
    /// A line sample of this style.
    Line(ShapeStyle),
    /// The markers of group k ([`draw_group`]).
    Group(usize),
    /// A dashed line sample of this style.
    Dashed(ShapeStyle),
}

/// Draws a legend in `area` (a strip below a chart, [`legend_strip`] high): a box like
/// plotters' own (translucent white, thin border), one entry per row, so that it
/// covers no data point however the points fall.
fn legend_below(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    entries: &[(Mark, String)],
) -> Result<()> {
    let font = TextStyle::from(("sans-serif", LABEL_FONT * OVERSAMPLE as f64).into_font()).pos(
        plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Left,
            plotters::style::text_anchor::VPos::Center,
        ),
    );
    // Text width estimated at 0.6 em per character (no font metrics here).
    let longest = entries
        .iter()
        .map(|e| e.1.chars().count())
        .max()
        .unwrap_or(0);
    let width = px(50) as i32 + (0.6 * LABEL_FONT * longest as f64) as i32 * OVERSAMPLE as i32;
    let (left, top) = (px(110) as i32, px(8) as i32);
    let height = (px(LEGEND_ROW) * entries.len() as u32 + px(10)) as i32;
    area.draw(&Rectangle::new(
        [(left, top), (left + width, top + height)],
        WHITE.mix(0.85).filled(),
    ))
    .map_err(plot_error)?;
    area.draw(&Rectangle::new(
        [(left, top), (left + width, top + height)],
        BLACK.mix(0.3).stroke_width(OVERSAMPLE),
    ))
    .map_err(plot_error)?;
    for (row, (mark, text)) in entries.iter().enumerate() {
        let y =
            top + px(5) as i32 + (px(LEGEND_ROW) as i32) * row as i32 + px(LEGEND_ROW / 2) as i32;
        let x = left + px(10) as i32;
        match *mark {
            Mark::Line(style) => area.draw(&legend_line(x, y, style)),
            Mark::Group(k) => area.draw(&group_marker(k, (x, y))),
            Mark::Dashed(style) => area
                .draw(&PathElement::new([(x, y), (x + px(8) as i32, y)], style))
                .and_then(|()| {
                    area.draw(&PathElement::new(
                        [(x + px(13) as i32, y), (x + px(21) as i32, y)],
                        style,
                    ))
                }),
        }
        .map_err(plot_error)?;
        area.draw(&Text::new(
            text.clone(),
            (x + px(30) as i32, y),
            font.clone(),
        ))
        .map_err(plot_error)?;
    }
    Ok(())
}

/// A legend sample line of `style` at (x, y).
fn legend_line(x: i32, y: i32, style: ShapeStyle) -> PathElement<(i32, i32)> {
    PathElement::new([(x, y), (x + px(20) as i32, y)], style)
}

/// A range that contains every value, padded by 5%, never empty.
fn padded(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        if v.is_finite() {
            (lo.min(v), hi.max(v))
        } else {
            (lo, hi)
        }
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

/// Markers of group `k`: the colour cycles through the palette, the shape (circle,
/// triangle, cross) changes at each cycle, so up to 18 groups look different.
fn draw_group<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, k: usize, group: &Group) -> Result<()> {
    let style = colour(k).filled();
    let size = px(5) as i32;
    let shape = (k / PALETTE.len()) % 3;
    let points = group.points.iter().copied();
    let annotation = match shape {
        0 => chart
            .draw_series(points.map(|p| Circle::new(p, size, style)))
            .map_err(plot_error)?,
        1 => chart
            .draw_series(points.map(|p| TriangleMarker::new(p, size + px(1) as i32, style)))
            .map_err(plot_error)?,
        _ => chart
            .draw_series(points.map(|p| Cross::new(p, size, colour(k).stroke_width(px(2)))))
            .map_err(plot_error)?,
    };
    annotation
        .label(group.name.clone())
        .legend(move |(x, y)| group_marker(k, (x, y)));
    Ok(())
}

/// A group's legend marker: a circle, a triangle and a cross, two of them transparent.
type GroupMarker<'b> = plotters::element::ComposedElement<
    (i32, i32),
    SVGBackend<'b>,
    Circle<(i32, i32), i32>,
    plotters::element::ComposedElement<
        (i32, i32),
        SVGBackend<'b>,
        TriangleMarker<(i32, i32), i32>,
        Cross<(i32, i32), i32>,
    >,
>;

/// The legend sample of group `k` at (x, y): its marker ([`draw_group`]), one element
/// type for every shape (the two shapes not used are transparent).
fn group_marker<'b>(k: usize, (x, y): (i32, i32)) -> GroupMarker<'b> {
    let style = colour(k).filled();
    let size = px(5) as i32;
    let shape = (k / PALETTE.len()) % 3;
    let pick = move |active: bool, style: ShapeStyle| {
        if active { style } else { TRANSPARENT.filled() }
    };
    let cross = colour(k).stroke_width(px(2));
    EmptyElement::at((x + px(10) as i32, y))
        + Circle::new((0, 0), size, pick(shape == 0, style))
        + TriangleMarker::new((0, 0), size + px(1) as i32, pick(shape == 1, style))
        + Cross::new((0, 0), size, pick(shape == 2, cross))
}

/// Measured input work against identified dissipated work per window, one colour per
/// record, with y = x; with `stored`, the identified work also holds the change of
/// stored energy and the work of constant forces (the non-periodic balance). `unit` is
/// the work's unit, when known.
pub(crate) fn work_balance(groups: &[Group], stored: bool, unit: Option<&str>) -> Result<String> {
    chart_svg(|root| {
        let range = padded(
            groups
                .iter()
                .flat_map(|g| g.points.iter().flat_map(|p| [p.0, p.1])),
        );
        let (x, y) = if stored {
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
        let axes = (
            super::super::units::with_unit(x, unit),
            super::super::units::with_unit(y, unit),
        );
        let mut chart = frame(
            root,
            "Energy balance per window",
            range.clone(),
            range.clone(),
            (&axes.0, &axes.1),
            (Ticks::Plain, Ticks::Plain),
        )?;
        let reference = BLACK.mix(0.5).stroke_width(px(1));
        chart
            .draw_series(LineSeries::new(
                [(range.start, range.start), (range.end, range.end)],
                reference,
            ))
            .map_err(plot_error)?
            .label("equality (input = identified)")
            .legend(move |(x, y)| legend_line(x, y, reference));
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    })
}

/// Residual per equation (1-based), one colour per record, with the zero line and the
/// mean residual, labelled as the residual bias (mean residual / mean |input work|) the
/// report's header gives. The legend sits below the plot, where it covers no point.
pub(crate) fn residuals(
    groups: &[Group],
    equations: usize,
    bias: f64,
    unit: Option<&str>,
) -> Result<String> {
    let strip = legend_strip(groups.len() + 1);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(px(SIZE.1));
        let all: Vec<f64> = groups
            .iter()
            .flat_map(|g| g.points.iter().map(|p| p.1))
            .collect();
        let n = equations.max(1) as f64;
        let mean = all.iter().sum::<f64>() / all.len().max(1) as f64;
        let y = padded(all.iter().copied().chain([0.0, mean]));
        let y_desc = super::super::units::with_unit("residual work b − Aθ", unit);
        let mut chart = frame(
            &plot,
            "Residuals b − Aθ per equation",
            0.5..(n + 0.5),
            y,
            ("equation (window)", &y_desc),
            (Ticks::Integers(equations.clamp(1, 12)), Ticks::Plain),
        )?;
        chart
            .draw_series(LineSeries::new(
                [(0.5, 0.0), (n + 0.5, 0.0)],
                BLACK.mix(0.5).stroke_width(px(1)),
            ))
            .map_err(plot_error)?;
        let mean_style = BLACK.stroke_width(px(2));
        chart
            .draw_series(LineSeries::new([(0.5, mean), (n + 0.5, mean)], mean_style))
            .map_err(plot_error)?;
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        let mut entries = vec![(
            Mark::Line(mean_style),
            format!("mean residual {mean:+.3e} = residual bias {bias:+.3e} × mean |input work|"),
        )];
        entries.extend(
            groups
                .iter()
                .enumerate()
                .map(|(k, g)| (Mark::Group(k), g.name.clone())),
        );
        legend_below(&below, &entries)
    })
}

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
    let strip = legend_strip(curves.len() + usize::from(extrapolated));
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
        let x_desc = super::super::units::with_unit("relative velocity v", units.0);
        let y_desc = super::super::units::with_unit("damping force θ f(v)", units.1);
        let mut chart = frame(
            &plot,
            title,
            x,
            y,
            (&x_desc, &y_desc),
            (Ticks::Plain, Ticks::Plain),
        )?;
        let mut entries = Vec::new();
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
            let mut measured_any = false;
            while start < curve.points.len() {
                let measured = inside(curve, curve.points[start].0);
                let mut end = start + 1;
                while end < curve.points.len() && inside(curve, curve.points[end].0) == measured {
                    end += 1;
                }
                let run = curve.points[start..(end + 1).min(curve.points.len())].to_vec();
                if measured {
                    measured_any = true;
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
            entries.push(if measured_any {
                (Mark::Line(style), curve.name.clone())
            } else {
                (
                    Mark::Dashed(style),
                    format!("{} (outside the measured range only)", curve.name),
                )
            });
        }
        if extrapolated {
            entries.push((
                Mark::Dashed(BLACK.mix(0.6).stroke_width(px(2))),
                "dashed: beyond the measured range of relative velocity (extrapolated)".into(),
            ));
        }
        legend_below(&below, &entries)
    })
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
    chart_svg(|root| {
        let all = || {
            points
                .iter()
                .chain(lines.iter().flat_map(|(_, l)| l.iter()))
        };
        let mut chart = frame(
            root,
            "Dissipated energy per cycle",
            padded(all().map(|p| p.0)),
            padded(all().map(|p| p.1)),
            ("response amplitude X (log10)", "energy per cycle (log10)"),
            (Ticks::Decades, Ticks::Decades),
        )?;
        let measured_colour = colour(0);
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&p| Circle::new(p, px(4) as i32, measured_colour.filled())),
            )
            .map_err(plot_error)?
            .label("measured π a X sin φ")
            .legend(move |(x, y)| {
                Circle::new(
                    (x + px(10) as i32, y),
                    px(4) as i32,
                    measured_colour.filled(),
                )
            });
        for (k, (name, line)) in lines.iter().enumerate() {
            let style = colour(k + 1).stroke_width(px(2));
            chart
                .draw_series(LineSeries::new(line.iter().copied(), style))
                .map_err(plot_error)?
                .label(name.as_str())
                .legend(move |(x, y)| legend_line(x, y, style));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    })
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
            measured: None,
        }
    }

    /// Whether the SVG has a text element reading exactly `text`.
    fn has_text(svg: &str, text: &str) -> bool {
        svg.contains(&format!(">\n{text}\n</text>"))
    }

    /// Tick labels never read "-0" or "-0.0", carry the decimals a tenth of the span
    /// needs, and switch to exponent form outside [1e-3, 1e5).
    #[test]
    fn tick_labels_are_tidy() {
        assert_eq!(tick_label(-1e-17, 2.0), "0");
        assert_eq!(tick_label(-0.04, 1.0), "0");
        assert_eq!(tick_label(0.5, 2.0), "0.5");
        assert_eq!(tick_label(-0.5, 2.0), "-0.5");
        assert_eq!(tick_label(2.0, 10.0), "2");
        assert_eq!(tick_label(250.0, 1000.0), "250");
        assert_eq!(tick_label(1.5e6, 3e6), "1.5e6");
        assert_eq!(tick_label(2e-5, 1e-4), "2.0e-5");
    }

    /// Charts are drawn at OVERSAMPLE times their size and shown at SIZE: the root
    /// says so, and coordinates inside are at drawn scale.
    #[test]
    fn charts_are_oversampled() {
        let svg = residuals(
            &[Group {
                name: "record 1".into(),
                points: vec![(1.0, 0.5), (2.0, -0.25)],
            }],
            2,
            0.01,
            Some("N·m"),
        )
        .unwrap();
        let head = &svg[..svg.find('>').unwrap()];
        // The residual chart is SIZE plus the strip its legend takes below the plot
        // (two entries: the mean and one record).
        let height = SIZE.1 + legend_strip(2);
        assert!(
            head.contains(&format!("width=\"{}\" height=\"{height}\"", SIZE.0)),
            "{head}"
        );
        assert!(
            head.contains(&format!("viewBox=\"0 0 {} {}\"", px(SIZE.0), px(height))),
            "{head}"
        );
        assert!(svg.contains("record 1") && svg.contains("[N·m]"));
        assert!(svg.contains("residual bias +1.000e-2 × mean |input work|"));
        // No font under 13 px as shown.
        for size in svg.split("font-size=\"").skip(1) {
            let value: f64 = size[..size.find('"').unwrap()].parse().unwrap();
            assert!(value / OVERSAMPLE as f64 >= 13.0, "{value}");
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
