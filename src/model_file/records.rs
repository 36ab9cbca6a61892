//! Where a model file's records come from: `[simulation]` (with the true
//! coefficients) or `[[data.records]]` (columns of a data file, DOFs 1-based, the
//! period given or detected from the force).

use std::collections::BTreeMap;
use std::path::Path;

use faer::Mat;

use super::settings::one_based;
use super::spec::{MatrixRef, RecordSpec, SimulationSpec};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::period::{PeriodEstimate, detect_period};
use crate::progress::Progress;
use crate::record::{Forcing, Record, RecordParts};
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

/// Reads one record; a `periodic` record without a period or frequency gets one detected
/// from its force, a non-periodic one gets its duration (which nothing uses). Also
/// returns the jitter of its time column, when it has one.
pub(super) fn read_record(
    spec: &RecordSpec,
    n: usize,
    base: &Path,
    periodic: bool,
) -> Result<(Record, Option<PeriodEstimate>, Option<f64>)> {
    let path = base.join(&spec.file);
    let table = crate::io::read_table(&path)?;
    if spec.displacements.len() != n {
        return Err(Error::mismatch(
            "displacement columns vs dofs",
            n,
            spec.displacements.len(),
        ));
    }
    let (step, jitter) = match (&spec.time, spec.step) {
        (Some(time), None) => {
            let time = table.uniform_step(time)?;
            (time.step, Some(time.jitter))
        }
        (None, Some(step)) => (step, None),
        (time, _) => {
            let given = if time.is_some() {
                "both `time` and `step`"
            } else {
                "neither `time` nor `step`"
            };
            return Err(Error::choice(
                "step",
                given,
                "give exactly one of `time` (a column) or `step`",
            ));
        }
    };
    let columns = |names: &[String]| table.matrix(names);
    let displacements = columns(&spec.displacements)?;
    let velocities = spec.velocities.as_deref().map(columns).transpose()?;
    let force_names: Vec<String> = spec.forces.iter().map(|f| f.column.clone()).collect();
    let dofs = spec
        .forces
        .iter()
        .map(|f| {
            f.dof
                .checked_sub(1)
                .filter(|d| *d < n)
                .ok_or_else(|| Error::DofOutOfRange {
                    what: format!("force column '{}'", f.column),
                    dof: f.dof,
                    dofs: n,
                })
        })
        .collect::<Result<Vec<_>>>()?;
    let start_time = spec
        .time
        .as_deref()
        .map_or(Ok(0.0), |t| table.column(t).map(|c| c[0]))?;
    let label = spec.label.clone().unwrap_or_else(|| spec.file.clone());
    let signals = columns(&force_names)?;
    let (period, detected) = match (spec.period, spec.frequency) {
        (Some(period), None) => (period, None),
        (None, Some(omega)) => (2.0 * std::f64::consts::PI / omega, None),
        (None, None) if !periodic => (step * (signals.nrows().max(2) - 1) as f64, None),
        (None, None) => {
            let estimate = detect_period(signals.as_ref(), step, &label)?;
            (estimate.period, Some(estimate))
        }
        (Some(period), Some(_)) => {
            return Err(Error::invalid(
                "period",
                period,
                "give at most one of `period` or `frequency` (rad per unit time); with neither, the period is detected from the force",
            ));
        }
    };
    let record = Record::new(RecordParts {
        label,
        step,
        start_time,
        displacements,
        velocities,
        forcing: Forcing::on_dofs(signals, dofs),
        period,
    })?
    .with_channel_names(force_names)?;
    Ok((record, detected, jitter))
}
