//! Detecting the driving period of a record from its force signals.
//!
//! For force channels s_c(t_i), t_i = i h, i = 0..N−1, the estimate is the frequency of
//! the single sinusoid that explains most of the force's variance, fitted by least
//! squares with an offset in every channel:
//!
//! ```text
//!   J(ω) = Σ_c ‖P_ω s_c‖² − N s̄_c²,   P_ω = projection on span{1, cos ωt, sin ωt},
//!   ω̂ = argmax J(ω),   T̂ = 2π / ω̂.
//! ```
//!
//! This is the maximum-likelihood frequency of a sinusoid in white noise, and exact
//! (to round-off) for a clean sinusoid whatever the number of samples per period.
//! Three stages:
//!
//! 1. **Coarse**: the peak of the summed periodogram Σ_c |DFT(s_c − s̄_c)|², zero-padded
//!    to M ≥ 4N points (bins 2π/(Mh) apart, a quarter of the resolution 2π/(Nh)),
//!    excluding DC;
//! 2. **Refine**: golden-section search for the maximum of J over ±2 padded bins around
//!    the peak (inside the main lobe, where J is unimodal), to round-off: on a clean
//!    sinusoid the relative error of T̂ is about √ε / (2π · cycles).
//! 3. **Whole periods**: the record spans N h (each sample stands for one step, as
//!    for the periodic closure of [`crate::prep::window::periodic_closure`]), so it
//!    holds c = N h / T̂ periods. Synchronous acquisition saves records of exactly k
//!    periods (N h = kT, kT/h = N/k samples per k periods, the sample at kT left out).
//!    When N/k is a whole number for k = round(c) and c is within three standard
//!    deviations of k, the record is taken as exactly k periods and T̂ = N h / k:
//!    the data cannot tell T̂ from N h/k, and the windows then close periodically. The
//!    standard deviation is that of ω̂ for sinusoids in white noise with each
//!    channel's offset and amplitudes as nuisance parameters (to first order, at any
//!    record length), from each channel's fit (b_c, d_c) and residual variance
//!    σ_c² = (‖s_c − s̄_c‖² − J_c)/(N − 3):
//!
//!    ```text
//!      D_c = ‖(I − P_ω) t∘(d_c cos ωt − b_c sin ωt)‖²,
//!      var(ω̂) = Σ_c σ_c² D_c / (Σ_c D_c)²,   sd(c) = N h sd(ω̂) / 2π
//!    ```
//!
//!    (J sums the channels unweighted; for one channel this is the Cramér–Rao bound),
//!    floored at [`WHOLE_PERIOD_FLOOR`]·k (the refinement's round-off). A record that
//!    is not whole periods keeps the estimate T̂.
//!
//! The force must show a period: its variance must be nonzero and the fitted sinusoid
//! must explain at least [`MIN_EXPLAINED`] of it (a square wave's fundamental explains
//! 81%, random excitation a few percent); the record must hold at least [`MIN_CYCLES`]
//! periods, N h ≥ (2 − 0.05) T̂ (a record of exactly two periods does, with noise). Every failure is
//! [`Error::NoPeriod`], which asks for the record's `period` or `frequency`. A periodic
//! force whose strongest component is not its fundamental gives that component's
//! period: give such a record's period explicitly.

use std::f64::consts::PI;

use faer::MatRef;
use nalgebra::{Matrix3, Vector3};
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, check_finite};
use crate::record::Record;

/// Least share of the force variance the fitted sinusoid must explain.
pub const MIN_EXPLAINED: f64 = 0.5;
/// Least number of whole periods a record must hold for its period to be detected,
/// N h / T̂, less [`CYCLE_SLACK`] for the estimate's own error (a noisy record of
/// exactly two periods qualifies).
pub const MIN_CYCLES: f64 = 2.0;
/// How far below [`MIN_CYCLES`] the estimated count may fall.
pub const CYCLE_SLACK: f64 = 0.05;
/// Least half-width, relative to k, within which N h / T̂ counts as k whole periods.
pub const WHOLE_PERIOD_FLOOR: f64 = 1e-7;
/// Least number of samples.
const MIN_SAMPLES: usize = 8;
/// Zero-padding factor of the coarse periodogram.
const PADDING: usize = 4;
/// Half-width of the refinement bracket, in padded bins.
const BRACKET_BINS: f64 = 2.0;
/// Relative variance below which a force counts as constant (round-off of its mean).
const CONSTANT_VARIANCE: f64 = 1e-24;

/// A detected driving period.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PeriodEstimate {
    /// Driving period T̂.
    pub period: f64,
    /// Driving frequency ω̂ = 2π/T̂ (rad per unit time).
    pub frequency: f64,
    /// Share of the force variance the fitted sinusoid explains, J(ω̂) / Σ_c ‖s_c − s̄_c‖².
    pub explained: f64,
    /// Periods in the record as estimated, N h ω̂ / 2π (each sample stands for one
    /// step), before any rounding to whole periods.
    pub cycles: f64,
    /// Standard deviation of `cycles` from the noise of the fit (Cramér–Rao).
    pub cycles_std: f64,
    /// `Some(k)` when the record was taken as exactly k whole periods, T̂ = N h / k.
    pub whole_periods: Option<usize>,
}

