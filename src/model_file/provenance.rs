//! A job's provenance for reports ([`crate::report::provenance`]): the model file's text,
//! each data file's size and SHA-256, and every setting in effect, defaults included:
//! one row per model-file key (docs/model-file.md) of `[identification]`,
//! `[non_periodic]`, `[design]` and `[units]`, its value in TOML form and whether the
//! model file set it (the value as written there) or it is the default (the value the
//! job runs with), then the fit's internal settings that no model-file key sets.

use std::path::Path;

use super::Job;
use super::settings::IDENTIFICATION_KEYS;
use crate::analysis::design::DesignSettings;
use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::prep::velocity::VelocitySource;
use crate::regressor::Windows;
use crate::report::provenance::{
    COMMIT, DataFile, Provenance, Setting, SettingSource, VERSION, now_utc,
};
use crate::report::units::Units;

impl Job {
    /// The provenance of a report on this job read from `model_file` and identified
    /// with `settings` (the job's, with what the command line changed), with the command
    /// line's own settings `extra` (name, value) listed first.
    pub fn provenance(
        &self,
        model_file: &Path,
        settings: &IdentifySettings,
        extra: &[(String, String)],
    ) -> Result<Provenance> {
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
        let file: toml::Table = toml::from_str(&model_text).unwrap_or_default();
        let in_effect = settings;
        let mut settings: Vec<Setting> = extra
            .iter()
            .map(|(key, value)| Setting {
                section: "command line".into(),
                key: key.clone(),
                value: value.clone(),
                source: SettingSource::CommandLine,
            })
            .collect();
        settings.extend(self.settings_in_effect(in_effect, &file));
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

/// `value` as TOML writes it (`"trapezoid"` for a string).
fn toml_text(value: impl Into<toml::Value>) -> String {
    value.into().to_string()
}

/// A serde enum's name (`Quadrature::Trapezoid` → `"trapezoid"`), as TOML writes it.
fn name_of(value: &impl serde::Serialize) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => toml_text(s),
        Ok(other) => other.to_string(),
        Err(_) => "–".into(),
    }
}

impl Job {
    /// Every model-file setting in effect: the file's value where it sets the key, else
    /// the job's (the default).
    fn settings_in_effect(&self, settings: &IdentifySettings, file: &toml::Table) -> Vec<Setting> {
        settings_in_effect(
            settings,
            self.design.as_ref(),
            &self.units,
            (file, SettingSource::ModelFile),
        )
    }
}

