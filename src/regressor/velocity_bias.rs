//! The expected velocity-noise bias of each column, computed while the rows are built
//! (from each window's samples, weights and velocities), for the assessment of
//! [`crate::analysis::velocity_noise`].
//!
//! Per window of whole periods, the noise σ_j of each displacement channel comes from
//! the noise floor between the harmonics ([`crate::prep::velocity::harmonic_selection`],
//! the estimate the noise-robust pipeline uses). White noise of variance σ_j² gives the
//! velocity estimate a variance per sample of
//!
//! ```text
//!   central differences  v_i = (x_{i+1} − x_{i−1})/2h:   Var v = σ²/(2h²)
//!   spectral, harmonic projection on the harmonics S over m samples of whole periods:
//!                                                        Var v = (2σ²/m) Σ_{k∈S} (kω)²
//! ```
//!
//! (the derivative of a least-squares Fourier series: each coefficient has variance
//! 2σ²/m). A column's expected noise contribution over the window is then
//!
//! ```text
//!   matrix term C₀ (viscous, θK, θM):  B = Σ_i w_i Σ_j C₀,jj Var v_j
//!   a law on element e (DOFs a, b):    B = Σ_i w_i E[p(x_i, v_i + δv) − p(x_i, v_i)],
//!                                      Var δv = Var v_a + Var v_b
//! ```
//!
//! ([`crate::terms::Law::noise_bias`]). Assessed: central differences, spectral
//! velocities and harmonic projection with the noise correction off, over windows of
//! whole periods. Not assessed: measured velocities (their noise is not in the
//! displacements), the noise-robust rows (already corrected), fixed spans (no whole
//! periods for the noise floor). Forces with memory and structural damping get no bias
//! model here (they add none).

use crate::terms::OnElements;
use faer::{Mat, MatRef};

use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::fourier::default_harmonics;
use crate::prep::velocity::{VelocitySource, harmonic_selection};
use crate::prep::window::Window;
use crate::record::{Record, col};
use crate::regressor::settings::{NoiseTreatment, RegressorSettings};
use crate::terms::{Coefficients, Term};

/// The expected velocity-noise bias B of every entry of the regressor.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct VelocityBias {
    /// The estimator (its model-file name).
    pub estimator: String,
    /// B, equations × coefficients.
    #[serde(with = "super::serde_mat")]
    pub matrix: Mat<f64>,
    /// σ_v / (ω σ): the estimator's velocity noise relative to that of the
    /// fundamental harmonic, the largest over the windows.
    pub gain: f64,
    /// The smallest and largest displacement noise σ estimated (per sample).
    pub displacement_noise: [f64; 2],
}

/// Which harmonics a Fourier-series velocity keeps.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Harmonics {
    /// Not a Fourier series (central differences).
    None,
    /// 1..K, or the default K for the period when `None`.
    Fixed(Option<usize>),
    /// Those above the noise floor.
    Selected,
}

impl Harmonics {
    /// The velocity estimator of `settings` when its bias is assessed (module doc).
    pub(crate) fn assessed(settings: &RegressorSettings) -> Option<Self> {
        settings.windows.cycles()?;
        match settings.velocity {
            VelocitySource::Measured => None,
            VelocitySource::HarmonicProjection { .. }
                if settings.noise != NoiseTreatment::Ignore =>
            {
                None
            }
            VelocitySource::CentralDifference => Some(Harmonics::None),
            VelocitySource::Spectral { harmonics } => Some(Harmonics::Fixed(harmonics)),
            VelocitySource::HarmonicProjection { harmonics: Some(k) } => {
                Some(Harmonics::Fixed(Some(k)))
            }
            VelocitySource::HarmonicProjection { harmonics: None } => Some(Harmonics::Selected),
        }
    }
}

/// One window's bias per column, its largest velocity-noise gain and its range of
/// displacement noise.
pub(crate) struct WindowBias {
    pub columns: Vec<f64>,
    pub gain: f64,
    pub noise: [f64; 2],
}