/// Detects the driving period of force signals `signals` (N × channels) sampled every
/// `step`; `label` names the record in errors.
pub fn detect_period(signals: MatRef<'_, f64>, step: f64, label: &str) -> Result<PeriodEstimate> {
    if !(step.is_finite() && step > 0.0) {
        return Err(Error::invalid("step", step, "must be finite and positive"));
    }
    let (samples, channels) = signals.shape();
    if channels == 0 {
        return Err(Error::Empty {
            what: format!("force channels of record '{label}'"),
        });
    }
    if samples < MIN_SAMPLES {
        return Err(Error::NoPeriod {
            record: label.to_string(),
            explained: 0.0,
            reason: format!("it has {samples} samples, detection needs at least {MIN_SAMPLES}"),
        });
    }
    check_finite("force signals", signals)?;
    let centred: Vec<Vec<f64>> = (0..channels)
        .map(|c| {
            let column: Vec<f64> = signals.col(c).iter().copied().collect();
            let mean = column.iter().sum::<f64>() / samples as f64;
            column.iter().map(|s| s - mean).collect()
        })
        .collect();
    let variance: f64 = centred.iter().flatten().map(|s| s * s).sum();
    let scale: f64 = signals
        .col_iter()
        .flat_map(|c| c.iter())
        .map(|s| s * s)
        .sum();
    if variance <= CONSTANT_VARIANCE * scale || variance == 0.0 {
        return Err(Error::NoPeriod {
            record: label.to_string(),
            explained: 0.0,
            reason: "the force is constant".into(),
        });
    }
    let padded = (PADDING * samples).next_power_of_two();
    let bin = 2.0 * PI / (padded as f64 * step);
    let peak = periodogram_peak(&centred, padded);
    let nyquist = PI / step;
    let low = ((peak as f64 - BRACKET_BINS) * bin).max(0.25 * bin);
    let high = ((peak as f64 + BRACKET_BINS) * bin).min(nyquist);
    let explained_energy = |omega: f64| explained(&centred, step, omega).iter().sum::<f64>();
    let frequency = golden_maximum(explained_energy, low, high);
    let per_channel = explained(&centred, step, frequency);
    // A share is at most 1; the fit can exceed the variance by round-off.
    let share = (per_channel.iter().sum::<f64>() / variance).min(1.0);
    if share < MIN_EXPLAINED {
        return Err(Error::NoPeriod {
            record: label.to_string(),
            explained: share,
            reason: format!(
                "the strongest sinusoid (ω = {frequency:.6}) explains only {:.1}% of its variance, below {:.0}%",
                100.0 * share,
                100.0 * MIN_EXPLAINED
            ),
        });
    }
    let duration = samples as f64 * step;
    let cycles = duration * frequency / (2.0 * PI);
    let cycles_std = duration * frequency_std(&centred, step, frequency) / (2.0 * PI);
    let whole = cycles.round();
    let tolerance = (3.0 * cycles_std).max(WHOLE_PERIOD_FLOOR * whole);
    if cycles < MIN_CYCLES - CYCLE_SLACK {
        return Err(Error::NoPeriod {
            record: label.to_string(),
            explained: share,
            reason: format!(
                "it holds {cycles:.2} periods of its strongest sinusoid (T = {:.6}), detection needs at least {MIN_CYCLES}",
                2.0 * PI / frequency
            ),
        });
    }
    let whole_periods =
        (whole >= 1.0 && (cycles - whole).abs() <= tolerance && samples % (whole as usize) == 0)
            .then_some(whole as usize);
    let (period, frequency) = match whole_periods {
        Some(k) => (duration / k as f64, 2.0 * PI * k as f64 / duration),
        None => (2.0 * PI / frequency, frequency),
    };
    Ok(PeriodEstimate {
        period,
        frequency,
        explained: share,
        cycles,
        cycles_std,
        whole_periods,
    })
}

