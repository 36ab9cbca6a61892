//! A self-contained HTML report of one identification, the same page for every fit,
//! truthful about what the data determine. In order:
//!
//! - the header: with estimated nonlinear parameters, how the variable projection went;
//!   the fit's status, equations and groups (records, or a table's sweeps), residual;
//!   every warning the text report gives;
//! - with estimated parameters, their table (estimation.rs: value, profile or joint
//!   interval, bounds, on a bound or not);
//! - the coefficients with their units, standard errors and 95 % intervals
//!   (coefficients.rs: θ ± 1.96 se, or the joint intervals that include the uncertainty
//!   of estimated parameters), "not determined" where the data do not determine a
//!   coefficient, and the combinations they do determine;
//! - the bootstrap, when one ran (bootstrap.rs: what was resampled, the percentile
//!   intervals);
//! - each record's or sweep's share of the residual (groups.rs), the energy balance and
//!   the residuals coloured by record or sweep, in the words of the equations'
//!   source (windows of records, or points of a stepped-sine table);
//! - the noise-robust model check and the steady-state verdicts (steady.rs);
//! - each identified damping law θ f(v) with its band (laws.rs), solid over the
//!   relative velocity its elements were measured at and dashed beyond;
//! - the identifiability (identifiability.rs: VIFs, correlations, near-null directions);
//! - the proper orthogonal modes when identification ran on them (pom.rs);
//! - a one-mode stepped-sine table's energy per cycle and equivalent damping ζ_eq(X)
//!   with its measured points per sweep (equivalent.rs);
//! - the provenance (provenance.rs: model file, data files with size and SHA-256,
//!   settings, version, commit, date) and the report's JSON.
//!
//! A fit with estimated parameters whose outer loop did not reach an estimate shows
//! its last trial as such and stops after the coefficients: no interval, curve or
//! equivalent damping. The plots are inline SVG (plots/); nothing is loaded from
//! outside the file.

mod backbone;
pub mod backbones;
mod bootstrap;
mod coefficients;
mod equivalent;
mod estimation;
mod groups;
mod identifiability;
mod laws;
mod plots;
mod pom;
mod provenance;
mod steady;

use std::fmt::Write as _;

use crate::analysis::equivalent::EquivalentDamping;
use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::pod::Reduction;
use crate::prep::steady_state::SteadyStateReport;
use crate::regressor::{Regressor, Source};
use crate::report::FitReport;
use crate::report::count;
use crate::report::provenance::Provenance;
use crate::report::units::Units;

/// Rows of a long table shown open; beyond, the table is folded.
const OPEN_ROWS: usize = 40;

/// What the report shows.
pub struct HtmlReport<'a> {
    /// Title (the model file's).
    pub title: &'a str,
    /// The damping model.
    pub model: &'a DampingModel,
    /// Where the equations came from: records (whose velocities bound the law plots),
    /// a stepped-sine table (its sweeps, points and file), or rows built already.
    pub source: Source<'a>,
    /// The regressor the fit used (for the input work of each equation).
    pub regressor: &'a Regressor,
    /// The fit report.
    pub report: &'a FitReport,
    /// True coefficients, when the records were simulated.
    pub truth: Option<&'a [(String, f64)]>,
    /// The POD reduction the records came from, when the model file asked for one.
    pub pod: Option<&'a Reduction>,
    /// The steady-state check of every window (`None`: not run, or non-periodic).
    pub steady: Option<&'a SteadyStateReport>,
    /// The equivalent damping of a one-mode stepped-sine table, or why it was not
    /// computed (`None`: not a one-mode table).
    pub equivalent: Option<std::result::Result<&'a EquivalentDamping, &'a str>>,
    /// The backbone of a free decay (`None`: not a free decay).
    pub backbone: Option<&'a crate::analysis::backbone::Backbone>,
    /// Where the report came from (`None`: no provenance block).
    pub provenance: Option<&'a Provenance>,
    /// The units of the numbers (`None` or empty: none shown).
    pub units: Option<&'a Units>,
}

/// What one equation is, for the words of the page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Equations {
    /// A window of whole periods (or a span) of a record.
    Windows,
    /// A point of a stepped-sine table.
    Points,
}

