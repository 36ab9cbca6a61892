//! SVG charts for the HTML report, drawn with plotters' SVG backend: the frame, ticks,
//! palette, markers and legends every chart shares (this file) and the charts by kind
//! (balance.rs: energy balance and residuals; laws.rs: damping laws against velocity;
//! energy.rs: energy per cycle and ζ_eq against amplitude; modes.rs: proper orthogonal
//! modes). Text is written as SVG `<text>` elements with estimated metrics, so no font
//! library is needed.
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

pub(crate) mod backbones;
mod balance;
mod decay;
mod energy;
mod laws;
mod modes;

pub(crate) use balance::{BalanceAxes, ResidualAxes, residuals, work_balance};
pub(crate) use decay::{envelope, frequency};
pub(crate) use energy::{ZetaCurve, damping_ratio, energy_per_cycle};
pub(crate) use laws::force_laws;
pub(crate) use modes::{energy_shares, mode_shapes};

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

/// Points of one group (a record or a sweep) in a scatter: its legend name and (x, y)
/// points; `rest` marks the group that gathers the groups a legend has no room for
/// (drawn grey).
pub(crate) struct Group {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub rest: bool,
}

/// Groups a scatter tells apart at most: the palette's six colours in three marker
/// shapes.
pub(crate) const MOST_GROUPS: usize = 18;

/// Entries a legend holds at most.
pub(crate) const MOST_ENTRIES: usize = 20;

/// `groups` fitted into `room` legend entries (at most [`MOST_GROUPS`]): when there are
/// more, the first `room` − 1 keep their own marker and the rest share one grey marker
/// and one entry, "N more `plural`" (e.g. "12 more sweeps").
pub(crate) fn gathered(mut groups: Vec<Group>, plural: &str, room: usize) -> Vec<Group> {
    let room = room.clamp(2, MOST_GROUPS);
    if groups.len() <= room {
        return groups;
    }
    let rest = groups.split_off(room - 1);
    groups.push(Group {
        name: format!("{} more {plural}", rest.len()),
        points: rest.into_iter().flat_map(|g| g.points).collect(),
        rest: true,
    });
    groups
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

/// Shown pixels per legend row (plotters' `legend_area_size` plus its spacing).
const LEGEND_ROW: u32 = 30;

/// Shown pixels from the chart's left edge to a legend below it.
const LEGEND_LEFT: u32 = 110;

/// Shown pixels a legend below a chart may span.
const LEGEND_WIDTH: u32 = SIZE.0 - LEGEND_LEFT - 20;

/// Shown pixels per character of legend text (an estimate: no font metrics here).
const LEGEND_CHAR: f64 = 0.5 * LABEL_FONT;

/// Shown pixels of an entry's mark and the gaps around it.
const LEGEND_MARK: u32 = 50;

/// How a legend below a chart is laid out: in order, an entry wider than a third of
/// the legend on a row of its own, and each run of narrower entries in a grid of as many
/// columns of its widest entry as fit (at most six).
struct LegendLayout {
    /// Each entry's shown offset from the legend's left edge and its row.
    places: Vec<(u32, usize)>,
    /// Rows in all.
    rows: usize,
    /// Shown width of the box.
    width: u32,
}

impl LegendLayout {
    fn of(entries: &[(Mark, String)]) -> Self {
        let widths: Vec<u32> = entries
            .iter()
            .map(|e| LEGEND_MARK + (LEGEND_CHAR * e.1.chars().count() as f64) as u32)
            .collect();
        let narrow = |k: usize| widths[k] <= LEGEND_WIDTH / 3;
        let mut places = Vec::with_capacity(entries.len());
        let (mut row, mut width, mut k) = (0, 0, 0);
        while k < entries.len() {
            if !narrow(k) {
                places.push((0, row));
                width = width.max(widths[k]);
                row += 1;
                k += 1;
                continue;
            }
            let end = (k..entries.len())
                .find(|&j| !narrow(j))
                .unwrap_or(entries.len());
            let column = widths[k..end].iter().copied().max().unwrap_or(1).max(1);
            let columns = ((LEGEND_WIDTH / column) as usize).clamp(1, 6).min(end - k);
            for j in 0..(end - k) {
                places.push(((j % columns) as u32 * column, row + j / columns));
            }
            width = width.max(column * columns as u32);
            row += (end - k).div_ceil(columns);
            k = end;
        }
        LegendLayout {
            places,
            rows: row,
            width: width.min(SIZE.0 - LEGEND_LEFT),
        }
    }
}

/// Shown pixels below the plot for a legend of `entries` (with its margins).
fn legend_strip(entries: &[(Mark, String)]) -> u32 {
    LEGEND_ROW * LegendLayout::of(entries).rows as u32 + 30
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
    /// The grey marker of the gathered groups ([`gathered`]).
    Rest,
    /// A band of this colour (as the curves' bands are filled).
    Band(RGBColor),
    /// Nothing: a note.
    Note,
    /// A line of `style` in dashes of (length, gap) shown pixels.
    Dash(ShapeStyle, u32, u32),
    /// The open square of a measured level ([`level_marker`]).
    Level,
}

/// The colour of the gathered groups.
const REST: RGBColor = RGBColor(0x99, 0x99, 0x99);

/// The legend entries of `groups` (their markers and names).
fn group_entries(groups: &[Group]) -> Vec<(Mark, String)> {
    groups
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let mark = if g.rest { Mark::Rest } else { Mark::Group(k) };
            (mark, g.name.clone())
        })
        .collect()
}

