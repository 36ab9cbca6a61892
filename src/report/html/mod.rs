//! A self-contained HTML report of one identification, truthful about what the data
//! determine: the warnings (every one the text report gives), the coefficients with
//! their units, standard errors and 95% intervals (θ ± 1.96 se), where a coefficient the
//! data do not determine reads "not determined" and the determined combinations are
//! given instead; each record's share of the residual; the identifiability (VIFs,
//! correlations, near-null directions, determined combinations) and the steady-state
//! verdict of every window; inline SVG plots (plots.rs): measured input work against
//! identified dissipated work per window and the residuals, both coloured by record, and
//! each identified damping law θ f(v) with its band, solid over the relative velocity
//! its elements were measured at and dashed beyond; when identification ran on proper orthogonal mode
//! coordinates, the modes (pom.rs); and the provenance (model file, data files with
//! SHA-256, settings, version, commit, date). Nothing is loaded from outside the file.

mod plots;
mod pom;
mod varpro;

use crate::terms::OnElements;
use std::fmt::Write as _;

use crate::analysis::digest;
use crate::analysis::equivalent::EquivalentDamping;
use crate::analysis::identifiability::DeterminedCombination;
use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::pod::Reduction;
use crate::prep::steady_state::{ComparedPeriods, SteadyStateReport};
use crate::record::{Record, col};
use crate::regressor::Regressor;
use crate::report::FitReport;
use crate::report::count;
use crate::report::provenance::Provenance;
use crate::report::units::Units;
use crate::terms::{Coefficients, Term};

/// Curves drawn per term at most (per-element terms may have thousands).
const MAX_CURVES: usize = 8;

/// The law plots extend this fraction of the largest measured speed beyond the measured
/// range on each side, dashed.
const EXTRAPOLATED: f64 = 0.2;

/// Points per law curve (besides the measured range's ends).
const LAW_POINTS: usize = 240;

