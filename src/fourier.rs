//! Least-squares Fourier series in the harmonics of the driving frequency ω:
//!
//!   x(t) ≈ a_0 + Σ_{k ∈ S} (a_k cos kωt + b_k sin kωt),
//!
//! over a set S of harmonic orders (usually 1..K), fitted over the samples of a window
//! of whole periods. The basis is exactly T-periodic whatever the sampling step, so it
//! serves windows whose period is not a whole number of samples (the four-mass case has
//! T/h = 101.67). Its derivative gives spectral velocities, and its mean a_0 times the
//! window span gives the spectral quadrature rule. When T/h is an integer and
//! K < T/(2h), the fit reproduces the truncated discrete Fourier series.
//!
//! Harmonic k as a phasor: a_k cos θ + b_k sin θ = A_k cos(θ − φ_k) with
//! A_k = √(a_k² + b_k²) and φ_k = atan2(b_k, a_k) (a phase lag).
//!
//! **Noise floor and automatic harmonic selection** ([`select_harmonics`]). Fit every
//! harmonic 1..K_max (K_max the default count, 45% of Nyquist) over the m samples of the
//! window's whole periods. For white noise of variance σ² each coefficient has variance
//! ≈ 2σ²/m, so a harmonic that carries noise only has power P_k = a_k² + b_k² ~
//! exponential with mean 4σ²/m, whose median is (4σ²/m)·ln 2. A periodic response
//! carries signal in a few low harmonics; the upper harmonics are out of band and carry
//! the noise. Per channel, the per-bin noise power is therefore estimated robustly as
//!
//!   P̂_noise = median_{k = 2..K_max} P_k / ln 2,   σ̂_A = √P̂_noise,
//!
//! (the median ignores the minority of bins that carry signal), floored at
//! 10⁻¹² max_k A_k for round-off. Harmonic k is kept when A_k > 3.5 σ̂_A in any
//! channel; the fundamental is always kept. A noise-only bin passes with probability
//! exp(−3.5²) ≈ 5·10⁻⁶.

use faer::prelude::*;
use faer::{Mat, MatRef};

use crate::error::{Error, Result};

/// Amplitude over the per-bin noise amplitude above which a harmonic is kept.
pub(crate) const NOISE_THRESHOLD: f64 = 3.5;

/// Round-off floor of the noise amplitude, relative to a channel's largest harmonic.
const ROUND_OFF: f64 = 1e-12;

/// Default number of harmonics for a period of `samples_per_period` samples: 45% of
/// the Nyquist count, leaving a margin so that the basis stays well conditioned when
/// the period is not a whole number of samples.
pub(crate) fn default_harmonics(samples_per_period: f64) -> usize {
    ((0.45 * samples_per_period).floor() as usize).max(1)
}

/// A harmonic A cos(ωt − φ): amplitude A ≥ 0 and phase lag φ in (−π, π].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Phasor {
    /// Amplitude A.
    pub amplitude: f64,
    /// Phase lag φ (rad).
    pub phase: f64,
}

impl Phasor {
    /// The phasor of a cos θ + b sin θ.
    pub(crate) fn from_cos_sin(a: f64, b: f64) -> Self {
        Phasor {
            amplitude: a.hypot(b),
            phase: b.atan2(a),
        }
    }
}

/// φ wrapped into (−π, π].
pub(crate) fn wrap_phase(phase: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    let wrapped = phase - two_pi * (phase / two_pi).round();
    if wrapped <= -std::f64::consts::PI {
        wrapped + two_pi
    } else {
        wrapped
    }
}

/// The samples of a window that cover its whole periods.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct WholePeriods {
    /// Whole driving periods k.
    pub(crate) periods: usize,
    /// Samples t_0 .. t_0 + kT, i.e. ⌊kT/h⌋ + 1 (fewer when the record ends first).
    pub(crate) samples: usize,
}

