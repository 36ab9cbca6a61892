//! The packed loops give bitwise the same sums at every instruction-set level the CPU
//! can run (`dampid::terms::simd`: AVX-512, AVX2, baseline SSE2): each level is forced
//! in turn and
//!
//! - whole regressors are compared bitwise, for a model with linear dashpots on
//!   arbitrary DOF pairs and to ground, quadratic and Coulomb dampers per DOF, a power
//!   law with a non-integer exponent (shared, with element weights), a law without a
//!   closed power form (its own `power_sum`), a sparse matrix term (entries one by one)
//!   and a dense one (the Gram matrix), and force channels through a load matrix, under
//!   rectangular (uniform weights), trapezoid and spectral (per-sample weights) rules
//!   and with measured and central-difference velocities;
//! - `terms::lanes` (`sum`, `sum_of_difference`, `dot`) are compared bitwise on every
//!   length from 0 to 69, with per-sample and uniform weights;
//! - the default pipeline's identification (steady-state check, noise floors, harmonic
//!   projections, noise-robust rows, reweighted fit) of noisy records with whole samples
//!   per period, the records simulated at the level (and their range and finiteness
//!   pass), is compared as JSON: every number of its report, the check's included.
//!
//! The level is process-wide, so this file holds one test.

use dampid::campaign;
use dampid::prelude::*;
use dampid::prep::steady_state::SteadyStateSettings;
use dampid::reference::{
    FOUR_MASS_OMEGA, four_mass_model, four_mass_records_with, with_displacement_noise,
};
use dampid::simulate::SimSettings;
use dampid::terms::lanes;
use dampid::terms::simd::{self, Level};
use dampid::terms::{Element, Weights};
use faer::Mat;

mod support;

use support::mixed_record::{mixed_record, noise};

const DOFS: usize = 36;

fn record(samples: usize) -> Record {
    mixed_record(DOFS, samples, 11, 5, "levels")
}

fn model() -> DampingModel {
    let pairs = vec![
        Element::between(5, 0),
        Element::between(3, 17),
        Element::between(35, 2),
        Element::to_ground(11),
        Element::between(20, 21),
    ];
    let mut r = noise(3);
    let sparse = Mat::from_fn(DOFS, DOFS, |j, k| match (j, k) {
        _ if j == k => 2.0,
        _ if j + 1 == k => -0.7,
        (30, 0) => 0.4,
        _ => 0.0,
    });
    DampingModel::new()
        .with(Term::on_elements(
            Linear,
            pairs.clone(),
            Coefficients::PerElement("lin".into()),
        ))
        .with(Term::per_dof(
            Quadratic,
            DOFS,
            Coefficients::PerElement("quad".into()),
        ))
        .with(Term::per_dof(
            Coulomb,
            DOFS,
            Coefficients::PerElement("coul".into()),
        ))
        .with(Term::weighted(
            PowerLaw::new(0.7).unwrap(),
            pairs.clone(),
            vec![0.5, 1.0, 2.0, 0.25, 1.5],
            Coefficients::Shared("pow".into()),
        ))
        .with(Term::on_elements(
            Custom::new("v|v|^0.3", |_, v: f64| v * v.abs().powf(0.3)),
            pairs,
            Coefficients::Shared("custom".into()),
        ))
        .with(Term::viscous("sparse", sparse))
        .with(Term::viscous("dense", Mat::from_fn(DOFS, DOFS, |_, _| r())))
}

/// Every regressor of the cases below, built at the current level.
fn regressors(model: &DampingModel, record: &Record) -> Vec<Regressor> {
    let cases = [
        (
            Quadrature::Rectangular,
            WindowSpec::cycles(4),
            VelocitySource::Measured,
        ),
        (
            Quadrature::Trapezoid,
            WindowSpec::cycles(3),
            VelocitySource::Measured,
        ),
        (
            Quadrature::Spectral,
            WindowSpec::cycles(1).first(2),
            VelocitySource::Measured,
        ),
        (
            Quadrature::Trapezoid,
            WindowSpec::cycles(2),
            VelocitySource::CentralDifference,
        ),
    ];
    cases
        .into_iter()
        .map(|(quadrature, windows, velocity)| {
            let settings = RegressorSettings {
                windows: windows.skipping(3).into(),
                quadrature,
                velocity,
                ..RegressorSettings::default()
            };
            Regressor::build(model, std::slice::from_ref(record), &settings).unwrap()
        })
        .collect()
}

