//! Least-squares Fourier series in the harmonics of the driving frequency ω:
//!
//!   x(t) ≈ a_0 + Σ_{k ∈ S} (a_k cos kωt + b_k sin kωt),
//!
//! over a set S of harmonic orders (usually 1..K), fitted over the samples of a window
//! of whole periods. The basis is exactly T-periodic whatever the sampling step, so it
//! serves windows whose period is not a whole number of samples (the four-mass case has
//! T/h = 101.67). Its derivative gives spectral velocities, and its mean a_0 times the
//! window span gives the spectral quadrature rule. When T/h is an integer and
//! K < T/(2h), the fit reproduces the truncated discrete Fourier series, and is computed
//! as such: one real FFT per channel ([`WholeSampleDft`], `dft.rs`, which derives the
//! agreement, also for the L + 1 samples that include the closing one).
//!
//! Harmonic k as a phasor: a_k cos θ + b_k sin θ = A_k cos(θ − φ_k) with
//! A_k = √(a_k² + b_k²) and φ_k = atan2(b_k, a_k) (a phase lag).
//!
//!
//! Files: `basis.rs` (the basis, its fit, derivative and integration weights),
//! `dft.rs` (the same fit by one real FFT per channel on whole samples per period),
//! `fused_sums.rs` (the sums of `packed.rs`, several columns per pass over the samples),
//! `noise_floor.rs` (the noise floor and the harmonics that stand above it),
//! `packed.rs` (one channel's fit on a design held column by column, in packed sums),
//! `record_noise.rs` (a record's harmonics and noise, estimated once for all its
//! windows).

mod basis;
mod dft;
mod fused_sums;
mod noise_floor;
mod packed;
mod record_noise;

pub(crate) use basis::{HarmonicBasis, first_orders};
pub(crate) use dft::{WholeSampleDft, whole_samples};
pub use noise_floor::HarmonicSelection;
pub(crate) use noise_floor::{select_harmonics, select_with_spectrum};
pub(crate) use packed::{fit_and_shifted_squares, fit_on_design};
pub(crate) use record_noise::{RecordNoise, RecordNoises};

use crate::error::{Error, Result};

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
    /// Samples t_0 .. t_0 + kT, i.e. ⌊kT/h⌋ + 1 (fewer when the record ends first:
    /// exactly L = kT/h for a window that closes periodically, whose record ends one step
    /// before t_0 + kT, see [`crate::prep::window::periodic_closure`]).
    pub(crate) samples: usize,
}

impl WholePeriods {
    /// The whole periods of a window of `count` samples that may read up to `available`
    /// samples: k = round(count·h/T) (the quadrature rules read between ⌊kT/h⌋ and
    /// ⌊kT/h⌋ + 2 samples), and the samples inside [t_0, t_0 + kT] that the record
    /// holds. Over exactly L = kT/h samples of k periods (a window that closes
    /// periodically) the harmonic basis is discretely orthogonal and the fit is the
    /// truncated DFT.
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

#[cfg(test)]
mod tests {
    use super::*;
    /// Each rule's window of k periods maps back to k whole periods and the ⌊kT/h⌋ + 1
    /// samples inside them (T/h = 101.67: 102 samples for one period, 204 for two).
    #[test]
    fn whole_periods_of_every_rule() {
        let (h, period) = (0.1, 10.167);
        for cycles in [1usize, 2, 7] {
            let span = cycles as f64 * period;
            let inside = (span / h).floor() as usize + 1;
            for rule in [
                crate::prep::quadrature::Quadrature::Rectangular,
                crate::prep::quadrature::Quadrature::Trapezoid,
                crate::prep::quadrature::Quadrature::Spectral,
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
}