/// Steady-state rows shown open; beyond, the table is folded.
const OPEN_WINDOWS: usize = 40;

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
    /// The steady-state check of every window (`None`: not run, or non-periodic).
    pub steady: Option<&'a SteadyStateReport>,
    /// Where the report came from (`None`: no provenance block).
    pub provenance: Option<&'a Provenance>,
    /// The units of the numbers (`None` or empty: none shown).
    pub units: Option<&'a Units>,
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
        if let Some(estimation) = &self.report.estimation {
            return self.render_estimated(estimation, stepped_sine);
        }
        let report = self.report;
        let mut page = String::new();
        let title = escape(self.title);
        let _ = write!(
            page,
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{title}</title>\n<style>{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
        );
        let estimate = if report.is_estimate() {
            "every coefficient is determined"
        } else {
            "<b>not every coefficient is determined</b>"
        };
        let _ = writeln!(
            page,
            "<p>Status <b>{:?}</b> ({:?}); {estimate}; {} from {}; relative residual {:.3e}; residual bias {:+.3e} of mean |input work| (mean residual / mean |b|; {} positive, {} negative).</p>",
            report.status,
            report.method,
            count(report.residuals.len(), "equation"),
            count(self.record_count(), "record"),
            report.relative_residual,
            report.residual_bias.relative_mean,
            report.residual_bias.positive,
            report.residual_bias.negative
        );
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
        page.push_str("<h2>Coefficients</h2>\n");
        page.push_str(&self.coefficient_table());
        page.push_str(&self.determined_combinations());
        page.push_str(&self.records_section());
        page.push_str("<h2>Energy balance</h2>\n");
        let work = self.units().work();
        page.push_str(&plots::work_balance(
            &self.balance_groups(),
            !report.nuisance.is_empty(),
            work.as_deref(),
        )?);
        page.push_str("\n<h2>Residuals</h2>\n");
        page.push_str(&plots::residuals(
            &self.residual_groups(),
            report.residuals.len(),
            report.residual_bias.relative_mean,
            work.as_deref(),
        )?);
        if let Some(noise) = &report.noise {
            page.push_str(&noise_section(noise));
        }
        page.push_str("\n<h2>Identified damping laws</h2>\n");
        let plotted = self.force_law_plots()?;
        if plotted.is_empty() {
            page.push_str("<p>No law on elements: nothing to draw against velocity.</p>\n");
        }
        for svg in plotted {
            page.push_str(&svg);
            page.push('\n');
        }
        page.push_str(&self.identifiability_section());
        page.push_str(&self.steady_state_section());
        if let Some(reduction) = self.pod {
            page.push_str(&pom::section(reduction)?);
        }
        if let Some(equivalent) = stepped_sine {
            page.push_str(&self.energy_section(equivalent)?);
        }
        if let Some(provenance) = self.provenance {
            page.push_str(&provenance_section(provenance, self.units()));
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
            measured: None,
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
                measured: None,
            });
        }
        Ok(format!(
            "\n<h2>Dissipated energy per cycle</h2>\n<p>Measured input work π a X sin φ of each point against its amplitude, and the fitted laws evaluated at ω_n = {:.4e} over the measured amplitude range only (log-log).</p>\n{}\n",
            equivalent.modal.natural_frequency,
            plots::energy_per_cycle(&measured, &curves)?
        ))
    }

    fn units(&self) -> Units {
        self.units.cloned().unwrap_or_default()
    }

    /// The records that gave equations (all records when the report has no rows).
    fn record_count(&self) -> usize {
        if self.report.records.is_empty() {
            self.records.len()
        } else {
            self.report.records.len()
        }
    }

    /// Points grouped by the record of each equation, in record order: (record label,
    /// values `of` each of its rows).
    fn by_record(&self, of: impl Fn(usize) -> (f64, f64)) -> Vec<plots::Group> {
        let mut groups: Vec<(usize, plots::Group)> = Vec::new();
        for (i, row) in self.report.rows.iter().enumerate() {
            let k = match groups.iter().position(|(r, _)| *r == row.record_index) {
                Some(k) => k,
                None => {
                    groups.push((
                        row.record_index,
                        plots::Group {
                            name: row.record.clone(),
                            points: Vec::new(),
                        },
                    ));
                    groups.len() - 1
                }
            };
            groups[k].1.points.push(of(i));
        }
        groups.into_iter().map(|(_, g)| g).collect()
    }

    fn balance_groups(&self) -> Vec<plots::Group> {
        let input = self.regressor.rhs();
        let residuals = &self.report.residuals;
        self.by_record(|i| (input[i], input[i] - residuals[i]))
    }

    fn residual_groups(&self) -> Vec<plots::Group> {
        let residuals = &self.report.residuals;
        self.by_record(|i| ((i + 1) as f64, residuals[i]))
    }

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

    /// The coefficient table; with more than [`digest::FULL_LISTING`] coefficients, the
    /// determined ones (and the nuisance unknowns) in the open table, the undetermined
    /// ones counted by term, and every row in a folded table, as the text report does.
    fn coefficient_table(&self) -> String {
        let coefficients = &self.report.coefficients;
        let undetermined: Vec<&str> = coefficients
            .iter()
            .filter(|c| !c.determined)
            .map(|c| c.name.as_str())
            .collect();
        if coefficients.len() <= digest::FULL_LISTING || undetermined.is_empty() {
            return self.coefficient_rows(|_| true);
        }
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
    }

    /// The rows `shown(k)` of the coefficient table (k in model order, the nuisance
    /// unknowns after the coefficients).
    fn coefficient_rows(&self, shown: impl Fn(usize) -> bool) -> String {
        let units = self.coefficient_units();
        let with_units = units.iter().any(Option::is_some);
        let bootstrap = self.report.bootstrap.as_ref().map(|b| b.level);
        let mut table = String::from("<table><tr><th>coefficient</th>");
        if with_units {
            table.push_str("<th>unit</th>");
        }
        table.push_str("<th>estimate</th><th>std error</th><th>95% interval</th>");
        if let Some(level) = bootstrap {
            let _ = write!(table, "<th>bootstrap {}% interval</th>", 100.0 * level);
        }
        if self.truth.is_some() {
            table.push_str("<th>true</th><th>error</th>");
        }
        table.push_str("</tr>\n");
        let damping = self.report.coefficients.len();
        let columns = 4
            + usize::from(with_units)
            + usize::from(bootstrap.is_some())
            + if self.truth.is_some() { 2 } else { 0 };
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
                    "<tr><th colspan=\"{columns}\">stored energy and constant forces (nuisance unknowns of the non-periodic balance)</th></tr>"
                );
            }
            let _ = write!(table, "<tr><td>{}</td>", escape(&c.name));
            if with_units {
                let unit = units.get(k).cloned().flatten().unwrap_or_default();
                let _ = write!(table, "<td>{}</td>", escape(&unit));
            }
            if c.determined {
                let (se, interval) = match c.std_error {
                    Some(se) => (
                        format!("{se:.3e}"),
                        format!("[{:.6e}, {:.6e}]", c.value - 1.96 * se, c.value + 1.96 * se),
                    ),
                    None => ("–".into(), "–".into()),
                };
                let _ = write!(
                    table,
                    "<td>{:.6e}</td><td>{se}</td><td>{interval}</td>",
                    c.value
                );
            } else {
                let _ = write!(
                    table,
                    "<td class=\"undetermined\" colspan=\"3\"><b>not determined</b> (the least-squares value {:.4e} is one point on a line of equally good fits; see the determined combinations)</td>",
                    c.value
                );
            }
            if bootstrap.is_some() {
                match &c.interval {
                    Some(i) => {
                        let _ = write!(table, "<td>[{:.6e}, {:.6e}]</td>", i.lower, i.upper);
                    }
                    None => table.push_str("<td>–</td>"),
                }
            }
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

    /// The combinations the data determine, when some coefficient is not determined.
    fn determined_combinations(&self) -> String {
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

    /// Each record's share of the residual and its standardised residual.
    fn records_section(&self) -> String {
        let records = &self.report.records;
        if records.is_empty() {
            return String::new();
        }
        let total = self.report.residuals.len();
        let mut out = String::from(
            "<h2>Records</h2>\n<p>Each record's share of the squared residual (weighted as fitted) against its share of the equations, and its RMS residual in units of the fit's residual standard deviation (about 1 when it fits like the rest).</p>\n<table><tr><th>record</th><th>equations</th><th>share of equations</th><th>share of squared residual</th><th>standardised residual</th><th>mean residual</th></tr>\n",
        );
        for r in records {
            let flag = r.dominates(records.len(), total);
            let z = r
                .standardised_residual
                .map_or("–".into(), |z| format!("{z:.2}"));
            let _ = writeln!(
                out,
                "<tr{}><td>{}</td><td>{}</td><td>{:.1}%</td><td>{:.1}%</td><td>{z}</td><td>{:+.3e}</td></tr>",
                if flag { " class=\"flag\"" } else { "" },
                escape(&r.record),
                r.equations,
                100.0 * r.equations as f64 / total.max(1) as f64,
                100.0 * r.residual_share,
                r.mean_residual
            );
        }
        out.push_str("</table>\n");
        out
    }

    fn identifiability_section(&self) -> String {
        let report = self.report;
        let id = &report.identifiability;
        let mut out = String::from("\n<h2>Identifiability</h2>\n");
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

    fn steady_state_section(&self) -> String {
        let Some(steady) = self.steady else {
            return if self.report.nuisance.is_empty() {
                "\n<h2>Steady state</h2>\n<p>Not checked for this report.</p>\n".into()
            } else {
                "\n<h2>Steady state</h2>\n<p>Non-periodic balance: the stored energy is an unknown, so no window needs to be in steady state.</p>\n".into()
            };
        };
        let rejected = steady.rejected().count();
        let mut out = String::from("\n<h2>Steady state</h2>\n");
        let criterion = if steady.energy_known {
            "the stored-energy mismatch |ΔE| as a share of the window's input work"
        } else {
            "the change of the motion over the window relative to its amplitude (δx, δv)"
        };
        let _ = writeln!(
            out,
            "<p>{} of {} windows steady, judged by {criterion}{}.</p>",
            steady.windows.len() - rejected,
            steady.windows.len(),
            if rejected > 0 {
                if steady.settings.accept_transient {
                    "; the others were accepted although not in steady state"
                } else {
                    ""
                }
            } else {
                ""
            }
        );
        let fold = steady.windows.len() > OPEN_WINDOWS;
        if fold {
            let _ = writeln!(
                out,
                "<details><summary>Every window ({})</summary>",
                steady.windows.len()
            );
        }
        out.push_str("<table><tr><th>record</th><th>window</th><th>start time</th><th>compared</th><th>δx</th><th>δv</th><th>|ΔE|/|W|</th><th>verdict</th></tr>\n");
        for w in &steady.windows {
            let compared = match w.compared {
                ComparedPeriods::FirstAndLastPeriod => "first/last",
                ComparedPeriods::NextPeriod => "next",
                ComparedPeriods::PreviousPeriod => "previous",
                ComparedPeriods::NotJudged => "–",
            };
            let energy = w
                .energy_mismatch
                .map_or("–".to_string(), |e| format!("{:.3}%", 100.0 * e));
            let verdict = if w.compared == ComparedPeriods::NotJudged {
                "not judged (accepted)"
            } else if w.steady {
                "steady"
            } else {
                "NOT steady (accepted)"
            };
            let _ = writeln!(
                out,
                "<tr{}><td>{}</td><td>{}</td><td>{:.6}</td><td>{compared}</td><td>{:.3}%</td><td>{:.3}%</td><td>{energy}</td><td title=\"{}\">{verdict}</td></tr>",
                if w.steady { "" } else { " class=\"flag\"" },
                escape(&w.record),
                w.window,
                w.start_time,
                100.0 * w.displacement_mismatch,
                100.0 * w.velocity_mismatch,
                escape(&w.reason)
            );
        }
        out.push_str("</table>\n");
        if fold {
            out.push_str("</details>\n");
        }
        out
    }

    /// One plot per element term: θ f(0, v) against relative velocity, solid over the
    /// range its elements were measured at and dashed beyond it (the plot spans the
    /// measured ranges of the term's curves and a fifth of the largest speed more on
    /// each side), with the band (θ ± 1.96 se) f(0, v) over the measured range when the
    /// coefficient is determined. Laws of x are drawn at x = 0.
    fn force_law_plots(&self) -> Result<Vec<String>> {
        let units = self.units();
        let velocity = units.velocity();
        let force = units.force.clone();
        let mut svgs = Vec::new();
        for (term, range) in self.model.term_columns() {
            let Term::Elements(term) = term else { continue };
            let law = term.law();
            let elements = term.elements();
            let shared = matches!(term.coefficients(), Coefficients::Shared(_));
            // The measured range of each drawn coefficient (None: nothing measured).
            let measured: Vec<Option<(f64, f64)>> = (0..range.len().min(MAX_CURVES))
                .map(|j| {
                    let (lo, hi) = if shared {
                        elements
                            .iter()
                            .map(|e| self.velocity_range(e.a, e.b))
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (a, b)| {
                                (l.min(a), h.max(b))
                            })
                    } else {
                        self.velocity_range(elements[j].a, elements[j].b)
                    };
                    (hi > lo).then_some((lo, hi))
                })
                .collect();
            let (lo, hi) = measured
                .iter()
                .flatten()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &(a, b)| {
                    (l.min(a), h.max(b))
                });
            let (lo, hi) = if hi > lo {
                let margin = EXTRAPOLATED * lo.abs().max(hi.abs());
                (lo - margin, hi + margin)
            } else {
                (-1.0, 1.0)
            };
            let curves: Vec<plots::Curve> = range
                .clone()
                .take(MAX_CURVES)
                .enumerate()
                .map(|(j, k)| {
                    let c = &self.report.coefficients[k];
                    // Uniform speeds with the measured range's ends among them, so the
                    // solid part ends exactly there.
                    let mut speeds: Vec<f64> = (0..=LAW_POINTS)
                        .map(|i| lo + (hi - lo) * i as f64 / LAW_POINTS as f64)
                        .chain(measured[j].iter().flat_map(|&(a, b)| [a, b]))
                        .collect();
                    speeds.sort_by(f64::total_cmp);
                    speeds.dedup();
                    let f = |theta: f64, v: f64| theta * law.force(0.0, v);
                    let name = if c.determined {
                        c.name.clone()
                    } else {
                        format!("{} (not determined)", c.name)
                    };
                    plots::Curve {
                        name,
                        points: speeds.iter().map(|&v| (v, f(c.value, v))).collect(),
                        band: c.std_error.filter(|_| c.determined).map(|se| {
                            speeds
                                .iter()
                                .map(|&v| {
                                    let (a, b) =
                                        (f(c.value - 1.96 * se, v), f(c.value + 1.96 * se, v));
                                    (v, a.min(b), a.max(b))
                                })
                                .collect()
                        }),
                        measured: measured[j],
                    }
                })
                .collect();
            let more = range.len().saturating_sub(MAX_CURVES);
            let title = if more > 0 {
                format!(
                    "{} law (first {MAX_CURVES} of {} coefficients)",
                    law.name(),
                    range.len()
                )
            } else {
                format!("{} law", law.name())
            };
            svgs.push(plots::force_laws(
                &title,
                &curves,
                (velocity.as_deref(), force.as_deref()),
            )?);
        }
        Ok(svgs)
    }

    /// The smallest and largest relative velocity v_a − v_b (v_a to ground) in the
    /// records (measured velocities, else central differences of the displacements).
    fn velocity_range(&self, a: usize, b: Option<usize>) -> (f64, f64) {
        let mut range = (f64::INFINITY, f64::NEG_INFINITY);
        for record in self.records {
            if a >= record.dofs() || b.is_some_and(|b| b >= record.dofs()) {
                continue;
            }
            let h2 = 2.0 * record.step();
            let velocity = |j: usize| -> Vec<f64> {
                match record.velocities() {
                    Some(v) => col(v, j).to_vec(),
                    None => col(record.displacements(), j)
                        .windows(3)
                        .map(|w| (w[2] - w[0]) / h2)
                        .collect(),
                }
            };
            let va = velocity(a);
            let vb = b.map(velocity);
            for (i, v) in va.iter().enumerate() {
                let relative = v - vb.as_ref().map_or(0.0, |vb| vb[i]);
                if relative.is_finite() {
                    range = (range.0.min(relative), range.1.max(relative));
                }
            }
        }
        range
    }
}

