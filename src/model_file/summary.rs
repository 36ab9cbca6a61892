//! What is printed about a job around its fit: the periods detected from the force, the
//! time columns read with jitter (above [`NOTED_JITTER`]), the
//! preamble of `dampid identify` (the mode, the
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

/// Time-column jitter below this (round-off of printed times) goes unmentioned; above
/// it, up to [`crate::io::table::MAX_TIME_JITTER`], the record was read with its mean
/// step and the summary says so.
pub const NOTED_JITTER: f64 = 1e-6;

/// The periods detected from the force of a job's records ([`Job::periods`]).
pub struct Periods<'a> {
    job: &'a Job,
}

/// What `dampid identify` prints before the fit ([`Job::preamble`]).
pub struct Preamble<'a> {
    job: &'a Job,
    /// Kept for the signature: windows accepted although not steady are now a warning
    /// of the fit report itself ([`crate::report::FitReport::with_steady_state`]), so
    /// the text, the JSON and the HTML all carry it.
    #[allow(dead_code)]
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

    /// The records whose time column was read with a jitter above [`NOTED_JITTER`].
    pub fn jittered(&self) -> Vec<JitteredTime> {
        self.source_records
            .iter()
            .zip(&self.time_jitter)
            .filter_map(|(record, jitter)| {
                jitter
                    .filter(|j| *j > NOTED_JITTER)
                    .map(|jitter| JitteredTime {
                        record: record.label().to_string(),
                        step: record.step(),
                        jitter,
                    })
            })
            .collect()
    }

    /// Detected periods, the non-periodic mode, the POD reduction and the harmonic
    /// approximation, when
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
        for jittered in self.job.jittered() {
            writeln!(f, "{jittered}")?;
        }
        Ok(())
    }
}

impl fmt::Display for Preamble<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let job = self.job;
        write!(f, "{}", job.periods())?;
        if let Some(table) = &job.stepped_sine {
            write!(f, "{}", SteppedSineSummary::of(table))?;
        }
        for inputs in job.inputs.iter().filter(|i| !i.is_plain()) {
            write!(f, "{inputs}")?;
        }
        if let Some(spans) = job.settings.regressor.windows.spans() {
            writeln!(
                f,
                "non-periodic energy balance: windows of {}, stored energy and constant forces as unknowns",
                WindowLengths::of(job, spans.length)
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
        let cycles = match p.whole_periods {
            Some(k) => format!(
                "exactly {k} whole periods (estimated {:.4} ± {:.1e}, so T = record length / {k})",
                p.cycles, p.cycles_std
            ),
            None => format!("{:.1} cycles", p.cycles),
        };
        write!(
            f,
            "period detected from the force of '{}': T = {:.9} (ω = {:.9}), {cycles}, the fundamental explains {:.3}% of the force",
            self.record,
            p.period,
            p.frequency,
            100.0 * p.explained
        )
    }
}

/// A record whose time column was read with jitter: uniform samples at the mean step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JitteredTime {
    /// The record's label.
    pub record: String,
    /// The mean step used.
    pub step: f64,
    /// max |Δt − h| / h.
    pub jitter: f64,
}

impl fmt::Display for JitteredTime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "time column of '{}': steps depart from their mean h = {:e} by up to {:.2e} of it (accepted up to {:e}); read as uniform samples at h",
            self.record,
            self.step,
            self.jitter,
            crate::io::table::MAX_TIME_JITTER
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
    /// Records whose time column was read with jitter above [`NOTED_JITTER`].
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
    /// Number of records the equations come from.
    pub records: usize,
    /// What a `[stepped_sine]` table holds (its records are the points' synthesized
    /// periods).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stepped_sine: Option<SteppedSineSummary>,
    /// The estimated nonlinear parameters (law parameters, a table's residual
    /// receptances), held at their initial values for the check: (name, value).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub held_at_initial: Vec<(String, f64)>,
    /// The regressor's size, conditioning and identifiability.
    #[serde(flatten)]
    pub regressor: RegressorCheck,
}

impl CheckReport {
    /// The check of `job` with its steady-state report `steady` and its `regressor`
    /// (built at the initial values of any estimated parameters,
    /// [`Job::initial_regressor`]).
    pub fn new(
        job: &Job,
        steady: Option<SteadyStateReport>,
        regressor: &Regressor,
    ) -> Result<Self> {
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
            records: job.records.len(),
            stepped_sine: job.stepped_sine.as_ref().map(SteppedSineSummary::of),
            held_at_initial: job
                .estimated_parameters()
                .into_iter()
                .map(|p| (p.name, p.initial))
                .collect(),
            regressor: RegressorCheck::new(regressor, &job.settings.fit)?,
        })
    }
}

/// The table of a `[stepped_sine]` job in a line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SteppedSineSummary {
    /// The data file.
    pub file: String,
    /// Points (equations).
    pub points: usize,
    /// Sweeps.
    pub sweeps: usize,
    /// Where the noise of the points came from.
    pub noise: crate::prep::harmonic::sweeps::NoiseOrigin,
}

