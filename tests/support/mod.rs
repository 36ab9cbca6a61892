//! Fixtures shared by the integration tests: records of pure harmonic motion whose
//! cycle integrals have closed forms.

#![allow(dead_code)]

pub mod cli;
pub mod complex_chain;
pub mod fuzz_chain;
pub mod mixed_record;
pub mod regressors;

use dampid::prelude::*;
use faer::Mat;

/// Writes a test's scratch CSV file (replacing one an earlier run left behind).
pub fn write_scratch_csv(path: &std::path::Path, headers: &[String], columns: &[Vec<f64>]) {
    dampid::io::csv::write(
        path,
        headers,
        columns,
        dampid::io::output::Overwrite::Replace,
    )
    .unwrap();
}

/// Harmonic motion x_i = X_i cos(ωt + φ_i) on n DOFs with exact velocities, and a
/// force F cos(ωt + ψ) on DOF `force_dof`; `per_period` samples per period (any real).
pub struct Harmonic {
    pub amplitudes: Vec<f64>,
    pub phases: Vec<f64>,
    pub omega: f64,
    pub per_period: f64,
    pub periods: f64,
    pub force: f64,
    pub force_phase: f64,
    pub force_dof: usize,
}

impl Harmonic {
    pub fn one_dof(amplitude: f64, omega: f64, per_period: f64) -> Self {
        Harmonic {
            amplitudes: vec![amplitude],
            phases: vec![0.0],
            omega,
            per_period,
            periods: 2.0,
            force: 1.0,
            force_phase: 0.7,
            force_dof: 0,
        }
    }

    /// Two DOFs over one period, a unit force on DOF 0 in phase with its velocity, so
    /// that it does work (π X_0 F); one in phase with the displacement would do none,
    /// and the regressor refuses a record whose force does no work.
    pub fn two_dofs(amplitudes: [f64; 2], phases: [f64; 2], omega: f64, per_period: f64) -> Self {
        Harmonic {
            amplitudes: amplitudes.to_vec(),
            phases: phases.to_vec(),
            omega,
            per_period,
            periods: 1.0,
            force: 1.0,
            force_phase: phases[0] + std::f64::consts::FRAC_PI_2,
            force_dof: 0,
        }
    }

    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }

    pub fn record(&self) -> Record {
        let h = self.period() / self.per_period;
        let samples = (self.periods * self.per_period).ceil() as usize + 3;
        let n = self.amplitudes.len();
        let phase = |i: usize, j: usize| self.omega * i as f64 * h + self.phases[j];
        let x = Mat::from_fn(samples, n, |i, j| self.amplitudes[j] * phase(i, j).cos());
        let v = Mat::from_fn(samples, n, |i, j| {
            -self.amplitudes[j] * self.omega * phase(i, j).sin()
        });
        let f = Mat::from_fn(samples, 1, |i, _| {
            self.force * (self.omega * i as f64 * h + self.force_phase).cos()
        });
        Record::new(RecordParts {
            label: "harmonic".into(),
            step: h,
            start_time: 0.0,
            displacements: x,
            velocities: Some(v),
            forcing: Forcing::on_dofs(f, vec![self.force_dof]),
            period: self.period(),
        })
        .expect("valid harmonic record")
    }
}

/// Regressor settings over the whole-period windows `windows`, with `quadrature` and
/// `velocity`; the rest at their defaults: noise treatment `Auto` (with harmonic
/// projection the noise-robust rows are built, unlike [`RegressorSettings::plain`]) and
/// velocity-weighted work.
pub fn settings(
    windows: WindowSpec,
    quadrature: Quadrature,
    velocity: VelocitySource,
) -> RegressorSettings {
    RegressorSettings {
        windows: windows.into(),
        quadrature,
        velocity,
        ..Default::default()
    }
}

/// [`settings`] for [`identify`], with the fit at its defaults.
pub fn identify_settings(
    windows: WindowSpec,
    quadrature: Quadrature,
    velocity: VelocitySource,
) -> IdentifySettings {
    IdentifySettings {
        regressor: settings(windows, quadrature, velocity),
        ..IdentifySettings::default()
    }
}

/// The single regressor row (columns, input work) of `model` on `record`.
pub fn row(
    model: &DampingModel,
    record: &Record,
    quadrature: Quadrature,
    velocity: VelocitySource,
) -> (Vec<f64>, f64) {
    let settings = settings(WindowSpec::default(), quadrature, velocity);
    let regressor =
        Regressor::build(model, std::slice::from_ref(record), &settings).expect("regressor");
    let a = regressor.matrix();
    (
        (0..a.ncols()).map(|k| a[(0, k)]).collect(),
        regressor.rhs()[0],
    )
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