impl WholePeriods {
    /// The whole periods of a window of `count` samples that may read up to `available`
    /// samples: k = round(count·h/T) (the quadrature rules read between ⌊kT/h⌋ and
    /// ⌊kT/h⌋ + 2 samples), and the samples inside [t_0, t_0 + kT].
    pub(crate) fn of_window(
        count: usize,
        available: usize,
        step: f64,
        period: f64,
    ) -> Result<Self> {
        let per_period = period / step;
        let periods = (count as f64 / per_period).round() as usize;
        if periods == 0 {
            return Err(Error::invalid(
                "samples per window",
                count as f64,
                &format!(
                    "a harmonic fit needs a window of whole periods, and {count} samples cover less than half of one period of {per_period:.3} samples"
                ),
            ));
        }
        let length = periods as f64 * per_period;
        let whole = if (length - length.round()).abs() <= 1e-9 * length.max(1.0) {
            length.round()
        } else {
            length.floor()
        };
        let samples = (whole as usize + 1).min(available.max(count));
        if samples < 3 {
            return Err(Error::invalid(
                "samples per window",
                samples as f64,
                "a harmonic fit needs at least 3 samples (a mean and one harmonic)",
            ));
        }
        Ok(WholePeriods { periods, samples })
    }
}

/// A harmonic basis on the times t_i = i h, i = 0..m, with harmonic orders S.
pub(crate) struct HarmonicBasis {
    omega: f64,
    orders: Vec<usize>,
    step: f64,
    samples: usize,
}

impl HarmonicBasis {
    /// Harmonics 1..=K. Checks that the fit is overdetermined and below the Nyquist
    /// frequency.
    pub(crate) fn new(omega: f64, harmonics: usize, step: f64, samples: usize) -> Result<Self> {
        let columns = 2 * harmonics + 1;
        if harmonics == 0 {
            return Err(Error::invalid("harmonics", 0.0, "must be at least 1"));
        }
        if samples < columns {
            return Err(Error::invalid(
                "harmonics",
                harmonics as f64,
                &format!(
                    "a window of {samples} samples can fit at most {} harmonics",
                    (samples.saturating_sub(1)) / 2
                ),
            ));
        }
        Self::with_orders(omega, (1..=harmonics).collect(), step, samples)
    }

