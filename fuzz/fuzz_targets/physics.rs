//! The physics checks (issue 29): steady harmonic records of a chain of 2 to 4 unit
//! masses between walls with unit springs and one dashpot per element (true
//! coefficients known), exact to round-off (the complex response of K − ω²M + iωC at
//! the drive), optionally with sensor noise, then corrupted the ways real data go wrong:
//! a force or a motion channel with the wrong sign, a force on the wrong DOF, two motion
//! channels swapped, a dead (all-zero) motion channel, a force in the wrong units, or
//! velocities given as displacements, in one record or all of them. `identify` then
//! runs with the default noise-robust pipeline or plain rows (spectral, central
//! differences, measured velocities), constrained to nonnegative or not.
//!
//! Asserted: an `Err` is always fine (a refusal names the problem), but a report that
//! gives a coefficient off the truth (× k when every record's force is in other units by
//! k: force × k scales every coefficient by k, which no check can see) by more than
//! [`TOLERANCE`] of the largest true
//! coefficient — and by more than [`SIGMAS`] of its own standard error, when it has one —
//! as determined, and not on a bound (printed "at lower bound", no standard error), must
//! carry a warning; and clean records (no corruption, no noise) are never refused by the
//! physics checks (negative input work, a dead motion sensor).
//! Every report also passes the shared checks (`support::check`).

#![no_main]

use arbitrary::Arbitrary;
use dampid::error::Error;
use dampid::fit::Constraints;
use dampid::prelude::*;
use dampid::prep::velocity::VelocitySource;
use dampid::regressor::{NoiseTreatment, RegressorSettings, Windows};
use dampid::terms::{Coefficients, Element};
use faer::Mat;
use libfuzzer_sys::fuzz_target;

mod support;

/// Samples per period.
const PER_PERIOD: usize = 48;
/// Whole periods per record.
const PERIODS: usize = 4;
/// A coefficient further than this share of the largest true coefficient from its truth
/// is wrong.
const TOLERANCE: f64 = 0.05;
/// … unless it is within this many of its own standard errors.
const SIGMAS: f64 = 6.0;

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Corruption {
    /// Force channel inverted.
    FlipForce { record: u8 },
    /// A motion channel (displacement and measured velocity) inverted.
    FlipMotion { record: u8, dof: u8 },
    /// The force declared on another DOF.
    MoveForce { record: u8, dof: u8 },
    /// Two motion channels swapped.
    SwapMotion { record: u8, a: u8, b: u8 },
    /// A motion channel all zero.
    DeadMotion { record: u8, dof: u8 },
    /// The force in other units (× 10, 100 or 1000).
    ScaleForce { record: u8, power: u8 },
    /// The velocities read as displacements.
    VelocityAsDisplacement { record: u8 },
}

#[derive(Arbitrary, Debug)]
struct Experiment {
    force_dof: u8,
    /// Which mode the drive is near, and how far off it (0.7 … 1.3 of its frequency).
    mode: u8,
    detune: u8,
    amplitude: u8,
}

#[derive(Arbitrary, Debug)]
struct Input {
    dofs: u8,
    dashpots: [u8; 5],
    experiments: Vec<Experiment>,
    corruptions: Vec<Corruption>,
    pipeline: u8,
    nonnegative: bool,
    /// Sensor noise: 0, 10⁻⁴ or 10⁻³ of each channel's amplitude.
    noise: u8,
    seed: u64,
}

/// One record's parts before `Record::new`: x, v, force signal, force DOF.
struct Raw {
    x: Mat<f64>,
    v: Mat<f64>,
    force: Vec<f64>,
    dof: usize,
    omega: f64,
}

