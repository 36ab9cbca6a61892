//! The whole cycles of one mode's free decay: windows between upward zero crossings of
//! its displacement, each with its frequency, amplitude and stored energies.
//!
//! An upward crossing lies between samples i and i + 1 with x_i < 0 ≤ x_{i+1}, at
//! t_c = (i + x_i/(x_i − x_{i+1})) h by linear interpolation. A crossing counts only
//! after the motion has since risen to a peak p of at least half the previous cycle's
//! and gone down past −p/4 (hysteresis: noise near zero cannot start a cycle). Window j
//! spans `cycles` = k crossings, from the first sample after crossing c_j to the first
//! sample after crossing c_{j+k}, so consecutive windows share their end samples. Its
//! frequency is ω = 2π k / (t_{c_{j+k}} − t_{c_j}), and with the modal mass m the stored
//! energy at each end sample is
//!
//! ```text
//!   E = ½ m v² + ½ m ω² x²
//! ```
//!
//! (near a zero crossing x is within one step of motion of zero, so the potential
//! term, with the stiffness m ω² of this cycle's own frequency, is a small correction
//! even for a nonlinear spring). The window's amplitude is the displacement of the mean
//! stored energy √(E_a E_b), X = √(2 √(E_a E_b) / m) / ω, and its measured damping ratio
//! is the energy decrement, E_b = E_a e^{−2ζωΔt} with Δt the window's time span:
//!
//! ```text
//!   ζ = ln(E_a / E_b) / (2 ω Δt).
//! ```

use serde::{Deserialize, Serialize};

/// One window of whole cycles of a free decay.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DecayCycle {
    /// First sample (the first after the opening crossing).
    pub start: usize,
    /// Last sample (the first after the closing crossing).
    pub end: usize,
    /// Frequency ω of the cycles (rad per time unit).
    pub frequency: f64,
    /// Stored energy at the first sample.
    pub energy_start: f64,
    /// Stored energy at the last sample.
    pub energy_end: f64,
    /// Amplitude X of the mean stored energy.
    pub amplitude: f64,
    /// The energy decrement's damping ratio ζ.
    pub damping_ratio: f64,
}

/// An upward zero crossing: the first sample at or above zero, and the interpolated time
/// in steps.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    sample: usize,
    time: f64,
}

/// The upward zero crossings of `x` (module doc).
fn crossings(x: &[f64]) -> Vec<Crossing> {
    let mut found = Vec::new();
    // The highest x since the last crossing, and the last cycle's.
    let (mut peak, mut last_peak) = (x.first().map_or(0.0, |x| x.max(0.0)), 0.0_f64);
    let mut armed = true;
    for i in 0..x.len().saturating_sub(1) {
        let (a, b) = (x[i], x[i + 1]);
        peak = peak.max(b);
        if !armed && peak >= 0.5 * last_peak && b < -0.25 * peak {
            armed = true;
        }
        if armed && a < 0.0 && b >= 0.0 {
            found.push(Crossing {
                sample: i + 1,
                time: i as f64 + a / (a - b),
            });
            armed = false;
            (last_peak, peak) = (peak, b);
        }
    }
    found
}

/// The windows of `cycles` whole cycles of the mode's displacement `x` and velocity
/// `v` (step `step`, modal mass `mass`), consecutive and sharing their end samples.
pub fn windows(x: &[f64], v: &[f64], step: f64, mass: f64, cycles: usize) -> Vec<DecayCycle> {
    let found = crossings(x);
    let k = cycles.max(1);
    let energy = |i: usize, omega: f64| 0.5 * mass * (v[i] * v[i] + omega * omega * x[i] * x[i]);
    (0..found.len().saturating_sub(k))
        .step_by(k)
        .filter_map(|j| {
            let (a, b) = (found[j], found[j + k]);
            let period = (b.time - a.time) * step / k as f64;
            let omega = 2.0 * std::f64::consts::PI / period;
            let (e_a, e_b) = (energy(a.sample, omega), energy(b.sample, omega));
            let span = (b.sample - a.sample) as f64 * step;
            (e_a > 0.0 && e_b > 0.0 && omega.is_finite()).then(|| DecayCycle {
                start: a.sample,
                end: b.sample,
                frequency: omega,
                energy_start: e_a,
                energy_end: e_b,
                amplitude: (2.0 * (e_a * e_b).sqrt() / mass).sqrt() / omega,
                damping_ratio: (e_a / e_b).ln() / (2.0 * omega * span),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear oscillator's free decay x = X e^{−ζωt} sin ω_d t: every window's ζ, f and
    /// amplitude are the closed form's.
    #[test]
    fn a_viscous_decay_gives_its_damping_ratio() {
        let (h, zeta, omega_n): (f64, f64, f64) =
            (1.0 / 12_800.0, 0.01, 2.0 * std::f64::consts::PI * 80.0);
        let omega_d = omega_n * (1.0 - zeta * zeta).sqrt();
        let sigma = zeta * omega_n;
        let n = 12_800;
        let t = |i: usize| i as f64 * h;
        let x: Vec<f64> = (0..n)
            .map(|i| (-sigma * t(i)).exp() * (omega_d * t(i)).sin())
            .collect();
        let v: Vec<f64> = (0..n)
            .map(|i| {
                (-sigma * t(i)).exp()
                    * (omega_d * (omega_d * t(i)).cos() - sigma * (omega_d * t(i)).sin())
            })
            .collect();
        let windows = windows(&x, &v, h, 1.0, 1);
        assert!(windows.len() > 70);
        for w in &windows {
            assert!((w.frequency / omega_d - 1.0).abs() < 1e-6);
            // The stored energy of a damped oscillator is not exactly ½v² + ½ω²x² at
            // every phase: the decrement holds to O(ζ²).
            assert!(
                (w.damping_ratio / zeta - 1.0).abs() < 0.02,
                "{}",
                w.damping_ratio
            );
            let middle = 0.5 * (w.start + w.end) as f64 * h;
            assert!(((w.amplitude / (-sigma * middle).exp()) - 1.0).abs() < 0.02);
        }
    }

    #[test]
    fn noise_at_zero_does_not_start_a_cycle() {
        let x = [1.0, -0.1, 0.01, -0.01, 0.02, 1.0, -1.0, 0.5];
        let found = crossings(&x);
        assert_eq!(found.iter().map(|c| c.sample).collect::<Vec<_>>(), [2, 7]);
    }
}
