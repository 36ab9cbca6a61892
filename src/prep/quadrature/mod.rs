//! Quadrature rules that turn sampled power p(t_i) into a window integral
//! ∫_{t_0}^{t_0 + kT} p dt ≈ Σ_i w_i p(t_i), for a window of k whole driving periods.
//!
//! Let L = kT/h be the window length in samples (not always an integer: the four-mass
//! case has T/h = 101.67) and F = ⌊L⌋, φ = L − F.
//!
//! - **Rectangular** (the paper's rule): w_i = h for i = 0..round(L). When L is not an
//!   integer the sum covers round(L)·h instead of kT: a relative span error
//!   |round(L) − L|/L ≤ 1/(2L), which moves the integral by at most that times
//!   max|p|/mean(p). Over k cycles it shrinks like 1/k.
//! - **Trapezoid**: the exact integral over [t_0, t_0 + kT] of the piecewise-linear
//!   interpolant of p. Interior weights h, w_0 = h/2; the last partial interval
//!   [t_F, t_F + φh] adds φh(1 − φ/2) to w_F and φ²h/2 to w_{F+1}.
//! - **Spectral**: fits p with a Fourier series in the harmonics of ω = 2π/T over the
//!   samples inside the window and integrates it exactly (span × mean). Exact for
//!   band-limited periodic integrands whatever φ; when φ = 0 it agrees with the
//!   rectangular rule on periodic data.
//!
//! **Periodic closure** (a window that ends one step before t_0 + kT on a record of
//! exactly its L = kT/h samples, see [`crate::prep::window::periodic_closure`]): the
//! sample at kT is the sample at 0, p_L = p_0, and every rule becomes the same rule,
//!
//! ```text
//!   trapezoid:   h (½p_0 + p_1 + … + p_{L−1} + ½p_L) = h Σ_{i<L} p_i,
//!   spectral:    kT · a_0 = kT · (1/L) Σ_{i<L} p_i   (the constant column is orthogonal
//!                                                   to every harmonic q < L/(2k) over L
//!                                                   samples of k periods),
//!   rectangular: h Σ_{i<L} p_i,
//! ```
//!
//! w_i = h for i = 0..L ([`crate::prep::window::Window::weights`]). It is exact for every
//! trigonometric polynomial in ω below the Nyquist limit, Σ_{i<L} cos(2π n i/L) = 0 for
//! n = qk not a multiple of L: h Σ cos²(qωt_i) = kT/2 and h Σ cos(pωt_i) cos(qωt_i) = 0
//! for p ≠ q, p + q < L/k.

mod weights;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::fourier::{HarmonicBasis, default_harmonics};

pub(crate) use weights::WindowWeights;

/// A quadrature rule for window integrals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quadrature {
    /// Σ h p_i over round(L) samples (the paper's rule).
    Rectangular,
    /// Exact trapezoid over the window span, with a fractional last interval.
    #[default]
    Trapezoid,
    /// Integral of the least-squares Fourier series of p over the window.
    Spectral,
}

impl Quadrature {
    /// Window length L = span/h in samples, with values within round-off of an
    /// integer snapped to it.
    pub(crate) fn length(span: f64, step: f64) -> (usize, f64) {
        let l = span / step;
        if l.is_infinite() {
            // A span no record holds (a huge period over a tiny step): saturate, as
            // `samples` does, rather than make φ = ∞ − ∞ = NaN.
            return (usize::MAX, 0.0);
        }
        let whole = l.round();
        if (l - whole).abs() <= 1e-9 * l.max(1.0) {
            (whole as usize, 0.0)
        } else {
            (l.floor() as usize, l - l.floor())
        }
    }

    /// How many samples, from the window's first, the rule reads (saturating: a span
    /// too long for any record gives `usize::MAX`).
    pub fn samples(&self, span: f64, step: f64) -> usize {
        let (whole, frac) = Self::length(span, step);
        match self {
            Quadrature::Rectangular => (whole as f64 + frac).round() as usize,
            Quadrature::Trapezoid => whole.saturating_add(1 + usize::from(frac > 0.0)),
            Quadrature::Spectral => whole.saturating_add(1),
        }
    }

    /// The weights of a window of `span` = kT = L h that closes periodically (L whole):
    /// w_i = h for i = 0..L, what every rule gives when p_L = p_0 (see the module doc).
    pub(crate) fn closed_weights(span: f64, step: f64) -> Result<WindowWeights> {
        let (whole, frac) = Self::length(span, step);
        if frac != 0.0 || whole == 0 || whole == usize::MAX {
            return Err(Error::invalid(
                "window span",
                span,
                &format!(
                    "closes periodically only over a whole number of sample steps h = {}",
                    crate::format::number(step)
                ),
            ));
        }
        Ok(WindowWeights::banded(vec![], step, vec![], whole))
    }

    /// The weights w_i, i = 0..samples(span, step), for a window of `span` = kT.
    pub fn weights(&self, span: f64, step: f64, period: f64) -> Result<Vec<f64>> {
        Ok(self.window_weights(span, step, period)?.to_vec())
    }

