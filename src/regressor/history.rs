//! The columns of history terms ([`crate::terms::history`]) in one window of whole
//! periods:
//!
//! ```text
//!   A_e = Σ_i w_i v_e,i s_e,i,      s_e = the element's force per unit coefficient on its periodic orbit,
//! ```
//!
//! summed like a force channel's work. The orbit is driven by one period of the
//! element's relative displacement x_e = x_a − x_b: the window's first L samples,
//! L = round(kT/h) (exactly the samples of a window that closes periodically), read
//! cyclically (`terms/history/orbit.rs`); a window that reads more samples (the
//! trapezoid's end sample, a rule's padding) takes s periodically, s_{i+L} = s_i.
//!
//! Structural damping ([`crate::terms::structural`]) is summed the same way, its s_e the
//! element's −k H\[x_e\] over the same L samples (one real FFT), taken periodically too.
//!
//! Only windows of whole periods have an orbit or harmonics: non-periodic spans refuse
//! history terms ([`refuse`]) and structural damping ([`refuse_structural`]). The
//! noise-robust rows refuse history terms too; they compute structural damping
//! themselves, on the projected motion, less its expected noise contribution
//! (`regressor/robust/structural.rs`), and never call [`add_columns`].

use crate::terms::OnElements;
use faer::MatRef;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::quadrature::{Quadrature, WindowWeights};
use crate::prep::window::Window;
use crate::record::{Record, col};
use crate::terms::history::orbit;
use crate::terms::structural::force_per_unit_loss;
use crate::terms::{Term, lanes};

/// Whether `model` holds a history term or structural damping (a column computed here).
pub(crate) fn has_history(model: &DampingModel) -> bool {
    model
        .terms()
        .iter()
        .any(|t| matches!(t, Term::History(_) | Term::Structural(_)))
}

/// An error when `model` holds structural damping, which needs windows of whole periods
/// (harmonics to rotate) that `mode` does not give, for `reason`.
pub(crate) fn refuse_structural(model: &DampingModel, mode: &str, reason: &str) -> Result<()> {
    if model
        .terms()
        .iter()
        .any(|t| matches!(t, Term::Structural(_)))
    {
        return Err(Error::choice(
            "damping term",
            format!("structural (a loss factor, −k H[x] of the window) in {mode}"),
            reason,
        ));
    }
    Ok(())
}

/// An error when `model` holds a history term: such terms need windows of whole
/// periods, which `mode` (e.g. "non-periodic spans") does not give, for `reason`.
pub(crate) fn refuse(model: &DampingModel, mode: &str, reason: &str) -> Result<()> {
    match model.terms().iter().find_map(|t| match t {
        Term::History(h) => Some(h),
        _ => None,
    }) {
        None => Ok(()),
        Some(h) => Err(Error::choice(
            "damping term",
            format!("{} (a force with memory) in {mode}", h.hysteresis().kind()),
            reason,
        )),
    }
}

/// Adds the history terms' columns of window `w` of `record` to `row`: `x` and `v` the
/// window's displacement and velocity rows (as many as `weights`).
pub(crate) fn add_columns(
    model: &DampingModel,
    record: &Record,
    w: &Window,
    x: MatRef<'_, f64>,
    v: MatRef<'_, f64>,
    weights: &WindowWeights,
    row: &mut [f64],
) -> Result<()> {
    let count = weights.len();
    if count == 0 {
        return Ok(());
    }
    let period = w
        .closed_length(record.step())
        .unwrap_or_else(|| Quadrature::length(w.span, record.step()).0.max(1))
        .clamp(1, count);
    let relative = |m: MatRef<'_, f64>, a: usize, b: Option<usize>, len: usize| -> Vec<f64> {
        let ca = &col(m, a)[..len];
        match b {
            None => ca.to_vec(),
            Some(b) => ca
                .iter()
                .zip(&col(m, b)[..len])
                .map(|(p, q)| p - q)
                .collect(),
        }
    };
    let window_sum = |s: &[f64], velocity: &[f64]| -> f64 {
        weights
            .pieces(0..count)
            .map(|piece| {
                lanes::dot(
                    piece.weights,
                    &velocity[piece.rows.clone()],
                    &s[piece.rows.clone()],
                )
            })
            .sum()
    };
    for (term, range) in model.term_columns() {
        if let Term::Structural(t) = term {
            for (index, (element, &k)) in t.elements().iter().zip(t.stiffness()).enumerate() {
                let path = relative(x, element.a, element.b, period);
                let force = force_per_unit_loss(&path, k);
                let s: Vec<f64> = (0..count).map(|i| force[i % period]).collect();
                let velocity = relative(v, element.a, element.b, count);
                row[range.start + t.column_of(index)] += window_sum(&s, &velocity);
            }
            continue;
        }
        let Term::History(t) = term else { continue };
        for (index, element) in t.elements().iter().enumerate() {
            let path = relative(x, element.a, element.b, period);
            let force = orbit::periodic_force_within(t.hysteresis(), &path, t.max_passes())
                .map_err(|e| Error::NoPeriodicOrbit {
                    record: record.label().to_string(),
                    window: w.index + 1,
                    term: format!("{} [{}]", t.hysteresis().kind(), element.label),
                    passes: e.passes,
                    change: e.change,
                    tolerance: e.tolerance,
                })?;
            let s: Vec<f64> = (0..count).map(|i| force[i % period]).collect();
            let velocity = relative(v, element.a, element.b, count);
            row[range.start + t.column_of(index)] += window_sum(&s, &velocity);
        }
    }
    Ok(())
}
