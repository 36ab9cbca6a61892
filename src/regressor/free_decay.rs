//! Free-decay rows: the stored energy a mode's ringdown has lost since its first whole
//! cycle ([`crate::prep::free_decay`]), against the damping work done meanwhile.
//!
//! Over window i of whole cycles (t_i to t_{i+1}, crossings of the displacement),
//!
//! ```text
//!   Σ_k θ_k ∫_{t_i}^{t_{i+1}} v g_k(x, v) dt  =  E_i − E_{i+1},     E = ½ m v² + ½ m ω² x²,
//! ```
//!
//! m the modal mass and ω the window's own frequency; the columns are the damping terms'
//! work, integrated by the same kernel as every other row (the non-periodic mode's
//! [`window_row`] with the stored energy known: no force acts, and the known energy
//! change is the right-hand side).
//!
//! **Rows.** The energies are measured once per crossing, from the velocity there, and
//! consecutive windows share a crossing: as one row per window, neighbouring rows
//! would share an error with opposite signs. Summed from the record's first crossing,
//! row j (crossing j = 1 … J) is the energy lost since the start,
//!
//! ```text
//!   Σ_k θ_k W_k(t_j) + e_0  =  Ê_0 − Ê_j,     W_k(t_j) = Σ_{i<j} ∫_{t_i}^{t_{i+1}} v g_k dt,
//! ```
//!
//! whose errors are the independent errors e_j of the measured Ê_j, once the error e_0
//! of the start's own Ê_0 is a nuisance unknown (`start_energy[r]`, one per record r,
//! with the row 0 · θ + e_0 = 0 for the start itself). At a crossing x ≈ 0 and
//! δE = m v δv, so the error of Ê_j grows with the speed there: each row is divided by
//! |v_j| = √(2 Ê_j / m), making the rows' errors equal (weighted least squares).
//! Row j is labelled with crossing j's window index and time, and no whole periods: the
//! rows of a decay are not replicates of one steady state
//! ([`crate::analysis::replicates`]), each is an amplitude of its own.

use faer::Mat;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::free_decay::{DecaySettings, of_record};
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::Window;
use crate::record::Record;
use crate::regressor::kernel::{Plan, build_in_parallel};
use crate::regressor::nonperiodic::{Kinetic, Potential, Rule, StorageModel, window_row};
use crate::regressor::settings::WorkForm;
use crate::regressor::{Regressor, RowLabel, map_windows};

/// Builds the free-decay regressor of the modes' `records` (one DOF each, as
/// [`crate::prep::free_decay::isolate`] returns them).
pub(crate) fn build(
    model: &DampingModel,
    records: &[Record],
    decay: &DecaySettings,
    quadrature: Quadrature,
) -> Result<Regressor> {
    decay.validate()?;
    if records.is_empty() {
        return Err(Error::Empty {
            what: "record list".into(),
        });
    }
    let mut windows = Vec::new();
    let mut frequencies = Vec::new();
    // Window j of record r is entry offsets[r] + j of `windows` and `storage`.
    let mut offsets = Vec::with_capacity(records.len());
    for (index, record) in records.iter().enumerate() {
        offsets.push(windows.len());
        if record.dofs() != 1 || record.velocities().is_none() {
            return Err(Error::invalid(
                "free-decay record",
                record.dofs() as f64,
                &format!(
                    "record '{}' is not a mode's record (one DOF with its velocity): isolate it first (dampid::prep::free_decay::isolate)",
                    record.label()
                ),
            ));
        }
        model.validate(1)?;
        for (j, cycle) in of_record(record, decay).into_iter().enumerate() {
            windows.push(Window {
                record: index,
                index: j,
                start: cycle.start,
                span: (cycle.end - cycle.start) as f64 * record.step(),
                cycles: decay.cycles,
                closed: false,
            });
            frequencies.push(cycle.frequency);
        }
    }
    if windows.is_empty() {
        return Err(Error::Empty {
            what: "free-decay cycles (no record holds a whole cycle)".into(),
        });
    }
    let plans: Vec<Plan<'_>> = records.iter().map(|r| Plan::new(model, r)).collect();
    let storage: Vec<StorageModel> = frequencies
        .iter()
        .map(|omega| StorageModel {
            kinetic: Kinetic::Known(Mat::from_fn(1, 1, |_, _| decay.mass)),
            potential: Potential::Known(Mat::from_fn(1, 1, |_, _| decay.mass * omega * omega)),
            offsets: Vec::new(),
        })
        .collect();
    let mut columns = model.coefficient_names();
    let rows = map_windows(build_in_parallel(records, columns.len()), &windows, |w| {
        let rule = Rule {
            quadrature,
            velocity: VelocitySource::Measured,
            work_form: WorkForm::Velocity,
            storage: &storage[offsets[w.record] + w.index],
        };
        window_row(&plans[w.record], model, &records[w.record], w, &rule)
    })?;
    let p = columns.len();
    let width = p + records.len();
    let mut matrix: Vec<Vec<f64>> = Vec::with_capacity(windows.len() + records.len());
    let mut rhs = Vec::with_capacity(matrix.capacity());
    let mut labels = Vec::with_capacity(matrix.capacity());
    for (r, record) in records.iter().enumerate() {
        let cycles = of_record(record, decay);
        let Some(first) = cycles.first() else {
            continue;
        };
        let speed = |energy: f64| (2.0 * energy / decay.mass).sqrt();
        let time = |sample: usize| record.start_time() + sample as f64 * record.step();
        let mut row = vec![0.0; width];
        row[p + r] = 1.0 / speed(first.energy_start);
        matrix.push(row);
        rhs.push(0.0);
        labels.push(RowLabel {
            record: record.label().to_string(),
            record_index: r,
            window: 0,
            start_time: time(first.start),
            cycles: 0,
            frequency: None,
        });
        let (mut work, mut lost) = (vec![0.0; p], 0.0);
        for (j, cycle) in cycles.iter().enumerate() {
            let (columns, b) = &rows[offsets[r] + j];
            for (w, c) in work.iter_mut().zip(columns) {
                *w += c;
            }
            lost += b;
            let weight = 1.0 / speed(cycle.energy_end);
            let mut row: Vec<f64> = work.iter().map(|w| w * weight).collect();
            row.resize(width, 0.0);
            row[p + r] = weight;
            matrix.push(row);
            rhs.push(lost * weight);
            labels.push(RowLabel {
                record: record.label().to_string(),
                record_index: r,
                window: j + 1,
                start_time: time(cycle.end),
                // Not whole periods of one steady state: each row is an amplitude of its
                // own, never a replicate (crate::analysis::replicates).
                cycles: 0,
                frequency: None,
            });
        }
    }
    columns.extend((1..=records.len()).map(|r| format!("start_energy[{r}]")));
    let matrix = Mat::from_fn(matrix.len(), width, |i, k| matrix[i][k]);
    Regressor::from_parts(matrix, rhs, columns, labels)?.with_nuisance_count(records.len())
}