/// Determined combinations listed per term in a model of many coefficients.
const GROUP_LISTED: usize = 3;

/// The term of a combination's largest weight (`dashpot[3-4]` → `dashpot`).
fn leading_term(combination: &crate::analysis::identifiability::Combination) -> &str {
    combination
        .terms
        .iter()
        .max_by(|a, b| a.weight.abs().total_cmp(&b.weight.abs()))
        .map_or("", |t| digest::term_of(&t.name))
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
fn correlated_pairs(c: &crate::analysis::diagnostics::Correlation) -> String {
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

/// Where the report came from: the model file (folded), the data files with their size
/// and SHA-256, the units, every setting (folded), dampid's version and commit, the date.
fn provenance_section(p: &Provenance, units: Units) -> String {
    let mut out = String::from("\n<h2>Provenance</h2>\n");
    let from = if p.arrays.is_empty() {
        format!("the model file <code>{}</code>", escape(&p.model_file))
    } else {
        "records from Python arrays".into()
    };
    let _ = writeln!(
        out,
        "<p>Made {} by dampid {} (git commit <code>{}</code>) from {from}.</p>",
        escape(&p.date),
        escape(&p.version),
        escape(&p.commit),
    );
    if p.arrays.is_empty() || !p.model_text.is_empty() {
        let _ = writeln!(
            out,
            "<details><summary>Model file <code>{}</code></summary><pre>{}</pre></details>",
            escape(&p.model_file),
            escape(&p.model_text)
        );
    }
    if !p.arrays.is_empty() {
        out.push_str("<table><tr><th>record</th><th>array</th><th>shape</th><th>SHA-256 (float64, little-endian, C order)</th></tr>\n");
        for a in &p.arrays {
            let shape: Vec<String> = a.shape.iter().map(|s| s.to_string()).collect();
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td><code class=\"hash\">{}</code></td></tr>",
                escape(&a.record),
                escape(&a.name),
                shape.join(" × "),
                a.sha256
            );
        }
        out.push_str("</table>\n");
    } else if p.data_files.is_empty() {
        out.push_str("<p>No data files: the records were simulated from the model file.</p>\n");
    }
    if !p.data_files.is_empty() {
        out.push_str("<table><tr><th>data file</th><th>bytes</th><th>SHA-256</th></tr>\n");
        for f in &p.data_files {
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td><code class=\"hash\">{}</code></td></tr>",
                escape(&f.path),
                f.bytes,
                f.sha256
            );
        }
        out.push_str("</table>\n");
    }
    if units.is_empty() {
        out.push_str("<p>Units: none given (a <code>[units]</code> section names them).</p>\n");
    } else {
        let given: Vec<String> = [
            ("length", &units.length),
            ("force", &units.force),
            ("time", &units.time),
            ("angle", &units.angle),
            ("mass", &units.mass),
        ]
        .iter()
        .filter_map(|(d, u)| u.as_ref().map(|u| format!("{d} {}", escape(u))))
        .collect();
        let _ = writeln!(out, "<p>Units: {}.</p>", given.join(", "));
    }
    out.push_str("<details><summary>Every setting in effect, defaults included</summary>\n<table><tr><th>section</th><th>key</th><th>value</th><th>source</th></tr>\n");
    for s in &p.settings {
        let _ = writeln!(
            out,
            "<tr><td class=\"left\">{}</td><td class=\"left\"><code>{}</code></td><td class=\"left\"><code>{}</code></td><td class=\"left\">{}</td></tr>",
            escape(&s.section),
            escape(&s.key),
            escape(&s.value),
            s.source.text()
        );
    }
    out.push_str("</table>\n</details>\n");
    out
}

const STYLE: &str = "body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}\
table{border-collapse:collapse;display:block;max-width:100%;overflow-x:auto}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}.warning{background:#fff3cd;border:1px solid #e0c060;padding:.5em}.flag td{background:#fde2d8}\
td.undetermined{text-align:left}.undetermined{color:#7a2e00}pre{white-space:pre-wrap;word-break:break-all;background:#f6f6f6;padding:.5em}\
code.hash{word-break:break-all}svg{display:block;margin:1em 0;width:100%;height:auto}\
td{white-space:nowrap}td.left,th.left,td.undetermined{text-align:left;white-space:normal}.bar{display:inline-block;height:.8em;background:#0072B2}";

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
    let fold = noise.windows.len() > OPEN_WINDOWS;
    if fold {
        let _ = writeln!(
            section,
            "<details><summary>Every window ({})</summary>",
            noise.windows.len()
        );
    }
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
    if fold {
        section.push_str("</details>\n");
    }
    section
}

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
