//! A self-contained HTML report of one identification: the coefficients with standard
//! errors and 95% intervals (θ ± 1.96 se), the warnings in words, the conditioning, and
//! inline SVG plots: measured input work against identified dissipated work per window,
//! the residuals with their bias, and each identified damping law θ f(v) against the
//! relative velocity with its uncertainty band. When identification ran on proper
//! orthogonal mode coordinates, a section shows the modes, their energy shares and the
//! retained shapes (`pom.rs`). Nothing is loaded from outside the file.

mod plots;
mod pom;

use std::fmt::Write as _;

use crate::analysis::equivalent::EquivalentDamping;
use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::pod::Reduction;
use crate::record::{Record, col};
use crate::regressor::Regressor;
use crate::report::FitReport;
use crate::report::count;
use crate::terms::Term;

/// Curves drawn per term at most (per-element terms may have thousands).
const MAX_CURVES: usize = 8;

/// What the report shows.
pub struct HtmlReport<'a> {
    /// Title (the model file's).
    pub title: &'a str,
    /// The damping model.
    pub model: &'a DampingModel,
    /// The records (for the velocity range of the force-law plots).
    pub records: &'a [Record],
    /// The regressor the fit used (for the input work per window).
    pub regressor: &'a Regressor,
    /// The fit report.
    pub report: &'a FitReport,
    /// True coefficients, when the records were simulated.
    pub truth: Option<&'a [(String, f64)]>,
    /// The POD reduction the records came from, when the model file asked for one.
    pub pod: Option<&'a Reduction>,
}

