//! `[string_simulation]`: records from the paper's string simulator (section 3.2.1),
//! one per load amplitude, sensed at the model file's `dofs` equally spaced points.

use std::collections::BTreeMap;

use super::records::{Truth, truth_of};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::record::Record;
use crate::simulate::SimSettings;
use crate::simulate::string::{StringSystem, simulate_string};

use super::spec::StringSimulationSpec;

/// Simulates every amplitude; progress counts records.
pub(super) fn string_records(
    spec: &StringSimulationSpec,
    model: &DampingModel,
    sensors: usize,
    progress: Progress<'_>,
) -> Result<(Vec<Record>, Truth)> {
    let truth = truth_of(&spec.coefficients, model)?;
    let value = |name: &str, role: &str| {
        lookup(&spec.coefficients, name).ok_or_else(|| Error::UnknownCoefficient {
            name: format!("{name} (the string's {role} damping)"),
            known: spec
                .coefficients
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", "),
        })
    };
    let linear_damping = value(&spec.linear, "linear")?;
    let quadratic_damping = value(&spec.quadratic, "quadratic")?;
    if spec.amplitudes.is_empty() {
        return Err(Error::Empty {
            what: "string_simulation.amplitudes".into(),
        });
    }
    let settings = SimSettings {
        step: spec.step,
        substeps: spec.substeps,
        transient_steps: spec.transient_steps,
        recorded_steps: spec.recorded_steps,
    };
    // Every record is held at once: the sensors' displacements and velocities and the
    // force channel.
    crate::budget::require_records(
        "the simulated string records",
        spec.amplitudes.len(),
        spec.recorded_steps,
        2 * sensors + 1,
        "reduce `recorded_steps` or the number of amplitudes",
    )?;
    let total = spec.amplitudes.len() as u64;
    spec.amplitudes
        .iter()
        .enumerate()
        .map(|(k, &amplitude)| {
            let system = StringSystem {
                tension: spec.tension,
                density: spec.density,
                length: spec.length,
                linear_damping,
                quadratic_damping,
                force_position: spec.force_position,
                amplitude,
                frequency: spec.frequency,
                modes: spec.modes,
                damping_points: spec.damping_points,
                sensors,
            };
            let record = simulate_string(&system, &settings);
            progress(k as u64 + 1, total);
            record
        })
        .collect::<Result<Vec<_>>>()
        .map(|records| (records, truth))
}

fn lookup(coefficients: &BTreeMap<String, f64>, name: &str) -> Option<f64> {
    coefficients.get(name).copied()
}
