//! The thin SVD of the column-scaled regressor, shared by every stage that reads it:
//!
//! ```text
//!   A_s = A S⁻¹ = U Σ Vᵀ,   S = diag(‖A_j‖₂),   b_s = b/‖b‖₂     (see [`super::scaling`])
//!   r = #{ i : σ_i > tol·σ_1 and σ_i > 0 }                      (numerical rank)
//!   κ = σ_1/σ_p when r = p, else ∞                             (condition number)
//!   c_i = u_iᵀ b_s                                              (projections of b_s)
//! ```
//!
//! Least squares reads θ_s = Σ_{i<r} v_i c_i/σ_i from it, the diagnostics read κ, r and
//! (A_sᵀA_s)⁻¹ = V Σ⁻² Vᵀ, the identifiability analysis reads σ, V and the residual of
//! the projection, and model comparison reads the column space U_r; `identify` factors
//! the matrix once for all of them ([`crate::analysis::solved::solved`]).
//!
//! A short regressor (m < p) is padded with zero rows to p rows, so that V holds all p
//! right singular vectors and Σ all p singular values (the missing ones are 0).

use faer::linalg::solvers::Svd;
use faer::{Mat, MatRef};

use crate::error::{Error, Result};
use crate::fit::scaling::Scaling;

/// The numerical rank of singular values `sigma` (descending): those above
/// `tolerance`·σ_1 and above 0.
pub(crate) fn numerical_rank(sigma: &[f64], tolerance: f64) -> usize {
    let largest = sigma.first().copied().unwrap_or(0.0);
    sigma
        .iter()
        .filter(|s| **s > tolerance * largest && **s > 0.0)
        .count()
}

/// The singular values alone of the column-scaled `a` (cheaper than [`ScaledSvd`] when
/// no vectors are needed); empty when the decomposition fails.
pub(crate) fn scaled_singular_values(a: &Mat<f64>, b: &[f64]) -> Vec<f64> {
    Scaling::of(a, b)
        .matrix(a)
        .singular_values()
        .unwrap_or_default()
}

/// The thin SVD of a column-scaled regressor, with its scaling and numerical rank.
#[derive(Debug, Clone)]
pub struct ScaledSvd {
    scaling: Scaling,
    /// U (max(m, p) × p), Σ and V (p × p), as faer returns them.
    svd: Svd<f64>,
    /// σ, p values, descending.
    sigma: Vec<f64>,
    /// b_s, padded like U.
    rhs: Mat<f64>,
    /// c = Uᵀ b_s.
    projections: Vec<f64>,
    equations: usize,
    rank: usize,
}

impl ScaledSvd {
    /// Scales `a` and `b` and factors A_s; singular values at or below
    /// `rank_tolerance`·σ_1 count as zero.
    pub fn new(a: &Mat<f64>, b: &[f64], rank_tolerance: f64) -> Result<Self> {
        let (m, p) = a.shape();
        let scaling = Scaling::of(a, b);
        let rows = m.max(p);
        let a_s = if rows == m {
            scaling.matrix(a)
        } else {
            Mat::from_fn(rows, p, |i, j| {
                if i < m {
                    a[(i, j)] / scaling.columns[j]
                } else {
                    0.0
                }
            })
        };
        let rhs = Mat::from_fn(rows, 1, |i, _| if i < m { b[i] / scaling.rhs } else { 0.0 });
        let svd = a_s.thin_svd().map_err(|e| Error::Numerical {
            stage: "SVD of the column-scaled regressor".into(),
            detail: format!("{e:?}"),
        })?;
        let s = svd.S().column_vector();
        let sigma: Vec<f64> = (0..p).map(|i| s[i]).collect();
        let c = svd.U().transpose() * &rhs;
        Ok(ScaledSvd {
            scaling,
            rank: numerical_rank(&sigma, rank_tolerance),
            projections: (0..p).map(|i| c[(i, 0)]).collect(),
            svd,
            sigma,
            rhs,
            equations: m,
        })
    }

    /// The column scaling S and ‖b‖.
    pub(crate) fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    /// σ_1 ≥ … ≥ σ_p of the scaled regressor.
    pub fn singular_values(&self) -> &[f64] {
        &self.sigma
    }

    /// The numerical rank r.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Number of equations m (rows before any padding).
    pub fn equations(&self) -> usize {
        self.equations
    }

    /// κ = σ_1/σ_p of the scaled regressor; infinite when it is rank deficient.
    pub fn condition_number(&self) -> f64 {
        match (self.sigma.first(), self.sigma.last()) {
            (Some(first), Some(last)) if self.rank == self.sigma.len() => first / last,
            _ => f64::INFINITY,
        }
    }

    /// U (max(m, p) × p): left singular vectors, zero in padded rows.
    pub fn u(&self) -> MatRef<'_, f64> {
        self.svd.U()
    }

    /// V (p × p): right singular vectors.
    pub fn v(&self) -> MatRef<'_, f64> {
        self.svd.V()
    }

    /// b_s, the scaled right-hand side (padded like U).
    pub fn rhs(&self) -> &Mat<f64> {
        &self.rhs
    }

    /// c_i = u_iᵀ b_s.
    pub fn projections(&self) -> &[f64] {
        &self.projections
    }

    /// The minimum-norm least-squares solution at rank r, in scaled coefficients:
    /// θ_s = Σ_{i<r} v_i c_i/σ_i.
    pub fn scaled_solution(&self) -> Vec<f64> {
        let p = self.sigma.len();
        let mut theta_s = vec![0.0; p];
        for i in 0..self.rank {
            let coefficient = self.projections[i] / self.sigma[i];
            let v = self.svd.V();
            for (j, t) in theta_s.iter_mut().enumerate() {
                *t += v[(j, i)] * coefficient;
            }
        }
        theta_s
    }
}
