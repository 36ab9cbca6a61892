//! Structural (hysteretic) damping of a stepped-sine table in closed form: a loss factor
//! η on an element of stiffness k dissipates, per cycle of harmonic motion,
//!
//! ```text
//!   E = π η k |Z_e|²,   Z_e = Z_a − Z_b,   Z_i = X_i e^{−iψ_i},
//! ```
//!
//! so the element's column is π k |Z_e|² (complex stiffness k(1 + iη); its damping
//! force is (ηk/ω) ẋ at frequency ω).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::harmonic::SteppedSinePoint;

/// Structural (hysteretic) damping: a loss factor η on one element of given stiffness
/// k, dissipating π η k |Z_e|² per cycle of harmonic motion (complex stiffness
/// k(1 + iη); its damping force is (ηk/ω) ẋ at frequency ω).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StructuralTerm {
    /// The coefficient's name (η).
    pub coefficient: String,
    /// The element's stiffness k (> 0).
    pub stiffness: f64,
    /// The element: DOFs (0-based), `None` for ground.
    pub from: Option<usize>,
    /// The other end (0-based), `None` for ground.
    pub to: Option<usize>,
}

impl StructuralTerm {
    /// Checks the stiffness and the DOFs against `dofs`.
    pub fn validate(&self, dofs: usize) -> Result<()> {
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return Err(Error::invalid(
                &format!("stiffness of structural damping '{}'", self.coefficient),
                self.stiffness,
                "must be finite and positive",
            ));
        }
        for dof in [self.from, self.to].into_iter().flatten() {
            if dof >= dofs {
                return Err(Error::dof_index(
                    format!("structural damping '{}'", self.coefficient),
                    dof,
                    dofs,
                ));
            }
        }
        if self.from == self.to {
            return Err(Error::choice(
                "structural damping element",
                format!("'{}' between a DOF and itself", self.coefficient),
                "give two different DOFs, or one DOF and ground (0)",
            ));
        }
        Ok(())
    }

    /// The closed-form column π k |Z_a − Z_b|² of `point` with synthesized lags `psi`.
    pub fn column(&self, point: &SteppedSinePoint, psi: &[f64]) -> f64 {
        let z = |dof: Option<usize>| {
            dof.map_or((0.0, 0.0), |i| {
                let x = point.amplitudes[i];
                (x * psi[i].cos(), -x * psi[i].sin())
            })
        };
        let (a, b) = (z(self.from), z(self.to));
        let (re, im) = (a.0 - b.0, a.1 - b.1);
        std::f64::consts::PI * self.stiffness * (re * re + im * im)
    }
}
