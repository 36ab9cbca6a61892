//! Energy balance over records that are not periodic: transients, random or closed-loop
//! excitation, drives that stop and start.
//!
//! Over whole periods of a steady response the stored energy returns to its start and
//! drops out of the balance. Over any other window [t_a, t_b] it does not, so its change
//! joins the unknowns. Multiplying M ẍ + ∇V(x) + Q_d(x, ẋ) + f = r by ẋᵀ and integrating:
//!
//! ```text
//!   Σ_j θ_j ∫ φ_j dt  +  Σ_i m_i ½[v_i²]  +  Σ_e k_e ½[δ_e²]  +  Σ_i f_i [x_i]  =  ∫ vᵀ r dt
//!   (damping terms)      (lumped masses)     (linear springs)     (constant forces)
//! ```
//!
//! with [g] = g(t_b) − g(t_a), φ_j the damping terms' power (as in the periodic
//! regressor) and f a constant force on the left-hand side (weight, preload, a bias of
//! the force sensor). Known M or K move their stored energy to the right-hand side
//! instead ([`Kinetic::Known`], [`Potential::Known`]). One equation per window; the
//! windows are consecutive and share their end samples, so their sum is the balance
//! over the whole record and no sample is used twice inside an integral.
//!
//! The stored-energy and offset coefficients are nuisance parameters: they make the
//! balance hold, and an estimated mass near the known one is a sanity check of the
//! data, but the fit reports them apart from the damping coefficients
//! ([`crate::report::FitReport::nuisance`]). Nonnegativity constraints apply to the
//! damping coefficients only.
//!
//! When to use it: when the records are not in steady periodic motion (the steady-state
//! check rejects their windows, there is no driving period, or the drive stops and
//! starts). Periodic data are better served by the periodic mode: its equations have
//! no stored-energy unknowns, so the same data determine the damping better. The
//! window length trades the two: long windows average the damping work over more
//! motion, but give fewer equations. The velocity at each window's ends enters the
//! kinetic column directly, so measured or finite-difference velocities are used (a
//! harmonic projection needs a period).

mod storage;

pub use storage::{Kinetic, Potential, StorageModel};

use faer::Mat;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::Window;
use crate::record::Record;
use crate::regressor::derivative_free;
use crate::regressor::kernel::{Plan, WindowSamples, build_in_parallel};
use crate::regressor::{Regressor, RowLabel, WorkForm};
use storage::Endpoints;

/// How non-periodic records are cut into windows and what stores energy.
#[derive(Debug, Clone, PartialEq)]
pub struct NonPeriodicSettings {
    /// Window length in time units (rounded to whole sample steps of each record).
    pub window: f64,
    /// Samples to skip at the start of each record.
    pub skip: usize,
    /// Rectangular or trapezoid (a spectral rule needs a period).
    pub quadrature: Quadrature,
    /// Measured or central-difference velocities.
    pub velocity: VelocitySource,
    /// Velocity-weighted or derivative-free input and Coulomb work.
    pub work_form: WorkForm,
    /// Kinetic and potential energy and constant forces.
    pub storage: StorageModel,
}

impl NonPeriodicSettings {
    /// Windows of `window` time units, trapezoid rule, central-difference velocities,
    /// an unknown lumped mass per DOF and no springs or constant forces.
    pub fn new(window: f64) -> Self {
        NonPeriodicSettings {
            window,
            skip: 0,
            quadrature: Quadrature::Trapezoid,
            velocity: VelocitySource::CentralDifference,
            work_form: WorkForm::Velocity,
            storage: StorageModel::default(),
        }
    }

    /// Checks the settings themselves (not against a record).
    pub fn validate(&self) -> Result<()> {
        if !(self.window.is_finite() && self.window > 0.0) {
            return Err(Error::invalid(
                "window",
                self.window,
                "the window length must be finite and positive",
            ));
        }
        if self.quadrature == Quadrature::Spectral {
            return Err(Error::invalid(
                "quadrature",
                f64::NAN,
                "a spectral rule integrates whole periods; non-periodic windows take `trapezoid` or `rectangular`",
            ));
        }
        if !matches!(
            self.velocity,
            VelocitySource::Measured | VelocitySource::CentralDifference
        ) {
            return Err(Error::invalid(
                "velocity",
                f64::NAN,
                &format!(
                    "{:?} needs a driving period; non-periodic windows take `measured` or `central_difference` velocities",
                    self.velocity
                ),
            ));
        }
        Ok(())
    }

