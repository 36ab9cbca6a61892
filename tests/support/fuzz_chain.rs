//! The physics fuzz target's chain (fuzz/fuzz_targets/physics.rs), copied so that a test
//! reproduces a fuzz finding's numbers exactly: n unit masses between walls with unit
//! springs and dashpot `c[i]` on element i, driven on one DOF near one mode; the exact
//! steady state sampled 48 times per period over 4 periods, with noise of `noise` times
//! each channel's amplitude (and of the force), drawn from the target's generator.

use dampid::prelude::*;
use faer::Mat;
use realfft::num_complex::Complex64;

/// Samples per period.
pub const PER_PERIOD: usize = 48;
/// Whole periods per record.
pub const PERIODS: usize = 4;

/// The fuzz target's generator: an LCG, normals as a centred sum of 4 uniforms.
pub struct Noise(pub u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        ((0..4).map(|_| self.uniform()).sum::<f64>() - 2.0) * 3f64.sqrt()
    }
}

/// X of (K − ω²I + iωC) X = a e_dof, by complex Gaussian elimination.
fn response(n: usize, c: &[f64], omega: f64, dof: usize, a: f64) -> Vec<Complex64> {
    let mut z = vec![vec![Complex64::new(0.0, 0.0); n + 1]; n];
    for i in 0..n {
        z[i][i] = Complex64::new(2.0 - omega * omega, omega * (c[i] + c[i + 1]));
        if i + 1 < n {
            z[i][i + 1] = Complex64::new(-1.0, -omega * c[i + 1]);
            z[i + 1][i] = Complex64::new(-1.0, -omega * c[i + 1]);
        }
    }
    z[dof][n] = Complex64::new(a, 0.0);
    for k in 0..n {
        let pivot = (k..n)
            .max_by(|&i, &j| z[i][k].norm().total_cmp(&z[j][k].norm()))
            .unwrap();
        z.swap(k, pivot);
        let pivot_row = z[k].clone();
        for row in z.iter_mut().skip(k + 1) {
            let f = row[k] / pivot_row[k];
            for (entry, p) in row.iter_mut().zip(&pivot_row).skip(k) {
                *entry -= f * p;
            }
        }
    }
    let mut x = vec![Complex64::new(0.0, 0.0); n];
    for i in (0..n).rev() {
        let mut s = z[i][n];
        for j in i + 1..n {
            s -= z[i][j] * x[j];
        }
        x[i] = s / z[i][i];
    }
    x
}

/// One record's channels before `Record::new`, for a corruption to edit.
pub struct Raw {
    /// Displacements, samples × DOFs.
    pub x: Mat<f64>,
    /// Velocities, samples × DOFs.
    pub v: Mat<f64>,
    /// The force signal.
    pub force: Vec<f64>,
    /// The DOF (0-based) the force is declared on.
    pub dof: usize,
    /// The drive frequency (rad/s).
    pub omega: f64,
}

/// One record: drive on `dof` near `mode` (1-based) at `detune` (0.7 … 1.3 of its
/// frequency, as the fuzz target's byte / 255), amplitude `a`.
#[allow(clippy::too_many_arguments)]
pub fn raw(
    n: usize,
    c: &[f64],
    dof: usize,
    mode: usize,
    detune: f64,
    a: f64,
    noise: f64,
    rng: &mut Noise,
) -> Raw {
    let natural = 2.0 * (mode as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin();
    let omega = natural * (0.7 + 0.6 * detune);
    let x_hat = response(n, c, omega, dof, a);
    let samples = PER_PERIOD * PERIODS + 1;
    let h = 2.0 * std::f64::consts::PI / omega / PER_PERIOD as f64;
    let level: Vec<f64> = x_hat.iter().map(|p| noise * p.norm()).collect();
    let mut x = Mat::zeros(samples, n);
    let mut v = Mat::zeros(samples, n);
    for i in 0..samples {
        let (cos, sin) = ((omega * i as f64 * h).cos(), (omega * i as f64 * h).sin());
        for j in 0..n {
            let (re, im) = (x_hat[j].re, x_hat[j].im);
            x[(i, j)] = re * cos - im * sin + level[j] * rng.normal();
            v[(i, j)] = omega * (-re * sin - im * cos) + omega * level[j] * rng.normal();
        }
    }
    let force = (0..samples)
        .map(|i| a * (omega * i as f64 * h).cos() * (1.0 + noise * rng.normal()))
        .collect();
    Raw {
        x,
        v,
        force,
        dof,
        omega,
    }
}

impl Raw {
    /// The record, labelled `label`.
    pub fn into_record(self, label: &str) -> Record {
        let samples = self.force.len();
        Record::new(RecordParts {
            label: label.into(),
            step: 2.0 * std::f64::consts::PI / self.omega / PER_PERIOD as f64,
            start_time: 0.0,
            displacements: self.x,
            velocities: Some(self.v),
            forcing: Forcing::on_dofs(
                Mat::from_fn(samples, 1, |i, _| self.force[i]),
                vec![self.dof],
            ),
            period: 2.0 * std::f64::consts::PI / self.omega,
        })
        .unwrap()
    }
}

/// The model the fuzz target fits: one linear dashpot per element of the chain.
pub fn model(n: usize) -> DampingModel {
    DampingModel::new().with(Term::on_elements(
        Linear,
        Element::chain_fixed_both_ends(n),
        Coefficients::PerElement("c".into()),
    ))
}

/// The fuzz input's byte for detune as a share of 0.7 … 1.3.
pub fn detune(byte: f64) -> f64 {
    byte / 255.0
}

/// The fuzz input's byte for a force amplitude.
pub fn amplitude(byte: f64) -> f64 {
    0.25 + byte / 64.0
}