impl HtmlReport<'_> {
    /// The whole page (module doc).
    pub fn render(&self) -> Result<String> {
        let report = self.report;
        let title = escape(self.title);
        let mut page = format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{title}</title>\n<style>{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
        );
        page.push_str(&self.header());
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
        if let Some(estimation) = &report.estimation {
            page.push_str(&self.parameter_table(estimation));
        }
        page.push_str("<h2>Coefficients</h2>\n");
        page.push_str(&self.coefficient_table());
        page.push_str(&self.determined_combinations());
        if let Some(bootstrap) = &report.bootstrap {
            page.push_str(&self.bootstrap_section(bootstrap));
        }
        if report.estimation.is_some() && !report.is_estimate() {
            return Ok(self.close(page));
        }
        page.push_str(&self.groups_section());
        page.push_str(&self.balance_section()?);
        if let Some(noise) = &report.noise {
            page.push_str(&self.noise_section(noise));
        }
        page.push_str(&self.laws_section()?);
        page.push_str(&self.identifiability_section());
        page.push_str(&self.steady_state_section());
        if let Some(reduction) = self.pod {
            page.push_str(&pom::section(reduction)?);
        }
        page.push_str(&self.equivalent_section()?);
        page.push_str(&self.backbone_section()?);
        Ok(self.close(page))
    }

    /// The header: how an estimation went, the fit's status, its equations and the
    /// residual.
    fn header(&self) -> String {
        let report = self.report;
        let mut out = String::from("<p>");
        let status = if report.estimation.is_some() {
            "status"
        } else {
            "Status"
        };
        if let Some(e) = &report.estimation {
            let s = &e.status;
            let _ = write!(
                out,
                "This fit <b>estimated {}</b> with the linear coefficients, by variable projection (the coefficients projected out at each trial of the nonlinear parameters η). Outer loop: <b>{}</b> ({}, {} iterations, {} built). Linear fit at η̂: ",
                count(e.parameters.len(), "nonlinear parameter"),
                escape(&s.reason),
                escape(&s.method),
                s.iterations,
                count(s.evaluations as usize, "regressor"),
            );
        }
        let determined = if report.coefficients.iter().all(|c| c.determined) {
            "every coefficient is determined"
        } else {
            "<b>not every coefficient is determined</b>"
        };
        let _ = writeln!(
            out,
            "{status} <b>{:?}</b> ({:?}); {determined}; {} from {}; relative residual {:.3e}; residual bias {:+.3e} of mean |input work| (mean residual / mean |b|; {} positive, {} negative).</p>",
            report.status,
            report.method,
            count(report.residuals.len(), self.equations().noun()),
            count(self.group_count(), self.equations().group()),
            report.relative_residual,
            report.residual_bias.relative_mean,
            report.residual_bias.positive,
            report.residual_bias.negative
        );
        if report.estimation.is_some() && !report.is_estimate() {
            out.push_str("<p class=\"warning\">⚠ <b>Not an estimate</b>: the outer optimisation did not converge or the linear fit at its end failed. The values below are the last trial, not estimates; no interval, fitted curve or equivalent damping is shown.</p>\n");
        }
        out
    }

    /// The provenance, the JSON of the report and the end of the page.
    fn close(&self, mut page: String) -> String {
        if let Some(provenance) = self.provenance {
            let files = match self.equations() {
                Equations::Points => "stepped-sine table",
                Equations::Windows => "data file",
            };
            page.push_str(&provenance::section(provenance, &self.units(), files));
        }
        let json = serde_json::to_string_pretty(self.report).unwrap_or_default();
        let _ = write!(
            page,
            "<details><summary>Report JSON</summary><pre>{}</pre></details>\n</body></html>\n",
            escape(&json)
        );
        page
    }

    fn units(&self) -> Units {
        self.units.cloned().unwrap_or_default()
    }

    /// What the equations are.
    fn equations(&self) -> Equations {
        match self.source {
            Source::Table { .. } => Equations::Points,
            _ => Equations::Windows,
        }
    }

    /// The records or sweeps that gave equations (all records when the report has no
    /// rows).
    fn group_count(&self) -> usize {
        if self.report.records.is_empty() {
            self.source.records().map_or(0, <[_]>::len)
        } else {
            self.report.records.len()
        }
    }
}

impl Equations {
    /// One equation, in words.
    fn noun(self) -> &'static str {
        match self {
            Equations::Windows => "equation",
            Equations::Points => "point",
        }
    }

    /// One group of equations, in words.
    fn group(self) -> &'static str {
        match self {
            Equations::Windows => "record",
            Equations::Points => "sweep",
        }
    }
}

const STYLE: &str = "body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}\
table{border-collapse:collapse;display:block;max-width:100%;overflow-x:auto}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}.warning{background:#fff3cd;border:1px solid #e0c060;padding:.5em}.flag td{background:#fde2d8}\
td.undetermined{text-align:left}.undetermined{color:#7a2e00}pre{white-space:pre-wrap;word-break:break-all;background:#f6f6f6;padding:.5em}\
code.hash{word-break:break-all}svg{display:block;margin:1em 0;width:100%;max-width:960px;height:auto}\
td{white-space:nowrap}td.left,th.left,td.undetermined{text-align:left;white-space:normal}.bar{display:inline-block;height:.8em;background:#0072B2}";

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
