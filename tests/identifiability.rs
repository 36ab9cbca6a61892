//! Identifiability diagnostics: practically zero singular values against the equation
//! noise, near-null directions and determined combinations by name, variance inflation
//! factors, and what the report and `dampid check` say in words.

use dampid::analysis::diagnostics::diagnose;
use dampid::analysis::identifiability::{IdentifiabilitySettings, analyse};
use dampid::fit;
use dampid::prelude::*;
use dampid::report::Warning;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use faer::Mat;

mod support;
use support::cli::dampid_ok;
use support::regressors::from_rows;

/// Column t1 = 0.2 · column t0, b = 1.4 · column t0 (θ = (1, 2)). With unit-norm columns
/// A_s = [u, u]: v_1 = (1, 1)/√2, v_2 = (1, −1)/√2. The null direction Δθ ∝ v_2/S =
/// (1, −5)/S_0, normalised to largest +1: (−0.2, 1). The determined functional
/// g ∝ v_1 ∘ S = (1, 0.2) S_0: t0 + 0.2 t1, whose value is 1 + 0.4 = 1.4 whatever
/// θ the minimum-norm solution picks.
#[test]
fn proportional_columns_name_the_trade_off_and_the_determined_combination() {
    let r = from_rows(
        &[&[1.0, 0.2], &[2.0, 0.4], &[3.0, 0.6], &[4.0, 0.8]],
        &[1.4, 2.8, 4.2, 5.6],
    );
    let id = analyse(&r, 1e-10);
    assert!(!id.separable());
    assert_eq!(id.unidentifiable, ["t0", "t1"]);
    assert_eq!(id.practical_rank, 1);
    assert_eq!(id.variance_inflation, [None, None]);
    let null = &id.null_directions[0].direction;
    assert_eq!(null.terms.len(), 2);
    assert!((null.terms[0].weight + 0.2).abs() < 1e-12, "{null:?}");
    assert_eq!(null.terms[1].weight, 1.0);
    assert!(id.null_directions[0].text.contains("t0 and t1 trade off"));
    let determined = &id.determined[0];
    assert_eq!(determined.combination.text, "t0 + 0.200 t1");
    assert!((determined.value - 1.4).abs() < 1e-12);
    assert!(determined.std_error.unwrap() < 1e-12);
}

/// Unit columns at angle φ: AᵀA = [[1, cos φ], [cos φ, 1]], so
/// VIF = [(AᵀA)⁻¹]_jj = 1/(1 − cos²φ) = 1/sin²φ = 4 at φ = 30°; singular values
/// √(1 ± cos φ). b in the span: no residual, every coefficient determined.
#[test]
fn variance_inflation_of_two_columns_at_thirty_degrees() {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let r = from_rows(&[&[1.0, c], &[0.0, s], &[0.0, 0.0]], &[1.0 + c, s, 0.0]);
    let id = analyse(&r, 1e-10);
    for vif in &id.variance_inflation {
        assert!((vif.unwrap() - 4.0).abs() < 1e-12, "{vif:?}");
    }
    assert!(id.separable());
    assert!(id.determined.is_empty());
    let d = diagnose(&r, &fit::least_squares(&r, 1e-10).unwrap(), 1e-10);
    assert!((d.singular_values[1] - (1.0 - c).sqrt()).abs() < 1e-12);
}

/// The noise rule. e, f, g orthonormal in R⁴; columns e and (e + δf)/√(1 + δ²) have
/// σ_2 = √(1 − 1/√(1 + δ²)) ≈ δ/√2 = 0.00707 for δ = 0.01. With b = e + ηg the
/// residual is ηg: in the scaled equations s = η/√(1 + η²)/√(4 − 2). κ = 3:
/// η = 0.01 gives τ = 3s = 0.0212 > σ_2, so the second direction is practically zero
/// although the regressor has full rank; η = 0.001 gives τ = 0.00212 < σ_2.
#[test]
fn a_direction_below_three_noise_levels_is_practically_zero() {
    let e = [0.5, 0.5, 0.5, 0.5];
    let f = [0.5, -0.5, 0.5, -0.5];
    let g = [0.5, 0.5, -0.5, -0.5];
    let delta: f64 = 0.01;
    let sigma2 = (1.0 - 1.0 / (1.0 + delta * delta).sqrt()).sqrt();
    for (eta, separable) in [(0.01f64, false), (0.001, true)] {
        let rows: Vec<[f64; 2]> = (0..4).map(|i| [e[i], e[i] + delta * f[i]]).collect();
        let row_refs: Vec<&[f64]> = rows.iter().map(|r| r.as_slice()).collect();
        let b: Vec<f64> = (0..4).map(|i| e[i] + eta * g[i]).collect();
        let r = from_rows(&row_refs, &b);
        let id = analyse(&r, 1e-10);
        let s = eta / (1.0 + eta * eta).sqrt() / 2f64.sqrt();
        assert!((id.noise_level.unwrap() - s).abs() < 1e-12 * s.max(1.0));
        assert!((id.threshold - 3.0 * s).abs() < 1e-12);
        assert_eq!(id.separable(), separable, "η = {eta}, σ_2 = {sigma2}");
        let d = diagnose(&r, &fit::least_squares(&r, 1e-10).unwrap(), 1e-10);
        assert_eq!(d.rank, 2, "full numerical rank either way");
        assert!((d.singular_values[1] - sigma2).abs() < 1e-12);
    }
}

