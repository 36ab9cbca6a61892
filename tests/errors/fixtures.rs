//! The fixtures every file of this binary shares, and the test that they are valid.
//!
//! Records are small and built by hand: x_j = X_j cos(ωt + φ_j) on 2 DOFs, T = 1,
//! h = 0.01 (100 samples per period), 201 samples (two periods), with measured
//! velocities and generalized forces r = c v (c = 0.3), so that a linear model with
//! one shared coefficient identifies c = 0.3 (checked by `fixtures_are_valid`: every
//! other test changes exactly one thing). The simulated system is a 2-DOF chain that
//! runs 20 steps.

use std::f64::consts::PI;

use dampid::prelude::*;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use faer::Mat;

/// Sampling step.
pub const H: f64 = 0.01;
/// Driving period.
pub const T: f64 = 1.0;
/// Samples in the fixture record (two periods plus the closing sample).
pub const N: usize = 201;
/// Samples one trapezoid window of one period reads: T/h + 1.
pub const WINDOW: usize = 101;
/// The linear damping coefficient the fixture forces balance.
pub const C_TRUE: f64 = 0.3;
/// Amplitudes and phases of the two DOFs.
const AMPLITUDE: [f64; 2] = [1.0, 0.5];
const PHASE: [f64; 2] = [0.0, 0.3];

/// The three quadrature rules.
pub const RULES: [Quadrature; 3] = [
    Quadrature::Rectangular,
    Quadrature::Trapezoid,
    Quadrature::Spectral,
];

fn omega() -> f64 {
    2.0 * PI / T
}

pub fn displacements(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| {
        AMPLITUDE[j] * (omega() * i as f64 * H + PHASE[j]).cos()
    })
}

pub fn velocities(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| {
        -omega() * AMPLITUDE[j] * (omega() * i as f64 * H + PHASE[j]).sin()
    })
}

/// Generalized forces r = c v: the input work balances linear damping c.
pub fn forces(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| C_TRUE * velocities(samples)[(i, j)])
}

pub fn parts(samples: usize) -> RecordParts {
    RecordParts {
        label: "fixture".into(),
        step: H,
        start_time: 0.0,
        displacements: displacements(samples),
        velocities: Some(velocities(samples)),
        forcing: Forcing::generalized(forces(samples)),
        period: T,
    }
}

pub fn record() -> Record {
    Record::new(parts(N)).expect("fixture record is valid")
}

/// [`Record::new`] of the fixture's parts after `edit`.
pub fn record_with(edit: impl FnOnce(&mut RecordParts)) -> Result<Record> {
    let mut p = parts(N);
    edit(&mut p);
    Record::new(p)
}

/// Linear damping on each DOF to ground, one shared coefficient "c".
pub fn shared_model() -> DampingModel {
    DampingModel::new().with(Term::per_dof(Linear, 2, Coefficients::Shared("c".into())))
}

/// Linear damping on each DOF to ground, coefficients "c[1]" and "c[2]".
pub fn per_dof_model() -> DampingModel {
    DampingModel::new().with(Term::per_dof(
        Linear,
        2,
        Coefficients::PerElement("c".into()),
    ))
}

/// The default settings with measured velocities: one window of one period per record,
/// trapezoid rule.
pub fn measured() -> IdentifySettings {
    windows(WindowSpec::default())
}

/// [`measured`] with the whole-period windows `spec`.
pub fn windows(spec: WindowSpec) -> IdentifySettings {
    crate::support::identify_settings(spec, Quadrature::Trapezoid, VelocitySource::Measured)
}

/// Two windows (count: None) so that the per-DOF model passes the equation count.
pub fn two_windows(constraints: Constraints) -> IdentifySettings {
    let mut settings = windows(WindowSpec::cycles(1));
    settings.fit.constraints = constraints;
    settings
}

/// Constraints of one bound on `name`.
pub fn bound(name: &str, lower: Option<f64>, upper: Option<f64>) -> Constraints {
    Constraints {
        bounds: vec![Bound {
            name: name.into(),
            lower,
            upper,
        }],
        ..Constraints::default()
    }
}

/// Constraints that fix `name` at `value`.
pub fn fixed(name: &str, value: f64) -> Constraints {
    Constraints {
        fixed: vec![Fixed {
            name: name.into(),
            value,
        }],
        ..Constraints::default()
    }
}

