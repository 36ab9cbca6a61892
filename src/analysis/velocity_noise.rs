//! Is the velocity estimator the problem? With noisy displacements, a velocity
//! estimated by differencing carries the noise amplified, and every column built from
//! v² or |v|³ is biased upwards by its variance: the fit then takes the input work as
//! more dissipation per unit coefficient and the coefficients come out low, even
//! negative. This module estimates that bias from the data and says when it matters.
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
//! ([`crate::terms::Law::noise_bias`]: Var v for a linear dashpot, so a viscous column is
//! biased by ≈ Σ w_i σ²/(2h²) per window with central differences; 3|v| Var v for a
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

use crate::error::Result;
use crate::fit::least_squares;
use crate::model::DampingModel;
use crate::prep::fourier::default_harmonics;
use crate::prep::velocity::{VelocitySource, harmonic_selection};
use crate::prep::window::Window;
use crate::record::{Record, col};
use crate::regressor::{NoiseTreatment, Regressor, RegressorSettings};
use crate::terms::{Coefficients, Term};

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

/// Assesses the velocity-noise bias of `regressor`, built from `records` with `model`
/// and `settings`; `None` when the estimator is not one assessed here (module doc) or
/// the windows do not match the regressor's rows.
pub fn assess(
    model: &DampingModel,
    records: &[Record],
    settings: &RegressorSettings,
    regressor: &Regressor,
) -> Result<Option<VelocityNoise>> {
    let Some(spec) = settings.windows.cycles() else {
        return Ok(None);
    };
    let harmonics = match settings.velocity {
        VelocitySource::Measured => return Ok(None),
        VelocitySource::HarmonicProjection { .. } if settings.noise != NoiseTreatment::Ignore => {
            return Ok(None);
        }
        VelocitySource::CentralDifference => Harmonics::None,
        VelocitySource::Spectral { harmonics } => Harmonics::Fixed(harmonics),
        VelocitySource::HarmonicProjection { harmonics: Some(k) } => Harmonics::Fixed(Some(k)),
        VelocitySource::HarmonicProjection { harmonics: None } => Harmonics::Selected,
    };
    let mut windows: Vec<Window> = Vec::new();
    for (r, record) in records.iter().enumerate() {
        windows.extend(spec.windows(record, r, settings.quadrature)?);
    }
    let damping = model.coefficient_count();
    let a = regressor.matrix();
    if windows.len() != a.nrows() || damping > a.ncols() {
        return Ok(None);
    }
    let mut bias = Mat::<f64>::zeros(a.nrows(), a.ncols());
    let (mut gain, mut lowest, mut highest) = (0.0f64, f64::INFINITY, 0.0f64);
    for (row, w) in windows.iter().enumerate() {
        let record = &records[w.record];
        let window = WindowNoise::of(record, w, settings, harmonics)?;
        gain = gain.max(window.gain);
        for s in &window.sigma {
            lowest = lowest.min(*s);
            highest = highest.max(*s);
        }
        let column_bias = window.column_bias(model, record, w, settings)?;
        for (k, b) in column_bias.into_iter().enumerate() {
            bias[(row, k)] = b;
        }
    }
    let corrected = Regressor::from_parts(
        a - &bias,
        regressor.rhs().to_vec(),
        regressor.columns().to_vec(),
        regressor.rows().to_vec(),
    )?;
    let tolerance = 1e-10;
    let before = least_squares(regressor, tolerance)?.coefficients;
    let after = least_squares(&corrected, tolerance)?.coefficients;
    let columns: Vec<ColumnBias> = (0..damping)
        .map(|k| {
            let size: f64 = (0..a.nrows()).map(|r| a[(r, k)].abs()).sum();
            let noise: f64 = (0..a.nrows()).map(|r| bias[(r, k)]).sum();
            ColumnBias {
                name: regressor.columns()[k].clone(),
                share: if size > 0.0 { noise / size } else { 0.0 },
                shift: after[k] - before[k],
                corrected: after[k],
            }
        })
        .collect();
    let material = columns.iter().any(|c| c.share >= MATERIAL_SHARE);
    Ok(Some(VelocityNoise {
        estimator: settings.velocity.name().to_string(),
        gain,
        displacement_noise: [lowest.min(highest), highest],
        columns,
        material,
        recommended: "harmonic_projection".into(),
    }))
}

/// [`assess`], with `None` when the assessment itself fails (a window too short for the
/// noise floor): it adds to a report and never stops an identification.
pub fn assess_or_none(
    model: &DampingModel,
    records: &[Record],
    settings: &RegressorSettings,
    regressor: &Regressor,
) -> Option<VelocityNoise> {
    assess(model, records, settings, regressor).ok().flatten()
}

/// Which harmonics a Fourier-series velocity keeps.
#[derive(Debug, Clone, Copy)]
enum Harmonics {
    /// Not a Fourier series (central differences).
    None,
    /// 1..K, or the default K for the period when `None`.
    Fixed(Option<usize>),
    /// Those above the noise floor.
    Selected,
}

/// One window's displacement noise and the velocity variance it gives per DOF.
struct WindowNoise {
    sigma: Vec<f64>,
    var_v: Vec<f64>,
    gain: f64,
}

impl WindowNoise {
    fn of(
        record: &Record,
        w: &Window,
        settings: &RegressorSettings,
        harmonics: Harmonics,
    ) -> Result<Self> {
        let h = record.step();
        let omega = 2.0 * std::f64::consts::PI / record.period();
        let count = w.samples(settings.quadrature, h);
        let selection = harmonic_selection(record, w.start, count)?;
        let sigma = selection.noise_std.clone();
        let m = selection.samples.max(1) as f64;
        let squares = |orders: &mut dyn Iterator<Item = usize>| -> f64 {
            orders.map(|k| (k * k) as f64).sum()
        };
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
        Ok(WindowNoise {
            var_v: sigma.iter().map(|s| s * s * ratio).collect(),
            sigma,
            gain: ratio.sqrt() / omega,
        })
    }

    /// B per column of `model` for window `w` (the module doc's sums).
    fn column_bias(
        &self,
        model: &DampingModel,
        record: &Record,
        w: &Window,
        settings: &RegressorSettings,
    ) -> Result<Vec<f64>> {
        let h = record.step();
        let weights = w.weights(settings.quadrature, h, record.period())?;
        let count = weights.len();
        let velocities = settings.velocity.velocities_of(record, w, count)?;
        let v = velocities.as_ref();
        let x = record.displacements();
        let index = |i: usize| sample_index(record, w, i);
        let mut out = vec![0.0; model.coefficient_count()];
        for (term, range) in model.term_columns() {
            match term {
                Term::Matrix(t) => {
                    let c0 = t.matrix();
                    let per_sample: f64 = (0..self.var_v.len())
                        .map(|j| c0[(j, j)] * self.var_v[j])
                        .sum();
                    out[range.start] += per_sample * weights.iter().sum::<f64>();
                }
                // A force with memory, or structural damping (whose −kH[x] shares the
                // noise of x with the differenced v, a bias not modelled here), has no
                // noise-bias model here: it adds none.
                Term::History(_) | Term::Structural(_) => {}
                Term::Elements(t) => {
                    let law = t.law();
                    for (e, element) in t.elements().iter().enumerate() {
                        let weight = t.weights().map_or(1.0, |w| w[e]);
                        let column = match t.coefficients() {
                            Coefficients::Shared(_) => range.start,
                            Coefficients::PerElement(_) => range.start + e,
                        };
                        let mut variance = self.var_v[element.a];
                        if let Some(b) = element.b {
                            variance += self.var_v[b];
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
        Ok(out)
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