/// The default pipeline's report, as JSON, on the four-mass records with 64 samples
/// per period (so the check and the noise floors read real FFTs) and 1 % displacement
/// noise, made at the current level; windows of one period, the steady-state check on.
fn default_pipeline() -> String {
    let period = 2.0 * std::f64::consts::PI / FOUR_MASS_OMEGA;
    let simulation = SimSettings {
        step: period / 64.0,
        transient_steps: 2000,
        recorded_steps: 6 * 64 + 1,
        ..SimSettings::default()
    };
    let clean = four_mass_records_with(false, &simulation).unwrap();
    let records = with_displacement_noise(&clean, 0.01, 3).unwrap();
    let model = four_mass_model();
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(1).into();
    settings.steady_state = Some(SteadyStateSettings::default());
    let rows = campaign::rows(&model, &records, 0, &settings).unwrap();
    let found = identify(
        &ParametricRegressor::linear(&model, &rows),
        &settings,
        &silent,
    )
    .unwrap();
    let check = found.steady_state.expect("the check was asked for");
    assert!(check.windows.len() == 24, "every window judged");
    serde_json::to_string(&(&found.report, &*check)).unwrap()
}

/// `lanes` on every length from 0 to 69, per-sample and uniform weights.
fn lane_sums() -> Vec<f64> {
    let mut out = Vec::new();
    let g = |v: f64| v * v * v.abs();
    for len in 0..70 {
        let w: Vec<f64> = (0..len).map(|i| 0.5 + (i % 3) as f64 * 0.3).collect();
        let a: Vec<f64> = (0..len).map(|i| (i as f64 * 0.7).sin()).collect();
        let b: Vec<f64> = (0..len).map(|i| (i as f64 * 0.3).cos()).collect();
        for weights in [Weights::PerSample(&w), Weights::Uniform(0.25)] {
            out.push(lanes::sum(weights, &a, g));
            out.push(lanes::sum_of_difference(weights, &a, &b, g));
            out.push(lanes::dot(weights, &a, &b));
        }
    }
    out
}

#[test]
fn every_level_gives_bitwise_the_same_sums() {
    let levels: Vec<Level> = Level::ALL
        .into_iter()
        .filter(|level| level.available())
        .collect();
    eprintln!(
        "levels compared: {:?} (detected: {})",
        levels.iter().map(|l| l.name()).collect::<Vec<_>>(),
        Level::detected().name()
    );
    let model = model();
    let record = record(5_000);
    let mut first: Option<(Level, Vec<Regressor>, Vec<f64>, String)> = None;
    for level in levels {
        assert!(simd::force(Some(level)), "{} is available", level.name());
        assert_eq!(simd::level(), level);
        let built = regressors(&model, &record);
        let sums = lane_sums();
        let report = default_pipeline();
        match &first {
            None => first = Some((level, built, sums, report)),
            Some((reference, built_then, sums_then, report_then)) => {
                let (a, b) = (reference.name(), level.name());
                for (case, (one, other)) in built_then.iter().zip(&built).enumerate() {
                    let (rows, columns) = one.matrix().shape();
                    assert_eq!(other.matrix().shape(), (rows, columns));
                    for r in 0..rows {
                        for k in 0..columns {
                            let (x, y) = (one.matrix()[(r, k)], other.matrix()[(r, k)]);
                            assert_eq!(
                                x.to_bits(),
                                y.to_bits(),
                                "case {case}, row {r}, column {} ({}): {a} {x} vs {b} {y}",
                                k,
                                one.columns()[k]
                            );
                        }
                        let (x, y) = (one.rhs()[r], other.rhs()[r]);
                        assert_eq!(x.to_bits(), y.to_bits(), "case {case}, b[{r}]: {x} vs {y}");
                    }
                }
                for (i, (x, y)) in sums_then.iter().zip(&sums).enumerate() {
                    assert_eq!(x.to_bits(), y.to_bits(), "lane sum {i}: {a} {x} vs {b} {y}");
                }
                assert!(
                    report == *report_then,
                    "the default pipeline's report differs between {a} and {b}"
                );
            }
        }
    }
    assert!(simd::force(None));
    assert_eq!(simd::level(), Level::detected());
}
