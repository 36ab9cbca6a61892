//! A record that reaches every path of the regressor kernel: n DOFs of sines and cosines
//! at pseudo-random phases with a third harmonic, measured velocities, and three force
//! channels through a load-distribution matrix (channel 2 zero everywhere, channel c on
//! the DOFs j with (j + c) divisible by `every`). Shared by tests/kernel.rs and
//! tests/simd_levels.rs.

use dampid::prelude::*;
use faer::Mat;

/// Deterministic pseudo-random numbers in [-1, 1).
pub fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The record (module doc): `dofs` DOFs, `samples` samples at h = 0.01, phases from
/// `seed`.
pub fn mixed_record(dofs: usize, samples: usize, seed: u64, every: usize, label: &str) -> Record {
    let h = 0.01;
    let mut r = noise(seed);
    let phases: Vec<f64> = (0..dofs).map(|_| 3.0 * r()).collect();
    let x = Mat::from_fn(samples, dofs, |i, j| {
        (i as f64 * h + phases[j]).sin() + 0.1 * (3.0 * i as f64 * h).cos()
    });
    let v = Mat::from_fn(samples, dofs, |i, j| {
        (i as f64 * h + phases[j]).cos() - 0.3 * (3.0 * i as f64 * h + j as f64).sin()
    });
    let signals = Mat::from_fn(samples, 3, |i, c| match c {
        1 => 0.0,
        _ => (i as f64 * h * (c + 1) as f64).cos(),
    });
    let distribution = Mat::from_fn(dofs, 3, |j, c| {
        if (j + c) % every == 0 {
            1.0 + c as f64
        } else {
            0.0
        }
    });
    Record::new(RecordParts {
        label: label.into(),
        step: h,
        start_time: 0.0,
        displacements: x,
        velocities: Some(v),
        forcing: Forcing::distributed(signals, distribution),
        period: 2.0 * std::f64::consts::PI,
    })
    .unwrap()
}
