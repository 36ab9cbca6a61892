//! The page of a variable-projection fit ([`crate::varpro`]): the [`HtmlReport`] fields
//! are those of the linear fit at the estimate η̂ (its model, regressor and
//! [`FitReport`]), and its [`crate::report::Estimation`] adds the estimated nonlinear parameters
//! (value, profile or joint Wald interval, bounds, whether on a bound, the outer loop's
//! method, iterations and status) and the coefficients' joint intervals, which include
//! the uncertainty of η̂ (the linear fit's own errors hold η fixed: shown beside them,
//! for comparison only). The law plots are drawn at η̂ with bands of ± 1.96 joint
//! standard errors of the coefficients; a one-mode stepped-sine job adds the energy per
//! cycle against amplitude at η̂ and the equivalent-damping table with its joint
//! intervals ([`crate::analysis::equivalent`]). When the outer loop did not
//! converge or the linear fit at its end is not an estimate, the page says so and shows
//! the last trial's values as such: no interval, no fitted curve, no equivalent damping.

use std::fmt::Write as _;

use super::{HtmlReport, STYLE, escape, noise_section, provenance_section};
use crate::analysis::bootstrap::{BootstrapSummary, Resampled};
use crate::analysis::equivalent::EquivalentDamping;
use crate::error::Result;
use crate::report::FitReport;
use crate::report::count;
use crate::report::estimation::{Estimation, bound};

