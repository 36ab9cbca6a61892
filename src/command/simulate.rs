//! `dampid simulate --out DIR`: a model file's `[simulation]` records written as CSV
//! files with a `[data]` stub and a manifest ([`crate::io::run`]), so that a simulated
//! run can be identified as measured data.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::Outcome;
use crate::error::{Error, Result};
use crate::io::output::Overwrite;
use crate::model_file::Job;

/// The files a simulation run wrote.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Simulated {
    /// Each record's file with the record's label and period, in record order.
    pub records: Vec<(PathBuf, String, f64)>,
    /// The `[data]` stub and the manifest.
    pub stub: Option<PathBuf>,
    /// The run's manifest.
    pub manifest: Option<PathBuf>,
    /// Files of an earlier run that were removed.
    pub removed: Vec<PathBuf>,
    /// Temporary files of an interrupted run that were removed.
    pub stale: Vec<PathBuf>,
}

/// Writes the records `job` simulated (from the file `model_file`) into `folder`.
pub fn run(job: &Job, model_file: &str, folder: &Path, overwrite: Overwrite) -> Result<Simulated> {
    if job.truth.is_none() {
        return Err(Error::choice(
            "dampid simulate",
            model_file.to_string(),
            "has no [simulation] section: nothing to simulate",
        ));
    }
    // Ctrl-C after the last simulation step: still nothing written.
    crate::cancel::check("simulate --out")?;
    let run = crate::io::run::write_run(folder, &job.source_records, model_file, overwrite)?;
    let records = run
        .written
        .iter()
        .zip(job.source_records.iter())
        .map(|(file, record)| (file.clone(), record.label().to_string(), record.period()))
        .collect();
    let (stub, manifest) = match run.written.as_slice() {
        [.., stub, manifest] if run.written.len() > job.source_records.len() => {
            (Some(stub.clone()), Some(manifest.clone()))
        }
        _ => (None, None),
    };
    Ok(Simulated {
        records,
        stub,
        manifest,
        removed: run.removed,
        stale: run.stale,
    })
}

impl fmt::Display for Simulated {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (file, label, period) in &self.records {
            writeln!(f, "{} ({label}, period {period:.6})", file.display())?;
        }
        if let Some(stub) = &self.stub {
            writeln!(
                f,
                "{} (the records as a [data] section for a model file)",
                stub.display()
            )?;
        }
        if let Some(manifest) = &self.manifest {
            writeln!(f, "{} (this run's records)", manifest.display())?;
        }
        Ok(())
    }
}

impl Outcome for Simulated {
    fn notices(&self) -> Vec<String> {
        self.removed
            .iter()
            .map(|p| format!("removed {} (an earlier run's record)", p.display()))
            .chain(self.stale.iter().map(|p| super::stale_notice(p)))
            .collect()
    }
}