    /// The same weights held compactly: the rectangular and trapezoid rules as their
    /// few end weights and the interior h, the spectral rule sample by sample.
    pub(crate) fn window_weights(
        &self,
        span: f64,
        step: f64,
        period: f64,
    ) -> Result<WindowWeights> {
        if !(span.is_finite() && span > 0.0) {
            return Err(Error::invalid(
                "window span",
                span,
                "must be finite and positive",
            ));
        }
        if span < step {
            return Err(Error::invalid(
                "window span",
                span,
                &format!("is shorter than one sample step h = {step}; record with a smaller step"),
            ));
        }
        let (whole, frac) = Self::length(span, step);
        let count = self.samples(span, step);
        Ok(match self {
            Quadrature::Rectangular => WindowWeights::banded(vec![], step, vec![], count),
            Quadrature::Trapezoid => {
                // Samples 0 and `whole` end the whole intervals (the same sample when
                // there is none); the partial interval adds to `whole` and `whole + 1`.
                let mut ends = vec![step / 2.0; count - whole];
                ends[0] = if whole == 0 { 0.0 } else { step / 2.0 };
                if frac > 0.0 {
                    ends[0] += frac * step * (1.0 - frac / 2.0);
                    ends[1] = frac * frac * step / 2.0;
                }
                let head = if whole == 0 { vec![] } else { vec![step / 2.0] };
                WindowWeights::banded(head, step, ends, count)
            }
            Quadrature::Spectral => {
                let omega = 2.0 * std::f64::consts::PI / period;
                let basis =
                    HarmonicBasis::new(omega, default_harmonics(period / step), step, count)?;
                WindowWeights::PerSample(basis.integration_weights(span))
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn integrate(rule: Quadrature, f: impl Fn(f64) -> f64, span: f64, h: f64, period: f64) -> f64 {
        let w = rule.weights(span, h, period).unwrap();
        w.iter().enumerate().map(|(i, w)| w * f(i as f64 * h)).sum()
    }

    /// The trapezoid rule integrates a linear function exactly over a span that ends
    /// between samples: ∫_0^{1.03} (2 + 3t) dt = 2.06 + 1.5·1.03².
    #[test]
    fn trapezoid_is_exact_for_linear_integrand_with_fractional_end() {
        let span = 1.03;
        let exact = 2.0 * span + 1.5 * span * span;
        let got = integrate(Quadrature::Trapezoid, |t| 2.0 + 3.0 * t, span, 0.1, span);
        assert!((got - exact).abs() < 1e-13, "{got} vs {exact}");
    }

    /// On a whole number of samples per period, all three rules give ∫_0^T cos²ωt dt = T/2.
    #[test]
    fn all_rules_agree_on_commensurate_periodic_integrand() {
        let period = 6.4;
        let omega = 2.0 * PI / period;
        for rule in [
            Quadrature::Rectangular,
            Quadrature::Trapezoid,
            Quadrature::Spectral,
        ] {
            let got = integrate(rule, |t| (omega * t).cos().powi(2), period, 0.1, period);
            assert!((got - period / 2.0).abs() < 1e-12, "{rule:?}: {got}");
        }
    }

    /// T/h = 101.67 (the paper's four-mass case): the spectral rule stays exact, the
    /// trapezoid is second-order accurate, the rectangular rule carries the span error.
    #[test]
    fn incommensurate_period_accuracy_ranks_the_rules() {
        let omega = 0.618;
        let period = 2.0 * PI / omega;
        let f = |t: f64| (omega * t + 0.3).cos().powi(2);
        let exact = period / 2.0;
        let err = |rule| (integrate(rule, f, period, 0.1, period) - exact).abs() / exact;
        assert!(err(Quadrature::Spectral) < 1e-12);
        assert!(err(Quadrature::Trapezoid) < 1e-3);
        // The rectangular sum covers 102 h instead of 101.67 h; its error is bounded
        // by that extra span times max|p| / mean(p) = 2.
        let l = period / 0.1;
        let rect = err(Quadrature::Rectangular);
        assert!(rect < 2.0 * (l.round() - l).abs() / l);
        assert!(rect > err(Quadrature::Trapezoid));
    }

    /// Over exactly L = kT/h samples (a window that closes periodically) the spectral
    /// rule's least-squares weights are h at every sample, the closed weights: over k
    /// whole periods the constant column is orthogonal to every harmonic of the basis.
    #[test]
    fn spectral_weights_over_closed_periods_are_the_closed_weights() {
        let (h, period, cycles, length) = (0.1, 6.4, 2.0, 128);
        let omega = 2.0 * PI / period;
        let basis = HarmonicBasis::new(omega, default_harmonics(period / h), h, length).unwrap();
        for w in basis.integration_weights(cycles * period) {
            assert!((w - h).abs() < 1e-14 * h, "{w}");
        }
        let closed = Quadrature::closed_weights(cycles * period, h).unwrap();
        assert_eq!(closed.to_vec(), vec![h; length]);
        // Only a whole number of steps closes.
        assert!(Quadrature::closed_weights(cycles * period + 0.05, h).is_err());
    }

    #[test]
    fn rejects_nonpositive_span() {
        assert!(matches!(
            Quadrature::Trapezoid.weights(0.0, 0.1, 1.0),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
