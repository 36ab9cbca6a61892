//! The charts of a free decay's backbone ([`crate::analysis::backbone`]), one colour per
//! record:
//!
//! - the frequency f(X) of each window against its amplitude X on a log axis, and the
//!   frequency the fitted law's windows would hold (the measured one: the law does not
//!   move it), so the chart shows how the mode softens or stiffens with amplitude;
//! - the decay envelope: each window's amplitude X against time, X on a log axis (a
//!   viscous decay is a straight line, Coulomb friction bends it down, a law stronger
//!   at large amplitude bends it up at the start).
//!
//! ζ(X) goes through the stepped-sine table's chart ([`super::energy::damping_ratio`]).

use super::{
    Group, SIZE, Ticks, chart_svg_of_height, draw_group, frame, group_entries, legend_below,
    legend_strip, padded,
};
use crate::error::Result;

/// `groups` with each point mapped by `point` (`None`: off a log axis, left out).
fn mapped(groups: &[Group], point: impl Fn((f64, f64)) -> Option<(f64, f64)>) -> Vec<Group> {
    groups
        .iter()
        .map(|g| Group {
            name: g.name.clone(),
            points: g.points.iter().filter_map(|&p| point(p)).collect(),
            rest: g.rest,
        })
        .collect()
}

/// Frequency against amplitude, X on a log axis (module doc).
pub(crate) fn frequency(groups: &[Group]) -> Result<String> {
    let logged = mapped(groups, |(x, f)| {
        (x > 0.0 && f.is_finite()).then(|| (x.log10(), f))
    });
    scatter(
        &logged,
        "Backbone frequency f(X)",
        ("amplitude X (log scale)", "frequency f of each window"),
        (Ticks::Decades, Ticks::Plain),
    )
}

/// Amplitude against time, X on a log axis (module doc).
pub(crate) fn envelope(groups: &[Group]) -> Result<String> {
    let logged = mapped(groups, |(t, x)| {
        (t.is_finite() && x > 0.0).then(|| (t, x.log10()))
    });
    scatter(
        &logged,
        "Decay envelope X(t)",
        ("time of the window's start", "amplitude X (log scale)"),
        (Ticks::Plain, Ticks::Decades),
    )
}

/// One scatter of `groups` with the legend below.
fn scatter(
    groups: &[Group],
    caption: &str,
    labels: (&str, &str),
    ticks: (Ticks, Ticks),
) -> Result<String> {
    let entries = group_entries(groups);
    let strip = legend_strip(&entries);
    chart_svg_of_height(SIZE.1 + strip, |root| {
        let (plot, below) = root.split_vertically(super::px(SIZE.1));
        let xs = groups.iter().flat_map(|g| g.points.iter().map(|p| p.0));
        let ys = groups.iter().flat_map(|g| g.points.iter().map(|p| p.1));
        let mut chart = frame(&plot, caption, padded(xs), padded(ys), labels, ticks)?;
        for (k, group) in groups.iter().enumerate() {
            draw_group(&mut chart, k, group)?;
        }
        legend_below(&below, &entries)
    })
}
