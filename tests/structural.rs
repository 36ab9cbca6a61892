//! Structural (hysteretic) damping in windows of whole periods (src/terms/structural.rs)
//! against closed-form steady states, with no time integration.
//!
//! A chain M ẍ + C ẋ + K(η) x = r, the elements' stiffnesses complex, k_e(1 + iη_e),
//! driven by r(t) = Σ_n F_n cos(nωt) on DOF 1, has the steady state
//! x(t) = Σ_n Re[X_n e^{inωt}] with, per harmonic,
//!
//! ```text
//!   (K(η) − M(nω)² + i nω C) X_n = F_n        (SDOF: X_n = F_n/(k − m(nω)² + i nωc + iηk)),
//! ```
//!
//! solved here by complex Gaussian elimination. Over one period T = 2π/ω the damping
//! work of the loss factor is η π k Σ_n n |X_e,n|² (X_e the element's deformation; the
//! module doc of src/terms/structural.rs derives it), and of a dashpot c on the same
//! deformation π c ω Σ_n n² |X_e,n|²: the first is the same per cycle at every
//! frequency, the second grows with nω, so records with different harmonic mixes or
//! frequencies separate them.

use std::f64::consts::PI;

use dampid::prelude::*;
use dampid::prep::harmonic::sweeps::{PointNoise, SweptTable};
use dampid::regressor::NoiseTreatment;
use dampid::regressor::stepped_sine::StructuralTerm;

mod support;
use support::complex_chain::{Chain, PERIODS, Spring};

/// Plain rows, one window per period, measured velocities.
fn settings() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(1).into();
    settings.regressor.velocity = VelocitySource::Measured;
    settings.regressor.noise = NoiseTreatment::Ignore;
    settings
}

fn structural(k: f64, element: Element) -> Term {
    Term::structural(vec![element], vec![k], Coefficients::Shared("eta".into()))
}

