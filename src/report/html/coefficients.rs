//! The coefficient table of every fit and the combinations the data determine.
//!
//! One row per coefficient (the nuisance unknowns of a non-periodic balance after them):
//! its unit, its estimate, standard error and 95 % interval θ ± 1.96 se; with estimated
//! nonlinear parameters the standard error and interval are the **joint** ones (from
//! the covariance of the full Jacobian [∂r/∂θ, ∂r/∂η], which includes the uncertainty
//! of η̂), the linear fit's own standard error (η held fixed) beside them for
//! comparison; the true value and the error when the records were simulated. A
//! coefficient the data do not determine reads "not determined", and the determined
//! combinations are listed instead. With more than [`digest::FULL_LISTING`]
//! coefficients the undetermined ones are counted by term and every row is folded, as
//! the text report does. A fit whose outer loop reached no estimate shows its last
//! trial only.

use std::fmt::Write as _;

use super::{HtmlReport, escape};
use crate::analysis::digest;
use crate::analysis::identifiability::{Combination, DeterminedCombination};
use crate::report::estimation::Estimation;

/// Determined combinations listed per term in a model of many coefficients.
const GROUP_LISTED: usize = 3;

/// The columns of the coefficient table.
struct Columns<'a> {
    /// The joint intervals of an estimation (`None`: the linear fit's own).
    joint: Option<&'a Estimation>,
    /// An estimation that reached no estimate: the values alone.
    last_trial: bool,
    /// A unit column.
    units: bool,
}

impl Columns<'_> {
    /// How many columns.
    fn count(&self, truth: bool) -> usize {
        if self.last_trial {
            return 2 + usize::from(self.units);
        }
        4 + usize::from(self.units) + usize::from(self.joint.is_some()) + if truth { 2 } else { 0 }
    }
}

