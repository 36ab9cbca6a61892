//! What the data determine, as the text report gives it: the column-scaled regressor's
//! rank, practical rank, condition number and singular values; the near-null
//! directions; each coefficient's variance inflation factor VIF = 1/(1 − R²) and the
//! correlation of the estimates. A model of more than [`digest::FULL_LISTING`]
//! coefficients gets the digest instead: the undetermined ones counted by term, the
//! [`digest::LISTED`] smallest undetermined directions, the largest VIFs sorted and a
//! histogram by decade, the [`PAIRS_LISTED`] most correlated pairs. With estimated
//! nonlinear parameters all of it is of the linear fit at η̂, η held fixed.

use std::fmt::Write as _;

use super::{HtmlReport, escape};
use crate::analysis::diagnostics::Correlation;
use crate::analysis::digest;

impl HtmlReport<'_> {
    /// The identifiability section (module doc).
    pub(super) fn identifiability_section(&self) -> String {
        let report = self.report;
        let id = &report.identifiability;
        let mut out = String::from("\n<h2>Identifiability</h2>\n");
        if report.estimation.is_some() {
            out.push_str("<p>Of the linear fit at η̂ (η held fixed).</p>\n");
        }
        let condition = report
            .condition_number
            .map_or("infinite".to_string(), |k| format!("{k:.3e}"));
        let singular: Vec<String> = report
            .singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect();
        let singular = if singular.len() > digest::FULL_LISTING {
            digest::sequence(&report.singular_values)
        } else {
            format!("[{}]", singular.join(", "))
        };
        let _ = writeln!(
            out,
            "<p>Column-scaled regressor: rank {}, practical rank {} of {}, condition number {condition}, singular values {singular}.</p>",
            report.rank,
            id.practical_rank,
            id.names.len(),
        );
        if id.names.len() > digest::FULL_LISTING {
            out.push_str(&self.identifiability_digest());
            return out;
        }
        if id.null_directions.is_empty() {
            out.push_str(
                "<p>No near-null direction: every coefficient is separated by the data.</p>\n",
            );
        } else {
            out.push_str("<p>Directions the data do not determine:</p>\n<ul>\n");
            for d in &id.null_directions {
                let _ = writeln!(out, "<li>{}</li>", escape(&d.text));
            }
            out.push_str("</ul>\n");
        }
        out.push_str("<h3>Variance inflation factors</h3>\n<p>VIF = 1/(1 − R²) of each column against the others: 1 for an orthogonal column, infinite for one the others reproduce.</p>\n<table><tr><th>coefficient</th><th>VIF</th><th>determined</th></tr>\n");
        for (name, vif) in id.names.iter().zip(&id.variance_inflation) {
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(name),
                vif.map_or("infinite".to_string(), |v| format!("{v:.3e}")),
                if id.is_identifiable(name) {
                    "yes"
                } else {
                    "no"
                }
            );
        }
        out.push_str("</table>\n");
        if let Some(c) = &report.correlation
            && c.names.len() > 1
        {
            out.push_str("<h3>Correlation of the estimates</h3>\n<table><tr><th></th>");
            for n in &c.names {
                let _ = write!(out, "<th>{}</th>", escape(n));
            }
            out.push_str("</tr>\n");
            for (n, row) in c.names.iter().zip(&c.matrix) {
                let _ = write!(out, "<tr><th>{}</th>", escape(n));
                for r in row {
                    let _ = write!(out, "<td>{r:.3}</td>");
                }
                out.push_str("</tr>\n");
            }
            out.push_str("</table>\n");
        }
        out
    }

    /// The identifiability of a model of many coefficients, as the text report gives
    /// it: the undetermined coefficients counted by term, the [`digest::LISTED`]
    /// smallest undetermined directions by their [`digest::CONTRIBUTORS`] largest
    /// components and "+ N more", the largest VIFs as a sorted list and a histogram by
    /// decade, and the most correlated pairs instead of the whole correlation matrix.
    fn identifiability_digest(&self) -> String {
        let report = self.report;
        let id = &report.identifiability;
        let p = id.names.len();
        let mut out = String::new();
        if id.separable() {
            out.push_str(
                "<p>No near-null direction: every coefficient is separated by the data.</p>\n",
            );
        } else {
            let names: Vec<&str> = id.unidentifiable.iter().map(String::as_str).collect();
            let _ = writeln!(
                out,
                "<p>These data cannot separate {} of {p} coefficients (by term: {}; every name in <code>identifiability.unidentifiable</code> in the JSON).</p>",
                names.len(),
                escape(&digest::by_term_text(names.iter().copied()))
            );
        }
        let nulls = id.null_directions.len();
        if nulls > 0 {
            let _ = writeln!(
                out,
                "<h3>Directions not determined</h3>\n<p>{nulls} direction(s) along which the fit does not change (σ below {:.3e}); {}each by its {} largest components:</p>\n<table><tr><th>σ</th><th class=\"left\">largest components of the direction Δθ</th></tr>",
                id.threshold,
                if nulls > digest::LISTED {
                    format!("the {} smallest, ", digest::LISTED)
                } else {
                    String::new()
                },
                digest::CONTRIBUTORS
            );
            for d in id.null_directions.iter().take(digest::LISTED) {
                let _ = writeln!(
                    out,
                    "<tr><td>{:.3e}</td><td class=\"left\"><code>{}</code></td></tr>",
                    d.singular_value,
                    escape(&d.direction.text)
                );
            }
            out.push_str("</table>\n");
            if nulls > digest::LISTED {
                let _ = writeln!(
                    out,
                    "<p>+ {} more (<code>identifiability.null_directions</code> in the JSON).</p>",
                    nulls - digest::LISTED
                );
            }
        }
        out.push_str("<h3>Variance inflation factors</h3>\n<p>VIF = 1/(1 − R²) of each column against the others: 1 for an orthogonal column, infinite for one the others reproduce.</p>\n");
        let finite: Vec<(usize, f64)> = id
            .variance_inflation
            .iter()
            .enumerate()
            .filter_map(|(j, v)| v.map(|v| (j, v)))
            .collect();
        if finite.is_empty() {
            let _ = writeln!(
                out,
                "<p>Infinite for all {p} coefficients: the regressor is rank deficient.</p>"
            );
        } else {
            let values: Vec<f64> = finite.iter().map(|f| f.1).collect();
            let top = digest::largest(&values, digest::LISTED);
            let _ = writeln!(
                out,
                "<p>The {} largest of {p}, sorted:</p>\n<table><tr><th>coefficient</th><th>VIF</th></tr>",
                top.len()
            );
            for k in top {
                let (j, v) = finite[k];
                let _ = writeln!(
                    out,
                    "<tr><td>{}</td><td>{v:.3e}</td></tr>",
                    escape(&id.names[j])
                );
            }
            out.push_str("</table>\n");
        }
        out.push_str(&vif_histogram(&id.variance_inflation));
        if let Some(c) = &report.correlation {
            out.push_str(&correlated_pairs(c));
        }
        out
    }
}

