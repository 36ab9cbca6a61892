//! `dampid backbones A.toml B.toml …`: ringdowns and one-mode stepped-sine tables of the
//! same mode, each identified once by the one pipeline ([`crate::identify::identify`],
//! with its model file's settings), their backbones ζ(X), f(X) side by side and each
//! job's fitted ζ against the first's at common amplitudes
//! ([`crate::analysis::backbones`]): text, JSON and an HTML page
//! ([`crate::report::html::backbones`]).
//!
//! A job that is neither a free decay nor a one-mode stepped-sine table, or a table whose
//! equivalent damping could not be computed, is refused ([`Error::Incomparable`]).

use std::fmt;

use serde::Serialize;

use super::Outcome;
use crate::analysis::backbones::{Backbones, JobBackbone, JobLabel, compare};
use crate::error::{Error, Result};
use crate::identify::{Equivalent, Identification, identify};
use crate::model_file::Job;
use crate::progress::Progress;

/// The outcome of `dampid backbones`: the comparison and whether every fit can be
/// trusted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ComparedBackbones {
    /// The backbones and the ratios.
    #[serde(flatten)]
    pub backbones: Backbones,
    /// Files whose fit is not usable (did not converge, or no rank).
    pub untrusted: Vec<String>,
}

/// One job's backbone from what identifying it found, or why it has none.
pub fn job_backbone(file: &str, job: &Job, found: &Identification) -> Result<JobBackbone> {
    let label = JobLabel {
        file: file.to_string(),
        title: job.title.clone(),
        length: job.units.length.clone(),
        time: job.units.time.clone(),
    };
    let refuse = |given: String, reason: &str| Error::Incomparable {
        files: file.to_string(),
        what: given,
        reason: reason.to_string(),
    };
    match (&found.backbone, &found.equivalent) {
        (Some(backbone), _) => Ok(JobBackbone::free_decay(label, backbone)),
        (None, Some(Equivalent::Computed(equivalent))) => {
            Ok(JobBackbone::stepped_sine(label, equivalent))
        }
        (None, Some(Equivalent::NotComputed { error })) => Err(refuse(
            "a one-mode stepped-sine table without equivalent damping".into(),
            &format!("its ζ_eq(X) was not computed ({error})"),
        )),
        (None, None) => Err(refuse(
            match &job.stepped_sine {
                Some(table) => format!("a stepped-sine table of {} DOFs", table.table.table.dofs()),
                None => "records of forced vibration".into(),
            },
            "a backbone needs one mode: a ringdown ([free_decay]) or a one-DOF stepped-sine table ([stepped_sine], dofs = 1)",
        )),
    }
}

/// Identifies each of `jobs` (model file name, job) with its own settings and compares
/// their backbones; `progress` counts jobs.
pub fn run(jobs: &[(String, Job)], progress: Progress<'_>) -> Result<ComparedBackbones> {
    let mut backbones = Vec::with_capacity(jobs.len());
    let mut untrusted = Vec::new();
    for (k, (file, job)) in jobs.iter().enumerate() {
        let found = identify(&job.problem(), &job.settings, &crate::progress::silent)?;
        if !found.report.is_usable() {
            untrusted.push(file.clone());
        }
        backbones.push(job_backbone(file, job, &found)?);
        progress(k as u64 + 1, jobs.len() as u64);
    }
    Ok(ComparedBackbones {
        backbones: compare(backbones)?,
        untrusted,
    })
}

impl ComparedBackbones {
    /// The HTML page.
    pub fn html(&self) -> Result<String> {
        crate::report::html::backbones::page(&self.backbones)
    }
}

impl fmt::Display for ComparedBackbones {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.backbones)?;
        for file in &self.untrusted {
            writeln!(
                f,
                "the fit of {file} is not usable: identify it alone to see why"
            )?;
        }
        Ok(())
    }
}

impl Outcome for ComparedBackbones {
    fn trusted(&self) -> bool {
        self.untrusted.is_empty()
    }
}