/// Draws a legend in `area` (a strip below a chart, [`legend_strip`] high): a box like
/// plotters' own (translucent white, thin border), laid out by [`LegendLayout`], so
/// that it covers no data point however the points fall.
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
    let layout = LegendLayout::of(entries);
    let width = px(layout.width) as i32;
    let (left, top) = (px(LEGEND_LEFT) as i32, px(8) as i32);
    let height = (px(LEGEND_ROW) * layout.rows as u32 + px(10)) as i32;
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
    for (k, (mark, text)) in entries.iter().enumerate() {
        let (offset, row) = layout.places[k];
        let y =
            top + px(5) as i32 + (px(LEGEND_ROW) as i32) * row as i32 + px(LEGEND_ROW / 2) as i32;
        let x = left + px(10) as i32 + px(offset) as i32;
        match *mark {
            Mark::Line(style) => area.draw(&legend_line(x, y, style)),
            Mark::Group(k) => area.draw(&group_marker(k, (x, y))),
            Mark::Rest => area.draw(&Circle::new(
                (x + px(10) as i32, y),
                px(4) as i32,
                REST.filled(),
            )),
            Mark::Band(colour) => area.draw(&Rectangle::new(
                [(x, y - px(6) as i32), (x + px(20) as i32, y + px(6) as i32)],
                colour.mix(0.2).filled(),
            )),
            Mark::Note => Ok(()),
            Mark::Level => area.draw(
                &(EmptyElement::at((x + px(10) as i32, y))
                    + Rectangle::new(LEVEL_SQUARE, BLACK.stroke_width(px(2)))),
            ),
            Mark::Dash(style, dash, gap) => {
                let mut drawn = Ok(());
                let mut at = 0;
                while at < 24 && drawn.is_ok() {
                    let end = (at + dash).min(24);
                    drawn = area.draw(&PathElement::new(
                        [(x + px(at) as i32, y), (x + px(end) as i32, y)],
                        style,
                    ));
                    at = end + gap;
                }
                drawn
            }
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
/// triangle, cross) changes at each cycle, so up to 18 groups look different; the
/// gathered rest ([`gathered`]) is small grey circles. Adds no legend entry (the
/// legends below a chart list the groups: [`group_entries`]).
fn draw_group<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, k: usize, group: &Group) -> Result<()> {
    let style = colour(k).filled();
    let size = px(5) as i32;
    let shape = (k / PALETTE.len()) % 3;
    let points = group.points.iter().copied();
    if group.rest {
        chart
            .draw_series(points.map(|p| Circle::new(p, px(3) as i32, REST.filled())))
            .map_err(plot_error)?;
        return Ok(());
    }
    match shape {
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
    Ok(())
}

/// The open black square of a measured level's ζ on the ζ_eq(X) plot, about its
/// centre (shown pixels).
const LEVEL_SQUARE: [(i32, i32); 2] = [
    (-(px(5) as i32), -(px(5) as i32)),
    (px(5) as i32, px(5) as i32),
];

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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Whether the SVG has a text element reading exactly `text`.
    pub(crate) fn has_text(svg: &str, text: &str) -> bool {
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
        let axes = ResidualAxes {
            title: "residuals",
            x: "equation (window)",
            index: Some(2),
            unit: Some("N·m"),
        };
        let groups = [Group {
            name: "record 1".into(),
            points: vec![(1.0, 0.5), (2.0, -0.25)],
            rest: false,
        }];
        let svg = residuals(&groups, &axes, 0.01).unwrap();
        let head = &svg[..svg.find('>').unwrap()];
        // The residual chart is SIZE plus the strip its legend takes below the plot
        // (two rows: the long mean entry, then the record).
        let entries = [
            (
                Mark::Note,
                "mean residual +1.250e-1 = residual bias +1.000e-2 × mean |input work|".to_string(),
            ),
            (Mark::Group(0), "record 1".to_string()),
        ];
        assert_eq!(LegendLayout::of(&entries).rows, 2);
        let height = SIZE.1 + legend_strip(&entries);
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

    /// Short entries share rows in columns; an entry too long for a third of the width
    /// has a row of its own; every entry has its own place and the box stays inside the
    /// chart.
    #[test]
    fn legends_below_lay_out_in_columns() {
        let short: Vec<(Mark, String)> = (1..=12)
            .map(|k| (Mark::Group(k), format!("level = {k}")))
            .collect();
        let layout = LegendLayout::of(&short);
        assert_eq!(layout.rows, 2, "six columns of twelve sweeps");
        let mut mixed = vec![
            (Mark::Note, "a".repeat(12)),
            (Mark::Note, "b".repeat(12)),
            (Mark::Note, "x".repeat(80)),
        ];
        mixed.extend(short);
        let layout = LegendLayout::of(&mixed);
        // Two short entries on one row, the long one alone, the sweeps on two rows.
        assert_eq!(layout.rows, 4);
        assert_eq!(layout.places[2], (0, 1));
        assert_eq!(layout.places[3], (0, 2));
        assert!(layout.width <= SIZE.0 - LEGEND_LEFT);
        let mut places = layout.places.clone();
        places.sort_unstable();
        places.dedup();
        assert_eq!(places.len(), mixed.len());
        // No entry: no row, no panic.
        assert_eq!(LegendLayout::of(&[]).rows, 0);
    }

    /// More groups than there is room for: the first room − 1 stay, the rest become one
    /// group holding all their points; never more than MOST_GROUPS.
    #[test]
    fn many_groups_are_gathered() {
        let groups = |n: usize| -> Vec<Group> {
            (0..n)
                .map(|k| Group {
                    name: format!("sweep {k}"),
                    points: vec![(k as f64, 1.0); 2],
                    rest: false,
                })
                .collect()
        };
        assert_eq!(
            gathered(groups(MOST_GROUPS), "sweeps", 100).len(),
            MOST_GROUPS
        );
        assert_eq!(gathered(groups(12), "sweeps", 12).len(), 12);
        for (room, kept) in [(100, MOST_GROUPS), (15, 15)] {
            let many = gathered(groups(30), "sweeps", room);
            assert_eq!(many.len(), kept);
            let last = &many[kept - 1];
            assert!(last.rest && !many[0].rest);
            assert_eq!(last.name, format!("{} more sweeps", 30 - (kept - 1)));
            assert_eq!(last.points.len(), 2 * (30 - (kept - 1)));
        }
    }
}