impl HtmlReport<'_> {
    /// The whole page.
    pub fn render(&self) -> Result<String> {
        self.render_with(None)
    }

    /// The whole page, with the dissipated energy per cycle against amplitude of a
    /// one-mode stepped-sine identification (log-log; the measured points and the
    /// fitted laws at ω_n over the measured amplitude range) when `stepped_sine` gives
    /// the equivalent damping. The measured points are the input work of each equation
    /// against the amplitude of the force DOF of `records` (the synthesized periods).
    pub fn render_with(&self, stepped_sine: Option<&EquivalentDamping>) -> Result<String> {
        let report = self.report;
        let input = self.regressor.rhs();
        let dissipated: Vec<f64> = input
            .iter()
            .zip(&report.residuals)
            .map(|(b, e)| b - e)
            .collect();
        let mut page = String::new();
        let title = escape(self.title);
        let _ = write!(
            page,
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>\n<style>{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
        );
        let _ = writeln!(
            page,
            "<p>Status <b>{:?}</b> ({:?}); {} from {}; relative residual {:.3e}; residual bias {:+.3e} of mean |input work| ({} positive, {} negative).</p>",
            report.status,
            report.method,
            count(report.residuals.len(), "equation"),
            count(self.records.len(), "record"),
            report.relative_residual,
            report.residual_bias.relative_mean,
            report.residual_bias.positive,
            report.residual_bias.negative
        );
        for warning in &report.warnings {
            let _ = writeln!(
                page,
                "<p class=\"warning\">⚠ {}</p>",
                escape(&warning.to_string())
            );
        }
        page.push_str(&self.coefficient_table());
        let condition = report
            .condition_number
            .map_or("infinite".to_string(), |k| format!("{k:.3e}"));
        let singular: Vec<String> = report
            .singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect();
        let _ = writeln!(
            page,
            "<p>Column-scaled regressor: rank {}, condition number {condition}, singular values [{}].</p>",
            report.rank,
            singular.join(", ")
        );
        page.push_str("<h2>Energy balance</h2>\n");
        page.push_str(&plots::work_balance(
            input,
            &dissipated,
            !report.nuisance.is_empty(),
        )?);
        page.push_str("\n<h2>Residuals</h2>\n");
        page.push_str(&plots::residuals(&report.residuals)?);
        if let Some(noise) = &report.noise {
            page.push_str(&noise_section(noise));
        }
        page.push_str("\n<h2>Identified damping laws</h2>\n");
        for svg in self.force_law_plots()? {
            page.push_str(&svg);
            page.push('\n');
        }
        if let Some(reduction) = self.pod {
            page.push_str(&pom::section(reduction)?);
        }
        if let Some(equivalent) = stepped_sine {
            page.push_str(&self.energy_section(equivalent)?);
        }
        let json = serde_json::to_string_pretty(report).unwrap_or_default();
        let _ = write!(
            page,
            "<details><summary>Report JSON</summary><pre>{}</pre></details>\n</body></html>\n",
            escape(&json)
        );
        Ok(page)
    }

    /// The stepped-sine section: energy per cycle against amplitude, log-log.
    fn energy_section(&self, equivalent: &EquivalentDamping) -> Result<String> {
        let measured: Vec<(f64, f64)> = self
            .records
            .iter()
            .zip(self.regressor.rhs())
            .map(|(record, b)| {
                let x = record.displacements();
                let peak = (0..x.nrows()).fold(0.0f64, |m, i| m.max(x[(i, 0)].abs()));
                (peak, *b)
            })
            .collect();
        let mut curves = vec![plots::Curve {
            name: "fitted model at ω_n".into(),
            points: equivalent
                .points
                .iter()
                .map(|p| (p.amplitude, p.dissipated_energy))
                .collect(),
            band: None,
        }];
        for (k, c) in self.report.coefficients.iter().enumerate() {
            curves.push(plots::Curve {
                name: format!("{} term", c.name),
                points: equivalent
                    .points
                    .iter()
                    .filter_map(|p| p.terms.get(k).map(|e| (p.amplitude, *e)))
                    .collect(),
                band: None,
            });
        }
        Ok(format!(
            "\n<h2>Dissipated energy per cycle</h2>\n<p>Measured input work π a X sin φ of each point against its amplitude, and the fitted laws evaluated at ω_n = {:.4e} over the measured amplitude range only (log-log).</p>\n{}\n",
            equivalent.modal.natural_frequency,
            plots::energy_per_cycle(&measured, &curves)?
        ))
    }

    fn coefficient_table(&self) -> String {
        let mut table = String::from(
            "<table><tr><th>coefficient</th><th>estimate</th><th>std error</th><th>95% interval</th>",
        );
        if self.truth.is_some() {
            table.push_str("<th>true</th><th>error</th>");
        }
        table.push_str("</tr>\n");
        let damping = self.report.coefficients.len();
        let columns = if self.truth.is_some() { 6 } else { 4 };
        for (k, c) in self
            .report
            .coefficients
            .iter()
            .chain(&self.report.nuisance)
            .enumerate()
        {
            if k == damping {
                let _ = writeln!(
                    table,
                    "<tr><th colspan=\"{columns}\">stored energy and constant forces (nuisance unknowns of the non-periodic balance)</th></tr>"
                );
            }
            let (se, interval) = match c.std_error {
                Some(se) => (
                    format!("{se:.3e}"),
                    format!("[{:.6e}, {:.6e}]", c.value - 1.96 * se, c.value + 1.96 * se),
                ),
                None => ("–".into(), "–".into()),
            };
            let _ = write!(
                table,
                "<tr><td>{}</td><td>{:.6e}</td><td>{se}</td><td>{interval}</td>",
                escape(&c.name),
                c.value
            );
            if let Some(truth) = self.truth {
                match truth.iter().find(|(n, _)| *n == c.name) {
                    Some((_, t)) if *t != 0.0 => {
                        let _ = write!(
                            table,
                            "<td>{t}</td><td>{:+.3}%</td>",
                            100.0 * (c.value - t) / t.abs()
                        );
                    }
                    Some((_, t)) => {
                        let _ = write!(table, "<td>{t}</td><td>{:+.3e}</td>", c.value - t);
                    }
                    None => table.push_str("<td></td><td></td>"),
                }
            }
            table.push_str("</tr>\n");
        }
        table.push_str("</table>\n");
        if self
            .report
            .coefficients
            .iter()
            .any(|c| c.std_error.is_some())
        {
            let _ = writeln!(
                table,
                "<p>{} (intervals: estimate ± 1.96 se).</p>",
                escape(&self.report.std_error_basis.to_string())
            );
        }
        table
    }

    /// One plot per element term: θ f(0, v) for v in ±max|v| of the records, with the
    /// band (θ ± 1.96 se) f(0, v). Laws of x are drawn at x = 0.
    fn force_law_plots(&self) -> Result<Vec<String>> {
        let v_max = self.velocity_range();
        let speeds: Vec<f64> = (0..=100).map(|i| v_max * (i as f64 / 50.0 - 1.0)).collect();
        let mut svgs = Vec::new();
        for (term, range) in self.model.term_columns() {
            let Term::Elements(term) = term else { continue };
            let law = term.law();
            let curves: Vec<plots::Curve> = range
                .take(MAX_CURVES)
                .map(|k| {
                    let c = &self.report.coefficients[k];
                    let f = |theta: f64, v: f64| theta * law.force(0.0, v);
                    plots::Curve {
                        name: c.name.clone(),
                        points: speeds.iter().map(|&v| (v, f(c.value, v))).collect(),
                        band: c.std_error.map(|se| {
                            speeds
                                .iter()
                                .map(|&v| {
                                    let (a, b) =
                                        (f(c.value - 1.96 * se, v), f(c.value + 1.96 * se, v));
                                    (v, a.min(b), a.max(b))
                                })
                                .collect()
                        }),
                    }
                })
                .collect();
            svgs.push(plots::force_laws(&format!("{} law", law.name()), &curves)?);
        }
        Ok(svgs)
    }

    /// The largest |velocity| in the records (measured, else central differences).
    fn velocity_range(&self) -> f64 {
        let mut v_max: f64 = 0.0;
        for record in self.records {
            let h2 = 2.0 * record.step();
            for j in 0..record.dofs() {
                match record.velocities() {
                    Some(v) => v_max = col(v, j).iter().fold(v_max, |m, v| m.max(v.abs())),
                    None => {
                        let x = col(record.displacements(), j);
                        v_max = x
                            .windows(3)
                            .fold(v_max, |m, w| m.max(((w[2] - w[0]) / h2).abs()));
                    }
                }
            }
        }
        if v_max > 0.0 { v_max } else { 1.0 }
    }
}