/// The standard deviation of ω̂ for the model s_c = a_c + b_c cos ωt + d_c sin ωt +
/// white noise of variance σ_c², with the offsets and amplitudes profiled out (exact
/// to first order for any record length, not only asymptotically). J sums the channels
/// unweighted, so with D_c = ‖(I − P) ∂s_c/∂ω‖², ∂s_c/∂ω = t (d_c cos ωt − b_c sin ωt),
/// P the projection on span{1, cos ωt, sin ωt}:
/// var(ω̂) = Σ_c σ_c² D_c / (Σ_c D_c)² (the Cramér–Rao bound σ²/D for one channel),
/// σ_c² = (‖s_c‖² − J_c)/(N − 3) for the centred channels. Zero when a channel fits
/// exactly (no noise to bound it).
fn frequency_std(centred: &[Vec<f64>], step: f64, omega: f64) -> f64 {
    let samples = centred[0].len();
    let Some(basis) = Basis::new(samples, step, omega) else {
        return f64::INFINITY;
    };
    let (mut curvature, mut spread) = (0.0, 0.0);
    for channel in centred {
        let (fitted, coefficients) = basis.fit(channel);
        let energy: f64 = channel.iter().map(|s| s * s).sum();
        let noise = (energy - fitted).max(0.0) / (samples as f64 - 3.0);
        if noise == 0.0 {
            return 0.0;
        }
        let derivative: Vec<f64> = (0..samples)
            .map(|i| {
                let t = i as f64 * step;
                t * (coefficients[2] * basis.cos[i] - coefficients[1] * basis.sin[i])
            })
            .collect();
        let (projected, _) = basis.fit(&derivative);
        let total: f64 = derivative.iter().map(|d| d * d).sum();
        let d = (total - projected).max(0.0);
        curvature += d;
        spread += noise * d;
    }
    if curvature > 0.0 {
        spread.sqrt() / curvature
    } else {
        f64::INFINITY
    }
}

/// The driving period of `record`, detected from its force channels (its own period is
/// not used).
pub fn detect_record_period(record: &Record) -> Result<PeriodEstimate> {
    detect_period(
        record.forcing().signals.as_ref(),
        record.step(),
        record.label(),
    )
}

/// Index of the largest bin, 1..padded/2, of Σ_c |DFT_padded(s_c)|².
fn periodogram_peak(centred: &[Vec<f64>], padded: usize) -> usize {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(padded);
    let mut power = vec![0.0; padded / 2 + 1];
    let mut buffer = vec![Complex::new(0.0, 0.0); padded];
    for channel in centred {
        buffer.fill(Complex::new(0.0, 0.0));
        for (b, s) in buffer.iter_mut().zip(channel) {
            b.re = *s;
        }
        fft.process(&mut buffer);
        for (p, b) in power.iter_mut().zip(&buffer) {
            *p += b.norm_sqr();
        }
    }
    (1..power.len())
        .max_by(|&a, &b| power[a].total_cmp(&power[b]))
        .unwrap_or(1)
}

/// The basis 1, cos ωt_i, sin ωt_i and the inverse of its Gram matrix.
struct Basis {
    cos: Vec<f64>,
    sin: Vec<f64>,
    inverse: Matrix3<f64>,
}

impl Basis {
    /// `None` when the Gram matrix is singular (ω at 0 or the Nyquist frequency).
    fn new(samples: usize, step: f64, omega: f64) -> Option<Self> {
        let (cos, sin): (Vec<f64>, Vec<f64>) = (0..samples)
            .map(|i| {
                let angle = omega * i as f64 * step;
                (angle.cos(), angle.sin())
            })
            .unzip();
        let ones = vec![1.0; samples];
        let basis = [&ones, &cos, &sin];
        let gram = Matrix3::from_fn(|i, j| dot(basis[i], basis[j]));
        let inverse = gram.try_inverse()?;
        Some(Basis { cos, sin, inverse })
    }

    /// ‖P y‖² and the least-squares coefficients of y on the basis.
    fn fit(&self, y: &[f64]) -> (f64, Vector3<f64>) {
        let rhs = Vector3::new(y.iter().sum(), dot(&self.cos, y), dot(&self.sin, y));
        let coefficients = self.inverse * rhs;
        (rhs.dot(&coefficients), coefficients)
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// J_c(ω) per channel: the variance of each centred channel explained by a
/// least-squares fit of a + b cos ωt + c sin ωt (J(ω) is their sum).
fn explained(centred: &[Vec<f64>], step: f64, omega: f64) -> Vec<f64> {
    let samples = centred[0].len();
    let Some(basis) = Basis::new(samples, step, omega) else {
        return vec![0.0; centred.len()];
    };
    centred
        .iter()
        .map(|y| {
            let (fitted, _) = basis.fit(y);
            // The centred channel has mean zero, so the offset alone explains nothing.
            let mean = y.iter().sum::<f64>();
            fitted - mean * mean / samples as f64
        })
        .collect()
}

/// The maximizer of a unimodal `f` on [a, b] by golden-section search, to round-off.
fn golden_maximum(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - ratio * (b - a);
    let mut d = a + ratio * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= 4.0 * f64::EPSILON * b.abs() {
            break;
        }
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    if fc >= fd { c } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    #[test]
    fn golden_section_finds_a_parabola_top() {
        let top = golden_maximum(|x| -(x - 0.3).powi(2), 0.0, 1.0);
        assert!((top - 0.3).abs() < 1e-7);
    }

    #[test]
    fn two_channels_share_one_period() {
        let (omega, h) = (1.3, 0.05);
        let s = Mat::from_fn(800, 2, |i, c| {
            let t = i as f64 * h;
            (omega * t + c as f64).cos() * (1.0 + c as f64) + 0.2
        });
        let estimate = detect_period(s.as_ref(), h, "two").unwrap();
        assert!((estimate.frequency - omega).abs() < 1e-8 * omega);
        assert!(estimate.explained > 0.999_999);
    }
}
