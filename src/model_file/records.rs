//! Simulated records: `[simulation]`, with the true coefficients (measured ones are
//! read by `measured.rs`), and optional sensor noise: with `noise = ε`, every recorded
//! channel c (each displacement, velocity and force column) gets independent Gaussian
//! samples of standard deviation σ_c = ε·RMS(c), RMS(c) = √(Σ_i c_i²/N), drawn from one
//! generator seeded by `noise_seed`, channel after channel in record order.

use std::collections::BTreeMap;

use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use super::settings::one_based;
use super::spec::{MatrixRef, SimulationSpec};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::record::Record;
use crate::simulate::{ConservativeForce, HarmonicForce, SimSettings, System, simulate};

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
    // Every record is held at once: x and v of n DOFs and one force channel each.
    crate::budget::require_records(
        "the simulated records",
        spec.experiments.len(),
        spec.recorded_steps,
        2 * n + 1,
        "reduce `recorded_steps` or the number of experiments",
    )?;
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
            let mut parts = simulate(&system, &settings, &|done, _| {
                progress(offset + done, total)
            })?
            .into_parts();
            parts.label = format!("a={} ω={} on DOF {}", e.amplitude, e.frequency, e.force_dof);
            Record::new(parts)
        })
        .collect::<Result<Vec<_>>>()?;
    let records = match spec.noise {
        None => records,
        Some(level) => with_noise(records, level, spec.noise_seed)?,
    };
    Ok((records, truth))
}

/// `records` with Gaussian noise of `level` times each channel's RMS (module doc).
fn with_noise(records: Vec<Record>, level: f64, seed: u64) -> Result<Vec<Record>> {
    if !(level.is_finite() && level >= 0.0) {
        return Err(Error::invalid(
            "noise",
            level,
            "must be a finite fraction ≥ 0 of each channel's RMS (0.01 is 1%)",
        ));
    }
    let mut rng = StdRng::seed_from_u64(seed);
    let mut add = |m: &mut Mat<f64>| {
        for j in 0..m.ncols() {
            let rms =
                (m.col(j).iter().map(|x| x * x).sum::<f64>() / m.nrows().max(1) as f64).sqrt();
            // σ ≥ 0 and finite: simulated records are finite (Record::new checks them).
            let Ok(normal) = Normal::new(0.0, level * rms) else {
                continue;
            };
            for i in 0..m.nrows() {
                m[(i, j)] += normal.sample(&mut rng);
            }
        }
    };
    records
        .into_iter()
        .map(|record| {
            let mut parts = record.into_parts();
            add(&mut parts.displacements);
            if let Some(v) = parts.velocities.as_mut() {
                add(v);
            }
            add(&mut parts.forcing.signals);
            Record::new(parts)
        })
        .collect()
}
