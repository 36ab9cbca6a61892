//! Noise-robust identification: the energy balance squares sensor noise, so columns
//! built from noisy velocity estimates are biased and equations of very different
//! accuracy are mixed. For periodic records whose velocities are estimated by harmonic
//! projection ([`crate::prep::velocity::VelocitySource::HarmonicProjection`]) this module
//!
//! 1. reads the noise of every displacement and force channel and the harmonics that
//!    stand above it in any channel from its record, estimated once from the
//!    out-of-band spectra of a few spans by medians (`prep/fourier/record_noise.rs`):
//!    one set for every window of the record, so that relative velocities of nearly
//!    rigid DOF pairs are not biased by per-channel masks, and every window is weighted
//!    by the same noise;
//!    A channel measured by a velocity or acceleration sensor is projected as measured
//!    and mapped per harmonic to displacement coefficients, c_x = S c_m, with its noise
//!    propagated through S (see `projected.rs`); below, c is c_x and R⁻ᵀ reads R⁻ᵀSᵀ;
//! 2. projects each displacement channel on the kept harmonics,
//!    x̂ = B c, c = (BᵀB)⁻¹ Bᵀ x with B = QR the m × p design of the whole periods;
//!    v̂ = D c with D the derivative design. White noise of variance σ_j² on channel j
//!    gives Cov(c) = σ_j² (RᵀR)⁻¹, so at sample i
//!    Var v̂_ij = σ_j² ‖R⁻ᵀ d_i‖² and Var x̂_ij = σ_j² ‖R⁻ᵀ b_i‖²;
//! 3. evaluates every term on (x̂, v̂) and subtracts its expected noise contribution,
//!    Σ_i w_i E[p(x̂ + δx, v̂ + δv) − p(x̂, v̂)] ([`crate::terms::Law::noise_bias`]):
//!    σ_v² for v² (linear laws, dashpots), 3σ_v²|v| for |v|³ (quadratic), Σ_j C₀,jj
//!    Var v̂_j for a matrix term. A law of power v² is taken in the coefficients, the
//!    same sums once per window: cᵀ(DᵀWD)c in the element's relative coefficients less
//!    Σ_j σ_j² tr(DᵀWD C_j) (`quadratic.rs`). Coulomb columns are the exact total
//!    variation of the projected displacement (no velocity difference, no quadrature
//!    error at the kinks of |v̂|), which zero-mean noise leaves unbiased to first order;
//!    the input work ∫ rᵀ v̂ dt = ∫ rᵀ dx̂ needs no correction either (the noise is
//!    independent of r).
//!    Structural damping (a loss factor, force −k H[x̂_e] per unit η) is a quadratic form
//!    k cᵀ N c in the element's relative coefficients, less k tr(N Cov δc) (see
//!    `structural.rs`). History terms (forces with memory) are refused before the rows
//!    are built: their noise bias is not modelled;
//! 4. propagates the noise to first order into each equation's residual
//!    e = b − Σ_k θ_k A_k: every column and the input work is a smooth function of the
//!    projection coefficients c_j of each channel, so δe = Σ_j u_j(θ)ᵀ δc_j with
//!    u_j(θ) = ∂b/∂c_j − Σ_k θ_k ∂A_k/∂c_j, and
//!
//!    ```text
//!      Var e(θ) = Σ_j σ_j² ‖R⁻ᵀ u_j(θ)‖² + Σ_k σ_{f,k}² ‖∂b/∂s_k‖²,
//!    ```
//!
//!    the last term for noise σ_{f,k} on force channel k. [`RowNoise`] stores the
//!    whitened vectors z = σ_j R⁻ᵀ ∂(·)/∂c_j per channel, so Var e(θ) is a sum of
//!    squares of z_b − Σ θ_k z_k. The fit then weights each equation by 1/√Var e(θ),
//!    iterated from a row-normalised start ([`crate::fit::Weighting`]), and the plug-in
//!    covariance (Aᵀ W A)⁻¹ gives standard errors.
//!
//! Without noise (σ = 0 to round-off) the corrections vanish and the weights only
//! rebalance equations that are all exact.

