//! A 3-DOF chain's ringdown with modal damping (tests/free_decay_sensors.rs,
//! tests/errors/free_decay.rs): unit masses, springs k between neighbours and to ground
//! at the first mass (fixed–free), mode shapes Φ and frequencies from the eigenproblem
//! K φ = ω² φ (Φ orthonormal, M = I); each modal coordinate rings down on its own,
//! mode 1 under a known law (c q̇ + d|q̇|^p sgn q̇, tests/support/ringdown.rs), modes 2
//! and 3 linearly; the sensors read y = Φ q̈ (accelerations) plus noise. Independent of
//! dampid.

#![allow(dead_code, clippy::needless_range_loop)]

use super::ringdown::{Ringdown, linear_mode_acceleration, with_noise};

/// The chain: mode shapes (columns, unit length, first entry positive) and frequencies
/// in Hz, scaled so that mode 1 is at `f1` Hz.
pub fn chain_modes(f1: f64) -> ([[f64; 3]; 3], [f64; 3]) {
    // K / k = [[2, −1, 0], [−1, 2, −1], [0, −1, 1]]: Jacobi rotations to convergence.
    let mut a: [[f64; 3]; 3] = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]];
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..100 {
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta: f64 = 0.5 * (2.0 * a[p][q]).atan2(a[q][q] - a[p][p]);
            let (c, s) = (theta.cos(), theta.sin());
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for k in 0..3 {
                let (vkp, vkq) = (v[k][p], v[k][q]);
                v[k][p] = c * vkp - s * vkq;
                v[k][q] = s * vkp + c * vkq;
            }
        }
    }
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let lowest = a[order[0]][order[0]];
    let mut shapes = [[0.0; 3]; 3];
    let mut frequencies = [0.0; 3];
    for (r, &i) in order.iter().enumerate() {
        let sign = if v[0][i] < 0.0 { -1.0 } else { 1.0 };
        for k in 0..3 {
            shapes[r][k] = sign * v[k][i];
        }
        frequencies[r] = f1 * (a[i][i] / lowest).sqrt();
    }
    (shapes, frequencies)
}

/// The three sensors' accelerations (each with `noise` × its RMS of Gaussian noise),
/// the mode shapes and frequencies, and mode 1's ringdown (its law and its modal
/// acceleration alone).
pub struct ChainRingdown {
    pub sensors: [Vec<f64>; 3],
    pub shapes: [[f64; 3]; 3],
    pub frequencies: [f64; 3],
    pub mode_1: Ringdown,
    pub modal_acceleration: Vec<f64>,
}

/// Mode 1 at 80 Hz with c = 2ζω (ζ = 0.1 %) and 5|q̇|^1.5, from q = 2e-3; modes 2 and 3
/// (224 and 324 Hz) linear, ζ = 0.2 %, from `others` × 2e-3.
pub fn chain_ringdown(samples: usize, others: f64, noise: f64, seed: u64) -> ChainRingdown {
    let (shapes, frequencies) = chain_modes(80.0);
    let mode_1 = Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        power: Some((5.0, 1.5)),
        x0: 2e-3,
        samples,
        ..Ringdown::at_80_hz()
    };
    let [_, _, q1, _] = mode_1.simulate();
    let q2 = linear_mode_acceleration(samples, mode_1.step, frequencies[1], 0.002, others * 2e-3);
    let q3 = linear_mode_acceleration(samples, mode_1.step, frequencies[2], 0.002, others * 2e-3);
    let sensor = |k: usize| -> Vec<f64> {
        let y: Vec<f64> = (0..samples)
            .map(|i| shapes[0][k] * q1[i] + shapes[1][k] * q2[i] + shapes[2][k] * q3[i])
            .collect();
        with_noise(&y, noise, seed + k as u64)
    };
    ChainRingdown {
        sensors: [sensor(0), sensor(1), sensor(2)],
        shapes,
        frequencies,
        mode_1,
        modal_acceleration: q1,
    }
}

/// The sensors as a CSV file's text: a header `a1,a2,a3`, one row per sample.
pub fn csv(sensors: &[Vec<f64>; 3]) -> String {
    let mut text = String::from("a1,a2,a3\n");
    for i in 0..sensors[0].len() {
        text.push_str(&format!(
            "{:e},{:e},{:e}\n",
            sensors[0][i], sensors[1][i], sensors[2][i]
        ));
    }
    text
}