/// The bias of window `w` of `record` (module doc), whose rows used the weights
/// `weights` and the velocities `v` (one row per weight).
pub(crate) fn window(
    model: &DampingModel,
    record: &Record,
    w: &Window,
    harmonics: Harmonics,
    weights: &[f64],
    v: MatRef<'_, f64>,
) -> Result<WindowBias> {
    let h = record.step();
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let count = weights.len();
    let selection = harmonic_selection(record, w.start, count)?;
    let sigma = &selection.noise_std;
    let m = selection.samples.max(1) as f64;
    let squares =
        |orders: &mut dyn Iterator<Item = usize>| -> f64 { orders.map(|k| (k * k) as f64).sum() };
    // Var v / σ² per sample, the same for every channel
    let ratio = match harmonics {
        Harmonics::None => 1.0 / (2.0 * h * h),
        Harmonics::Fixed(k) => {
            let k = k.unwrap_or_else(|| default_harmonics(record.period() / h));
            2.0 / m * omega * omega * squares(&mut (1..=k))
        }
        Harmonics::Selected => {
            2.0 / m * omega * omega * squares(&mut selection.kept.iter().copied())
        }
    };
    let var_v: Vec<f64> = sigma.iter().map(|s| s * s * ratio).collect();
    let x = record.displacements();
    let index = |i: usize| sample_index(record, w, i);
    let mut out = vec![0.0; model.coefficient_count()];
    for (term, range) in model.term_columns() {
        match term {
            Term::Matrix(t) => {
                let c0 = t.matrix();
                let per_sample: f64 = (0..var_v.len()).map(|j| c0[(j, j)] * var_v[j]).sum();
                out[range.start] += per_sample * weights.iter().sum::<f64>();
            }
            // A force with memory, or structural damping (whose −kH[x] shares the noise
            // of x with the differenced v, a bias not modelled here), adds none.
            Term::History(_) | Term::Structural(_) => {}
            Term::Elements(t) => {
                let law = t.law();
                for (e, element) in t.elements().iter().enumerate() {
                    let weight = t.weights().map_or(1.0, |w| w[e]);
                    let column = match t.coefficients() {
                        Coefficients::Shared(_) => range.start,
                        Coefficients::PerElement(_) => range.start + e,
                    };
                    let mut variance = var_v[element.a];
                    if let Some(b) = element.b {
                        variance += var_v[b];
                    }
                    let (xa, va) = (col(x, element.a), col(v, element.a));
                    let mut sum = 0.0;
                    for (i, wi) in weights.iter().enumerate() {
                        let (mut xr, mut vr) = (xa[index(i)], va[i]);
                        if let Some(b) = element.b {
                            xr -= col(x, b)[index(i)];
                            vr -= col(v, b)[i];
                        }
                        sum += wi * law.noise_bias(xr, vr, 0.0, variance);
                    }
                    out[column] += weight * sum;
                }
            }
        }
    }
    let (lowest, highest) = sigma
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, u), s| (l.min(*s), u.max(*s)));
    Ok(WindowBias {
        columns: out,
        gain: ratio.sqrt() / omega,
        noise: [lowest, highest],
    })
}

impl VelocityBias {
    /// The bias of every window, in row order, with `columns` columns (the damping
    /// coefficients; nuisance columns, if any, get none).
    pub(crate) fn of(
        settings: &RegressorSettings,
        windows: Vec<WindowBias>,
        columns: usize,
    ) -> Self {
        let mut matrix = Mat::<f64>::zeros(windows.len(), columns);
        let (mut gain, mut lowest, mut highest) = (0.0f64, f64::INFINITY, 0.0f64);
        for (row, w) in windows.iter().enumerate() {
            gain = gain.max(w.gain);
            lowest = lowest.min(w.noise[0]);
            highest = highest.max(w.noise[1]);
            for (k, b) in w.columns.iter().enumerate().take(columns) {
                matrix[(row, k)] = *b;
            }
        }
        VelocityBias {
            estimator: settings.velocity.name().to_string(),
            matrix,
            gain,
            displacement_noise: [lowest.min(highest), highest],
        }
    }
}

/// The record's sample for the window's i-th weight (wrapped for a window that closes
/// periodically).
fn sample_index(record: &Record, w: &Window, i: usize) -> usize {
    match w.closed_length(record.step()) {
        Some(length) => w.start + i % length,
        None => (w.start + i).min(record.samples() - 1),
    }
}
