//! The backbone of a free decay ([`crate::analysis::backbone`]) on the page: ζ(X) with
//! each window's energy decrement beside the fitted law's ζ_eq at the same amplitude and
//! frequency, the frequency f(X), and the decay envelope X(t), one colour per record;
//! then a table of windows spread over the amplitude range.

use std::fmt::Write as _;

use super::plots::{self, Group, ZetaCurve};
use super::{HtmlReport, escape};
use crate::analysis::backbone::Backbone;
use crate::error::Result;

/// The records' groups of `(x, y)` points of the backbone.
fn groups(
    backbone: &Backbone,
    point: impl Fn(&crate::analysis::backbone::BackbonePoint) -> (f64, f64),
) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for p in &backbone.points {
        match groups.iter_mut().find(|g| g.name == p.record) {
            Some(g) => g.points.push(point(p)),
            None => groups.push(Group {
                name: p.record.clone(),
                points: vec![point(p)],
                rest: false,
            }),
        }
    }
    plots::gathered(groups, "records", plots::MOST_GROUPS)
}

impl HtmlReport<'_> {
    /// The backbone's charts and table; nothing for other problems.
    pub(super) fn backbone_section(&self) -> Result<String> {
        let Some(backbone) = self.backbone else {
            return Ok(String::new());
        };
        let mut fitted: Vec<(f64, f64, Option<f64>)> = backbone
            .points
            .iter()
            .map(|p| (p.amplitude, p.fitted, None))
            .collect();
        fitted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let zeta = plots::damping_ratio(
            &ZetaCurve {
                name: "the fitted law's ζ_eq at each window's amplitude and frequency".into(),
                points: fitted,
            },
            &groups(backbone, |p| (p.amplitude, p.measured)),
            &format!(
                "the energy decrement ζ = ln(E_a/E_b)/(2ωΔt) over the {} windows around each, by record:",
                2 * crate::analysis::backbone::SPAN + 1
            ),
            &[],
        )?;
        let frequency = plots::frequency(&groups(backbone, |p| (p.amplitude, p.frequency)))?;
        let envelope = plots::envelope(&groups(backbone, |p| (p.time, p.amplitude)))?;
        let mut out = String::from("\n<h2>Free decay: backbone</h2>\n");
        let _ = writeln!(
            out,
            "<p>{} windows of whole cycles; the coefficients are per modal mass {}. The points are the energy decrement around each window; the curve is the fitted law's equivalent ratio at the windows' amplitudes and frequencies.</p>",
            backbone.points.len(),
            backbone.mass
        );
        for svg in [zeta, frequency, envelope] {
            let _ = writeln!(out, "{svg}");
        }
        out.push_str("<pre>");
        out.push_str(&escape(&backbone.to_string()));
        out.push_str("</pre>\n");
        Ok(out)
    }
}
