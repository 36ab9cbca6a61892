//! Simulated records: `[simulation]`, with the true coefficients (measured ones are
//! read by `measured.rs`).

use std::collections::BTreeMap;

use faer::Mat;

use super::settings::one_based;
use super::spec::{MatrixRef, SimulationSpec};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::record::Record;
use crate::simulate::{
    ConservativeForce, HarmonicForce, SimSettings, System, simulate_with_progress,
};

pub(super) type Truth = Vec<(String, f64)>;

/// The true value of every coefficient of `model`, in model order, from a table that
/// must name each of them and nothing else.
pub(super) fn truth_of(
    coefficients: &BTreeMap<String, f64>,
    model: &DampingModel,
) -> Result<Truth> {
    let names = model.coefficient_names();
    for name in coefficients.keys() {
        if !names.contains(name) {
            return Err(Error::UnknownCoefficient {
                name: name.clone(),
                known: names.join(", "),
            });
        }
    }
    names
        .iter()
        .map(|name| {
            coefficients
                .get(name)
                .map(|v| (name.clone(), *v))
                .ok_or_else(|| {
                    Error::missing(
                        format!("simulation coefficient '{name}'"),
                        "[simulation] coefficients give the true value of every coefficient of the model",
                    )
                })
        })
        .collect()
}

/// Simulates every experiment; progress counts integration steps over all of them.
pub(super) fn simulate_records(
    spec: &SimulationSpec,
    model: &DampingModel,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
    progress: Progress<'_>,
) -> Result<(Vec<Record>, Truth)> {
    let truth = truth_of(&spec.coefficients, model)?;
    let one_based = |dof: usize, what: &str| one_based(dof, n, what);
    let conservative = spec
        .cubic_springs
        .iter()
        .map(|c| {
            Ok(ConservativeForce::Cubic {
                dof: one_based(c.dof, "cubic spring")?,
                coefficient: c.coefficient,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let settings = SimSettings {
        step: spec.step,
        substeps: spec.substeps,
        transient_steps: spec.transient_steps,
        recorded_steps: spec.recorded_steps,
    };
    let (mass, stiffness) = (matrix(&spec.mass)?, matrix(&spec.stiffness)?);
    let steps = spec.transient_steps.saturating_add(spec.recorded_steps) as u64;
    let total = steps.saturating_mul(spec.experiments.len() as u64);
    let records = spec
        .experiments
        .iter()
        .enumerate()
        .map(|(k, experiment)| {
            let e = experiment.get_ref();
            let system = System {
                mass: mass.clone(),
                stiffness: stiffness.clone(),
                damping: model.clone(),
                damping_coefficients: truth.iter().map(|(_, v)| *v).collect(),
                conservative: conservative.clone(),
                forcing: vec![HarmonicForce {
                    dof: one_based(e.force_dof, "experiment force")?,
                    amplitude: e.amplitude,
                    frequency: e.frequency,
                    phase: e.phase,
                }],
            };
            let offset = k as u64 * steps;
            let mut parts = simulate_with_progress(&system, &settings, &|done, _| {
                progress(offset + done, total)
            })?
            .into_parts();
            parts.label = format!("a={} ω={} on DOF {}", e.amplitude, e.frequency, e.force_dof);
            Record::new(parts)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((records, truth))
}
