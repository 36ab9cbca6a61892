//! Is the velocity estimator the problem? With noisy displacements, a velocity
//! estimated by differencing carries the noise amplified, and every column built from
//! v² or |v|³ is biased upwards by its variance: the fit then takes the input work as
//! more dissipation per unit coefficient and the coefficients come out low, even
//! negative. This module estimates that bias from the data and says when it matters.
//!
//! The build records each entry's expected noise contribution B while it makes the
//! rows, from each window's samples, weights and velocities
//! ([`crate::regressor::velocity_bias`]: the noise floor of the displacements, the
//! estimator's velocity variance, and ([`crate::terms::Law::noise_bias`]) its effect on
//! each column: Var v for a linear dashpot, 3|v| Var v for a
//! quadratic law). The assessment reports, per column, the share Σ_r B_r / Σ_r |A_r| of
//! the column that is noise, and, per coefficient, the shift of the least-squares
//! estimate when B is removed from the rows, θ(A − B) − θ(A). The bias is material when
//! it is at least [`MATERIAL_SHARE`] of some damping column: the coefficients are then
//! biased by about as much, more than the accuracy the method reaches on clean data.
//! The estimator to use instead is the harmonic projection with the noise-robust rows
//! (`velocity = "harmonic_projection"`, `noise = "auto"`, the default), which removes
//! this bias (see docs/noise.md).
//!
//! Assessed: central differences, spectral velocities and harmonic projection with the
//! noise correction off, in the periodic mode. Not assessed: measured velocities (their
//! noise is not in the displacements), the noise-robust rows (already corrected), the
//! non-periodic mode (no whole periods for the noise floor). Coulomb columns get no
//! bias here ([`crate::terms::Law::noise_bias`] is 0 for them), so a friction-only model
//! is never flagged.

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::fit::least_squares;
use crate::regressor::Regressor;

/// Share of a damping column that is velocity-noise bias from which the assessment
/// calls it material (1%: it moves the coefficients by about as much).
pub const MATERIAL_SHARE: f64 = 0.01;

/// The noise bias of one column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColumnBias {
    /// Coefficient name.
    pub name: String,
    /// Σ_r B_r / Σ_r |A_r|: the share of the column that is velocity noise.
    pub share: f64,
    /// θ(A − B) − θ(A): how far the least-squares estimate moves when the bias is
    /// removed from the rows (positive: the estimate shown is too low).
    pub shift: f64,
    /// The least-squares estimate with the bias removed, θ(A − B).
    pub corrected: f64,
}

/// What the velocity estimator's noise does to the damping columns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VelocityNoise {
    /// The estimator assessed (its model-file name).
    pub estimator: String,
    /// σ_v / (ω σ): the estimator's velocity noise relative to that of the fundamental
    /// harmonic, the largest over the windows (1/(√2 ωh) for central differences).
    pub gain: f64,
    /// The smallest and largest displacement noise σ estimated (per sample, over
    /// windows and channels).
    pub displacement_noise: [f64; 2],
    /// Per damping column, its noise share and the shift of its coefficient.
    pub columns: Vec<ColumnBias>,
    /// True when some column's share reaches [`MATERIAL_SHARE`].
    pub material: bool,
    /// The estimator to use instead (model-file name).
    pub recommended: String,
}

impl VelocityNoise {
    /// The column with the largest noise share.
    pub fn worst(&self) -> Option<&ColumnBias> {
        self.columns
            .iter()
            .max_by(|a, b| a.share.total_cmp(&b.share))
    }
}

/// The velocity-noise assessment of `regressor` from the bias its build recorded
/// ([`Regressor::velocity_bias`]; `None` when the estimator is not one assessed, module
/// doc): each column's noise share and the shift of the least-squares estimate when
/// the bias is removed. A least-squares failure gives `None` too: the assessment adds
/// to a report and never stops an identification.
pub fn assess(regressor: &Regressor) -> Option<VelocityNoise> {
    let bias = regressor.velocity_bias()?;
    let a = regressor.matrix();
    let damping = bias.matrix.ncols().min(a.ncols());
    if bias.matrix.nrows() != a.nrows() {
        return None;
    }
    let mut full = Mat::<f64>::zeros(a.nrows(), a.ncols());
    for k in 0..damping {
        for r in 0..a.nrows() {
            full[(r, k)] = bias.matrix[(r, k)];
        }
    }
    let corrected = Regressor::from_parts(
        a - &full,
        regressor.rhs().to_vec(),
        regressor.columns().to_vec(),
        regressor.rows().to_vec(),
    )
    .ok()?;
    let tolerance = 1e-10;
    let before = least_squares(regressor, tolerance).ok()?.coefficients;
    let after = least_squares(&corrected, tolerance).ok()?.coefficients;
    let columns: Vec<ColumnBias> = (0..damping)
        .map(|k| {
            let size: f64 = (0..a.nrows()).map(|r| a[(r, k)].abs()).sum();
            let noise: f64 = (0..a.nrows()).map(|r| full[(r, k)]).sum();
            ColumnBias {
                name: regressor.columns()[k].clone(),
                share: if size > 0.0 { noise / size } else { 0.0 },
                shift: after[k] - before[k],
                corrected: after[k],
            }
        })
        .collect();
    let material = columns.iter().any(|c| c.share >= MATERIAL_SHARE);
    Some(VelocityNoise {
        estimator: bias.estimator.clone(),
        gain: bias.gain,
        displacement_noise: bias.displacement_noise,
        columns,
        material,
        recommended: "harmonic_projection".into(),
    })
}