    /// The windows of `record`: consecutive, L = round(window/h) steps each, sharing
    /// their end samples, as many as fit after `skip`.
    fn windows(&self, record: &Record, record_index: usize) -> Result<Vec<Window>> {
        let steps = (self.window / record.step()).round();
        if steps < 1.0 {
            return Err(Error::invalid(
                "window",
                self.window,
                &format!(
                    "is shorter than one sample step h = {} of record '{}'",
                    record.step(),
                    record.label()
                ),
            ));
        }
        let length = steps as usize;
        let span = length as f64 * record.step();
        let last = record.samples() - 1;
        let count = last.saturating_sub(self.skip) / length;
        if count == 0 || self.skip >= last {
            return Err(Error::RecordTooShort {
                record: record.label().to_string(),
                needed: self.skip.saturating_add(length).saturating_add(1),
                available: record.samples(),
            });
        }
        Ok((0..count)
            .map(|index| Window {
                record: record_index,
                index,
                start: self.skip + index * length,
                span,
                cycles: 0,
            })
            .collect())
    }
}

/// Builds the non-periodic regressor: the damping model's columns, then the nuisance
/// columns of `settings.storage` ([`Regressor::nuisance_count`]), one row per window.
pub fn build(
    model: &DampingModel,
    records: &[Record],
    settings: &NonPeriodicSettings,
) -> Result<Regressor> {
    settings.validate()?;
    let Some(first) = records.first() else {
        return Err(Error::Empty {
            what: "record list".into(),
        });
    };
    let dofs = first.dofs();
    for record in records {
        if record.dofs() != dofs {
            return Err(Error::mismatch(
                format!("DOFs of record '{}' vs the first", record.label()),
                dofs,
                record.dofs(),
            ));
        }
    }
    model.validate(dofs)?;
    settings.storage.validate(dofs)?;
    let mut windows = Vec::new();
    for (index, record) in records.iter().enumerate() {
        windows.extend(settings.windows(record, index)?);
    }
    let plans: Vec<Plan<'_>> = records.iter().map(|r| Plan::new(model, r)).collect();
    let mut columns = model.coefficient_names();
    let row = |w: &Window| window_row(&plans[w.record], model, &records[w.record], w, settings);
    let rows: Vec<(Vec<f64>, f64)> = if build_in_parallel(records, columns.len()) {
        windows.par_iter().map(row).collect::<Result<_>>()?
    } else {
        windows.iter().map(row).collect::<Result<_>>()?
    };
    let nuisance = settings.storage.coefficient_names(dofs);
    columns.extend(nuisance.iter().cloned());
    let matrix = Mat::from_fn(rows.len(), columns.len(), |r, k| rows[r].0[k]);
    let rhs = rows.iter().map(|(_, b)| *b).collect();
    let labels = windows
        .iter()
        .map(|w| RowLabel::of(w, &records[w.record]))
        .collect();
    Regressor::from_parts(matrix, rhs, columns, labels)?.with_nuisance_count(nuisance.len())
}

/// One equation: damping columns and input work from the kernel over the window's
/// samples, then the nuisance columns from its end states; known stored energy is
/// subtracted from the input work.
fn window_row(
    plan: &Plan<'_>,
    model: &DampingModel,
    record: &Record,
    w: &Window,
    settings: &NonPeriodicSettings,
) -> Result<(Vec<f64>, f64)> {
    let count = (w.span / record.step()).round() as usize + 1;
    // The rectangular rule reads L samples; the end sample is still needed for its state.
    let weights = settings
        .quadrature
        .window_weights(w.span, record.step(), w.span)?
        .padded_to(count);
    let v = settings
        .velocity
        .window_velocities(record, w.start, count)?;
    let v = v.as_ref();
    let x = record.displacements().subrows(w.start, count);
    let samples = WindowSamples {
        x,
        v,
        signals: record.forcing().signals.as_ref().subrows(w.start, count),
        weights: &weights,
    };
    let (mut row, mut input) = plan.row(&samples);
    if settings.work_form == WorkForm::DerivativeFree {
        input = derivative_free::replace_with_raw(model, record, w, &mut row)?;
    }
    let state =
        |m: faer::MatRef<'_, f64>, i: usize| -> Vec<f64> { m.row(i).iter().copied().collect() };
    let (x_start, x_end) = (state(x, 0), state(x, count - 1));
    let (v_start, v_end) = (state(v, 0), state(v, count - 1));
    let (nuisance, known) = settings.storage.columns(&Endpoints {
        x_start: &x_start,
        x_end: &x_end,
        v_start: &v_start,
        v_end: &v_end,
    });
    row.extend(nuisance);
    Ok((row, input - known))
}
