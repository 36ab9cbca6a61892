//! What stores energy, for the steady-state check: M, K and grounded cubic springs,
//!
//! ```text
//!   E(x, v) = ½ vᵀ M v + ½ xᵀ K x + ¼ Σ_d k_d x_d⁴,
//!   ∂E/∂x = K_s x + (k_d x_d³)_d,   ∂E/∂v = M_s v,   M_s = ½ (M + Mᵀ), K_s likewise,
//! ```
//!
//! the gradient linearising the noise of a stored-energy change.

use faer::Mat;

use crate::error::{Error, Result};

/// What stores energy: M, K and grounded cubic springs, on the records' DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredEnergy {
    /// Mass matrix M (n × n).
    pub mass: Mat<f64>,
    /// Stiffness matrix K (n × n).
    pub stiffness: Mat<f64>,
    /// Grounded cubic springs (DOF, 0-based; k), potential ¼ k x⁴.
    pub cubic_springs: Vec<(usize, f64)>,
}

/// yᵀ m y.
fn quadratic(m: &Mat<f64>, y: &[f64]) -> f64 {
    let mut sum = 0.0;
    for (i, yi) in y.iter().enumerate() {
        for (j, yj) in y.iter().enumerate() {
            sum += yi * m[(i, j)] * yj;
        }
    }
    sum
}

/// ½ (m + mᵀ) y.
fn symmetric_times(m: &Mat<f64>, y: &[f64]) -> Vec<f64> {
    (0..y.len())
        .map(|i| {
            y.iter()
                .enumerate()
                .map(|(j, yj)| 0.5 * (m[(i, j)] + m[(j, i)]) * yj)
                .sum()
        })
        .collect()
}

impl StoredEnergy {
    /// ½ vᵀ M v + ½ xᵀ K x + ¼ Σ k x_d⁴.
    pub fn energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let springs: f64 = self
            .cubic_springs
            .iter()
            .map(|&(dof, k)| 0.25 * k * x[dof].powi(4))
            .sum();
        0.5 * quadratic(&self.mass, v) + 0.5 * quadratic(&self.stiffness, x) + springs
    }

    /// (∂E/∂x, ∂E/∂v) at the state (x, v).
    pub fn gradient(&self, x: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut dx = symmetric_times(&self.stiffness, x);
        for &(dof, k) in &self.cubic_springs {
            dx[dof] += k * x[dof].powi(3);
        }
        (dx, symmetric_times(&self.mass, v))
    }

    pub(super) fn validate(&self, dofs: usize) -> Result<()> {
        for (what, m) in [("mass", &self.mass), ("stiffness", &self.stiffness)] {
            if m.nrows() != dofs || m.ncols() != dofs {
                let found = if m.nrows() != dofs {
                    m.nrows()
                } else {
                    m.ncols()
                };
                return Err(Error::mismatch(
                    format!("{what} matrix size vs record DOFs (steady-state check)"),
                    dofs,
                    found,
                ));
            }
        }
        for &(dof, _) in &self.cubic_springs {
            if dof >= dofs {
                return Err(Error::dof_index(
                    "cubic spring (steady-state check)",
                    dof,
                    dofs,
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient is the derivative of the energy (central differences, a cubic
    /// spring and a non-symmetric M to exercise the symmetrisation).
    #[test]
    fn gradient_is_the_derivative_of_the_energy() {
        let energy = StoredEnergy {
            mass: Mat::from_fn(2, 2, |i, j| [[2.0, 0.3], [0.1, 1.0]][i][j]),
            stiffness: Mat::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 2.0]][i][j]),
            cubic_springs: vec![(1, 0.7)],
        };
        let (x, v) = ([0.3, -0.8], [1.1, 0.4]);
        let (gx, gv) = energy.gradient(&x, &v);
        let e = 1e-6;
        for d in 0..2 {
            let (mut xp, mut xm, mut vp, mut vm) = (x, x, v, v);
            xp[d] += e;
            xm[d] -= e;
            vp[d] += e;
            vm[d] -= e;
            let nx = (energy.energy(&xp, &v) - energy.energy(&xm, &v)) / (2.0 * e);
            let nv = (energy.energy(&x, &vp) - energy.energy(&x, &vm)) / (2.0 * e);
            assert!((nx - gx[d]).abs() < 1e-8, "{nx} vs {}", gx[d]);
            assert!((nv - gv[d]).abs() < 1e-8, "{nv} vs {}", gv[d]);
        }
    }
}