/// The complex steady response X of (K − ω²I + iωC) X = e_d a for the chain with
/// element dashpots `c` (element 0 = DOF 1 to the left wall, element n = DOF n to the
/// right wall), by Gaussian elimination with partial pivoting (n ≤ 4).
fn response(n: usize, c: &[f64], omega: f64, dof: usize, a: f64) -> Vec<(f64, f64)> {
    let mut z = vec![vec![(0.0, 0.0); n + 1]; n];
    for i in 0..n {
        z[i][i].0 = 2.0 - omega * omega;
        z[i][i].1 = omega * (c[i] + c[i + 1]);
        if i + 1 < n {
            z[i][i + 1] = (-1.0, -omega * c[i + 1]);
            z[i + 1][i] = (-1.0, -omega * c[i + 1]);
        }
    }
    z[dof][n] = (a, 0.0);
    let mul = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
    let div = |p: (f64, f64), q: (f64, f64)| {
        let d = q.0 * q.0 + q.1 * q.1;
        ((p.0 * q.0 + p.1 * q.1) / d, (p.1 * q.0 - p.0 * q.1) / d)
    };
    for k in 0..n {
        let pivot = (k..n)
            .max_by(|&i, &j| {
                let m = |r: usize| z[r][k].0.hypot(z[r][k].1);
                m(i).total_cmp(&m(j))
            })
            .unwrap_or(k);
        z.swap(k, pivot);
        for i in k + 1..n {
            let f = div(z[i][k], z[k][k]);
            for j in k..=n {
                let t = mul(f, z[k][j]);
                z[i][j] = (z[i][j].0 - t.0, z[i][j].1 - t.1);
            }
        }
    }
    let mut x = vec![(0.0, 0.0); n];
    for i in (0..n).rev() {
        let mut s = z[i][n];
        for j in i + 1..n {
            let t = mul(z[i][j], x[j]);
            s = (s.0 - t.0, s.1 - t.1);
        }
        x[i] = div(s, z[i][i]);
    }
    x
}

/// A deterministic standard-normal-ish sequence (sum of 4 uniforms, centred, scaled).
struct Noise(u64);

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