/// A well-posed 2-DOF chain: M = I, K = tridiag(−1, 2, −1), linear damping 0.1,
/// a unit force at ω = 1 on DOF 1; 20 recorded steps of h = 0.1 (fast).
pub fn system() -> System {
    System {
        mass: Mat::identity(2, 2),
        stiffness: Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 }),
        damping: shared_model(),
        damping_coefficients: vec![0.1],
        conservative: Vec::new(),
        forcing: vec![HarmonicForce {
            dof: 1,
            amplitude: 1.0,
            frequency: 1.0,
            phase: 0.0,
        }],
    }
}

pub fn sim_settings() -> SimSettings {
    SimSettings {
        step: 0.1,
        substeps: 1,
        transient_steps: 0,
        recorded_steps: 20,
    }
}

/// [`simulate`] of the fixture system after `edit`, with the fixture settings.
pub fn simulate_with(edit: impl FnOnce(&mut System)) -> Result<Record> {
    let mut sys = system();
    edit(&mut sys);
    simulate(&sys, &sim_settings(), &dampid::progress::silent)
}

/// Asserts `result` is `InvalidParameter` named `name` with value `value` (NaN-aware).
#[track_caller]
pub fn assert_invalid<T: std::fmt::Debug>(result: Result<T>, name: &str, value: f64) -> Error {
    match result {
        Err(
            ref e @ Error::InvalidParameter {
                name: ref n,
                value: v,
                ref reason,
            },
        ) => {
            assert_eq!(n, name, "{e}");
            assert!(
                v == value || (v.is_nan() && value.is_nan()),
                "value {v}, expected {value}: {e}"
            );
            assert!(!reason.is_empty(), "{e}");
            e.clone()
        }
        other => panic!("expected InvalidParameter '{name}' = {value}, got {other:?}"),
    }
}

/// Asserts `err` is `NonFinite` in `what` at (`row`, `column`), with a NaN value.
#[track_caller]
pub fn assert_nan_at(err: &Error, what: &str, row: usize, column: usize) {
    match err {
        Error::NonFinite {
            what: w,
            row: r,
            column: c,
            value,
        } => {
            assert_eq!(w, what);
            assert_eq!((*r, *c), (row, column));
            assert!(value.is_nan());
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
}

/// [`dampid::model_file::parse`] of `text` as the file `file`, relative to `.`.
/// A 3-DOF model file reading models/data/chain3/record_1.csv with the motion columns
/// `motion` (lines of `[[data.records]]`; the block starts on line 7).
pub fn chain3_with_motion(motion: &str) -> String {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/chain3/record_1.csv");
    format!(
        "dofs = 3\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n[[data.records]]\nfile = \"{}\"\ntime = \"t\"\n{motion}\nforces = [{{ column = \"f1\", dof = 1 }}]\nfrequency = 0.765367\n",
        file.display()
    )
}

pub fn parse_model(text: &str, file: &str) -> Result<dampid::model_file::Job> {
    dampid::model_file::parse(text, file, std::path::Path::new("."), Default::default())
}

/// The fixture record with its amplitude growing by half over its two periods: the
/// state at the end of the first window differs from its start by about a quarter of
/// the amplitude, and the steady-state check names record, window and mismatch.
pub fn growing_record_is_not_steady() -> Error {
    let grow = |i: usize| 1.0 + 0.5 * i as f64 / N as f64;
    let record = record_with(|p| {
        let x = p.displacements.clone();
        let v = p.velocities.clone().unwrap();
        p.displacements = Mat::from_fn(N, 2, |i, j| grow(i) * x[(i, j)]);
        p.velocities = Some(Mat::from_fn(N, 2, |i, j| grow(i) * v[(i, j)]));
        p.label = "growing".into();
    })
    .unwrap();
    let settings = measured().regressor;
    let report = dampid::prep::steady_state::check(
        &[record],
        settings.windows.cycles().unwrap(),
        settings.quadrature,
        None,
        &dampid::prep::steady_state::SteadyStateSettings::default(),
    )
    .unwrap();
    report.enforce().unwrap_err()
}

#[test]
fn fixtures_are_valid() {
    let report = identify(
        &ParametricRegressor::linear(&shared_model(), &[record()]),
        &measured(),
        &silent,
    )
    .unwrap()
    .report;
    let c = report.coefficient("c").unwrap();
    assert!((c - C_TRUE).abs() < 1e-6 * C_TRUE, "c = {c}");

    let sim = simulate(&system(), &sim_settings(), &dampid::progress::silent).unwrap();
    assert_eq!(sim.samples(), 20);
    assert_eq!(sim.dofs(), 2);
}