/// Every setting in effect, defaults included: one row per model-file key of
/// `[identification]`, `[non_periodic]` (when `given` has that section), `[design]` and
/// `[units]` (when given), then the fit's internal settings. `given` is the model file's
/// table, or the Python package's keywords laid out as one (`{"identification": {...},
/// "non_periodic": {...}}`); a key it holds is marked with its `source`, the others are
/// defaults. The values are those in effect (the settings'), as TOML writes them.
pub fn settings_in_effect(
    settings: &IdentifySettings,
    design: Option<&DesignSettings>,
    units: &Units,
    given: (&toml::Table, SettingSource),
) -> Vec<Setting> {
    let (file, set) = given;
    let steady_state = &settings.steady_state.unwrap_or_default();
    let mut rows = Vec::new();
    let section = |rows: &mut Vec<Setting>, name: &str, keys: Vec<(&str, String)>| {
        let written = file.get(name).and_then(toml::Value::as_table);
        for (key, default) in keys {
            let (value, source) = match written.and_then(|t| t.get(key)) {
                Some(v) => (v.to_string(), set),
                None => (default, SettingSource::Default),
            };
            rows.push(Setting {
                section: name.into(),
                key: key.into(),
                value,
                source,
            });
        }
    };
    let regressor = &settings.regressor;
    let fit = &settings.fit;
    let (velocity, harmonics) = match regressor.velocity {
        VelocitySource::Measured => ("measured", None),
        VelocitySource::CentralDifference => ("central_difference", None),
        VelocitySource::Spectral { harmonics } => ("spectral", Some(harmonics)),
        VelocitySource::HarmonicProjection { harmonics } => {
            ("harmonic_projection", Some(harmonics))
        }
    };
    let periodic_only = "– (does not apply: [non_periodic] windows)".to_string();
    let (cycles, windows, skip) = match &regressor.windows {
        Windows::Cycles(w) => (
            toml_text(w.cycles as i64),
            w.count
                .map_or("– (as many as fit)".into(), |n| toml_text(n as i64)),
            toml_text(w.skip as i64),
        ),
        Windows::Spans(w) => (
            periodic_only.clone(),
            periodic_only.clone(),
            toml_text(w.skip as i64),
        ),
        Windows::Decay(d) => (
            toml_text(d.cycles as i64),
            "– (every whole cycle above the noise floor: [free_decay])".into(),
            "– (does not apply: [free_decay] start)".into(),
        ),
    };
    let none = || "– (none)".to_string();
    let constraints = &fit.constraints;
    let identification: Vec<(&str, String)> = IDENTIFICATION_KEYS
        .iter()
        .map(|&key| {
            let value = match key {
                "quadrature" => name_of(&regressor.quadrature),
                "velocity" => toml_text(velocity),
                "harmonics" => match harmonics {
                    Some(Some(k)) => toml_text(k as i64),
                    Some(None) => "– (chosen from the data: the noise floor)".into(),
                    None => "– (does not apply to this velocity source)".into(),
                },
                "noise" => name_of(&regressor.noise),
                "weighting" => name_of(&fit.weighting),
                "work_form" => name_of(&regressor.work_form),
                "cycles" => cycles.clone(),
                "windows" => windows.clone(),
                "skip" => skip.clone(),
                "nonnegative" => toml_text(constraints.nonnegative),
                "bounds" if constraints.bounds.is_empty() => none(),
                "fixed" if constraints.fixed.is_empty() => none(),
                "constraints" if constraints.linear.is_empty() => none(),
                "max_energy_mismatch" => toml_text(steady_state.max_energy_mismatch),
                "max_state_mismatch" => toml_text(steady_state.max_state_mismatch),
                "accept_transient" => toml_text(steady_state.accept_transient),
                "accept_negative_work" => toml_text(fit.accept_negative_work),
                _ => "– (see the model file)".into(),
            };
            (key, value)
        })
        .collect();
    section(&mut rows, "identification", identification);
    // `--accept-transient` overrides the file: the value in effect is the job's.
    if steady_state.accept_transient
        && let Some(row) = rows
            .iter_mut()
            .find(|r| r.section == "identification" && r.key == "accept_transient")
        && row.value != "true"
    {
        row.value = "true".into();
        row.source = SettingSource::CommandLine;
    }
    if file.contains_key("non_periodic") {
        section(
            &mut rows,
            "non_periodic",
            vec![
                ("window", "– (required)".into()),
                ("mass", toml_text("each_dof")),
                ("stiffness", toml_text("none")),
                ("offsets", none()),
                ("high_pass", none()),
            ],
        );
    }
    if let Some(design) = design {
        section(
            &mut rows,
            "design",
            vec![
                ("criterion", name_of(&design.criterion)),
                ("picks", toml_text(design.picks as i64)),
                (
                    "start",
                    if design.start.is_empty() {
                        none()
                    } else {
                        toml_text(
                            design
                                .start
                                .iter()
                                .map(|&k| toml::Value::from(k as i64 + 1))
                                .collect::<Vec<_>>(),
                        )
                    },
                ),
                (
                    "target_condition",
                    design.target_condition.map_or_else(none, toml_text),
                ),
            ],
        );
    }
    if !units.is_empty() {
        let dimensions = [
            ("length", &units.length),
            ("force", &units.force),
            ("time", &units.time),
            ("angle", &units.angle),
            ("mass", &units.mass),
        ];
        section(
            &mut rows,
            "units",
            dimensions
                .iter()
                .map(|(d, u)| (*d, (*u).clone().map_or_else(none, toml_text)))
                .collect(),
        );
    }
    let internal = "fit (not in model files)";
    for (key, value) in [
        ("rank_tolerance", toml_text(fit.rank_tolerance)),
        ("solver.tolerance", toml_text(fit.solver.tolerance)),
        (
            "solver.max_iterations",
            toml_text(i64::from(fit.solver.max_iterations)),
        ),
        ("solver.polish", toml_text(fit.solver.polish)),
        (
            "steady_state.noise_sigmas",
            toml_text(steady_state.noise_sigmas),
        ),
    ] {
        rows.push(Setting {
            section: internal.into(),
            key: key.into(),
            value,
            source: SettingSource::Default,
        });
    }
    rows
}