impl HtmlReport<'_> {
    /// The unit of each coefficient, in model order.
    fn coefficient_units(&self) -> Vec<Option<String>> {
        let units = self.units();
        self.model
            .term_columns()
            .flat_map(|(term, range)| {
                let unit = units.coefficient(term);
                range.map(move |_| unit.clone())
            })
            .collect()
    }

    /// The coefficient table (module doc).
    pub(super) fn coefficient_table(&self) -> String {
        let coefficients = &self.report.coefficients;
        let undetermined: Vec<&str> = coefficients
            .iter()
            .filter(|c| !c.determined)
            .map(|c| c.name.as_str())
            .collect();
        let mut out = if coefficients.len() <= digest::FULL_LISTING || undetermined.is_empty() {
            self.coefficient_rows(|_| true)
        } else {
            let mut out = String::new();
            if undetermined.len() < coefficients.len() {
                out.push_str(
                    &self.coefficient_rows(|k| coefficients.get(k).is_none_or(|c| c.determined)),
                );
            }
            let _ = writeln!(
                out,
                "<p class=\"undetermined\"><b>not determined</b>: {} of {} coefficients (by term: {}); their least-squares values are not estimates (see the determined combinations).</p>",
                undetermined.len(),
                coefficients.len(),
                escape(&digest::by_term_text(undetermined.iter().copied()))
            );
            let _ = writeln!(
                out,
                "<details><summary>Every coefficient ({})</summary>\n{}</details>",
                coefficients.len() + self.report.nuisance.len(),
                self.coefficient_rows(|_| true)
            );
            out
        };
        out.push_str(&self.coefficient_note());
        out
    }

    /// What the intervals are.
    fn coefficient_note(&self) -> String {
        match &self.report.estimation {
            Some(e) if self.report.is_estimate() => format!(
                "<p>The intervals shown are <b>joint</b>: from the covariance of the full Jacobian [∂r/∂θ, ∂r/∂η] at the optimum ({} degrees of freedom), so they include the uncertainty of the estimated nonlinear parameters. The linear fit's own standard errors (η fixed, last column) leave it out: they are not honest intervals here and are shown for comparison only.</p>\n",
                e.degrees_of_freedom
            ),
            Some(_) => String::new(),
            None if self
                .report
                .coefficients
                .iter()
                .any(|c| c.std_error.is_some()) =>
            {
                format!(
                    "<p>{} (intervals: estimate ± 1.96 se).</p>\n",
                    escape(&self.report.std_error_basis.to_string())
                )
            }
            None => String::new(),
        }
    }

    /// The rows `shown(k)` of the coefficient table (k in model order, the nuisance
    /// unknowns after the coefficients).
    fn coefficient_rows(&self, shown: impl Fn(usize) -> bool) -> String {
        let units = self.coefficient_units();
        let columns = Columns {
            joint: self.report.estimation.as_ref(),
            last_trial: self.report.estimation.is_some() && !self.report.is_estimate(),
            units: units.iter().any(Option::is_some),
        };
        let truth = self.truth.filter(|_| !columns.last_trial);
        let mut table = String::from("<table><tr><th>coefficient</th>");
        if columns.units {
            table.push_str("<th>unit</th>");
        }
        match columns.joint {
            _ if columns.last_trial => table.push_str("<th>last trial (not an estimate)</th>"),
            Some(e) => {
                let percent = (100.0 * e.level * 1e6).round() / 1e6;
                let _ = write!(
                    table,
                    "<th>estimate</th><th>joint std error</th><th>joint {percent}% interval</th><th>std error with η fixed</th>"
                );
            }
            None => table.push_str("<th>estimate</th><th>std error</th><th>95% interval</th>"),
        }
        if truth.is_some() {
            table.push_str("<th>true</th><th>error</th>");
        }
        table.push_str("</tr>\n");
        let damping = self.report.coefficients.len();
        let width = columns.count(truth.is_some());
        for (k, c) in self
            .report
            .coefficients
            .iter()
            .chain(&self.report.nuisance)
            .enumerate()
        {
            if !shown(k) {
                continue;
            }
            if k == damping {
                let _ = writeln!(
                    table,
                    "<tr><th colspan=\"{width}\">nuisance unknowns of the energy balance (stored energy, constant forces, a free decay's start energy)</th></tr>"
                );
            }
            let _ = write!(table, "<tr><td>{}</td>", escape(&c.name));
            if columns.units {
                let unit = units.get(k).cloned().flatten().unwrap_or_default();
                let _ = write!(table, "<td>{}</td>", escape(&unit));
            }
            let joint = columns.joint.and_then(|e| e.coefficients.get(k));
            let value = joint.map_or(c.value, |j| j.value);
            if columns.last_trial {
                let _ = writeln!(table, "<td>{value:.6e}</td></tr>");
                continue;
            }
            if !c.determined {
                let _ = write!(
                    table,
                    "<td class=\"undetermined\" colspan=\"{}\"><b>not determined</b> (the least-squares value {:.4e} is one point on a line of equally good fits; see the determined combinations)</td>",
                    3 + usize::from(columns.joint.is_some()),
                    c.value
                );
            } else if columns.joint.is_some() {
                let se = joint
                    .and_then(|j| j.std_error)
                    .map_or("–".to_string(), |s| format!("{s:.3e}"));
                let interval = match joint.map(|j| (j.lower, j.upper)) {
                    Some((Some(l), Some(u))) => format!("[{l:.6e}, {u:.6e}]"),
                    _ => "–".to_string(),
                };
                let fixed = c.std_error.map_or("–".to_string(), |s| format!("{s:.3e}"));
                let _ = write!(
                    table,
                    "<td>{value:.6e}</td><td>{se}</td><td>{interval}</td><td>{fixed}</td>"
                );
            } else {
                let (se, interval) = match c.std_error {
                    Some(se) => (
                        format!("{se:.3e}"),
                        format!("[{:.6e}, {:.6e}]", c.value - 1.96 * se, c.value + 1.96 * se),
                    ),
                    None => ("–".into(), "–".into()),
                };
                let _ = write!(
                    table,
                    "<td>{value:.6e}</td><td>{se}</td><td>{interval}</td>"
                );
            }
            if let Some(truth) = truth {
                match truth.iter().find(|(n, _)| *n == c.name) {
                    Some((_, t)) if *t != 0.0 => {
                        let _ = write!(
                            table,
                            "<td>{t}</td><td>{:+.3}%</td>",
                            100.0 * (value - t) / t.abs()
                        );
                    }
                    Some((_, t)) => {
                        let _ = write!(table, "<td>{t}</td><td>{:+.3e}</td>", value - t);
                    }
                    None => table.push_str("<td></td><td></td>"),
                }
            }
            table.push_str("</tr>\n");
        }
        table.push_str("</table>\n");
        table
    }

    /// The combinations the data determine, when some coefficient is not determined.
    pub(super) fn determined_combinations(&self) -> String {
        let id = &self.report.identifiability;
        if id.determined.is_empty() {
            return String::new();
        }
        if id.names.len() > digest::FULL_LISTING {
            return self.determined_digest();
        }
        let mut out = String::from(
            "<h3>Determined combinations</h3>\n<p>These combinations of the coefficients are what the data determine (value ± standard error):</p>\n<ul>\n",
        );
        for d in &id.determined {
            let se = d
                .std_error
                .map(|s| format!(" ± {s:.3e}"))
                .unwrap_or_default();
            let _ = writeln!(
                out,
                "<li><code>{}</code> = {:.6e}{se}</li>",
                escape(&d.combination.text),
                d.value
            );
        }
        out.push_str("</ul>\n");
        out
    }

    /// The determined combinations of a model of many coefficients, grouped by the term
    /// of each one's largest weight: per term, how many, and its [`GROUP_LISTED`] best
    /// determined, each by its [`digest::CONTRIBUTORS`] largest weights (their written
    /// form); every weight vector is in the JSON.
    fn determined_digest(&self) -> String {
        let id = &self.report.identifiability;
        let mut groups: Vec<(&str, Vec<&DeterminedCombination>)> = Vec::new();
        for d in &id.determined {
            let term = leading_term(&d.combination);
            match groups.iter_mut().find(|(t, _)| *t == term) {
                Some((_, members)) => members.push(d),
                None => groups.push((term, vec![d])),
            }
        }
        let mut out = format!(
            "<h3>Determined combinations</h3>\n<p>{} combinations of the {} coefficients are what the data determine, grouped by the term of each one's largest weight; per term the {GROUP_LISTED} best determined (largest singular value), each by its {} largest weights (every weight vector: <code>identifiability.determined</code> in the JSON).</p>\n<table><tr><th>term</th><th>combinations</th><th class=\"left\">best determined (value ± standard error)</th></tr>\n",
            id.determined.len(),
            id.names.len(),
            digest::CONTRIBUTORS
        );
        for (term, members) in &groups {
            let listed: Vec<String> = members
                .iter()
                .take(GROUP_LISTED)
                .map(|d| {
                    let se = d
                        .std_error
                        .map(|s| format!(" ± {s:.2e}"))
                        .unwrap_or_default();
                    format!(
                        "<code>{}</code> = {:.4e}{se}",
                        escape(&d.combination.text),
                        d.value
                    )
                })
                .collect();
            let more = members.len().saturating_sub(GROUP_LISTED);
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td class=\"left\">{}{}</td></tr>",
                escape(term),
                members.len(),
                listed.join("<br>"),
                if more > 0 {
                    format!("<br>+ {more} more")
                } else {
                    String::new()
                }
            );
        }
        out.push_str("</table>\n");
        out
    }
}

/// The term of a combination's largest weight (`dashpot[3-4]` → `dashpot`).
fn leading_term(combination: &Combination) -> &str {
    combination
        .terms
        .iter()
        .max_by(|a, b| a.weight.abs().total_cmp(&b.weight.abs()))
        .map_or("", |t| digest::term_of(&t.name))
}
