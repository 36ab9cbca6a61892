//! `dampid check`: a model file and its data before any fit (periods, steady state, the
//! regressor's conditioning and identifiability at the initial values of any estimated
//! parameters), as text and JSON.

use std::fmt;

use serde::Serialize;

use super::Outcome;
use crate::analysis::check::RegressorCheck;
use crate::error::Result;
use crate::model_file::summary::WindowLengths;
use crate::model_file::{DetectedPeriod, JitteredTime, Job, SteppedSineSummary};
use crate::prep::steady_state::SteadyStateReport;
use crate::report::count;

/// The report of `dampid check`: a model file and its data, before any fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// The job's title.
    pub model: String,
    /// Periods detected from the force, for records that gave none.
    pub detected_periods: Vec<DetectedPeriod>,
    /// Records whose time column was read with jitter above [`crate::model_file::NOTED_JITTER`].
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub time_jitter: Vec<JitteredTime>,
    /// How far each window is from steady state (`None` in the non-periodic mode).
    pub steady_state: Option<SteadyStateReport>,
    /// The window length the non-periodic mode was asked for (`None` for whole periods).
    pub non_periodic_window: Option<f64>,
    /// The lengths the windows have where they differ from the one asked for: L h with
    /// L = round(length/h) whole steps of each record's step h (absent when equal).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub non_periodic_window_used: Vec<f64>,
    /// Number of records (of sweeps, for a stepped-sine table) the equations come from.
    pub records: usize,
    /// What they are: "record" or "sweep".
    #[serde(skip)]
    pub unit: &'static str,
    /// What a `[stepped_sine]` table holds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stepped_sine: Option<SteppedSineSummary>,
    /// What isolating each record's mode found, for a free decay: its band, its usable
    /// amplitude range and the windows dropped at its ends and at the noise floor.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub free_decay: Vec<crate::prep::free_decay::DecaySummary>,
    /// The estimated nonlinear parameters (law parameters, a table's residual
    /// receptances), held at their initial values for the check: (name, value).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub held_at_initial: Vec<(String, f64)>,
    /// The regressor's size, conditioning and identifiability.
    #[serde(flatten)]
    pub regressor: RegressorCheck,
    /// Why `dampid identify` would refuse these data as they are (windows not in steady
    /// state), when it would.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
}

/// What `dampid check` takes besides the model file: what to accept whatever
/// `[identification]` says.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CheckOptions {
    /// Windows that are not in steady state (reported, not refused).
    pub accept_transient: bool,
    /// Input work negative beyond its noise ([`crate::regressor::passive`]).
    pub accept_negative_work: bool,
}

/// The check of `job` with `options` (windows accepted as transient, negative input
/// work accepted, whatever `[identification]` says):
/// the periods, the steady state, and the regressor at the initial values of any
/// estimated parameters ([`Job::initial_regressor`]) with its conditioning and
/// identifiability. Windows that are not in steady state are reported, with the
/// refusal `dampid identify` would give.
pub fn run(job: &Job, options: CheckOptions) -> Result<CheckReport> {
    let mut settings = job.settings.clone();
    if let Some(steady) = &mut settings.steady_state {
        steady.accept_transient |= options.accept_transient;
    }
    settings.fit.accept_negative_work |= options.accept_negative_work;
    let problem = job.problem();
    // the check, then the rows, of one problem, as `identify` runs them
    let steady = match &settings.steady_state {
        Some(thresholds) => problem.steady_state(&settings.regressor, thresholds)?,
        None => None,
    };
    let refused = steady
        .as_ref()
        .and_then(|s| s.enforce().err())
        .map(|e| format!("{e}; {}", super::TRANSIENT_HINT));
    let source = problem.source();
    settings.fit.validate()?;
    // the job's initial regressor (Job::initial_regressor), of the problem checked above
    let regressor = problem.regressor(&problem.initial_values(), &settings.regressor)?;
    Ok(CheckReport {
        model: job.title.clone(),
        detected_periods: job.detected(),
        time_jitter: job.jittered(),
        steady_state: steady,
        non_periodic_window: job.settings.regressor.windows.spans().map(|s| s.length),
        non_periodic_window_used: job
            .settings
            .regressor
            .windows
            .spans()
            .map(|s| WindowLengths::of(job, s.length).rounded())
            .unwrap_or_default(),
        records: source.groups(),
        unit: source.unit(),
        stepped_sine: job.stepped_sine.as_ref().map(SteppedSineSummary::of),
        free_decay: job.free_decay.clone(),
        held_at_initial: problem
            .parameters()
            .into_iter()
            .map(|p| (p.name, p.initial))
            .collect(),
        regressor: RegressorCheck::new(&regressor, &settings.fit)?,
        refused,
    })
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.refused {
            None => writeln!(f, "{}: model and data are valid", self.model)?,
            Some(_) => writeln!(
                f,
                "{}: windows not in steady state (below); identify refuses them",
                self.model
            )?,
        }
        if let Some(table) = &self.stepped_sine {
            write!(f, "{table}")?;
        }
        for detected in &self.detected_periods {
            writeln!(f, "{detected}")?;
        }
        for jittered in &self.time_jitter {
            writeln!(f, "{jittered}")?;
        }
        match (&self.steady_state, self.non_periodic_window) {
            (Some(steady), _) => write!(f, "{steady}")?,
            (None, None) if self.stepped_sine.is_some() => {}
            (None, None) if !self.free_decay.is_empty() => {
                for decay in &self.free_decay {
                    write!(f, "{decay}")?;
                }
            }
            (None, window) => {
                let requested = window.unwrap_or(0.0);
                let lengths = WindowLengths {
                    requested,
                    used: self
                        .non_periodic_window_used
                        .iter()
                        .map(|&length| (length, None))
                        .collect(),
                };
                writeln!(
                    f,
                    "non-periodic mode: windows of {lengths}, no steady state needed"
                )?
            }
        }
        if !self.held_at_initial.is_empty() {
            let held: Vec<String> = self
                .held_at_initial
                .iter()
                .map(|(n, v)| format!("{n} = {v}"))
                .collect();
            writeln!(
                f,
                "estimated parameters held at their initial values for this check: {} (`dampid identify` estimates them; its report gives the conditioning at the estimate)",
                held.join(", ")
            )?;
        }
        let check = &self.regressor;
        writeln!(
            f,
            "{}, {}, {}: {}",
            count(self.records, self.unit),
            count(check.equations, "equation"),
            count(check.coefficients.len(), "coefficient"),
            if check.coefficients.len() > crate::analysis::digest::FULL_LISTING {
                format!(
                    "by term {}",
                    crate::analysis::digest::by_term_text(
                        check.coefficients.iter().map(String::as_str)
                    )
                )
            } else {
                check.coefficients.join(", ")
            }
        )?;
        write!(f, "{check}")
    }
}

impl Outcome for CheckReport {
    fn refused(&self) -> Option<String> {
        self.refused.clone()
    }
}