impl HtmlReport<'_> {
    /// The page of a variable-projection fit (module doc); `self.report` is
    /// `varpro.fit` and `self.model`, `self.regressor` are those at η̂. `stepped_sine`
    /// gives the equivalent damping of a one-mode stepped-sine job at η̂.
    pub(super) fn render_estimated(
        &self,
        varpro: &Estimation,
        stepped_sine: Option<&EquivalentDamping>,
    ) -> Result<String> {
        let estimate = self.report.is_estimate();
        // The linear fit with the joint standard errors in place of the conditional
        // ones, for the law bands (none when the fit is not an estimate).
        let mut joint: FitReport = self.report.clone();
        for (c, j) in joint.coefficients.iter_mut().zip(&varpro.coefficients) {
            c.std_error = j.std_error.filter(|_| estimate);
            c.interval = None;
        }
        let page_of = HtmlReport {
            report: &joint,
            ..*self
        };
        let report = self.report;
        let s = &varpro.status;
        let mut page = String::new();
        let title = escape(self.title);
        let _ = write!(
            page,
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{title}</title>\n<style>{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
        );
        let _ = writeln!(
            page,
            "<p>This fit <b>estimated {}</b> with the linear coefficients, by variable projection (the coefficients projected out at each trial of the nonlinear parameters η). Outer loop: <b>{}</b> ({}, {} iterations, {} built). Linear fit at η̂: status <b>{:?}</b> ({:?}); {} from {}; relative residual {:.3e}.</p>",
            count(varpro.parameters.len(), "nonlinear parameter"),
            escape(&s.reason),
            escape(&s.method),
            s.iterations,
            count(s.evaluations as usize, "regressor"),
            report.status,
            report.method,
            count(report.residuals.len(), "equation"),
            count(self.record_count(), "record"),
            report.relative_residual,
        );
        if !estimate {
            page.push_str("<p class=\"warning\">⚠ <b>Not an estimate</b>: the outer optimisation did not converge or the linear fit at its end failed. The values below are the last trial, not estimates; no interval, fitted curve or equivalent damping is shown.</p>\n");
        }
        if report.warnings.is_empty() {
            page.push_str("<p>No warnings.</p>\n");
        }
        for warning in &report.warnings {
            let _ = writeln!(
                page,
                "<p class=\"warning\">⚠ {}</p>",
                escape(&warning.to_string())
            );
        }
        page.push_str(&self.parameter_table(varpro));
        page.push_str(&self.joint_coefficient_table(varpro));
        if let Some(bootstrap) = &report.bootstrap {
            page.push_str(&self.bootstrap_table(varpro, bootstrap));
        }
        if !estimate {
            return Ok(self.close(page));
        }
        page.push_str(&self.records_section());
        page.push_str("<h2>Energy balance</h2>\n<p>At the estimated nonlinear parameters.</p>\n");
        let work = self.units().work();
        page.push_str(&super::plots::work_balance(
            &self.balance_groups(),
            !report.nuisance.is_empty(),
            work.as_deref(),
        )?);
        page.push_str("\n<h2>Residuals</h2>\n");
        page.push_str(&super::plots::residuals(
            &self.residual_groups(),
            report.residuals.len(),
            report.residual_bias.relative_mean,
            work.as_deref(),
        )?);
        if let Some(noise) = &report.noise {
            page.push_str(&noise_section(noise));
        }
        page.push_str("\n<h2>Identified damping laws</h2>\n<p>Each law at the estimated nonlinear parameters η̂; the bands are ± 1.96 joint standard errors of its coefficient (which include the uncertainty of η̂ in the coefficient, not the change of the curve's shape with η).</p>\n");
        let plotted = page_of.force_law_plots()?;
        if plotted.is_empty() {
            page.push_str("<p>No law on elements: nothing to draw against velocity.</p>\n");
        }
        for svg in plotted {
            page.push_str(&svg);
            page.push('\n');
        }
        let identifiability = self.identifiability_section().replacen(
            "<h2>Identifiability</h2>\n",
            "<h2>Identifiability</h2>\n<p>Of the linear fit at η̂ (η held fixed).</p>\n",
            1,
        );
        page.push_str(&identifiability);
        page.push_str(&self.steady_state_section());
        if let Some(reduction) = self.pod {
            page.push_str(&super::pom::section(reduction)?);
        }
        if let Some(equivalent) = stepped_sine {
            page.push_str(&self.energy_section(equivalent)?);
            page.push_str(&equivalent_table(equivalent));
        }
        Ok(self.close(page))
    }

    /// The provenance, the JSON of the report and the end of the page.
    fn close(&self, mut page: String) -> String {
        if let Some(provenance) = self.provenance {
            page.push_str(&provenance_section(provenance, self.units()));
        }
        let json = serde_json::to_string_pretty(self.report).unwrap_or_default();
        let _ = write!(
            page,
            "<details><summary>Report JSON</summary><pre>{}</pre></details>\n</body></html>\n",
            escape(&json)
        );
        page
    }

    /// The estimated nonlinear parameters.
    fn parameter_table(&self, varpro: &Estimation) -> String {
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

    /// The linear coefficients with their joint intervals.
    fn joint_coefficient_table(&self, varpro: &Estimation) -> String {
        let estimate = self.report.is_estimate();
        let percent = (100.0 * varpro.level * 1e6).round() / 1e6;
        let units = self.coefficient_units();
        let with_units = units.iter().any(Option::is_some);
        let mut out = String::from("<h2>Coefficients</h2>\n<table><tr><th>coefficient</th>");
        if with_units {
            out.push_str("<th>unit</th>");
        }
        if estimate {
            let _ = write!(
                out,
                "<th>estimate</th><th>joint std error</th><th>joint {percent}% interval</th><th>std error with η fixed</th>"
            );
        } else {
            out.push_str("<th>last trial (not an estimate)</th>");
        }
        if self.truth.is_some() && estimate {
            out.push_str("<th>true</th><th>error</th>");
        }
        out.push_str("</tr>\n");
        let conditional = self.report.coefficients.iter().chain(&self.report.nuisance);
        for (k, (c, fixed)) in varpro.coefficients.iter().zip(conditional).enumerate() {
            let _ = write!(out, "<tr><td>{}</td>", escape(&c.name));
            if with_units {
                let unit = units.get(k).cloned().flatten().unwrap_or_default();
                let _ = write!(out, "<td>{}</td>", escape(&unit));
            }
            let _ = write!(out, "<td>{:.6e}</td>", c.value);
            if estimate {
                let se = c.std_error.map_or("–".to_string(), |s| format!("{s:.3e}"));
                let interval = match (c.lower, c.upper) {
                    (Some(l), Some(u)) => format!("[{l:.6e}, {u:.6e}]"),
                    _ => "–".to_string(),
                };
                let conditional = fixed
                    .std_error
                    .map_or("–".to_string(), |s| format!("{s:.3e}"));
                let _ = write!(
                    out,
                    "<td>{se}</td><td>{interval}</td><td>{conditional}</td>"
                );
                if let Some(truth) = self.truth {
                    match truth.iter().find(|(n, _)| *n == c.name) {
                        Some((_, t)) if *t != 0.0 => {
                            let _ = write!(
                                out,
                                "<td>{t}</td><td>{:+.3}%</td>",
                                100.0 * (c.value - t) / t.abs()
                            );
                        }
                        Some((_, t)) => {
                            let _ = write!(out, "<td>{t}</td><td>{:+.3e}</td>", c.value - t);
                        }
                        None => out.push_str("<td></td><td></td>"),
                    }
                }
            }
            out.push_str("</tr>\n");
        }
        out.push_str("</table>\n");
        if estimate {
            let _ = writeln!(
                out,
                "<p>The intervals shown are <b>joint</b>: from the covariance of the full Jacobian [∂r/∂θ, ∂r/∂η] at the optimum ({} degrees of freedom), so they include the uncertainty of the estimated nonlinear parameters. The linear fit's own standard errors (η fixed, last column) leave it out: they are not honest intervals here and are shown for comparison only.</p>",
                varpro.degrees_of_freedom
            );
        }
        out
    }
}

impl HtmlReport<'_> {
    /// The percentile intervals of `--bootstrap` (every estimated parameter, then every
    /// coefficient), with what was resampled.
    fn bootstrap_table(&self, estimation: &Estimation, b: &BootstrapSummary) -> String {
        let percent = (100.0 * b.level * 1e6).round() / 1e6;
        let mut out = format!(
            "\n<h2>Bootstrap</h2>\n<p>{} of {} replicates kept ({} not converged, {} with an unusable linear fit), seed {}; each drew {} {} with replacement from the {} there are and refitted the whole variable projection from the estimate. Percentile intervals at {percent}%.{}</p>\n<table><tr><th>quantity</th><th>bootstrap std error</th><th>{percent}% percentile interval</th></tr>\n",
            b.used,
            b.replicates,
            b.not_converged,
            b.unusable,
            b.seed,
            b.groups,
            b.resampled,
            b.groups,
            match b.resampled {
                Resampled::Sweeps => {
                    " A sweep's own unknown (its residual receptance) sees the same points in every replicate that draws its sweep: its interval understates its uncertainty, read its joint interval above."
                }
                Resampled::Windows => "",
            }
        );
        let parameters = estimation
            .parameters
            .iter()
            .filter_map(|p| p.bootstrap.as_ref());
        let coefficients = self
            .report
            .coefficients
            .iter()
            .chain(&self.report.nuisance)
            .filter_map(|c| c.interval.as_ref());
        for i in parameters.chain(coefficients) {
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{:.3e}</td><td>[{:.6e}, {:.6e}]</td></tr>",
                escape(&i.name),
                i.std_error,
                i.lower,
                i.upper
            );
        }
        out.push_str("</table>\n");
        out
    }
}

