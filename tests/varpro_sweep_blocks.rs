//! Variable projection of a stepped-sine table with per-sweep residual receptances
//! (src/varpro/sweep_blocks.rs: sweeps rebuilt one at a time, closed-form Jacobian
//! columns of the residual unknowns) against the simulated truth of the bolted-joint
//! generator (models/data/bolted_joint/generate.py: c = 1.2566, d = 5, exponent 1.5,
//! R = −2e-6 m/N in every sweep), with the power law's exponent estimated too.

use std::path::Path;

use dampid::identify::identify;
use dampid::progress::silent;

#[test]
fn exponent_and_residuals_estimated_cover_the_truth() {
    let text = std::fs::read_to_string("models/bolted_joint_stepped_sine_residual.toml")
        .unwrap()
        .replace(
            "exponent = 1.5 ",
            "exponent = { estimate = true, initial = 1.2, lower = 0.5, upper = 3.0 } ",
        );
    assert!(text.contains("estimate = true"));
    let job = dampid::model_file::parse(
        &text,
        "residual.toml",
        Path::new("models"),
        Default::default(),
    )
    .unwrap();
    let found = identify(&job.problem(), &job.settings, &silent).unwrap();
    let estimation = found.report.estimation.as_ref().unwrap();
    assert!(estimation.status.converged, "{}", found.report);
    // the exponent's profile interval holds 1.5
    let exponent = &estimation.parameters[0];
    let interval = exponent.interval.as_ref().unwrap();
    let (lo, hi) = (interval.lower.unwrap(), interval.upper.unwrap());
    assert!(
        lo < 1.5 && 1.5 < hi,
        "exponent {} in [{lo}, {hi}]",
        exponent.value
    );
    // every sweep's r_k: its joint interval holds −2e-6
    assert_eq!(estimation.parameters.len(), 1 + 7);
    for r in &estimation.parameters[1..] {
        let [lo, hi] = r.joint_interval.unwrap();
        assert!(
            lo < -2e-6 && -2e-6 < hi,
            "{}: {} in [{lo}, {hi}]",
            r.name,
            r.value
        );
    }
    // c and d: their joint intervals hold the truth
    for (coefficient, truth) in estimation.coefficients.iter().zip([1.2566, 5.0]) {
        let (lo, hi) = (coefficient.lower.unwrap(), coefficient.upper.unwrap());
        assert!(
            lo < truth && truth < hi,
            "{}: {} in [{lo}, {hi}]",
            coefficient.name,
            coefficient.value
        );
    }
}

/// The shipped residual example under ordinary weighting, its exponent estimated
/// (`estimated`) or fixed at `exponent` (the r_k estimated alone).
fn ordinary_job(exponent: Option<f64>) -> dampid::model_file::Job {
    let law = match exponent {
        None => "exponent = { estimate = true, initial = 1.2, lower = 0.5, upper = 3.0 } ".into(),
        Some(p) => format!("exponent = {p:e} "),
    };
    let text = std::fs::read_to_string("models/bolted_joint_stepped_sine_residual.toml")
        .unwrap()
        .replace("exponent = 1.5 ", &law)
        + "\n[identification]\nweighting = \"ordinary\"\n";
    assert!(text.contains(&law));
    dampid::model_file::parse(
        &text,
        "residual.toml",
        Path::new("models"),
        Default::default(),
    )
    .unwrap()
}

/// The exponent's profile interval (its nested searches reading the kept regressor of
/// each iteration, src/varpro/problem.rs) against its definition, computed apart: at
/// each end p_e, a separate variable projection with the exponent fixed at p_e (the r_k
/// and c, d estimated from the model file's start, no continuation, no root search)
/// reaches the cost φ̂ + Δ, to 10⁻³ Δ (the root search stops within 10⁻⁶ of the bound
/// interval in p, the nested searches within 10⁻⁸ of the cost).
#[test]
fn profile_interval_ends_meet_their_definition() {
    let job = ordinary_job(None);
    let found = identify(&job.problem(), &job.settings, &silent).unwrap();
    let estimation = found.report.estimation.as_ref().unwrap();
    assert!(estimation.status.converged, "{}", found.report);
    let interval = estimation.parameters[0].interval.as_ref().unwrap();
    let (minimum, rise) = (estimation.cost, interval.rise);
    assert!(rise > 0.0 && rise < minimum, "{rise} vs {minimum}");
    for end in [interval.lower.unwrap(), interval.upper.unwrap()] {
        let fixed = ordinary_job(Some(end));
        let at = identify(&fixed.problem(), &fixed.settings, &silent).unwrap();
        let e = at.report.estimation.as_ref().unwrap();
        assert!(e.status.converged, "{}", at.report);
        assert_eq!(e.parameters.len(), 7);
        let excess = e.cost - minimum;
        assert!(
            (excess - rise).abs() <= 1e-3 * rise,
            "end {end}: P − φ̂ = {excess:e}, Δ = {rise:e}"
        );
    }
}
