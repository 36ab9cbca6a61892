//! The stepped-sine tables of tests/stepped_sine.rs and tests/varpro_bootstrap.rs: a
//! one-DOF oscillator with viscous and power-law damping in the harmonic approximation
//! (the derivation is in tests/stepped_sine.rs), with or without the residual receptance
//! of other modes, and the model file that reads them.

#![allow(dead_code)]

use std::path::Path;

pub const M: f64 = 1.0;
pub const K: f64 = 98_696.044_010_893_6; // (2π·50)²
pub const C: f64 = 1.2566;
pub const D: f64 = 5.0;

/// ∫₀^{2π} |sin θ|^p dθ by the midpoint rule on 2·10⁵ points (the integrand is C²).
pub fn sine_power_integral(p: f64) -> f64 {
    let n = 200_000;
    let h = 2.0 * std::f64::consts::PI / n as f64;
    (0..n)
        .map(|i| ((i as f64 + 0.5) * h).sin().abs().powf(p))
        .sum::<f64>()
        * h
}

/// (X, lag φ) of the oscillator driven at `omega` with amplitude `force`.
pub fn response(omega: f64, force: f64, c: f64, d: f64) -> (f64, f64) {
    let integral = sine_power_integral(2.5);
    let c_eq = |x: f64| c + d * (omega * x).sqrt() * integral / std::f64::consts::PI;
    let stiff = K - M * omega * omega;
    let h = |x: f64| x * (stiff.powi(2) + (omega * c_eq(x)).powi(2)).sqrt() - force;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if h(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let x = 0.5 * (lo + hi);
    (x, (omega * c_eq(x)).atan2(stiff))
}

/// A small deterministic generator (splitmix64 → two uniforms → Box–Muller).
pub struct Normal(pub u64);
impl Normal {
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

pub fn headers() -> Vec<String> {
    ["level", "f_hz", "force", "x", "phase_deg"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// The model file of the viscous + power-law model on `file`, `extra` appended.
pub fn model_text(file: &Path, extra: &str) -> String {
    format!(
        r#"
dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[terms]]
kind = "law"
law = "power"
exponent = 1.5
elements = "each_dof"
coefficient = "d"
[stepped_sine]
file = "{}"
frequency = {{ column = "f_hz", scale = 6.283185307179586 }}
force = "force"
amplitudes = ["x"]
phases = [{{ column = "phase_deg", scale = 0.017453292519943295 }}]
sweep = "level"
{extra}
"#,
        file.display()
    )
}

/// The bolted-joint generator's levels, 21 frequencies over ±3 % of 50 Hz each.
pub const LEVELS: [f64; 7] = [0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 3.0];

/// The truth of the residual tables: r_k (m/N) and r_m (m/N · (rad/s)²).
pub const R_K: f64 = -2.0e-6;

/// The table's columns (level, f_hz, force, x, phase_deg) of the oscillator with
/// the residual R(ω) = `r_k` − `r_m`/ω² added, every force × `force_scale`
/// (the response is the oscillator's at the unscaled force: a linear change of the
/// force's unit). Noise as the generator: relative `noise.1` on force and amplitude,
/// `noise.2` rad on the phase.
pub fn residual_columns(
    r_k: f64,
    r_m: f64,
    force_scale: f64,
    noise: Option<(u64, f64, f64)>,
) -> Vec<Vec<f64>> {
    residual_columns_at(&LEVELS, 21, r_k, r_m, force_scale, noise)
}

/// [`residual_columns`] at force `levels`, `frequencies` (at least 2) per level over
/// ±3 % of 50 Hz.
pub fn residual_columns_at(
    levels: &[f64],
    frequencies: usize,
    r_k: f64,
    r_m: f64,
    force_scale: f64,
    noise: Option<(u64, f64, f64)>,
) -> Vec<Vec<f64>> {
    let mut columns = vec![Vec::new(); 5];
    let mut rng = Normal(noise.map_or(0, |n| n.0));
    for (l, &force) in levels.iter().enumerate() {
        for i in 0..frequencies {
            let f_hz = 50.0 * (0.97 + 0.06 * i as f64 / (frequencies - 1) as f64);
            let omega = 2.0 * std::f64::consts::PI * f_hz;
            let (x, phi) = response(omega, force, C, D);
            let r = r_k - r_m / (omega * omega);
            // Z = X e^{−iφ} + R a
            let (re, im) = (x * phi.cos() + r * force, -x * phi.sin());
            let (mut a, mut x, mut phi) = (force, re.hypot(im), (-im).atan2(re));
            if let Some((_, relative, phase)) = noise {
                x *= 1.0 + relative * rng.sample();
                phi += phase * rng.sample();
                a *= 1.0 + relative * rng.sample();
            }
            columns[0].push(l as f64 + 1.0);
            columns[1].push(f_hz);
            columns[2].push(a * force_scale);
            // the measured receptance |Z|/a is in m per scaled force unit
            columns[3].push(x);
            columns[4].push(phi.to_degrees());
        }
    }
    columns
}
