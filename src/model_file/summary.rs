//! What is printed about a job around its fit: the periods detected from the force, the
//! preamble of `dampid identify` (the mode, windows accepted although not steady, the
//! POD reduction, the harmonic approximation), and the report of `dampid check`
//! (periods, steady state, and the regressor's conditioning and identifiability before
//! any fit). Each is a `Display`; the check report is also `Serialize`.

use std::fmt;

use serde::Serialize;

use super::Job;
use crate::analysis::check::RegressorCheck;
use crate::error::Result;
use crate::prep::period::PeriodEstimate;
use crate::prep::steady_state::SteadyStateReport;
use crate::regressor::Regressor;
use crate::report::count;

/// The periods detected from the force of a job's records ([`Job::periods`]).
pub struct Periods<'a> {
    job: &'a Job,
}

/// What `dampid identify` prints before the fit ([`Job::preamble`]).
pub struct Preamble<'a> {
    job: &'a Job,
    steady: Option<&'a SteadyStateReport>,
}

impl Job {
    /// The periods detected from the force, one line per record that had none given.
    pub fn periods(&self) -> Periods<'_> {
        Periods { job: self }
    }

    /// The periods detected from the force of the records that had none given.
    pub fn detected(&self) -> Vec<DetectedPeriod> {
        self.source_records
            .iter()
            .zip(&self.detected_periods)
            .filter_map(|(record, detected)| {
                detected.map(|estimate| DetectedPeriod {
                    record: record.label().to_string(),
                    estimate,
                })
            })
            .collect()
    }

    /// Detected periods, the non-periodic mode, windows accepted although not in steady
    /// state (from `steady`), the POD reduction and the harmonic approximation, when
    /// there are any.
    pub fn preamble<'a>(&'a self, steady: Option<&'a SteadyStateReport>) -> Preamble<'a> {
        Preamble { job: self, steady }
    }
}

impl fmt::Display for Periods<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for detected in self.job.detected() {
            writeln!(f, "{detected}")?;
        }
        Ok(())
    }
}

impl fmt::Display for Preamble<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let job = self.job;
        write!(f, "{}", job.periods())?;
        for inputs in job.inputs.iter().filter(|i| !i.is_plain()) {
            write!(f, "{inputs}")?;
        }
        if let Some(spans) = job.settings.regressor.windows.spans() {
            writeln!(
                f,
                "non-periodic energy balance: windows of {} time units, stored energy and constant forces as unknowns",
                spans.length
            )?;
        }
        let rejected = self.steady.iter().flat_map(|s| s.rejected()).count();
        if rejected > 0 {
            writeln!(
                f,
                "warning: {rejected} window(s) not in steady state, accepted (dampid check shows them)"
            )?;
        }
        if let Some(reduction) = &job.pod {
            let reports = reduction.reports();
            let retained = reports.iter().map(|r| r.retained).max().unwrap_or(0);
            writeln!(
                f,
                "POD: {} basis(es), {} mode(s) retained; energy share of the retained modes:",
                reports.len(),
                retained
            )?;
            for (k, r) in reports.iter().enumerate() {
                let label = match reduction.bases.len() {
                    1 if job.source_records.len() > 1 => "all records (stacked)".to_string(),
                    _ => job.source_records[k].label().to_string(),
                };
                let shares: Vec<String> = r
                    .modes
                    .iter()
                    .map(|m| format!("{:.4}", 100.0 * m.energy_share))
                    .collect();
                writeln!(
                    f,
                    "  {label:<32} retained {:.4}%, every mode [{}] %",
                    100.0 * r.retained_share,
                    shares.join(", ")
                )?;
            }
        }
        if let Some(table) = &job.harmonic {
            writeln!(
                f,
                "harmonic approximation (eq. 4): {} stepped-sine points, synchronous motion synthesized",
                table.points().len()
            )?;
        }
        Ok(())
    }
}

/// A period detected from a record's force.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectedPeriod {
    /// The record's label.
    pub record: String,
    /// The estimate.
    #[serde(flatten)]
    pub estimate: PeriodEstimate,
}

impl fmt::Display for DetectedPeriod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = &self.estimate;
        write!(
            f,
            "period detected from the force of '{}': T = {:.9} (ω = {:.9}), {:.1} cycles, the fundamental explains {:.3}% of the force",
            self.record,
            p.period,
            p.frequency,
            p.cycles,
            100.0 * p.explained
        )
    }
}

/// The report of `dampid check`: a model file and its data, before any fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// The job's title.
    pub model: String,
    /// Periods detected from the force, for records that gave none.
    pub detected_periods: Vec<DetectedPeriod>,
    /// How far each window is from steady state (`None` in the non-periodic mode).
    pub steady_state: Option<SteadyStateReport>,
    /// The window length of the non-periodic mode (`None` for whole periods).
    pub non_periodic_window: Option<f64>,
    /// Number of records the equations come from.
    pub records: usize,
    /// The regressor's size, conditioning and identifiability.
    #[serde(flatten)]
    pub regressor: RegressorCheck,
}

impl CheckReport {
    /// The check of `job` with its steady-state report `steady` and its `regressor`.
    pub fn new(
        job: &Job,
        steady: Option<SteadyStateReport>,
        regressor: &Regressor,
    ) -> Result<Self> {
        Ok(CheckReport {
            model: job.title.clone(),
            detected_periods: job.detected(),
            steady_state: steady,
            non_periodic_window: job.settings.regressor.windows.spans().map(|s| s.length),
            records: job.records.len(),
            regressor: RegressorCheck::new(regressor, job.settings.fit.rank_tolerance)?,
        })
    }
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}: model and data are valid", self.model)?;
        for detected in &self.detected_periods {
            writeln!(f, "{detected}")?;
        }
        match (&self.steady_state, self.non_periodic_window) {
            (Some(steady), _) => write!(f, "{steady}")?,
            (None, window) => writeln!(
                f,
                "non-periodic mode: windows of {} time units, no steady state needed",
                window.unwrap_or(0.0)
            )?,
        }
        let check = &self.regressor;
        writeln!(
            f,
            "{}, {}, {}: {}",
            count(self.records, "record"),
            count(check.equations, "equation"),
            count(check.coefficients.len(), "coefficient"),
            check.coefficients.join(", ")
        )?;
        write!(f, "{check}")
    }
}