mod gradients;
mod projected;
mod quadratic;
mod row;
mod sensitivity;
mod structural;

pub use sensitivity::{ChannelSensitivity, RowNoise};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::fourier::RecordNoises;
use crate::prep::quadrature::Quadrature;
use crate::prep::window::Window;
use crate::record::Record;
use crate::regressor::settings::WorkForm;
use crate::regressor::{Row, map_windows};

/// The noise-robust rows of `windows` of `records` (in parallel), and their noise
/// model. `harmonics`: `Some(K)` keeps harmonics 1..K, `None` those above the noise
/// floor of their record. `noises`: the records' harmonics and noise estimated already
/// (`prep/fourier/record_noise.rs`), where they are of these records; else estimated
/// here.
pub(crate) fn rows(
    model: &DampingModel,
    records: &[Record],
    windows: &[Window],
    quadrature: Quadrature,
    harmonics: Option<usize>,
    work_form: WorkForm,
    noises: Option<&RecordNoises>,
) -> Result<(Vec<Row>, NoiseModel)> {
    let noises = RecordNoises::given_or_of(noises, records);
    let robust = map_windows(true, windows, |w| {
        row::robust_row(
            model,
            &records[w.record],
            w,
            quadrature,
            harmonics,
            work_form,
            noises.get(w.record)?,
        )
    })?;
    let mut rows = Vec::with_capacity(robust.len());
    let mut noise = NoiseModel {
        rows: Vec::with_capacity(robust.len()),
        windows: Vec::with_capacity(robust.len()),
    };
    for r in robust {
        rows.push((r.columns, r.input));
        noise.rows.push(r.noise);
        noise.windows.push(r.window);
    }
    Ok((rows, noise))
}

/// What the noise-robust pipeline found in one window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowNoise {
    /// The record's label.
    pub record: String,
    /// The window's index within its record.
    pub window: usize,
    /// Harmonic orders kept for the velocities.
    pub harmonics: Vec<usize>,
    /// Estimated noise standard deviation per motion channel (per sample, in the units
    /// of its sensor: a displacement unless `sensors` says otherwise).
    pub displacement_noise: Vec<f64>,
    /// What each motion channel measures, when not every one is a displacement (empty
    /// otherwise); those channels are integrated per kept harmonic, with the mean of x̂
    /// and v̂ over the window set to zero.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<crate::record::Sensor>,
    /// Estimated noise standard deviation per force channel (per sample).
    pub force_noise: Vec<f64>,
}

/// Fewest rows a task of [`NoiseModel::residual_std`] takes: a row's variance is a few
/// hundred to a few thousand flops, so smaller tasks would cost more to share than to do.
const RESIDUAL_STD_ROWS: usize = 64;

/// The noise model of a regressor: one [`RowNoise`] and one [`WindowNoise`] per row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseModel {
    /// First-order noise sensitivities of each equation.
    pub rows: Vec<RowNoise>,
    /// What was estimated per window.
    pub windows: Vec<WindowNoise>,
}

impl NoiseModel {
    /// The standard deviation of each equation's residual at coefficients `theta`: the
    /// rows in parallel, each the same sums in the same order at any number of threads.
    pub fn residual_std(&self, theta: &[f64]) -> Vec<f64> {
        // one scratch buffer per task, not per row
        self.rows
            .par_iter()
            .with_min_len(RESIDUAL_STD_ROWS)
            .map_init(Vec::new, |buffer, r| r.std_with(theta, buffer))
            .collect()
    }

    /// The rows `indices` (with repeats), for resampling.
    pub fn select(&self, indices: &[usize]) -> Self {
        NoiseModel {
            rows: indices.iter().map(|&i| self.rows[i].clone()).collect(),
            windows: indices.iter().map(|&i| self.windows[i].clone()).collect(),
        }
    }
}
