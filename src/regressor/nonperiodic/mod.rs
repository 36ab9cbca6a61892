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
//! with \[g\] = g(t_b) − g(t_a), φ_j the damping terms' power (as in the periodic
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

pub(crate) mod storage;

pub use storage::{Kinetic, Potential, StorageModel};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::{Window, span_windows};
use crate::record::Record;
use crate::regressor::derivative_free;
use crate::regressor::kernel::{Plan, WindowSamples, build_in_parallel};
use crate::regressor::settings::{SpanWindows, WorkForm};
use crate::regressor::{Regressor, Row, map_windows};
pub(crate) use storage::Endpoints;

/// Builds the non-periodic regressor: the damping model's columns, then the nuisance
/// columns of `settings.storage` ([`Regressor::nuisance_count`]), one row per window.
pub(crate) fn build(
    model: &DampingModel,
    records: &[Record],
    spans: &SpanWindows,
    quadrature: Quadrature,
    velocity: VelocitySource,
    work_form: WorkForm,
) -> Result<Regressor> {
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
    spans.storage.validate(dofs)?;
    let mut windows = Vec::new();
    for (index, record) in records.iter().enumerate() {
        windows.extend(span_windows(record, index, spans.length, spans.skip)?);
    }
    let plans: Vec<Plan<'_>> = records.iter().map(|r| Plan::new(model, r)).collect();
    let mut columns = model.coefficient_names();
    let rule = Rule {
        quadrature,
        velocity,
        work_form,
        storage: &spans.storage,
    };
    let rows = map_windows(build_in_parallel(records, columns.len()), &windows, |w| {
        window_row(&plans[w.record], model, &records[w.record], w, &rule)
    })?;
    let nuisance = spans.storage.coefficient_names(dofs);
    columns.extend(nuisance.iter().cloned());
    Regressor::assemble(records, &windows, rows, columns)?.with_nuisance_count(nuisance.len())
}

/// How each window's row is integrated.
pub(crate) struct Rule<'a> {
    pub(crate) quadrature: Quadrature,
    pub(crate) velocity: VelocitySource,
    pub(crate) work_form: WorkForm,
    pub(crate) storage: &'a StorageModel,
}

/// One equation: damping columns and input work from the kernel over the window's
/// samples, then the nuisance columns from its end states; known stored energy is
/// subtracted from the input work.
pub(crate) fn window_row(
    plan: &Plan<'_>,
    model: &DampingModel,
    record: &Record,
    w: &Window,
    settings: &Rule<'_>,
) -> Result<Row> {
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
