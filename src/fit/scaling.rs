//! Column scaling. The fit works on A_s = A S⁻¹ and b_s = b/β with S = diag(‖A_j‖₂)
//! and β = ‖b‖₂, so that every column and the right-hand side have unit norm and the
//! scaled coefficients θ_s = S θ / β are of order one. Conditioning is reported on A_s:
//! it measures how well the data separate the coefficients, not their units.
//! An all-zero column keeps scale 1 (and shows as a zero singular value). A column (or
//! b) of finite entries whose 2-norm overflows (entries near f64::MAX) is scaled by its
//! largest entry instead, so every scale is finite and positive.

use faer::Mat;

/// ‖x‖₂ without overflow or underflow for any finite x (faer scales internally).
pub(crate) fn norm(x: &[f64]) -> f64 {
    faer::ColRef::from_slice(x).norm_l2()
}

/// Column norms and the right-hand side norm.
#[derive(Debug, Clone)]
pub(crate) struct Scaling {
    pub columns: Vec<f64>,
    pub rhs: f64,
}

impl Scaling {
    pub fn of(a: &Mat<f64>, b: &[f64]) -> Self {
        let columns = (0..a.ncols())
            .map(|j| scale_of(a.col(j).norm_l2(), || a.col(j).norm_max()))
            .collect();
        let rhs = scale_of(norm(b), || faer::ColRef::from_slice(b).norm_max());
        Scaling { columns, rhs }
    }

    /// A_s = A S⁻¹.
    pub fn matrix(&self, a: &Mat<f64>) -> Mat<f64> {
        Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] / self.columns[j])
    }

    /// b_s = b / β, as a column.
    pub fn rhs(&self, b: &[f64]) -> Mat<f64> {
        Mat::from_fn(b.len(), 1, |i, _| b[i] / self.rhs)
    }

    /// θ from θ_s.
    pub fn unscale(&self, theta_s: &[f64]) -> Vec<f64> {
        theta_s
            .iter()
            .zip(&self.columns)
            .map(|(t, s)| t * self.rhs / s)
            .collect()
    }

    /// θ_s from θ. Zero and ±∞ (a bound at zero, or no bound) map to themselves: the
    /// factor S_j/β is positive, and 0 · ∞ would be NaN if it overflowed.
    pub fn scale(&self, j: usize, theta: f64) -> f64 {
        if theta == 0.0 || theta.is_infinite() {
            theta
        } else {
            theta * self.columns[j] / self.rhs
        }
    }
}

/// The 2-norm when it is finite and positive; else the largest entry (the norm
/// overflowed); else 1 (all zero, or not finite).
fn scale_of(norm: f64, largest: impl FnOnce() -> f64) -> f64 {
    if norm.is_finite() && norm > 0.0 {
        return norm;
    }
    let largest = largest();
    if largest.is_finite() && largest > 0.0 {
        largest
    } else {
        1.0
    }
}