impl SteppedSineSummary {
    fn of(job: &super::SteppedSineJob) -> Self {
        SteppedSineSummary {
            file: job.file.clone(),
            points: job.table.table.points().len(),
            sweeps: job.table.sweep_names.len(),
            noise: job.table.noise_origin,
        }
    }
}

impl fmt::Display for SteppedSineSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let noise = match self.noise {
            crate::prep::harmonic::sweeps::NoiseOrigin::Given => "given per point",
            crate::prep::harmonic::sweeps::NoiseOrigin::SweepScatter => {
                "estimated from the scatter along each sweep"
            }
        };
        writeln!(
            f,
            "stepped-sine table {}: {} in {}, noise {noise}; one energy equation per point, weighted by its propagated variance",
            self.file,
            count(self.points, "point"),
            count(self.sweeps, "sweep")
        )
    }
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}: model and data are valid", self.model)?;
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
            count(self.records, "record"),
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

/// The window length of the non-periodic mode: the one asked for and, where a record's
/// step does not divide it, the length used, L h with L = round(length/h)
/// ([`crate::prep::window::span_windows`]).
struct WindowLengths {
    requested: f64,
    /// Each distinct length used that differs from `requested`, with its steps and step.
    used: Vec<(f64, Option<(usize, f64)>)>,
}

impl WindowLengths {
    fn of(job: &Job, requested: f64) -> Self {
        let mut used: Vec<(f64, Option<(usize, f64)>)> = Vec::new();
        for record in job.records.iter() {
            let h = record.step();
            let steps = (requested / h).round();
            let length = steps * h;
            let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
            if steps >= 1.0
                && !same(length, requested)
                && !used.iter().any(|(l, _)| same(*l, length))
            {
                used.push((length, Some((steps as usize, h))));
            }
        }
        WindowLengths { requested, used }
    }

    fn rounded(&self) -> Vec<f64> {
        self.used.iter().map(|(length, _)| *length).collect()
    }
}

impl fmt::Display for WindowLengths {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.used.is_empty() {
            return write!(f, "{} time units", self.requested);
        }
        let used: Vec<String> = self
            .used
            .iter()
            .map(|(length, steps)| match steps {
                Some((l, h)) => format!("{length} ({l} steps of {h})"),
                None => format!("{length}"),
            })
            .collect();
        write!(
            f,
            "{} time units (whole steps; {} requested)",
            used.join(", "),
            self.requested
        )
    }
}

/// One experiment a design selected, as a model file writes it (DOF 1-based).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SelectedExperiment {
    /// Its number among the candidates, `[[simulation.experiments]]` order, from 1.
    pub candidate: usize,
    /// `"start"` (in the design's start set) or `"added"` (chosen by the design).
    pub selected_as: &'static str,
    /// The candidate's description in the design report.
    pub description: String,
    /// `force_dof`, 1-based.
    pub force_dof: usize,
    /// `amplitude`.
    pub amplitude: f64,
    /// `frequency` (rad per time unit).
    pub frequency: f64,
    /// `phase` (rad).
    pub phase: f64,
}

/// The experiments `report` selected (its start set, then the ones it added);
/// `experiments` are the job's ([`Job::experiments`]), in candidate order. `dampid
/// design --json` gives them beside the report, so the JSON stands alone.
pub fn selected_experiments(
    report: &crate::analysis::design::DesignReport,
    experiments: &[crate::simulate::HarmonicForce],
) -> Vec<SelectedExperiment> {
    report
        .selected()
        .into_iter()
        .filter_map(|k| {
            let e = experiments.get(k)?;
            Some(SelectedExperiment {
                candidate: k + 1,
                selected_as: if report.start.contains(&k) {
                    "start"
                } else {
                    "added"
                },
                description: report.candidates.get(k).cloned().unwrap_or_default(),
                force_dof: e.dof + 1,
                amplitude: e.amplitude,
                frequency: e.frequency,
                phase: e.phase,
            })
        })
        .collect()
}

/// The experiments `report` selected ([`selected_experiments`]) as
/// `[[simulation.experiments]]` blocks to paste into a model file.
pub fn selected_experiments_toml(
    report: &crate::analysis::design::DesignReport,
    experiments: &[crate::simulate::HarmonicForce],
) -> String {
    let mut text = String::from(
        "# The selected experiments as [[simulation.experiments]], to paste into a model file:\n",
    );
    for e in selected_experiments(report, experiments) {
        text.push_str(&format!(
            "\n[[simulation.experiments]]   # candidate {} ({}): {}\nforce_dof = {}\namplitude = {:?}\nfrequency = {:?}\n",
            e.candidate, e.selected_as, e.description, e.force_dof, e.amplitude, e.frequency
        ));
        if e.phase != 0.0 {
            text.push_str(&format!("phase = {:?}\n", e.phase));
        }
    }
    text
}