/// Noise-free data carry quadrature and velocity errors that hide from the residual:
/// the floor ε·σ_1 (ε = 1e-6) still counts σ_2/σ_1 = 1e-8 as zero.
#[test]
fn the_precision_floor_applies_when_the_residual_is_tiny() {
    let r = from_rows(
        &[&[1.0, 1.0], &[1.0, 1.0 + 1e-8], &[1.0, 1.0]],
        &[2.0, 2.0, 2.0],
    );
    let id = analyse(&r, 1e-12);
    assert!(!id.separable());
    let loose = dampid::analysis::identifiability::analyse_with(
        &r,
        1e-12,
        &IdentifiabilitySettings {
            precision: 0.0,
            ..IdentifiabilitySettings::default()
        },
    );
    assert!(loose.separable(), "{loose:?}");
    assert!(
        IdentifiabilitySettings {
            noise_factor: 0.0,
            ..IdentifiabilitySettings::default()
        }
        .validate()
        .is_err()
    );
}

/// The report never presents the least-squares numbers of unseparated coefficients as
/// estimates: `determined: false`, "not determined" in the table, a warning in words.
/// Under constraints the warning says the constraints place the solution.
/// A zero regressor: every σ_i of A_s is 0, so the relative threshold tol·σ_1 is 0 and
/// every σ_i ≥ 0 used to count as determined ("practical rank 0 of 2", then "every
/// coefficient is determined"). The absolute floor κ·ε = 3e-6 keeps τ positive, each
/// coefficient is a null direction of its own, and the fit refuses the regressor.
#[test]
fn a_zero_regressor_determines_nothing() {
    let r = from_rows(&[&[0.0, 0.0], &[0.0, 0.0], &[0.0, 0.0]], &[1.0, 2.0, 3.0]);
    let id = analyse(&r, 1e-10);
    assert_eq!(id.practical_rank, 0);
    assert!((id.threshold - 3e-6).abs() < 1e-18, "{}", id.threshold);
    assert!(!id.separable());
    assert_eq!(id.unidentifiable, ["t0", "t1"]);
    let texts: Vec<&str> = id.null_directions.iter().map(|d| d.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "t0 is not determined: changing it leaves the fit unchanged",
            "t1 is not determined: changing it leaves the fit unchanged"
        ]
    );
    assert!(!id.to_string().contains("every coefficient is determined"));
    assert!(matches!(
        identify(&ParametricRegressor::rows(&r), &IdentifySettings { fit: fit::FitSettings::default(), ..Default::default() }, &silent).map(|i| i.report),
        Err(Error::NoInformation { ref coefficients, .. }) if coefficients == "t0 and t1"
    ));
}

