//! Ordinary least squares, min ‖A θ − b‖₂, through the thin SVD of the column-scaled
//! regressor A_s = U Σ Vᵀ ([`ScaledSvd`]): θ_s = Σ_{i<r} v_i (u_iᵀ b_s)/σ_i, with r the
//! numerical rank (σ_i > tol · σ_1). When r is below the number of coefficients this is the
//! minimum-norm solution, and the report flags it: the data do not determine θ.

use faer::Mat;

use crate::error::{Error, Result};
use crate::fit::svd::ScaledSvd;
use crate::fit::{Fit, FitMethod, FitStatus};
use crate::regressor::Regressor;

/// Plain least squares with rank tolerance `rank_tolerance` relative to σ_1.
pub fn least_squares(regressor: &Regressor, rank_tolerance: f64) -> Result<Fit> {
    factored_least_squares(regressor, rank_tolerance).map(|(fit, _)| fit)
}

/// [`least_squares`], also returning the factorization it solved with, for the
/// diagnostics of the same rows.
pub(crate) fn factored_least_squares(
    regressor: &Regressor,
    rank_tolerance: f64,
) -> Result<(Fit, ScaledSvd)> {
    let a = regressor.matrix();
    let (m, p) = a.shape();
    if m < p {
        return Err(Error::TooFewEquations {
            equations: m,
            coefficients: p,
        });
    }
    let svd = ScaledSvd::new(a, regressor.rhs(), rank_tolerance)?;
    let mut theta_s = svd.scaled_solution();
    // An all-zero column keeps scale 1, so its round-off share of the minimum-norm
    // solution would be unscaled in b's units (1e-4 for a weighted b of norm 1e12):
    // the minimum-norm solution has exactly 0 there.
    for (j, t) in theta_s.iter_mut().enumerate() {
        if (0..m).all(|i| a[(i, j)] == 0.0) {
            *t = 0.0;
        }
    }
    let fit = Fit {
        coefficients: svd.scaling().unscale(&theta_s),
        status: FitStatus::Solved,
        method: FitMethod::LeastSquares,
        active: Vec::new(),
        solver: None,
        residual_std: None,
    };
    Ok((fit, svd))
}

/// Solves min ‖A_F θ_F − c‖ for the columns in `free`, by QR (used by the polish step).
pub(crate) fn solve_subset(a: &Mat<f64>, c: &Mat<f64>, free: &[usize]) -> Mat<f64> {
    use faer::prelude::*;
    let sub = Mat::from_fn(a.nrows(), free.len(), |i, j| a[(i, free[j])]);
    sub.qr().solve_lstsq(c)
}
