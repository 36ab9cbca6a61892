//! Equivalent viscous damping ratio and loss factor versus amplitude
//! ([`super::equivalent`]) of a one-mode stepped-sine fit whose law parameters η were
//! estimated with the coefficients θ by variable projection ([`crate::varpro`]), with
//! intervals that include the uncertainty of η̂.
//!
//! The dissipated energy per cycle at amplitude X and ω_n is E_d(X) = g(X; η)ᵀθ, g the
//! columns of the model at η ([`crate::regressor::stepped_sine::columns_of`]); ζ_eq
//! and the loss factor are E_d over 2πkX² and πkX². To first order about (θ̂, η̂)
//!
//! ```text
//!   δE_d = g(X; η̂)ᵀ δθ + θ̂ᵀ ∂g/∂η(X; η̂) δη = uᵀ (δθ, δη),
//!   u = [g(X; η̂),  (∂g/∂η_j)ᵀ θ̂ for each law parameter j,  0 for the other unknowns],
//!   Var E_d(X) = uᵀ Σ u,
//! ```
//!
//! with Σ the joint covariance of (θ, η) of the variable-projection report (σ²(JᵀJ)⁻¹,
//! θ in column order then η). ∂g/∂η_j by central differences of the columns at
//! η̂ ± h e_j, h = 10⁻⁵ of the parameter's bound interval (one-sided at a bound), as the
//! joint Jacobian is differenced. Unknowns of η that change the table but not the law
//! (a stepped-sine table's residual receptances, which correct the measured response,
//! [`crate::prep::harmonic::residual`]) do not enter g: their entries of u are 0,
//! though their covariance with θ still reaches E_d through g(X; η̂)ᵀδθ.
//!
//! With η held fixed the same formula with u = g and the conditional covariance of θ
//! is [`super::equivalent::equivalent_damping`]; the joint Σ adds the spread of η̂.

use super::equivalent::{EquivalentDamping, Modal, amplitude_grid, point, quadratic_form};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::harmonic::HarmonicApproximation;
use crate::prep::harmonic::sweeps::SweptTable;
use crate::regressor::stepped_sine::{StructuralTerm, columns_of};

/// The estimated law parameters: the damping model as a function of them, their
/// estimates and bounds (for the difference step).
pub struct EstimatedLaw<'a> {
    /// The damping model at given law parameters (in order).
    pub model: &'a (dyn Fn(&[f64]) -> Result<DampingModel> + Sync),
    /// η̂ of the law parameters.
    pub values: &'a [f64],
    /// Their lower bounds.
    pub lower: &'a [f64],
    /// Their upper bounds.
    pub upper: &'a [f64],
}

/// ζ_eq(X) and η(X) at η̂ (module doc): `law`'s parameters are the first entries of η
/// in `covariance` (the joint (p + q) × (p + q) covariance, p = `coefficients.len()`),
/// any further entries are unknowns that do not enter the law; without `law` the model
/// is `model` and only θ enters. Without `covariance`, no intervals.
#[allow(clippy::too_many_arguments)]
pub fn equivalent_damping_estimated(
    model: &DampingModel,
    law: Option<&EstimatedLaw<'_>>,
    structural: &[StructuralTerm],
    approximation: &HarmonicApproximation,
    swept: &SweptTable,
    coefficients: &[f64],
    covariance: Option<&[Vec<f64>]>,
    modal: Modal,
) -> Result<EquivalentDamping> {
    let p = coefficients.len();
    let q_law = law.map_or(0, |l| l.values.len());
    if let Some(c) = covariance
        && (c.len() < p + q_law || c.iter().any(|row| row.len() != c.len()))
    {
        return Err(Error::mismatch(
            "joint covariance rows vs coefficients and law parameters",
            p + q_law,
            c.len(),
        ));
    }
    let (grid, synthetic) = amplitude_grid(swept, &modal)?;
    let columns = columns_of(model, structural, approximation, &synthetic)?;
    if columns.first().is_some_and(|g| g.len() != p) {
        return Err(Error::mismatch(
            "columns of the model vs coefficients",
            p,
            columns[0].len(),
        ));
    }
    // (∂g/∂η_j)ᵀ θ̂ at each grid amplitude, per law parameter j.
    let mut sensitivities: Vec<Vec<f64>> = Vec::with_capacity(q_law);
    if let (Some(law), Some(_)) = (law, covariance) {
        for j in 0..q_law {
            let h = 1e-5 * (law.upper[j] - law.lower[j]);
            let (lo, hi) = (
                (law.values[j] - h).max(law.lower[j]),
                (law.values[j] + h).min(law.upper[j]),
            );
            let energies = |t: f64| -> Result<Vec<f64>> {
                let mut at = law.values.to_vec();
                at[j] = t;
                let g = columns_of(&(law.model)(&at)?, structural, approximation, &synthetic)?;
                Ok(g.iter()
                    .map(|g| g.iter().zip(coefficients).map(|(g, t)| g * t).sum())
                    .collect())
            };
            let (e_lo, e_hi) = (energies(lo)?, energies(hi)?);
            sensitivities.push(
                e_lo.iter()
                    .zip(&e_hi)
                    .map(|(l, h)| (h - l) / (hi - lo))
                    .collect(),
            );
        }
    }
    let points = grid
        .iter()
        .zip(&columns)
        .enumerate()
        .map(|(i, (&x, g))| {
            let std = covariance.map(|c| {
                let mut u = vec![0.0; c.len()];
                u[..p].copy_from_slice(g);
                for (j, s) in sensitivities.iter().enumerate() {
                    u[p + j] = s[i];
                }
                quadratic_form(&u, c).max(0.0).sqrt()
            });
            point(x, g, coefficients, std, &modal)
        })
        .collect();
    Ok(EquivalentDamping { modal, points })
}
