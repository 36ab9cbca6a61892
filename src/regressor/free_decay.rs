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
//!
//! **Trials.** Everything but the damping columns is the same at every trial of an
//! estimated exponent: the cycles, windows, quadrature weights, stored energies and row
//! weights are made once ([`PreparedDecay`], kept across the trials of a
//! [`crate::regressor::ParametricRegressor`]), and a power law's |v|^q is summed from
//! ln|v| made once per record (`kernel/log_speed.rs`): one exponential per sample and
//! trial instead of a `powf`.

use std::sync::{Arc, Mutex, OnceLock};

use faer::Mat;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::free_decay::{DecayCycle, DecaySettings, of_record};
use crate::prep::quadrature::{Quadrature, WindowWeights};
use crate::prep::window::Window;
use crate::record::{Record, col};
use crate::regressor::kernel::{Plan, WindowSamples, build_in_parallel, log_speed};
use crate::regressor::nonperiodic::{Endpoints, Kinetic, Potential, StorageModel};
use crate::regressor::{Regressor, Row, RowLabel, map_windows};
use crate::terms::{PowerForm, Term};

/// Builds the free-decay regressor of the modes' `records` (one DOF each, as
/// [`crate::prep::free_decay::isolate`] returns them).
pub(crate) fn build(
    model: &DampingModel,
    records: &[Record],
    decay: &DecaySettings,
    quadrature: Quadrature,
) -> Result<Regressor> {
    PreparedDecay::new(records, decay, quadrature)?.regressor(model, records)
}

/// The free-decay regressor of `records` from the part kept in `cache` when it was made
/// for these records and settings, else from a part made now and kept there.
pub(crate) fn build_cached(
    model: &DampingModel,
    records: &[Record],
    decay: &DecaySettings,
    quadrature: Quadrature,
    cache: &DecayCache,
) -> Result<Regressor> {
    let prepared = {
        // A poisoned lock only means another trial panicked; the kept part is whole.
        let mut kept = cache
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match kept.as_ref() {
            Some(p) if p.made_for(records, decay, quadrature) => Arc::clone(p),
            _ => {
                let made = Arc::new(PreparedDecay::new(records, decay, quadrature)?);
                *kept = Some(Arc::clone(&made));
                made
            }
        }
    };
    prepared.regressor(model, records)
}

/// The η-independent part of a free-decay regressor, kept across the trials of one
/// problem (empty until the first free-decay build).
#[derive(Debug, Default, Clone)]
pub struct DecayCache(Arc<Mutex<Option<Arc<PreparedDecay>>>>);

/// One window's equation before the damping columns: its window, quadrature weights
/// and the stored energy it loses.
#[derive(Debug)]
struct DecayWindow {
    window: Window,
    count: usize,
    weights: WindowWeights,
    /// E_end − E_start (the known change of stored energy).
    known: f64,
}

/// One record's cycles and where its windows start in [`PreparedDecay::windows`].
#[derive(Debug)]
struct DecayRecord {
    cycles: Vec<DecayCycle>,
    offset: usize,
    /// ln|v| of every sample, made at the first build whose model has a power law.
    log_speed: OnceLock<Vec<f64>>,
}

/// What every build of a free-decay regressor over the same records shares (module doc,
/// **Trials**).
#[derive(Debug)]
pub struct PreparedDecay {
    decay: DecaySettings,
    quadrature: Quadrature,
    /// The records' address and count, to tell whether a build reads the same ones.
    source: (usize, usize),
    records: Vec<DecayRecord>,
    windows: Vec<DecayWindow>,
}

impl PreparedDecay {
    /// The cycles, windows, weights and stored energies of `records`.
    fn new(records: &[Record], decay: &DecaySettings, quadrature: Quadrature) -> Result<Self> {
        decay.validate()?;
        if records.is_empty() {
            return Err(Error::Empty {
                what: "record list".into(),
            });
        }
        let mut windows = Vec::new();
        let mut prepared = Vec::with_capacity(records.len());
        for (index, record) in records.iter().enumerate() {
            let Some(v) = record.velocities().filter(|_| record.dofs() == 1) else {
                return Err(Error::invalid(
                    "free-decay record",
                    record.dofs() as f64,
                    &format!(
                        "record '{}' is not a mode's record (one DOF with its velocity): isolate it first (dampid::prep::free_decay::isolate)",
                        record.label()
                    ),
                ));
            };
            let x = record.displacements();
            let cycles = of_record(record, decay);
            prepared.push(DecayRecord {
                cycles: cycles.clone(),
                offset: windows.len(),
                log_speed: OnceLock::new(),
            });
            for (j, cycle) in cycles.into_iter().enumerate() {
                let window = Window {
                    record: index,
                    index: j,
                    start: cycle.start,
                    span: (cycle.end - cycle.start) as f64 * record.step(),
                    cycles: decay.cycles,
                    closed: false,
                };
                let count = (window.span / record.step()).round() as usize + 1;
                // The rectangular rule reads L samples; the end sample is still needed
                // for its state.
                let weights = quadrature
                    .window_weights(window.span, record.step(), window.span)?
                    .padded_to(count);
                let omega = cycle.frequency;
                let storage = StorageModel {
                    kinetic: Kinetic::Known(Mat::from_fn(1, 1, |_, _| decay.mass)),
                    potential: Potential::Known(Mat::from_fn(1, 1, |_, _| {
                        decay.mass * omega * omega
                    })),
                    offsets: Vec::new(),
                };
                let end = window.start + count - 1;
                let (_, known) = storage.columns(&Endpoints {
                    x_start: &[x[(window.start, 0)]],
                    x_end: &[x[(end, 0)]],
                    v_start: &[v[(window.start, 0)]],
                    v_end: &[v[(end, 0)]],
                });
                windows.push(DecayWindow {
                    window,
                    count,
                    weights,
                    known,
                });
            }
        }
        if windows.is_empty() {
            return Err(Error::Empty {
                what: "free-decay cycles (no record holds a whole cycle)".into(),
            });
        }
        Ok(PreparedDecay {
            decay: *decay,
            quadrature,
            source: (records.as_ptr() as usize, records.len()),
            records: prepared,
            windows,
        })
    }

