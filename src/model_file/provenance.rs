//! A job's provenance for reports ([`crate::report::provenance`]): the model file's text,
//! each data file's size and SHA-256, and every setting in effect, defaults included
//! (the settings structs as Rust writes them out, so no field is left out).

use std::path::Path;

use super::Job;
use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::prep::steady_state::SteadyStateSettings;
use crate::report::provenance::{COMMIT, DataFile, Provenance, VERSION, now_utc};

/// The identification settings in effect, defaults included, as a report's provenance
/// lists them (name, value): the regressor's, the fit's and the steady-state check's.
pub fn settings_in_effect(
    settings: &IdentifySettings,
    steady_state: &SteadyStateSettings,
) -> Vec<(String, String)> {
    vec![
        (
            "identification (windows, quadrature, velocity, noise)".into(),
            format!("{:#?}", settings.regressor),
        ),
        ("fit".into(), format!("{:#?}", settings.fit)),
        ("steady-state check".into(), format!("{steady_state:#?}")),
    ]
}

impl Job {
    /// The provenance of a report on this job read from `model_file`, with the command
    /// line's own settings `extra` (name, value) listed first.
    pub fn provenance(&self, model_file: &Path, extra: &[(String, String)]) -> Result<Provenance> {
        let model_text = std::fs::read_to_string(model_file).map_err(|e| Error::ModelFile {
            file: model_file.display().to_string(),
            line: 0,
            column: 0,
            message: e.to_string(),
            cause: None,
        })?;
        let data_files = self
            .data_files
            .iter()
            .map(|p| DataFile::read(p))
            .collect::<Result<Vec<_>>>()?;
        let mut settings: Vec<(String, String)> = extra.to_vec();
        settings.extend(settings_in_effect(&self.settings, &self.steady_state));
        if let Some(design) = &self.design {
            settings.push(("design".into(), format!("{design:#?}")));
        }
        if !self.units.is_empty() {
            settings.push(("units".into(), format!("{:#?}", self.units)));
        }
        Ok(Provenance {
            model_file: model_file.display().to_string(),
            model_text,
            data_files,
            arrays: Vec::new(),
            settings,
            version: VERSION.into(),
            commit: COMMIT.into(),
            date: now_utc(),
        })
    }
}
