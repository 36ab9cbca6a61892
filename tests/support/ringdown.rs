//! Ringdowns of a one-DOF oscillator for the free-decay tests,
//! m ẍ + c ẋ + d|ẋ|^p sgn ẋ + μ sgn ẋ + k x = f(t), integrated by RK4 with substeps, from an initial displacement
//! or from rest under a half-sine hammer force; a second, linear mode may be added to the
//! measured signal. Independent of the crate: the truth the tests compare with.

#![allow(dead_code, clippy::needless_range_loop)]

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// One ringdown: the oscillator, how it starts, and how it is sampled.
#[derive(Clone, Copy)]
pub struct Ringdown {
    pub frequency_hz: f64,
    pub mass: f64,
    pub viscous: f64,
    /// (d, p) of d|v|^p sgn v.
    pub power: Option<(f64, f64)>,
    /// Coulomb force μ (regularised as μ tanh(v/v_ε) with v_ε = 1e-6 of the peak speed).
    pub coulomb: f64,
    pub step: f64,
    pub samples: usize,
    pub substeps: usize,
    /// Initial displacement (no hammer).
    pub x0: f64,
    /// A half-sine force of this peak and duration, starting after `quiet` samples.
    pub hammer: Option<(f64, f64)>,
    pub quiet: usize,
}

impl Ringdown {
    /// 80 Hz, m = 1, 12.8 kHz, 65 536 samples, 8 substeps, from x0 = 1e-3.
    pub fn at_80_hz() -> Self {
        Ringdown {
            frequency_hz: 80.0,
            mass: 1.0,
            viscous: 0.0,
            power: None,
            coulomb: 0.0,
            step: 1.0 / 12_800.0,
            samples: 65_536,
            substeps: 8,
            x0: 1e-3,
            hammer: None,
            quiet: 0,
        }
    }

    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency_hz
    }

    pub fn stiffness(&self) -> f64 {
        self.mass * self.omega() * self.omega()
    }

    fn force(&self, t: f64) -> f64 {
        match self.hammer {
            Some((peak, duration)) => {
                let t0 = self.quiet as f64 * self.step;
                if t >= t0 && t <= t0 + duration {
                    peak * (std::f64::consts::PI * (t - t0) / duration).sin()
                } else {
                    0.0
                }
            }
            None => 0.0,
        }
    }

    /// The damping force at velocity v.
    pub fn damping(&self, v: f64) -> f64 {
        let v_eps = 1e-6 * self.omega() * self.x0.abs().max(1e-12);
        let mut f = self.viscous * v + self.coulomb * (v / v_eps).tanh();
        if let Some((d, p)) = self.power {
            f += d * v.abs().powf(p) * v.signum();
        }
        f
    }

    fn acceleration(&self, t: f64, x: f64, v: f64) -> f64 {
        (self.force(t) - self.damping(v) - self.stiffness() * x) / self.mass
    }

    /// Displacement, velocity, acceleration and force at every sample.
    pub fn simulate(&self) -> [Vec<f64>; 4] {
        let n = self.samples;
        let (mut x, mut v) = (if self.hammer.is_some() { 0.0 } else { self.x0 }, 0.0);
        let h = self.step / self.substeps as f64;
        let mut out = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for i in 0..n {
            let t = i as f64 * self.step;
            out[0][i] = x;
            out[1][i] = v;
            out[2][i] = self.acceleration(t, x, v);
            out[3][i] = self.force(t);
            for s in 0..self.substeps {
                let t = t + s as f64 * h;
                let k1 = (v, self.acceleration(t, x, v));
                let k2 = (
                    v + 0.5 * h * k1.1,
                    self.acceleration(t + 0.5 * h, x + 0.5 * h * k1.0, v + 0.5 * h * k1.1),
                );
                let k3 = (
                    v + 0.5 * h * k2.1,
                    self.acceleration(t + 0.5 * h, x + 0.5 * h * k2.0, v + 0.5 * h * k2.1),
                );
                let k4 = (
                    v + h * k3.1,
                    self.acceleration(t + h, x + h * k3.0, v + h * k3.1),
                );
                x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
        }
        out
    }
}

/// A linear mode's free acceleration: amplitude `x0` (displacement), frequency `f` Hz,
/// damping ratio ζ, from t = 0 (x = x0 cos-like start).
pub fn linear_mode_acceleration(samples: usize, step: f64, f: f64, zeta: f64, x0: f64) -> Vec<f64> {
    let wn = 2.0 * std::f64::consts::PI * f;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let s = zeta * wn;
    (0..samples)
        .map(|i| {
            let t = i as f64 * step;
            // x = x0 e^{−st} cos(wd t); a = ẍ.
            let e = (-s * t).exp();
            let (c, sn) = ((wd * t).cos(), (wd * t).sin());
            x0 * e * ((s * s - wd * wd) * c + 2.0 * s * wd * sn)
        })
        .collect()
}

/// `signal` plus Gaussian noise of standard deviation `share` × its RMS.
pub fn with_noise(signal: &[f64], share: f64, seed: u64) -> Vec<f64> {
    let rms = (signal.iter().map(|s| s * s).sum::<f64>() / signal.len() as f64).sqrt();
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let noise = Normal::new(0.0, share * rms).expect("a finite positive σ");
    signal.iter().map(|s| s + noise.sample(&mut rng)).collect()
}
