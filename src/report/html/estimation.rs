//! The estimated nonlinear parameters of a variable-projection fit
//! ([`crate::varpro`]): each one's value, its profile-likelihood interval (where the
//! projected cost rises by the quantile) or, where no profile is computed, its joint
//! Wald interval, its bounds and initial value, whether it sits on a bound, and the
//! outer loop's method, iterations and status. When the outer loop reached no estimate
//! the values are the last trial's, with no interval.

use std::fmt::Write as _;

use super::{HtmlReport, escape};
use crate::report::count;
use crate::report::estimation::{Estimation, bound};

impl HtmlReport<'_> {
    /// The estimated nonlinear parameters.
    pub(super) fn parameter_table(&self, varpro: &Estimation) -> String {
        let estimate = self.report.is_estimate();
        // The true values when the simulation's truth names some parameter.
        let truth = self.truth.filter(|truth| {
            varpro
                .parameters
                .iter()
                .any(|p| truth.iter().any(|(n, _)| *n == p.name))
        });
        let percent = (100.0 * varpro.level * 1e6).round() / 1e6;
        let mut out = format!(
            "<h2>Estimated nonlinear parameters</h2>\n<table><tr><th>parameter</th><th>{}</th><th>joint std error</th><th>{percent}% interval</th><th>interval kind</th><th>bounds</th><th>initial</th><th>on a bound</th>",
            if estimate {
                "estimate"
            } else {
                "last trial (not an estimate)"
            }
        );
        if truth.is_some() {
            out.push_str("<th>true</th>");
        }
        out.push_str("</tr>\n");
        for p in &varpro.parameters {
            let (interval, kind) = match (estimate, &p.interval, p.joint_interval) {
                (false, _, _) => ("–".to_string(), "–"),
                (true, Some(i), _) => (
                    format!(
                        "[{}, {}]",
                        i.lower
                            .map_or(format!("open below {}", bound(p.lower_bound)), |v| format!(
                                "{v:.6e}"
                            )),
                        i.upper
                            .map_or(format!("open above {}", bound(p.upper_bound)), |v| format!(
                                "{v:.6e}"
                            ))
                    ),
                    "profile likelihood",
                ),
                (true, None, Some([l, u])) => (format!("[{l:.6e}, {u:.6e}]"), "joint (Wald)"),
                (true, None, None) => ("–".to_string(), "–"),
            };
            let se = p
                .std_error
                .filter(|_| estimate)
                .map_or("–".to_string(), |s| format!("{s:.3e}"));
            let _ = write!(
                out,
                "<tr{}><td>{}</td><td>{:.6e}</td><td>{se}</td><td>{interval}</td><td>{kind}</td><td>[{}, {}]</td><td>{}</td><td>{}</td>",
                if p.at_bound { " class=\"flag\"" } else { "" },
                escape(&p.name),
                p.value,
                bound(p.lower_bound),
                bound(p.upper_bound),
                bound(p.initial),
                if p.at_bound { "<b>yes</b>" } else { "no" }
            );
            if let Some(truth) = truth {
                match truth.iter().find(|(n, _)| *n == p.name) {
                    Some((_, t)) => {
                        let _ = write!(out, "<td>{t}</td>");
                    }
                    None => out.push_str("<td></td>"),
                }
            }
            out.push_str("</tr>\n");
        }
        out.push_str("</table>\n");
        let _ = writeln!(
            out,
            "<p>Outer loop: {} after {} iterations ({}; {} built, for the trials, the joint Jacobian and the profile searches). Profile-likelihood intervals: where the projected cost rises by the {percent}% quantile; an end the cost does not reach within the bounds is open. Joint (Wald) intervals: estimate ± quantile × joint standard error, where no profile is computed. A parameter on a bound is not an interior estimate: widen the bound or fix it.</p>",
            escape(&varpro.status.reason),
            varpro.status.iterations,
            escape(&varpro.status.method),
            count(varpro.status.evaluations as usize, "regressor"),
        );
        out
    }
}