fn raw(n: usize, c: &[f64], e: &Experiment, noise: f64, rng: &mut Noise) -> Raw {
    let dof = usize::from(e.force_dof) % n;
    let mode = 1 + usize::from(e.mode) % n;
    let natural = 2.0 * (mode as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin();
    let omega = natural * (0.7 + 0.6 * f64::from(e.detune) / 255.0);
    let a = 0.25 + f64::from(e.amplitude) / 64.0;
    let x_hat = response(n, c, omega, dof, a);
    let samples = PER_PERIOD * PERIODS + 1;
    let h = 2.0 * std::f64::consts::PI / omega / PER_PERIOD as f64;
    let level: Vec<f64> = x_hat.iter().map(|p| noise * p.0.hypot(p.1)).collect();
    let mut x = Mat::zeros(samples, n);
    let mut v = Mat::zeros(samples, n);
    for i in 0..samples {
        let (cos, sin) = ((omega * i as f64 * h).cos(), (omega * i as f64 * h).sin());
        for j in 0..n {
            let (re, im) = x_hat[j];
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

/// Applies `corruption`; returns the factor by which it scales every true coefficient:
/// the force in other units in *every* record is the invariant force × k → θ × k, which
/// no check of the data can tell from a k times more damped structure.
fn corrupt(raws: &mut [Raw], n: usize, corruption: Corruption) -> f64 {
    let each = |record: u8| -> Vec<usize> {
        if record == u8::MAX {
            (0..raws.len()).collect()
        } else {
            vec![usize::from(record) % raws.len()]
        }
    };
    match corruption {
        Corruption::FlipForce { record } => {
            for r in each(record) {
                raws[r].force.iter_mut().for_each(|f| *f = -*f);
            }
        }
        Corruption::FlipMotion { record, dof } => {
            let j = usize::from(dof) % n;
            for r in each(record) {
                for i in 0..raws[r].x.nrows() {
                    raws[r].x[(i, j)] = -raws[r].x[(i, j)];
                    raws[r].v[(i, j)] = -raws[r].v[(i, j)];
                }
            }
        }
        Corruption::MoveForce { record, dof } => {
            for r in each(record) {
                raws[r].dof = usize::from(dof) % n;
            }
        }
        Corruption::SwapMotion { record, a, b } => {
            let (a, b) = (usize::from(a) % n, usize::from(b) % n);
            for r in each(record) {
                for i in 0..raws[r].x.nrows() {
                    let (xa, xb) = (raws[r].x[(i, a)], raws[r].x[(i, b)]);
                    raws[r].x[(i, a)] = xb;
                    raws[r].x[(i, b)] = xa;
                    let (va, vb) = (raws[r].v[(i, a)], raws[r].v[(i, b)]);
                    raws[r].v[(i, a)] = vb;
                    raws[r].v[(i, b)] = va;
                }
            }
        }
        Corruption::DeadMotion { record, dof } => {
            let j = usize::from(dof) % n;
            for r in each(record) {
                for i in 0..raws[r].x.nrows() {
                    raws[r].x[(i, j)] = 0.0;
                    raws[r].v[(i, j)] = 0.0;
                }
            }
        }
        Corruption::ScaleForce { record, power } => {
            let factor = 10f64.powi(1 + i32::from(power % 3));
            for r in each(record) {
                raws[r].force.iter_mut().for_each(|f| *f *= factor);
            }
            if record == u8::MAX {
                return factor;
            }
        }
        Corruption::VelocityAsDisplacement { record } => {
            for r in each(record) {
                raws[r].x = raws[r].v.clone();
            }
        }
    }
    1.0
}

fn settings(pipeline: u8, nonnegative: bool) -> IdentifySettings {
    let windows = Windows::Cycles(WindowSpec::cycles(1));
    let regressor = match pipeline % 4 {
        0 => RegressorSettings {
            windows,
            ..RegressorSettings::default()
        },
        p => RegressorSettings {
            windows,
            quadrature: Quadrature::Trapezoid,
            velocity: match p {
                1 => VelocitySource::Spectral { harmonics: None },
                2 => VelocitySource::CentralDifference,
                _ => VelocitySource::Measured,
            },
            noise: NoiseTreatment::Ignore,
            ..RegressorSettings::default()
        },
    };
    let mut settings = IdentifySettings {
        regressor,
        ..IdentifySettings::default()
    };
    if nonnegative {
        settings.fit.constraints = Constraints::nonnegative();
    }
    settings
}

fuzz_target!(|input: Input| {
    let n = 2 + usize::from(input.dofs) % 3;
    let truth: Vec<f64> = input.dashpots[..=n]
        .iter()
        .map(|k| (1.0 + f64::from(k % 16)) / 64.0)
        .collect();
    if input.experiments.is_empty() || input.experiments.len() > 8 || input.corruptions.len() > 3 {
        return;
    }
    let noise = [0.0, 1e-4, 1e-3][usize::from(input.noise) % 3];
    let mut rng = Noise(input.seed);
    let mut raws: Vec<Raw> = input
        .experiments
        .iter()
        .map(|e| raw(n, &truth, e, noise, &mut rng))
        .collect();
    let mut units = 1.0;
    for c in &input.corruptions {
        units *= corrupt(&mut raws, n, *c);
    }
    // What a consistent units error makes of the truth (force × k → θ × k).
    let truth: Vec<f64> = truth.iter().map(|t| t * units).collect();
    let clean = input.corruptions.is_empty() && noise == 0.0;
    let mut records = Vec::new();
    for (k, r) in raws.into_iter().enumerate() {
        let record = Record::new(RecordParts {
            label: format!("r{}", k + 1),
            step: 2.0 * std::f64::consts::PI / r.omega / PER_PERIOD as f64,
            start_time: 0.0,
            displacements: r.x,
            velocities: Some(r.v),
            forcing: Forcing::on_dofs(
                Mat::from_fn(r.force.len(), 1, |i, _| r.force[i]),
                vec![r.dof],
            ),
            period: 2.0 * std::f64::consts::PI / r.omega,
        });
        match record {
            Ok(record) => records.push(record),
            Err(_) => return,
        }
    }
    let model = DampingModel::new().with(Term::on_elements(
        dampid::terms::laws::Linear,
        Element::chain_fixed_both_ends(n),
        Coefficients::PerElement("c".into()),
    ));
    let settings = settings(input.pipeline, input.nonnegative);
    let report = match identify(
        &ParametricRegressor::linear(&model, &records),
        &settings,
        &silent,
    ) {
        Ok(found) => found.report,
        Err(e) => {
            assert!(
                !(clean
                    && matches!(
                        e,
                        Error::NegativeInputWork { .. } | Error::DeadMotionSensor { .. }
                    )),
                "clean records refused: {e}"
            );
            return;
        }
    };
    support::check(&report);
    let largest = truth.iter().copied().fold(0.0, f64::max);
    for (c, t) in report.coefficients.iter().zip(&truth) {
        let off = (c.value - t).abs();
        // A value on a bound is printed "(at lower bound)": the constraint, not the
        // data, set it, and it carries no standard error.
        let at_bound = report.active_constraints.iter().any(|a| a.name == c.name);
        let wrong = c.determined
            && !at_bound
            && off > TOLERANCE * largest
            && c.std_error.is_none_or(|se| off > SIGMAS * se);
        assert!(
            !wrong || !report.warnings.is_empty(),
            "{} = {} (truth {t}, se {:?}) reported without a warning\n{report}",
            c.name,
            c.value,
            c.std_error
        );
    }
});