    /// Whether this part was made for `records` with these settings.
    fn made_for(&self, records: &[Record], decay: &DecaySettings, quadrature: Quadrature) -> bool {
        self.source == (records.as_ptr() as usize, records.len())
            && self.decay == *decay
            && self.quadrature == quadrature
    }

    /// The regressor of `model` on `records` (the records this part was made from).
    fn regressor(&self, model: &DampingModel, records: &[Record]) -> Result<Regressor> {
        let decay = &self.decay;
        let rows = self.window_rows(model, records)?;
        let mut columns = model.coefficient_names();
        let p = columns.len();
        let width = p + records.len();
        let mut matrix: Vec<Vec<f64>> = Vec::with_capacity(rows.len() + records.len());
        let mut rhs = Vec::with_capacity(matrix.capacity());
        let mut labels = Vec::with_capacity(matrix.capacity());
        for (r, record) in records.iter().enumerate() {
            let cycles = &self.records[r].cycles;
            let Some(first) = cycles.first() else {
                continue;
            };
            let offset = self.records[r].offset;
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
                let (columns, b) = &rows[offset + j];
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
                    // Not whole periods of one steady state: each row is an amplitude of
                    // its own, never a replicate (crate::analysis::replicates).
                    cycles: 0,
                    frequency: None,
                });
            }
        }
        columns.extend((1..=records.len()).map(|r| format!("start_energy[{r}]")));
        let matrix = Mat::from_fn(matrix.len(), width, |i, k| matrix[i][k]);
        Regressor::from_parts(matrix, rhs, columns, labels)?.with_nuisance_count(records.len())
    }

    /// One row per window, in window order: the damping work of each coefficient over
    /// the window, and the stored energy it loses (the kernel's row of `window_row` with
    /// its stored energy known, the power laws summed from ln|v|).
    fn window_rows(&self, model: &DampingModel, records: &[Record]) -> Result<Vec<Row>> {
        model.validate(1)?;
        let has_power_law = model.terms().iter().any(|t| match t {
            Term::Elements(t) => matches!(t.law().power_form(), Some(PowerForm::AbsPow(_))),
            _ => false,
        });
        let plans: Vec<Plan<'_>> = records.iter().map(|r| Plan::new(model, r)).collect();
        let logs: Vec<&[f64]> = records
            .iter()
            .zip(&self.records)
            .map(|(record, prepared)| match record.velocities() {
                Some(v) if has_power_law => prepared
                    .log_speed
                    .get_or_init(|| log_speed(col(v, 0)))
                    .as_slice(),
                _ => &[][..],
            })
            .collect();
        let windows: Vec<Window> = self.windows.iter().map(|w| w.window).collect();
        let columns = model.coefficient_count();
        map_windows(build_in_parallel(records, columns), &windows, |w| {
            let record = &records[w.record];
            let prepared = &self.windows[self.records[w.record].offset + w.index];
            let count = prepared.count;
            let v = record
                .velocities()
                .ok_or_else(|| Error::MissingVelocities {
                    record: record.label().to_string(),
                })?
                .subrows(w.start, count);
            let samples = WindowSamples {
                x: record.displacements().subrows(w.start, count),
                v,
                signals: record.forcing().signals.as_ref().subrows(w.start, count),
                weights: &prepared.weights,
            };
            let log = logs[w.record];
            let log = if log.is_empty() {
                log
            } else {
                &log[w.start..w.start + count]
            };
            let (row, input) = plans[w.record].row_from_logs(&samples, &[log]);
            Ok((row, input - prepared.known))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::velocity::VelocitySource;
    use crate::record::{Forcing, RecordParts};
    use crate::regressor::nonperiodic::{Rule, window_row};
    use crate::regressor::settings::WorkForm;
    use crate::terms::laws::{Coulomb, PowerLaw, Quadratic};
    use crate::terms::{Coefficients, Term};

    /// A mode's record: x = X e^{−ζωt} sin ωt with its exact velocity, 80 cycles.
    fn mode_record() -> Record {
        let (omega, zeta, h) = (2.0 * std::f64::consts::PI, 0.01, 1.0 / 64.0);
        let n = 80 * 64;
        let x = |t: f64| 1e-3 * (-zeta * omega * t).exp() * (omega * t).sin();
        let v = |t: f64| {
            1e-3 * (-zeta * omega * t).exp()
                * (omega * (omega * t).cos() - zeta * omega * (omega * t).sin())
        };
        Record::new(RecordParts {
            label: "mode".into(),
            step: h,
            start_time: 0.0,
            displacements: Mat::from_fn(n, 1, |i, _| x(i as f64 * h - 0.3 * h)),
            velocities: Some(Mat::from_fn(n, 1, |i, _| v(i as f64 * h - 0.3 * h))),
            forcing: Forcing::on_dofs(Mat::zeros(n, 0), Vec::new()),
            period: 1.0,
        })
        .expect("a valid record")
    }

    /// Each window's row from the kept part (power laws from ln|v|) is the kernel's row
    /// of the same window (`window_row`, |v|^q by `powf`): bitwise for the closed forms
    /// other than a power, to a few ε for the power law, for both rules.
    #[test]
    fn window_rows_are_the_kernels_rows() {
        let record = mode_record();
        let model = DampingModel::new()
            .with(Term::per_dof(
                PowerLaw::new(1.0).unwrap(),
                1,
                Coefficients::Shared("c".into()),
            ))
            .with(Term::per_dof(
                PowerLaw::new(1.37).unwrap(),
                1,
                Coefficients::Shared("d".into()),
            ))
            .with(Term::per_dof(
                Quadratic,
                1,
                Coefficients::Shared("q".into()),
            ))
            .with(Term::per_dof(Coulomb, 1, Coefficients::Shared("mu".into())))
            .with(Term::viscous("v", Mat::identity(1, 1)));
        let records = [record];
        for quadrature in [Quadrature::Trapezoid, Quadrature::Rectangular] {
            let decay = DecaySettings::unit_mass();
            let prepared = PreparedDecay::new(&records, &decay, quadrature).unwrap();
            assert!(
                prepared.windows.len() > 70,
                "{} windows",
                prepared.windows.len()
            );
            let rows = prepared.window_rows(&model, &records).unwrap();
            let plan = Plan::new(&model, &records[0]);
            for (w, (row, b)) in prepared.windows.iter().zip(&rows) {
                let storage = StorageModel {
                    kinetic: Kinetic::Known(Mat::from_fn(1, 1, |_, _| 1.0)),
                    potential: Potential::Known(Mat::from_fn(1, 1, |_, _| {
                        let omega = prepared.records[0].cycles[w.window.index].frequency;
                        omega * omega
                    })),
                    offsets: Vec::new(),
                };
                let rule = Rule {
                    quadrature,
                    velocity: VelocitySource::Measured,
                    work_form: WorkForm::Velocity,
                    storage: &storage,
                };
                let (kernel, kernel_b) =
                    window_row(&plan, &model, &records[0], &w.window, &rule).unwrap();
                assert_eq!(b.to_bits(), kernel_b.to_bits(), "stored energy");
                assert_eq!(row[2].to_bits(), kernel[2].to_bits(), "quadratic");
                assert_eq!(row[3].to_bits(), kernel[3].to_bits(), "Coulomb");
                assert_eq!(row[4].to_bits(), kernel[4].to_bits(), "viscous matrix");
                for k in 0..2 {
                    let relative = (row[k] - kernel[k]).abs() / kernel[k].abs();
                    assert!(relative < 1e-14, "column {k}: {} vs {}", row[k], kernel[k]);
                }
            }
        }
    }

    /// A build through the cache equals a build afresh, at every exponent, and the cache
    /// is remade for other settings.
    #[test]
    fn cached_builds_are_fresh_builds() {
        let records = [mode_record()];
        let model = |p: f64| {
            DampingModel::new()
                .with(Term::viscous("c", Mat::identity(1, 1)))
                .with(Term::per_dof(
                    PowerLaw::new(p).unwrap(),
                    1,
                    Coefficients::Shared("d".into()),
                ))
        };
        let cache = DecayCache::default();
        for (cycles, p) in [(1, 1.5), (1, 2.5), (2, 2.5), (1, 0.5)] {
            let decay = DecaySettings {
                cycles,
                ..DecaySettings::unit_mass()
            };
            let q = Quadrature::Trapezoid;
            let cached = build_cached(&model(p), &records, &decay, q, &cache).unwrap();
            let fresh = build(&model(p), &records, &decay, q).unwrap();
            assert_eq!(cached.matrix(), fresh.matrix());
            assert_eq!(cached.rhs(), fresh.rhs());
            let kept = cache.0.lock().unwrap();
            assert_eq!(kept.as_ref().unwrap().decay.cycles, cycles);
        }
    }
}
