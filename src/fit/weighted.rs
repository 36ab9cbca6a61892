//! Weighted least squares with propagated variances. Equation r's residual
//! e_r = b_r − A_r θ has, to first order in the sensor noise, variance
//! s_r²(θ) = Var e_r(θ) ([`crate::regressor::robust::RowNoise::variance`]). The fit minimises
//!
//! ```text
//!   Σ_r (e_r / s_r)²,
//! ```
//!
//! iterated because s_r depends on θ: start from row-normalised weights
//! 1/‖(A_r, b_r)‖ (every equation counts the same relative to its size), fit, set
//! w_r = 1/s_r(θ), refit, until θ moves by less than 10⁻¹⁰ relative or after
//! [`ITERATIONS`] fits. Bounds and constraints apply to every fit (clarabel works on the
//! weighted rows). The plug-in covariance (Aᵀ W A)⁻¹ with W = diag(1/s_r²) is in
//! [`crate::analysis::diagnostics`].

use crate::error::Result;
use crate::fit::{Fit, FitSettings, solve_rows};
use crate::regressor::Regressor;
use crate::regressor::robust::NoiseModel;

/// Most fits of the reweighting iteration.
pub(crate) const ITERATIONS: usize = 6;

/// Relative change of θ below which the iteration stops.
const CONVERGED: f64 = 1e-10;

/// The weighted fit of `regressor` with the residual variances of `noise`.
pub(crate) fn solve(
    regressor: &Regressor,
    noise: &NoiseModel,
    settings: &FitSettings,
) -> Result<Fit> {
    let a = regressor.matrix();
    let b = regressor.rhs();
    let mut weights: Vec<f64> = (0..b.len())
        .map(|r| {
            let norm = (0..a.ncols())
                .map(|k| a[(r, k)] * a[(r, k)])
                .sum::<f64>()
                .max(b[r] * b[r])
                .sqrt();
            if norm > 0.0 { 1.0 / norm } else { 1.0 }
        })
        .collect();
    let mut fit = solve_rows(&regressor.weighted(&weights)?, settings)?;
    for _ in 1..ITERATIONS {
        if !fit.status.is_usable() {
            break;
        }
        weights = inverse_std(&noise.residual_std(&fit.coefficients));
        let next = solve_rows(&regressor.weighted(&weights)?, settings)?;
        let change = relative_change(&fit.coefficients, &next.coefficients);
        fit = next;
        if change < CONVERGED {
            break;
        }
    }
    fit.residual_std = Some(noise.residual_std(&fit.coefficients));
    Ok(fit)
}

/// 1/s_r, with a residual of zero variance (a row noise cannot reach) given the weight
/// of the most precise row with a positive variance, or 1 when none has one.
pub(crate) fn inverse_std(std: &[f64]) -> Vec<f64> {
    let smallest = std
        .iter()
        .copied()
        .filter(|s| *s > 0.0 && s.is_finite())
        .fold(f64::INFINITY, f64::min);
    let floor = if smallest.is_finite() { smallest } else { 1.0 };
    std.iter()
        .map(|s| {
            if *s > 0.0 && s.is_finite() {
                1.0 / s
            } else {
                1.0 / floor
            }
        })
        .collect()
}

/// max_k |a_k − b_k| / max_k |b_k|.
fn relative_change(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let change = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if scale > 0.0 { change / scale } else { change }
}
