//! `dampid design`: choose, among a model file's simulated experiments, those that
//! separate the coefficients ([`crate::analysis::design`]), with the selected ones as
//! data and as `[[simulation.experiments]]` TOML to paste.

use std::fmt;

use serde::Serialize;

use super::Outcome;
use crate::analysis::design::{DesignReport, select};
use crate::error::{Error, Result};
use crate::model_file::Job;
use crate::progress::Progress;

/// The design of `job` (its `[design]` settings, its `[simulation]` experiments as the
/// candidates); `progress` counts the candidates evaluated. A job without a
/// `[simulation]` has no candidates: an error naming `model_file`.
pub fn run(job: &Job, model_file: &str, progress: Progress<'_>) -> Result<Designed> {
    if job.truth.is_none() {
        return Err(Error::choice(
            "dampid design",
            model_file.to_string(),
            "has no [simulation] section: its experiments are the candidates a design chooses from",
        ));
    }
    let settings = job.design.clone().unwrap_or_default();
    let report = select(
        &job.model,
        &job.records,
        &job.settings.regressor,
        &settings,
        progress,
    )?;
    Ok(Designed {
        title: job.title.clone(),
        selected_experiments: selected_experiments(&report, &job.experiments),
        selected_experiments_toml: selected_experiments_toml(&report, &job.experiments),
        report,
    })
}

/// The outcome of `dampid design`. Its JSON is the report's, with the selected
/// experiments as data and as TOML, so that it stands alone.
#[derive(Debug, Clone, PartialEq)]
pub struct Designed {
    /// The job's title.
    pub title: String,
    /// The design.
    pub report: DesignReport,
    /// The selected experiments as data.
    pub selected_experiments: Vec<SelectedExperiment>,
    /// The same as `[[simulation.experiments]]` blocks.
    pub selected_experiments_toml: String,
}

impl Serialize for Designed {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        let mut json = serde_json::to_value(&self.report).map_err(serde::ser::Error::custom)?;
        if let Some(object) = json.as_object_mut() {
            object.insert(
                "selected_experiments".into(),
                serde_json::to_value(&self.selected_experiments)
                    .map_err(serde::ser::Error::custom)?,
            );
            object.insert(
                "selected_experiments_toml".into(),
                serde_json::Value::String(self.selected_experiments_toml.clone()),
            );
        }
        json.serialize(serializer)
    }
}

impl fmt::Display for Designed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: the [simulation] coefficients are the nominal damping\n{}\n{}",
            self.title, self.report, self.selected_experiments_toml
        )
    }
}

impl Outcome for Designed {
    fn trusted(&self) -> bool {
        self.report.succeeded()
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
/// `experiments` are the job's ([`crate::model_file::Job::experiments`]), in candidate order. `dampid
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
