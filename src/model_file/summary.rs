//! What is printed about a job around its fit: the periods detected from the force, the
//! time columns read with jitter (above [`NOTED_JITTER`]), the
//! preamble of `dampid identify` (the mode, the stepped-sine table, the gains, the POD
//! reduction, the harmonic approximation). Each is a `Display`; the commands
//! ([`crate::command`]) print them.

use std::fmt;

use serde::Serialize;

use super::Job;
use crate::prep::period::PeriodEstimate;
use crate::prep::steady_state::SteadyStateReport;
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
        for decay in &job.free_decay {
            write!(f, "{decay}")?;
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
    /// Sweeps too short for their own scatter, given the pooled scatter of the others.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub pooled: Vec<String>,
}

impl SteppedSineSummary {
    /// The summary of `table`.
    pub fn of(table: &crate::regressor::SteppedSineSource) -> Self {
        SteppedSineSummary {
            file: table.file.clone().unwrap_or_default(),
            points: table.table.table.points().len(),
            sweeps: table.table.sweep_names.len(),
            noise: table.table.noise_origin,
            pooled: table
                .table
                .pooled
                .iter()
                .map(|&s| table.table.sweep_names[s].clone())
                .collect(),
        }
    }
}

impl fmt::Display for SteppedSineSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let noise = match self.noise {
            crate::prep::harmonic::sweeps::NoiseOrigin::Given => "given per point".to_string(),
            crate::prep::harmonic::sweeps::NoiseOrigin::SweepScatter if self.pooled.is_empty() => {
                "estimated from the scatter along each sweep".to_string()
            }
            crate::prep::harmonic::sweeps::NoiseOrigin::SweepScatter => format!(
                "estimated from the scatter along each sweep ({}: fewer than 3 points, the pooled scatter of the others)",
                self.pooled.join(", ")
            ),
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

/// The window length of the non-periodic mode: the one asked for and, where a record's
/// step does not divide it, the length used, L h with L = round(length/h)
/// ([`crate::prep::window::span_windows`]).
pub(crate) struct WindowLengths {
    pub(crate) requested: f64,
    /// Each distinct length used that differs from `requested`, with its steps and step.
    pub(crate) used: Vec<(f64, Option<(usize, f64)>)>,
}

impl WindowLengths {
    pub(crate) fn of(job: &Job, requested: f64) -> Self {
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

    pub(crate) fn rounded(&self) -> Vec<f64> {
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