const STYLE: &str = "body{font-family:sans-serif;max-width:60em;margin:2em auto;color:#222}\
table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}.warning{background:#fff3cd;border:1px solid #e0c060;padding:.5em}svg{display:block;margin:1em 0}";

/// The noise-robust pipeline's model check and, per window, the harmonics kept and the
/// estimated noise.
fn noise_section(noise: &crate::report::NoiseSummary) -> String {
    let mut section = String::from("\n<h2>Noise and model check</h2>\n");
    let check = match noise.p_value {
        Some(p) => format!(
            "χ² = {:.3} for {} degrees of freedom (P = {p:.3}){}",
            noise.chi_square,
            noise.degrees_of_freedom,
            if p < crate::report::INADEQUATE_P_VALUE {
                ": the residuals exceed what the estimated noise explains"
            } else {
                ": the residuals are as large as the noise explains"
            }
        ),
        None => "no degrees of freedom left for a check".into(),
    };
    let _ = writeln!(
        section,
        "<p>Equations weighted by their propagated residual standard deviation. {check}.</p>"
    );
    section.push_str(
        "<table><tr><th>record</th><th>window</th><th>harmonics kept</th><th>displacement noise σ</th><th>residual sd</th></tr>\n",
    );
    for (w, sd) in noise.windows.iter().zip(&noise.residual_std) {
        let harmonics: Vec<String> = w.harmonics.iter().map(|k| k.to_string()).collect();
        let sigma: Vec<String> = w
            .displacement_noise
            .iter()
            .map(|s| format!("{s:.2e}"))
            .collect();
        let _ = writeln!(
            section,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{sd:.3e}</td></tr>",
            escape(&w.record),
            w.window,
            harmonics.join(", "),
            sigma.join(", ")
        );
    }
    section.push_str("</table>\n");
    section
}

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