/// The equivalent damping table (±1.96 standard deviations, joint).
fn equivalent_table(equivalent: &EquivalentDamping) -> String {
    let m = &equivalent.modal;
    let source = match &m.source {
        crate::analysis::equivalent::ModalSource::System => "from [system]".to_string(),
        crate::analysis::equivalent::ModalSource::LowestLevelFrf { sweep, points, .. } => format!(
            "estimated from the frequency response of the lowest level ({}, {points} points)",
            escape(sweep)
        ),
    };
    let mut out = format!(
        "\n<h2>Equivalent damping</h2>\n<p>Equivalent viscous damping ratio ζ_eq = E_d/(2πkX²) and loss factor η = 2ζ_eq at ω_n = {:.4e}, modal mass {:.4e}, stiffness {:.4e} ({source}). Intervals ± 1.96 standard deviations from the joint covariance of the coefficients and the estimated nonlinear parameters (the law parameters through the change of the law, every unknown through its correlation with the coefficients).</p>\n<table><tr><th>amplitude</th><th>E_d per cycle</th><th>ζ_eq</th><th>ζ_eq interval</th><th>η</th><th>η interval</th></tr>\n",
        m.natural_frequency, m.mass, m.stiffness
    );
    for p in &equivalent.points {
        let band = |v: f64, s: Option<f64>| {
            s.map_or("–".to_string(), |s| {
                format!("[{:.4e}, {:.4e}]", v - 1.96 * s, v + 1.96 * s)
            })
        };
        let _ = writeln!(
            out,
            "<tr><td>{:.4e}</td><td>{:.4e}</td><td>{:.4e}</td><td>{}</td><td>{:.4e}</td><td>{}</td></tr>",
            p.amplitude,
            p.dissipated_energy,
            p.damping_ratio,
            band(p.damping_ratio, p.damping_ratio_std),
            p.loss_factor,
            band(p.loss_factor, p.loss_factor_std)
        );
    }
    out.push_str("</table>\n");
    out
}
