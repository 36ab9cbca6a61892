//! Least-squares Fourier series in the harmonics of the driving frequency ω:
//!
//!   x(t) ≈ a_0 + Σ_{k=1..K} (a_k cos kωt + b_k sin kωt),
//!
//! fitted over the samples of a window of whole periods. The basis is exactly
//! T-periodic whatever the sampling step, so it serves windows whose period is not a
//! whole number of samples (the four-mass case has T/h = 101.67). Its derivative gives
//! spectral velocities, and its mean a_0 times the window span gives the spectral
//! quadrature rule. When T/h is an integer and K < T/(2h), the fit reproduces the
//! truncated discrete Fourier series.

use faer::Mat;
use faer::prelude::*;

use crate::error::{Error, Result};

/// Default number of harmonics for a period of `samples_per_period` samples: 45% of
/// the Nyquist count, leaving a margin so that the basis stays well conditioned when
/// the period is not a whole number of samples.
pub(crate) fn default_harmonics(samples_per_period: f64) -> usize {
    ((0.45 * samples_per_period).floor() as usize).max(1)
}

/// A harmonic basis on the times t_i = i h, i = 0..m.
pub(crate) struct HarmonicBasis {
    omega: f64,
    harmonics: usize,
    step: f64,
    samples: usize,
}

impl HarmonicBasis {
    /// Checks that the fit is overdetermined and below the Nyquist frequency.
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
        let nyquist = std::f64::consts::PI / step;
        if harmonics as f64 * omega >= nyquist {
            return Err(Error::invalid(
                "harmonics",
                harmonics as f64,
                &format!(
                    "harmonic {harmonics} of ω = {omega} is above the Nyquist frequency {nyquist}"
                ),
            ));
        }
        Ok(HarmonicBasis {
            omega,
            harmonics,
            step,
            samples,
        })
    }

    fn columns(&self) -> usize {
        2 * self.harmonics + 1
    }

    /// m × (2K+1) design matrix [1, cos ωt, sin ωt, cos 2ωt, sin 2ωt, …].
    fn design(&self) -> Mat<f64> {
        Mat::from_fn(self.samples, self.columns(), |i, j| {
            if j == 0 {
                return 1.0;
            }
            let k = j.div_ceil(2) as f64;
            let phase = k * self.omega * i as f64 * self.step;
            if j % 2 == 1 { phase.cos() } else { phase.sin() }
        })
    }

    /// The time derivative of the design matrix.
    fn derivative_design(&self) -> Mat<f64> {
        Mat::from_fn(self.samples, self.columns(), |i, j| {
            if j == 0 {
                return 0.0;
            }
            let k = j.div_ceil(2) as f64;
            let kw = k * self.omega;
            let phase = kw * i as f64 * self.step;
            if j % 2 == 1 {
                -kw * phase.sin()
            } else {
                kw * phase.cos()
            }
        })
    }

    /// Fits every column of `values` (m × n) and returns the derivative of the fitted
    /// series at the same samples (m × n).
    pub(crate) fn differentiate(&self, values: MatRef<'_, f64>) -> Mat<f64> {
        let coefficients = self.design().qr().solve_lstsq(values);
        self.derivative_design() * coefficients
    }

    /// Weights w (length m) such that Σ w_i p(t_i) = span · a_0(p): the integral over
    /// the window of the fitted periodic series. w = span · Q R^{-T} e_0 for B = QR.
    pub(crate) fn integration_weights(&self, span: f64) -> Vec<f64> {
        let qr = self.design().qr();
        let r = qr.thin_R();
        let q = qr.compute_thin_Q();
        let mut u = Mat::<f64>::zeros(self.columns(), 1);
        u[(0, 0)] = 1.0;
        r.transpose().solve_lower_triangular_in_place(u.as_mut());
        let w = q * u;
        (0..self.samples).map(|i| span * w[(i, 0)]).collect()
    }
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