fn viscous_to_ground(dofs: usize) -> Term {
    Term::per_dof(Linear, dofs, Coefficients::Shared("c".into()))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

const M: f64 = 2.0;
const K: f64 = 800.0;
const ETA: f64 = 0.03;
const C: f64 = 0.4;

fn no_extra(_: f64) -> f64 {
    0.0
}

/// The window's column is π k Σ_n n |X_n|², the hand-derived damping work per unit η,
/// and the input work η times it.
#[test]
fn column_is_the_hand_derived_work() {
    let chain = Chain::sdof(M, K, ETA, 0.0);
    let omega = 0.8 * (K / M).sqrt();
    let harmonics = [(1, 3.0), (2, 1.5)];
    let record = chain.record(omega, &harmonics, 1.0, &no_extra);
    let model = DampingModel::new().with(structural(K, Element::to_ground(0)));
    let regressor = Regressor::build(&model, &[record], &settings().regressor).unwrap();
    let squares = chain.deformation_squared(0, omega, &harmonics);
    let expected = PI * K * (squares[0] + 2.0 * squares[1]);
    assert_eq!(regressor.matrix().nrows(), PERIODS);
    for r in 0..PERIODS {
        let column = regressor.matrix()[(r, 0)];
        assert!(rel(column, expected) < 1e-10, "{column} vs {expected}");
        let input = regressor.rhs()[r];
        assert!(rel(input, ETA * expected) < 1e-10, "{input}");
    }
}

/// An SDOF driven by two harmonics: η comes back to 1e-8.
#[test]
fn sdof_loss_factor_from_two_harmonics() {
    let chain = Chain::sdof(M, K, ETA, 0.0);
    let omega = 0.55 * (K / M).sqrt();
    let record = chain.record(omega, &[(1, 2.0), (2, 1.0)], 1.0, &no_extra);
    let model = DampingModel::new().with(structural(K, Element::to_ground(0)));
    let report = identify(
        &ParametricRegressor::linear(&model, &[record]),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    let eta = report.coefficient("eta").unwrap();
    assert!(rel(eta, ETA) < 1e-8, "η = {eta}");
}

fn viscous_and_structural(records: &[Record]) -> (f64, f64) {
    let model = DampingModel::new()
        .with(viscous_to_ground(1))
        .with(structural(K, Element::to_ground(0)));
    let report = identify(
        &ParametricRegressor::linear(&model, records),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    (
        report.coefficient("c").unwrap(),
        report.coefficient("eta").unwrap(),
    )
}

/// With a dashpot beside the loss factor, two records of different harmonic mixes
/// separate them: the viscous work weighs harmonic n by n², the structural one by n.
#[test]
fn viscous_and_structural_separate_with_two_harmonics() {
    let chain = Chain::sdof(M, K, ETA, C);
    let omega = 0.45 * (K / M).sqrt();
    let records = [
        chain.record(omega, &[(1, 2.0), (2, 0.2)], 1.0, &no_extra),
        chain.record(omega, &[(1, 0.3), (2, 2.0)], 1.0, &no_extra),
    ];
    let (c, eta) = viscous_and_structural(&records);
    assert!(rel(c, C) < 1e-8, "c = {c}");
    assert!(rel(eta, ETA) < 1e-8, "η = {eta}");
}

/// … and so do two records at two frequencies, one harmonic each.
#[test]
fn viscous_and_structural_separate_with_two_frequencies() {
    let chain = Chain::sdof(M, K, ETA, C);
    let wn = (K / M).sqrt();
    let records = [
        chain.record(0.7 * wn, &[(1, 2.0)], 1.0, &no_extra),
        chain.record(1.3 * wn, &[(1, 2.0)], 1.0, &no_extra),
    ];
    let (c, eta) = viscous_and_structural(&records);
    assert!(rel(c, C) < 1e-8, "c = {c}");
    assert!(rel(eta, ETA) < 1e-8, "η = {eta}");
    // one frequency alone cannot: its two columns are proportional
    let model = DampingModel::new()
        .with(viscous_to_ground(1))
        .with(structural(K, Element::to_ground(0)));
    let regressor = Regressor::build(&model, &records[..1], &settings().regressor).unwrap();
    let a = regressor.matrix();
    let ratio = a[(0, 0)] / a[(0, 1)];
    // π c ω X² against π k X²: ω/k per unit c and η
    assert!(rel(ratio, 0.7 * wn / K) < 1e-10, "{ratio}");
}

/// The energy balance is linear in the force: a force λ times larger gives
/// coefficients λ times larger.
#[test]
fn force_scale_scales_the_coefficients() {
    let chain = Chain::sdof(M, K, ETA, C);
    let omega = 0.45 * (K / M).sqrt();
    let lambda = 7.5;
    let records = [
        chain.record(omega, &[(1, 2.0), (2, 0.2)], lambda, &no_extra),
        chain.record(omega, &[(1, 0.3), (2, 2.0)], lambda, &no_extra),
    ];
    let (c, eta) = viscous_and_structural(&records);
    assert!(rel(c, lambda * C) < 1e-8, "c = {c}");
    assert!(rel(eta, lambda * ETA) < 1e-8, "η = {eta}");
}

/// A conservative force g(x) added to the recorded force does no work over whole
/// periods, so it changes nothing (the quadrature is exact for the trigonometric
/// polynomial v·g(x), of degree 8 ≪ 100 samples' Nyquist).
#[test]
fn a_conservative_force_changes_nothing() {
    let chain = Chain::sdof(M, K, ETA, C);
    let omega = 0.45 * (K / M).sqrt();
    let spring = |x: f64| 300.0 * x + 1.0e7 * x * x * x;
    let records = [
        chain.record(omega, &[(1, 2.0), (2, 0.2)], 1.0, &spring),
        chain.record(omega, &[(1, 0.3), (2, 2.0)], 1.0, &spring),
    ];
    let (c, eta) = viscous_and_structural(&records);
    assert!(rel(c, C) < 1e-8, "c = {c}");
    assert!(rel(eta, ETA) < 1e-8, "η = {eta}");
}

/// A 2-DOF chain (ground–1–2, spring 2 between the masses) with the loss factor on the
/// spring between the masses only and dashpots to ground: η on element [1, 2] and c
/// come back, two frequencies (near each mode) and two harmonics.
#[test]
fn two_dof_chain_with_the_loss_factor_on_one_element() {
    let (k1, k2, eta) = (1000.0, 400.0, 0.05);
    let chain = Chain {
        mass: vec![1.0, 0.5],
        springs: vec![
            Spring {
                a: 0,
                b: None,
                k: k1,
                eta: 0.0,
            },
            Spring {
                a: 0,
                b: Some(1),
                k: k2,
                eta,
            },
        ],
        c: 0.3,
    };
    let records = [
        chain.record(15.0, &[(1, 1.0), (2, 0.4)], 1.0, &no_extra),
        chain.record(33.0, &[(1, 1.0)], 1.0, &no_extra),
    ];
    let model = DampingModel::new()
        .with(viscous_to_ground(2))
        .with(structural(k2, Element::between(0, 1)));
    let report = identify(
        &ParametricRegressor::linear(&model, &records),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    let (c, found) = (
        report.coefficient("c").unwrap(),
        report.coefficient("eta").unwrap(),
    );
    assert!(rel(c, 0.3) < 1e-8, "c = {c}");
    assert!(rel(found, eta) < 1e-8, "η = {found}");
    // the column is π k₂ Σ n |X₁ − X₂|²
    let squares = chain.deformation_squared(1, 15.0, &[(1, 1.0), (2, 0.4)]);
    let regressor = Regressor::build(&model, &records, &settings().regressor).unwrap();
    let expected = PI * k2 * (squares[0] + 2.0 * squares[1]);
    assert!(rel(regressor.matrix()[(0, 1)], expected) < 1e-10);
}

/// The stepped-sine closed form π k |Z_e|² and the time-domain column of the same
/// harmonic motion (the table's points synthesized, one period each, by the harmonic
/// approximation) agree, on an SDOF and on an element between two DOFs.
#[test]
fn stepped_sine_closed_form_and_time_domain_agree() {
    let k = 5.0e3;
    let points: Vec<SteppedSinePoint> = [(0.01, 0.3, 0.004, 1.2), (0.02, 0.9, 0.03, 2.0)]
        .iter()
        .enumerate()
        .map(|(i, &(x1, p1, x2, p2))| SteppedSinePoint {
            label: format!("p{i}"),
            frequency: 10.0 + 5.0 * i as f64,
            force_dof: 0,
            force_amplitude: 2.0,
            amplitudes: vec![x1, x2],
            phases: vec![p1, p2],
        })
        .collect();
    let n = points.len();
    let swept = SweptTable::with_noise(
        SteppedSineTable::new(points).unwrap(),
        vec![0; n],
        vec!["all".into()],
        vec![
            PointNoise {
                force: 0.0,
                amplitudes: vec![0.0, 0.0],
                phases: vec![1e-3, 1e-3],
            };
            n
        ],
    )
    .unwrap();
    let approximation = HarmonicApproximation::default();
    for (from, to, element) in [
        (Some(0), None, Element::to_ground(0)),
        (Some(0), Some(1), Element::between(0, 1)),
    ] {
        let mut table = SteppedSineSource::new(swept.clone(), approximation);
        table.structural = vec![StructuralTerm {
            coefficient: "eta".into(),
            stiffness: k,
            from,
            to,
        }];
        let closed = Regressor::build(&DampingModel::new(), &table, &settings().regressor).unwrap();
        let plain = SteppedSineSource::new(swept.clone(), approximation);
        let time_domain = Regressor::build(
            &DampingModel::new().with(structural(k, element)),
            &plain,
            &settings().regressor,
        )
        .unwrap();
        for r in 0..n {
            let (a, b) = (closed.matrix()[(r, 0)], time_domain.matrix()[(r, 0)]);
            assert!(rel(b, a) < 1e-10, "point {r}: {b} vs {a}");
        }
    }
}
