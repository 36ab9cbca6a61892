//! The equations by group — a record's windows, or a stepped-sine table's sweep — in
//! the words of their source:
//!
//! - the **Records** table: each record's equations, its share of the squared residual
//!   (weighted as fitted) against its share of the equations, its standardised and
//!   mean residual ([`crate::report::records`]);
//! - for a table, the **Sweeps** table instead: one row per sweep with its force level
//!   (the median force amplitude a of its points), its range of response amplitude X
//!   and of frequency ω/2π, its points and the same residual columns;
//! - the energy balance (input work b against identified work Aθ per equation; for a
//!   table, the energy per cycle π a X sin φ of each point on log-log axes) and the
//!   residuals b − Aθ (against the equation's index, or a point's frequency), coloured
//!   by record or sweep, gathered into one beyond the legend's
//!   room ([`plots::MOST_ENTRIES`] entries in all).

use std::fmt::Write as _;

use super::plots::{self, BalanceAxes, Group, ResidualAxes};
use super::{Equations, HtmlReport, escape};
use crate::error::Result;
use crate::regressor::SteppedSineSource;

impl HtmlReport<'_> {
    /// The Records table, or a table's Sweeps table (module doc); nothing without rows.
    pub(super) fn groups_section(&self) -> String {
        let records = &self.report.records;
        if records.is_empty() {
            return String::new();
        }
        let total = self.report.residuals.len();
        let table = self.source.stepped_sine();
        let mut out = match table {
            Some(_) => format!(
                "<h2>Sweeps</h2>\n<p>Each sweep's force level (the median force amplitude of its points), its range of response amplitude and of frequency, and its share of the squared residual (weighted as fitted) against its share of the points, with its RMS residual in units of the fit's residual standard deviation (about 1 when it fits like the rest).</p>\n<table><tr><th>sweep</th><th>force a</th><th>amplitude X</th><th>{}</th><th>points</th><th>share of points</th><th>share of squared residual</th><th>standardised residual</th><th>mean residual</th></tr>\n",
                escape(&self.frequency_axis())
            ),
            None => String::from(
                "<h2>Records</h2>\n<p>Each record's share of the squared residual (weighted as fitted) against its share of the equations, and its RMS residual in units of the fit's residual standard deviation (about 1 when it fits like the rest).</p>\n<table><tr><th>record</th><th>equations</th><th>share of equations</th><th>share of squared residual</th><th>standardised residual</th><th>mean residual</th></tr>\n",
            ),
        };
        for r in records {
            let flag = r.dominates(records.len(), total);
            let z = r
                .standardised_residual
                .map_or("–".into(), |z| format!("{z:.2}"));
            let level = table.map_or(String::new(), |t| sweep_cells(t, r.record_index));
            let _ = writeln!(
                out,
                "<tr{}><td>{}</td>{level}<td>{}</td><td>{:.1}%</td><td>{:.1}%</td><td>{z}</td><td>{:+.3e}</td></tr>",
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

    /// The energy balance and the residuals (module doc).
    pub(super) fn balance_section(&self) -> Result<String> {
        let report = self.report;
        let mut out = String::from("<h2>Energy balance</h2>\n");
        if report.estimation.is_some() {
            out.push_str("<p>At the estimated nonlinear parameters.</p>\n");
        }
        // A free decay's rows are energies divided by the speed at their crossing
        // (src/regressor/free_decay.rs): no unit of work.
        let decay = self.backbone.is_some();
        let work = if decay { None } else { self.units().work() };
        let stored = !report.nuisance.is_empty();
        let axes = match (self.equations(), stored) {
            _ if decay => BalanceAxes {
                title: "Energy balance since each record's first crossing",
                input: "stored energy lost since the first crossing ÷ the speed there",
                identified: "identified damping work + start energy ÷ the speed",
                log: false,
                unit: None,
            },
            (Equations::Points, _) => BalanceAxes {
                title: "Energy balance per point",
                input: "input energy per cycle π a X sin φ",
                identified: "identified dissipated energy per cycle Σ θ_k A_k",
                log: true,
                unit: work.as_deref(),
            },
            (Equations::Windows, true) => BalanceAxes {
                title: "Energy balance per window",
                input: "input work ∫ vᵀr dt",
                identified: "identified dissipated + stored work Σ θ_k A_k",
                log: false,
                unit: work.as_deref(),
            },
            (Equations::Windows, false) => BalanceAxes {
                title: "Energy balance per window",
                input: "input work ∮ vᵀr dt",
                identified: "identified dissipated work Σ θ_k A_k",
                log: false,
                unit: work.as_deref(),
            },
        };
        let input = self.regressor.rhs();
        let residuals = &report.residuals;
        // Room for the line of equality and a note of points off the log axes.
        let room = plots::MOST_ENTRIES - 2;
        let balance = self.by_group(room, |i| Some((input[i], input[i] - residuals[i])));
        out.push_str(&plots::work_balance(&balance, &axes)?);
        out.push_str("\n<h2>Residuals</h2>\n");
        let frequency = self.frequency_axis();
        let axes = match self.equations() {
            Equations::Points => ResidualAxes {
                title: "Residuals b − Aθ per point",
                x: &frequency,
                index: None,
                unit: work.as_deref(),
            },
            Equations::Windows => ResidualAxes {
                title: "Residuals b − Aθ per equation",
                x: "equation (window)",
                index: Some(residuals.len()),
                unit: work.as_deref(),
            },
        };
        let rows = &report.rows;
        // Room for the mean residual's line.
        let room = plots::MOST_ENTRIES - 1;
        let groups = match self.equations() {
            Equations::Points => self.by_group(room, |i| {
                let omega = rows.get(i)?.frequency?;
                Some((omega / std::f64::consts::TAU, residuals[i]))
            }),
            Equations::Windows => self.by_group(room, |i| Some(((i + 1) as f64, residuals[i]))),
        };
        out.push_str(&plots::residuals(
            &groups,
            &axes,
            report.residual_bias.relative_mean,
        )?);
        Ok(out)
    }

    /// The frequency axis's words: ω/2π in Hz when time is in seconds (or not named).
    pub(super) fn frequency_axis(&self) -> String {
        match self.units().time.as_deref() {
            None | Some("s") => "frequency ω/2π [Hz]".into(),
            Some(t) => format!("frequency ω/2π [1/{t}]"),
        }
    }

    /// Points grouped by the record or sweep of each equation, in order of first
    /// appearance: (its label, the point `of` each of its rows that has one), gathered
    /// into `room` legend entries ([`plots::gathered`]).
    pub(super) fn by_group(
        &self,
        room: usize,
        of: impl Fn(usize) -> Option<(f64, f64)>,
    ) -> Vec<Group> {
        let mut groups: Vec<(usize, Group)> = Vec::new();
        for (i, row) in self.report.rows.iter().enumerate() {
            let k = match groups.iter().position(|(r, _)| *r == row.record_index) {
                Some(k) => k,
                None => {
                    groups.push((
                        row.record_index,
                        Group {
                            name: row.record.clone(),
                            points: Vec::new(),
                            rest: false,
                        },
                    ));
                    groups.len() - 1
                }
            };
            if let Some(point) = of(i) {
                groups[k].1.points.push(point);
            }
        }
        let plural = match self.equations() {
            Equations::Points => "sweeps",
            Equations::Windows => "records",
        };
        plots::gathered(groups.into_iter().map(|(_, g)| g).collect(), plural, room)
    }
}

/// The force level, amplitude range and frequency range cells of sweep `s` of `table`.
fn sweep_cells(table: &SteppedSineSource, s: usize) -> String {
    let swept = &table.table;
    let points = swept.table.points();
    let members = swept.members(s);
    if members.is_empty() {
        return "<td>–</td><td>–</td><td>–</td>".into();
    }
    let mut forces: Vec<f64> = members.iter().map(|&i| points[i].force_amplitude).collect();
    forces.sort_by(f64::total_cmp);
    let median = forces[forces.len() / 2];
    let range = |value: &dyn Fn(usize) -> Option<f64>| {
        members
            .iter()
            .filter_map(|&i| value(i))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    let amplitude = range(&|i| points[i].amplitudes.get(points[i].force_dof).copied());
    let hz = range(&|i| Some(points[i].frequency / std::f64::consts::TAU));
    format!(
        "<td>{median:.4e}</td><td>{:.3e} – {:.3e}</td><td>{:.2} – {:.2}</td>",
        amplitude.0, amplitude.1, hz.0, hz.1
    )
}
