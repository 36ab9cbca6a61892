//! The plain periodic rows: for window w of whole periods and the quadrature weights
//! w_i over its samples, one fused pass of the kernel gives
//!
//! ```text
//!   A_wk = Σ_i w_i v_iᵀ f_k(x_i, v_i),    b_w = Σ_i w_i v_iᵀ r_i,
//! ```
//!
//! with velocities from the chosen source ([`crate::prep::velocity`]). A window that
//! closes periodically ([`Window::closed`]) reads its L = kT/h samples with w_i = h and
//! wrapped central differences. History terms add their columns on each window's
//! periodic orbit ([`crate::regressor::history`]). With
//! [`WorkForm::DerivativeFree`] the input work (and Coulomb columns) are then replaced
//! by their derivative-free forms ([`crate::regressor::derivative_free`]).

use rayon::prelude::*;

use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::quadrature::{Quadrature, WindowWeights};
use crate::prep::window::{Window, WindowSpec};
use crate::record::Record;
use crate::regressor::kernel::{Plan, WindowSamples, build_in_parallel};
use crate::regressor::settings::{RegressorSettings, WorkForm};
use crate::regressor::velocity_bias::{self, Harmonics, VelocityBias, WindowBias};
use crate::regressor::{Row, map_windows};
use crate::regressor::{derivative_free, history};

/// The rows of `windows` (cut by `spec` from `records`) under `settings`, with each
/// window's velocity-noise bias when the velocity estimator is one whose bias is
/// assessed ([`velocity_bias`]).
pub(super) fn rows(
    model: &DampingModel,
    records: &[Record],
    windows: &[Window],
    spec: &WindowSpec,
    settings: &RegressorSettings,
    coefficients: usize,
) -> Result<(Vec<Row>, Option<VelocityBias>)> {
    let weights = record_weights(records, windows, spec, settings)?;
    // Small builds stay on the calling thread: every parallel call below would
    // otherwise be a hand-off to the pool costing more than its work.
    let parallel = build_in_parallel(records, coefficients);
    let share = |(record, weights): (&Record, WindowWeights)| RecordShared {
        plan: Plan::new(model, record),
        weights,
    };
    let shared: Vec<RecordShared<'_>> = if parallel {
        records.par_iter().zip(weights).map(share).collect()
    } else {
        records.iter().zip(weights).map(share).collect()
    };
    let assessed = Harmonics::assessed(settings);
    let rows = map_windows(parallel, windows, |w| {
        window_row(
            &shared[w.record],
            model,
            &records[w.record],
            w,
            settings,
            assessed,
        )
    })?;
    let (rows, bias): (Vec<Row>, Vec<Option<WindowBias>>) = rows.into_iter().unzip();
    let bias = bias
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .filter(|_| assessed.is_some())
        .map(|windows| VelocityBias::of(settings, windows, model.coefficient_count()));
    Ok((rows, bias))
}

/// What the windows of one record share: the kernel's plan and the quadrature weights
/// (every window of a record spans the same k periods; a window that closes
/// periodically has its own, w_i = h).
struct RecordShared<'m> {
    plan: Plan<'m>,
    weights: WindowWeights,
}

/// The quadrature weights of every record's windows. Every window of a record spans the
/// same k periods. Spectral weights scale with the step, w(kT, h, T) = h w(kT/h, 1, T/h),
/// so they are computed once per distinct (kT/h, T/h): once for a stepped-sine table
/// sampled at a fixed number of samples per period, however many points it has (the
/// spectral rule costs a QR of the Fourier basis).
fn record_weights(
    records: &[Record],
    windows: &[Window],
    spec: &WindowSpec,
    settings: &RegressorSettings,
) -> Result<Vec<WindowWeights>> {
    let span_of = |index: usize, record: &Record| {
        windows
            .iter()
            .find(|w| w.record == index)
            .map_or(spec.cycles as f64 * record.period(), |w| w.span)
    };
    if settings.quadrature != Quadrature::Spectral {
        // Rectangular and trapezoid weights are a few numbers each (no per-sample
        // vector): made directly at each record's step.
        return records
            .iter()
            .enumerate()
            .map(|(index, record)| {
                settings.quadrature.window_weights(
                    span_of(index, record),
                    record.step(),
                    record.period(),
                )
            })
            .collect();
    }
    let ratios: Vec<(f64, f64)> = records
        .iter()
        .enumerate()
        .map(|(index, record)| {
            (
                span_of(index, record) / record.step(),
                record.period() / record.step(),
            )
        })
        .collect();
    let key = |(span, period): (f64, f64)| (span.to_bits(), period.to_bits());
    let mut distinct: Vec<(f64, f64)> = Vec::new();
    for &ratio in &ratios {
        if !distinct.iter().any(|&d| key(d) == key(ratio)) {
            distinct.push(ratio);
        }
    }
    let per_step: Vec<Vec<f64>> = distinct
        .par_iter()
        .map(|&(span, period)| settings.quadrature.weights(span, 1.0, period))
        .collect::<Result<_>>()?;
    Ok(records
        .iter()
        .zip(&ratios)
        .map(|(record, &ratio)| {
            // cannot fail: `distinct` was built from these same ratios by `key`.
            let unit = distinct
                .iter()
                .position(|&d| key(d) == key(ratio))
                .expect("every ratio is in the distinct list");
            WindowWeights::PerSample(per_step[unit].iter().map(|w| w * record.step()).collect())
        })
        .collect())
}

/// One row: every term's columns and the input work for window `w`, in one fused pass
/// over the window's samples (`src/regressor/kernel/`); with `assessed`, the window's
/// velocity-noise bias from the same weights and velocities. A window too short for the
/// noise floor gets no bias (the assessment adds to a report and never stops a build).
fn window_row(
    shared: &RecordShared<'_>,
    model: &DampingModel,
    record: &Record,
    w: &Window,
    settings: &RegressorSettings,
    assessed: Option<Harmonics>,
) -> Result<(Row, Option<WindowBias>)> {
    // A window that closes periodically reads its L samples, each weighted h.
    let closed;
    let weights = if w.closed {
        closed = w.window_weights(settings.quadrature, record.step(), record.period())?;
        &closed
    } else {
        &shared.weights
    };
    let count = weights.len();
    let v = settings.velocity.velocities_of(record, w, count)?;
    let samples = WindowSamples {
        x: record.displacements().subrows(w.start, count),
        v: v.as_ref(),
        signals: record.forcing().signals.as_ref().subrows(w.start, count),
        weights,
    };
    let (mut row, mut input) = shared.plan.row(&samples);
    if history::has_history(model) {
        history::add_columns(model, record, w, samples.x, samples.v, weights, &mut row)?;
    }
    if settings.work_form == WorkForm::DerivativeFree {
        input = derivative_free::replace_with_raw(model, record, w, &mut row)?;
    }
    let bias = assessed.and_then(|harmonics| {
        velocity_bias::window(model, record, w, harmonics, &weights.to_vec(), v.as_ref()).ok()
    });
    Ok(((row, input), bias))
}