/// The VIFs counted by decade ([`digest::decade_histogram`]), as a table with a bar per
/// decade (its width the count's share of the largest count).
fn vif_histogram(values: &[Option<f64>]) -> String {
    let (decades, infinite) = digest::decade_histogram(values);
    let mut rows: Vec<(String, usize)> = decades
        .iter()
        .map(|(d, n)| (format!("10<sup>{d}</sup> – 10<sup>{}</sup>", d + 1), *n))
        .collect();
    if infinite > 0 {
        rows.push(("infinite".into(), infinite));
    }
    let most = rows.iter().map(|r| r.1).max().unwrap_or(1).max(1);
    let mut out = String::from(
        "<p>Histogram of the VIFs by decade:</p>\n<table class=\"histogram\"><tr><th>VIF</th><th>coefficients</th><th></th></tr>\n",
    );
    for (label, n) in rows {
        let _ = writeln!(
            out,
            "<tr><td>{label}</td><td>{n}</td><td class=\"left\"><span class=\"bar\" style=\"width:{:.1}em\"></span></td></tr>",
            20.0 * n as f64 / most as f64
        );
    }
    out.push_str("</table>\n");
    out
}

/// Pairs of estimates listed by their correlation when the matrix is too large to show.
const PAIRS_LISTED: usize = 10;

/// The [`PAIRS_LISTED`] most correlated pairs of estimates (largest |r|, ties in model
/// order), for a correlation matrix too large to show.
fn correlated_pairs(c: &Correlation) -> String {
    let n = c.names.len();
    let mut pairs: Vec<(usize, usize, f64)> = (0..n)
        .flat_map(|i| ((i + 1)..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let r = *c.matrix.get(i)?.get(j)?;
            r.is_finite().then_some((i, j, r))
        })
        .collect();
    if pairs.is_empty() {
        return String::new();
    }
    pairs.sort_by(|a, b| {
        b.2.abs()
            .total_cmp(&a.2.abs())
            .then((a.0, a.1).cmp(&(b.0, b.1)))
    });
    let mut out = format!(
        "<h3>Correlation of the estimates</h3>\n<p>The {} most correlated of {} pairs (the whole matrix: <code>correlation</code> in the JSON).</p>\n<table><tr><th>coefficient</th><th>coefficient</th><th>correlation</th></tr>\n",
        pairs.len().min(PAIRS_LISTED),
        pairs.len()
    );
    for (i, j, r) in pairs.into_iter().take(PAIRS_LISTED) {
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{}</td><td>{r:.4}</td></tr>",
            escape(&c.names[i]),
            escape(&c.names[j])
        );
    }
    out.push_str("</table>\n");
    out
}
