//! A self-contained HTML report of one identification, truthful about what the data
//! determine: the warnings (every one the text report gives), the coefficients with
//! their units, standard errors and 95% intervals (θ ± 1.96 se), where a coefficient the
//! data do not determine reads "not determined" and the determined combinations are
//! given instead; each record's share of the residual; the identifiability (VIFs,
//! correlations, near-null directions, determined combinations) and the steady-state
//! verdict of every window; inline SVG plots (plots.rs): measured input work against
//! identified dissipated work per window and the residuals, both coloured by record, and
//! each identified damping law θ f(v) with its band over the relative velocity its
//! elements were measured at; when identification ran on proper orthogonal mode
//! coordinates, the modes (pom.rs); and the provenance (model file, data files with
//! SHA-256, settings, version, commit, date). Nothing is loaded from outside the file.

mod plots;
mod pom;

use std::fmt::Write as _;

use crate::analysis::equivalent::EquivalentDamping;
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

    fn coefficient_table(&self) -> String {
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
        let _ = writeln!(
            out,
            "<p>Column-scaled regressor: rank {}, practical rank {} of {}, condition number {condition}, singular values [{}].</p>",
            report.rank,
            id.practical_rank,
            id.names.len(),
            singular.join(", ")
        );
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

    /// One plot per element term: θ f(0, v) over the relative velocity its elements were
    /// measured at (nothing drawn beyond), with the band (θ ± 1.96 se) f(0, v) when the
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
            let curves: Vec<plots::Curve> = range
                .clone()
                .take(MAX_CURVES)
                .enumerate()
                .map(|(j, k)| {
                    let c = &self.report.coefficients[k];
                    let (lo, hi) = if shared {
                        elements
                            .iter()
                            .map(|e| self.velocity_range(e.a, e.b))
                            .fold((0.0f64, 0.0f64), |(l, h), (a, b)| (l.min(a), h.max(b)))
                    } else {
                        self.velocity_range(elements[j].a, elements[j].b)
                    };
                    let (lo, hi) = if hi > lo { (lo, hi) } else { (-1.0, 1.0) };
                    let speeds: Vec<f64> = (0..=200)
                        .map(|i| lo + (hi - lo) * i as f64 / 200.0)
                        .collect();
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
    out.push_str("<details><summary>Every setting in effect, defaults included</summary>\n");
    for (name, value) in &p.settings {
        let _ = writeln!(out, "<h4>{}</h4><pre>{}</pre>", escape(name), escape(value));
    }
    out.push_str("</details>\n");
    out
}

const STYLE: &str = "body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}\
table{border-collapse:collapse;display:block;max-width:100%;overflow-x:auto}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}.warning{background:#fff3cd;border:1px solid #e0c060;padding:.5em}.flag td{background:#fde2d8}\
td.undetermined{text-align:left;color:#7a2e00}pre{white-space:pre-wrap;word-break:break-all;background:#f6f6f6;padding:.5em}\
code.hash{word-break:break-all}svg{display:block;margin:1em 0;width:100%;height:auto}";

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