/// A zero column beside a nonzero one: A_s = [u, 0] has σ = (1, 0) and v_2 = e_2, so t1
/// is a null direction of its own (σ_2 = 0 is below τ = κ·ε, and never counts as
/// determined) while t0 = 2 is determined.
#[test]
fn a_zero_column_beside_a_nonzero_one_is_not_determined() {
    let r = from_rows(&[&[1.0, 0.0], &[2.0, 0.0], &[3.0, 0.0]], &[2.0, 4.0, 6.0]);
    let id = analyse(&r, 1e-10);
    assert_eq!(id.practical_rank, 1);
    assert_eq!(id.unidentifiable, ["t1"]);
    assert_eq!(
        id.null_directions[0].text,
        "t1 is not determined: changing it leaves the fit unchanged"
    );
    let report = identify(
        &ParametricRegressor::rows(&r),
        &IdentifySettings {
            fit: fit::FitSettings::default(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    assert!(!report.coefficients[1].determined, "{report}");
    assert!(report.coefficients[0].determined, "{report}");
    assert!((report.coefficient("t0").unwrap() - 2.0).abs() < 1e-12);
}

#[test]
fn the_report_says_the_values_are_not_estimates() {
    let r = from_rows(
        &[&[1.0, 0.2], &[2.0, 0.4], &[3.0, 0.6], &[4.0, 0.8]],
        &[1.4, 2.8, 4.2, 5.6],
    );
    let ls = fit::least_squares(&r, 1e-10).unwrap();
    let report = FitReport::new(&r, ls.clone(), diagnose(&r, &ls, 1e-10));
    assert!(report.coefficients.iter().all(|c| !c.determined));
    assert!(!report.is_estimate());
    let text = report.to_string();
    assert!(text.contains("not determined"), "{text}");
    assert!(text.contains("only t0 + 0.200 t1 is determined"), "{text}");
    let warning = report
        .warnings
        .iter()
        .find(|w| matches!(w, Warning::Unidentifiable { .. }))
        .unwrap();
    assert!(warning.to_string().contains("are not estimates"));
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["coefficients"][0]["determined"], false);
    assert_eq!(
        json["identifiability"]["determined"][0]["combination"]["text"],
        "t0 + 0.200 t1"
    );
    assert_eq!(json["warnings"][1]["kind"], "unidentifiable");

    let nn = fit::constrained(
        &r,
        &Constraints::nonnegative(),
        &fit::SolverSettings::default(),
    )
    .unwrap();
    let report = FitReport::new(&r, nn.clone(), diagnose(&r, &nn, 1e-10));
    assert!(
        report
            .to_string()
            .contains("the constraints, not the data, decide")
    );
}

fn chain(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2.0,
        1 => -1.0,
        _ => 0.0,
    })
}

/// A 3-DOF chain, C = c0 I + c1 K, driven at its first resonance only: the determined
/// combination is c0 + λ_1 c1 with λ_1 = 2 − 2cos(π/4) = 2 − √2 (the velocity Rayleigh
/// quotient, off by the small off-resonant modal content). Adding the second resonance
/// separates them.
#[test]
fn first_resonance_of_a_rayleigh_chain_determines_c0_plus_lambda1_c1() {
    let n = 3;
    let model = DampingModel::new()
        .with(Term::mass_proportional("c0", Mat::identity(n, n)))
        .with(Term::stiffness_proportional("c1", chain(n)));
    let lambda = |k: f64| 2.0 - 2.0 * (k * std::f64::consts::PI / 4.0).cos();
    let record = |mode: f64| {
        let system = System {
            mass: Mat::identity(n, n),
            stiffness: chain(n),
            damping: model.clone(),
            damping_coefficients: vec![0.02, 0.03],
            conservative: Vec::new(),
            forcing: vec![HarmonicForce {
                dof: 1,
                amplitude: 1.0,
                frequency: lambda(mode).sqrt(),
                phase: 0.0,
            }],
        };
        let settings = SimSettings {
            step: 0.1,
            substeps: 2,
            transient_steps: 12_000,
            recorded_steps: 300,
        };
        simulate(&system, &settings, &dampid::progress::silent).unwrap()
    };
    let settings = support::identify_settings(
        WindowSpec::cycles(1),
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    let first = identify(
        &ParametricRegressor::linear(&model, &[record(1.0)]),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!(!first.is_estimate());
    let terms = &first.identifiability.determined[0].combination.terms;
    let found = terms[1].weight / terms[0].weight;
    let lambda1 = 2.0 - 2f64.sqrt();
    assert!(
        (found - lambda1).abs() < 0.01 * lambda1,
        "{found} vs {lambda1}"
    );

    let both = identify(
        &ParametricRegressor::linear(&model, &[record(1.0), record(2.0)]),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!(both.is_estimate(), "{both}");
    for (name, truth) in [("c0", 0.02), ("c1", 0.03)] {
        let value = both.coefficient(name).unwrap();
        assert!((value - truth).abs() < 1e-3 * truth, "{name} = {value}");
    }
}

/// `dampid check` names the trade-off and the determined combination before any fit.
#[test]
fn check_reports_identifiability_in_words() {
    let output = dampid_ok(&["check", "models/rayleigh_chain6_resonance.toml"]);
    let text = String::from_utf8_lossy(&output.stdout);
    for needle in [
        "these data cannot separate c0 and c1",
        "c0 and c1 trade off against each other",
        "c0 + 0.198 c1",
        "variance inflation factors: c0 infinite, c1 infinite",
    ] {
        assert!(text.contains(needle), "missing '{needle}' in\n{text}");
    }
}
