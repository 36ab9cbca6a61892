//! The paper's section 2.2 as tests: every four-mass case is simulated and identified
//! and must land within its tolerance of the truth (c = 0.15, d = 0.10).

use dampid::prelude::*;
use dampid::prep::quadrature::Quadrature;
use dampid::reference::{FOUR_MASS_C, FOUR_MASS_D, FourMassSummary, four_mass_records};
use dampid::simulate::chain_stiffness;

#[test]
fn four_mass_cases_meet_their_tolerances_with_the_papers_rule() {
    let summary = FourMassSummary::run(Quadrature::Rectangular).unwrap();
    assert_eq!(summary.cases.len(), 6);
    for (case, outcome) in &summary.cases {
        assert!(
            outcome.passes(case),
            "{}: errors {} {}",
            case.name,
            outcome.error_c,
            outcome.error_d
        );
    }
    let json = summary.to_json();
    assert_eq!(json["cases"].as_array().unwrap().len(), 6);
    assert!(json["cases"][0]["report"]["coefficients"][0]["value"].is_f64());
}

#[test]
fn four_mass_cases_meet_their_tolerances_with_exact_rules() {
    for rule in [Quadrature::Trapezoid, Quadrature::Spectral] {
        let summary = FourMassSummary::run(rule).unwrap();
        assert!(summary.all_pass(), "{rule:?}\n{summary}");
    }
}

/// The chain with the cubic spring and a spurious Coulomb term on every mass (true value
/// 0), on measured velocities: least squares puts it slightly below zero (−1.1e-4 with
/// these settings; the simulation is deterministic), the nonnegative fit holds it
/// exactly at 0 and keeps c and d on the truth. (The default pipeline puts it at
/// +8e-5 on these noise-free records, where its weights are set by round-off, so it
/// has no bound to hold there.)
#[test]
fn nonnegative_fit_holds_a_spurious_friction_term_at_zero() {
    let records = four_mass_records(true, 4).unwrap();
    let model = DampingModel::new()
        .with(Term::stiffness_proportional("c", chain_stiffness(4)))
        .with(Term::per_dof(
            Quadratic,
            4,
            Coefficients::Shared("d".into()),
        ))
        .with(Term::per_dof(Coulomb, 4, Coefficients::Shared("mu".into())));
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(1).first(4).into();
    settings.regressor.velocity = VelocitySource::Measured;
    let ls = identify(
        &ParametricRegressor::linear(&model, &records),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    settings.fit.constraints = Constraints::nonnegative();
    let nn = identify(
        &ParametricRegressor::linear(&model, &records),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    let mu_ls = ls.coefficient("mu").unwrap();
    let mu_nn = nn.coefficient("mu").unwrap();
    assert!(mu_ls < 0.0 && mu_ls > -1e-3, "least squares mu = {mu_ls}");
    assert_eq!(mu_nn, 0.0);
    assert_eq!(nn.active_constraints.len(), 1);
    assert_eq!(nn.active_constraints[0].name, "mu");
    assert!((nn.coefficient("c").unwrap() - FOUR_MASS_C).abs() < 0.005 * FOUR_MASS_C);
    assert!((nn.coefficient("d").unwrap() - FOUR_MASS_D).abs() < 0.01 * FOUR_MASS_D);
}