    /// The harmonic orders `orders` (ascending, distinct, ≥ 1).
    pub(crate) fn with_orders(
        omega: f64,
        orders: Vec<usize>,
        step: f64,
        samples: usize,
    ) -> Result<Self> {
        let Some(&highest) = orders.last() else {
            return Err(Error::invalid("harmonics", 0.0, "must be at least 1"));
        };
        if orders[0] == 0 || orders.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::invalid(
                "harmonics",
                orders[0] as f64,
                "harmonic orders must be ascending, distinct and at least 1",
            ));
        }
        let columns = 2 * orders.len() + 1;
        if samples < columns {
            return Err(Error::invalid(
                "harmonics",
                orders.len() as f64,
                &format!(
                    "a window of {samples} samples can fit at most {} harmonics",
                    (samples.saturating_sub(1)) / 2
                ),
            ));
        }
        let nyquist = std::f64::consts::PI / step;
        if highest as f64 * omega >= nyquist {
            return Err(Error::invalid(
                "harmonics",
                highest as f64,
                &format!(
                    "harmonic {highest} of ω = {omega} is above the Nyquist frequency {nyquist}"
                ),
            ));
        }
        Ok(HarmonicBasis {
            omega,
            orders,
            step,
            samples,
        })
    }

    fn columns(&self) -> usize {
        2 * self.orders.len() + 1
    }

    /// rows × (2|S|+1) design matrix [1, cos k₁ωt, sin k₁ωt, cos k₂ωt, …] at t_i = i h.
    fn design(&self, rows: usize) -> Mat<f64> {
        let mut design = Mat::<f64>::zeros(rows, self.columns());
        self.for_each_harmonic(rows, |i, slot, _, (cos, sin)| {
            design[(i, 2 * slot + 1)] = cos;
            design[(i, 2 * slot + 2)] = sin;
        });
        design.col_mut(0).fill(1.0);
        design
    }

    /// The time derivative of the design matrix at t_i = i h, i = 0..rows.
    fn derivative_design(&self, rows: usize) -> Mat<f64> {
        let mut design = Mat::<f64>::zeros(rows, self.columns());
        self.for_each_harmonic(rows, |i, slot, kw, (cos, sin)| {
            design[(i, 2 * slot + 1)] = -kw * sin;
            design[(i, 2 * slot + 2)] = kw * cos;
        });
        design
    }

    /// Calls `f(i, slot, kω, (cos kωt_i, sin kωt_i))` for every sample i < rows and every
    /// order k = S[slot]. One sine and cosine per sample; the harmonics follow by
    /// complex multiplication, e^{ikθ} = e^{iθ} e^{i(k−1)θ} (relative error about k ε,
    /// against 2|S| calls of sin and cos per sample).
    fn for_each_harmonic(&self, rows: usize, mut f: impl FnMut(usize, usize, f64, (f64, f64))) {
        let highest = *self.orders.last().expect("a basis has at least one order");
        for i in 0..rows {
            let (sin1, cos1) = (self.omega * i as f64 * self.step).sin_cos();
            let (mut cos, mut sin) = (1.0, 0.0);
            let mut slot = 0;
            for k in 1..=highest {
                (cos, sin) = (cos * cos1 - sin * sin1, sin * cos1 + cos * sin1);
                if self.orders[slot] == k {
                    f(i, slot, k as f64 * self.omega, (cos, sin));
                    slot += 1;
                    if slot == self.orders.len() {
                        break;
                    }
                }
            }
        }
    }

    /// Least-squares coefficients ((2|S|+1) × n: a_0, then a_k, b_k per order) of every
    /// column of `values` (m × n).
    pub(crate) fn fit(&self, values: MatRef<'_, f64>) -> Mat<f64> {
        self.design(self.samples).qr().solve_lstsq(values)
    }

    /// The phasor of the `index`-th order of S in every column of `coefficients`.
    pub(crate) fn phasors(&self, coefficients: &Mat<f64>, index: usize) -> Vec<Phasor> {
        (0..coefficients.ncols())
            .map(|c| {
                Phasor::from_cos_sin(
                    coefficients[(2 * index + 1, c)],
                    coefficients[(2 * index + 2, c)],
                )
            })
            .collect()
    }

    /// The derivative of the fitted series at t_i = i h, i = 0..rows (rows may exceed
    /// the fitted samples: the series is periodic).
    pub(crate) fn derivative(&self, coefficients: &Mat<f64>, rows: usize) -> Mat<f64> {
        self.derivative_design(rows) * coefficients
    }

    /// Fits every column of `values` (m × n) and returns the derivative of the fitted
    /// series at the same samples (m × n).
    pub(crate) fn differentiate(&self, values: MatRef<'_, f64>) -> Mat<f64> {
        let coefficients = self.fit(values);
        self.derivative(&coefficients, self.samples)
    }

    /// Weights w (length m) such that Σ w_i p(t_i) = span · a_0(p): the integral over
    /// the window of the fitted periodic series. w = span · Q R^{-T} e_0 for B = QR.
    ///
    /// Since Q = B R⁻¹, w = span · B z with z = R⁻¹ R⁻ᵀ e_0: two triangular solves and
    /// one product, without forming Q.
    pub(crate) fn integration_weights(&self, span: f64) -> Vec<f64> {
        let design = self.design(self.samples);
        let r = design.qr().thin_R().to_owned();
        let mut z = Mat::<f64>::zeros(self.columns(), 1);
        z[(0, 0)] = 1.0;
        r.transpose().solve_lower_triangular_in_place(z.as_mut());
        r.solve_upper_triangular_in_place(z.as_mut());
        let w = design * z;
        (0..self.samples).map(|i| span * w[(i, 0)]).collect()
    }
}

