//! A linear damping matrix scaled by one coefficient: C = θ C₀ (viscous with a given
//! C₀, stiffness-proportional C₀ = K, mass-proportional C₀ = M, or a discretized
//! damping operator for a continuum).
//!
//! Column: ∫ vᵀ C₀ v dt ≈ Σ_i w_i v_iᵀ C₀ v_i = Σ_jk (C₀)_jk G_jk = tr(C₀ᵀ G), with
//! G = Vᵀ W V the weighted velocity Gram matrix of the window, formed once for all
//! matrix terms. Only the symmetric part of C₀ dissipates.

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, check_finite};

/// What a matrix term's C₀ is, for reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MatrixKind {
    /// A given viscous damping matrix.
    Viscous,
    /// C₀ = K (Rayleigh stiffness-proportional).
    StiffnessProportional,
    /// C₀ = M (Rayleigh mass-proportional).
    MassProportional,
}

/// A damping matrix with one coefficient.
#[derive(Debug, Clone)]
pub struct MatrixTerm {
    name: String,
    kind: MatrixKind,
    matrix: Mat<f64>,
}

impl MatrixTerm {
    /// Coefficient `name` scales `matrix` (n × n).
    pub fn new(name: impl Into<String>, kind: MatrixKind, matrix: Mat<f64>) -> Self {
        MatrixTerm {
            name: name.into(),
            kind,
            matrix,
        }
    }

    /// What the matrix is.
    pub fn kind(&self) -> MatrixKind {
        self.kind
    }

    /// C₀.
    pub fn matrix(&self) -> &Mat<f64> {
        &self.matrix
    }

    pub(crate) fn coefficient_names(&self) -> Vec<String> {
        vec![self.name.clone()]
    }

    pub(crate) fn validate(&self, dofs: usize) -> Result<()> {
        let what = format!("matrix of term '{}'", self.name);
        if self.matrix.nrows() != dofs {
            return Err(Error::mismatch(
                format!("rows of {what} vs DOFs"),
                dofs,
                self.matrix.nrows(),
            ));
        }
        if self.matrix.ncols() != dofs {
            return Err(Error::mismatch(
                format!("columns of {what} vs DOFs"),
                dofs,
                self.matrix.ncols(),
            ));
        }
        check_finite(&what, self.matrix.as_ref())
    }

    pub(crate) fn add_force(&self, coefficients: &[f64], v: &[f64], out: &mut [f64]) {
        let theta = coefficients[0];
        for (k, vk) in v.iter().enumerate() {
            let scaled = theta * vk;
            if scaled != 0.0 {
                for (j, o) in out.iter_mut().enumerate() {
                    *o += self.matrix[(j, k)] * scaled;
                }
            }
        }
    }
}