/// Which harmonics stand above the noise floor of a window, and the evidence.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HarmonicSelection {
    /// Whole driving periods in the window.
    pub periods: usize,
    /// Samples fitted (those inside the whole periods).
    pub samples: usize,
    /// Harmonic orders kept, ascending; always starts with 1.
    pub kept: Vec<usize>,
    /// Per channel, the estimated per-bin noise amplitude σ̂_A.
    pub noise_amplitude: Vec<f64>,
    /// Per channel, the amplitude A_k of harmonics k = 1..=K_max of the full fit.
    pub amplitudes: Vec<Vec<f64>>,
}

/// Selects the harmonics of ω = 2π/`period` that stand above the noise floor in any
/// column of `x` (m × n samples of `periods` whole periods), by the rule of the module
/// doc.
pub(crate) fn select_harmonics(
    x: MatRef<'_, f64>,
    step: f64,
    period: f64,
    periods: usize,
) -> Result<HarmonicSelection> {
    let m = x.nrows();
    let omega = 2.0 * std::f64::consts::PI / period;
    let most = default_harmonics(period / step).min((m.saturating_sub(1)) / 2);
    let basis = HarmonicBasis::new(omega, most, step, m)?;
    let coefficients = basis.fit(x);
    let mut kept = vec![1];
    let mut noise_amplitude = Vec::with_capacity(x.ncols());
    let mut amplitudes = Vec::with_capacity(x.ncols());
    let mut above = vec![false; most + 1];
    for channel in 0..x.ncols() {
        let amps: Vec<f64> = (0..most)
            .map(|k| coefficients[(2 * k + 1, channel)].hypot(coefficients[(2 * k + 2, channel)]))
            .collect();
        let mut powers: Vec<f64> = amps[1..].iter().map(|a| a * a).collect();
        let floor = ROUND_OFF * amps.iter().cloned().fold(0.0, f64::max);
        let noise = if powers.is_empty() {
            floor
        } else {
            powers.sort_by(f64::total_cmp);
            let mid = powers.len() / 2;
            let median = if powers.len() % 2 == 1 {
                powers[mid]
            } else {
                0.5 * (powers[mid - 1] + powers[mid])
            };
            (median / std::f64::consts::LN_2).sqrt().max(floor)
        };
        for (k, a) in amps.iter().enumerate().skip(1) {
            if *a > NOISE_THRESHOLD * noise {
                above[k + 1] = true;
            }
        }
        noise_amplitude.push(noise);
        amplitudes.push(amps);
    }
    kept.extend((2..=most).filter(|&k| above[k]));
    Ok(HarmonicSelection {
        periods,
        samples: m,
        kept,
        noise_amplitude,
        amplitudes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x = 1 + 0.5 cos ωt − 0.2 sin 3ωt sampled with T/h = 37.3 (not an integer):
    /// the derivative must be exact to round-off, v = −0.5ω sin ωt − 0.6ω cos 3ωt.
    #[test]
    fn differentiates_band_limited_signal_exactly_on_incommensurate_grid() {
        let omega = 2.0 * std::f64::consts::PI / 3.73;
        let h = 0.1;
        let m = 75; // two periods (74.6 samples) and a bit
        let x = Mat::from_fn(m, 1, |i, _| {
            let t = i as f64 * h;
            1.0 + 0.5 * (omega * t).cos() - 0.2 * (3.0 * omega * t).sin()
        });
        let basis = HarmonicBasis::new(omega, 8, h, m).unwrap();
        let v = basis.differentiate(x.as_ref());
        for i in 0..m {
            let t = i as f64 * h;
            let exact = -0.5 * omega * (omega * t).sin() - 0.6 * omega * (3.0 * omega * t).cos();
            assert!((v[(i, 0)] - exact).abs() < 1e-10, "sample {i}");
        }
    }

    /// ∫_0^T cos²(ωt) dt = T/2 exactly from samples that do not close the period.
    #[test]
    fn integration_weights_are_exact_for_trigonometric_polynomials() {
        let period = 3.73;
        let omega = 2.0 * std::f64::consts::PI / period;
        let h = 0.1;
        let m = 38; // t = 0 .. 3.7 < T
        let basis = HarmonicBasis::new(omega, 5, h, m).unwrap();
        let w = basis.integration_weights(period);
        let integral: f64 = (0..m)
            .map(|i| w[i] * (omega * i as f64 * h).cos().powi(2))
            .sum();
        assert!((integral - period / 2.0).abs() < 1e-12);
    }

    /// A chosen set of orders {1, 4} fits x = cos ωt + 0.1 sin 4ωt exactly and gives its
    /// phasors: 0.1 sin θ = 0.1 cos(θ − π/2).
    #[test]
    fn fits_a_set_of_orders_and_reads_phasors() {
        let omega = 2.0 * std::f64::consts::PI / 2.91;
        let (h, m) = (0.1, 30);
        let x = Mat::from_fn(m, 1, |i, _| {
            let t = i as f64 * h;
            (omega * t).cos() + 0.1 * (4.0 * omega * t).sin()
        });
        let basis = HarmonicBasis::with_orders(omega, vec![1, 4], h, m).unwrap();
        let c = basis.fit(x.as_ref());
        let first = basis.phasors(&c, 0)[0];
        let fourth = basis.phasors(&c, 1)[0];
        assert!((first.amplitude - 1.0).abs() < 1e-12 && first.phase.abs() < 1e-12);
        assert!((fourth.amplitude - 0.1).abs() < 1e-12);
        assert!((fourth.phase - std::f64::consts::FRAC_PI_2).abs() < 1e-10);
        assert!(HarmonicBasis::with_orders(omega, vec![2, 2], h, m).is_err());
        assert!(HarmonicBasis::with_orders(omega, vec![], h, m).is_err());
    }

    /// Each rule's window of k periods maps back to k whole periods and the ⌊kT/h⌋ + 1
    /// samples inside them (T/h = 101.67: 102 samples for one period, 204 for two).
    #[test]
    fn whole_periods_of_every_rule() {
        let (h, period) = (0.1, 10.167);
        for cycles in [1usize, 2, 7] {
            let span = cycles as f64 * period;
            let inside = (span / h).floor() as usize + 1;
            for rule in [
                crate::quadrature::Quadrature::Rectangular,
                crate::quadrature::Quadrature::Trapezoid,
                crate::quadrature::Quadrature::Spectral,
            ] {
                let count = rule.samples(span, h);
                let whole = WholePeriods::of_window(count, 10_000, h, period).unwrap();
                assert_eq!(whole.periods, cycles, "{rule:?}");
                assert_eq!(whole.samples, inside, "{rule:?}");
            }
        }
        assert!(WholePeriods::of_window(40, 10_000, h, period).is_err());
    }

    #[test]
    fn wraps_phases_into_the_half_open_interval() {
        use std::f64::consts::PI;
        assert_eq!(wrap_phase(PI), PI);
        assert!((wrap_phase(-PI) - PI).abs() < 1e-15);
        assert!((wrap_phase(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert!((wrap_phase(0.3 + 4.0 * PI) - 0.3).abs() < 1e-14);
    }

    #[test]
    fn rejects_more_harmonics_than_samples_allow() {
        assert!(matches!(
            HarmonicBasis::new(1.0, 10, 0.01, 15),
            Err(Error::InvalidParameter { .. })
        ));
        // harmonic 40 of ω = 1 is above Nyquist π/0.1 ≈ 31.4
        assert!(matches!(
            HarmonicBasis::new(1.0, 40, 0.1, 1000),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
