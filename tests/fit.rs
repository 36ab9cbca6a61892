//! Least-squares and constrained fits on regressors small enough to solve by hand, and
//! the report's diagnostics.

use dampid::analysis::diagnostics::diagnose;
use dampid::fit::{self, BoundSide, FitMethod, SolverSettings};
use dampid::prelude::*;
use dampid::report::Warning;

mod support;
use support::regressors::from_rows;

fn constrained(r: &Regressor, constraints: Constraints, solver: SolverSettings) -> Fit {
    fit::constrained(r, &constraints, &solver).unwrap()
}

/// A = [[1,0],[0,1],[1,1]], b = [1, −0.2, 0.8]. Normal equations [[2,1],[1,2]]θ = [1.8, 0.6]
/// give θ = (1.0, −0.2). With θ ≥ 0, θ₂ = 0 and θ₁ minimizes (θ₁−1)² + (θ₁−0.8)²: 0.9.
/// KKT: ∂/∂θ₂ at (0.9, 0) = 2(0.2) + 2(0.1) = 0.6 ≥ 0.
#[test]
fn nonnegative_fit_where_least_squares_goes_negative() {
    let r = from_rows(&[&[1.0, 0.0], &[0.0, 1.0], &[1.0, 1.0]], &[1.0, -0.2, 0.8]);
    let ls = fit::least_squares(&r, 1e-12).unwrap();
    assert!((ls.coefficients[0] - 1.0).abs() < 1e-12 && (ls.coefficients[1] + 0.2).abs() < 1e-12);
    let nn = constrained(&r, Constraints::nonnegative(), SolverSettings::default());
    assert_eq!(nn.status, FitStatus::Solved);
    assert_eq!(nn.method, FitMethod::Constrained);
    assert_eq!(
        nn.coefficients[1], 0.0,
        "a coefficient held at zero must be exactly zero"
    );
    assert!(
        (nn.coefficients[0] - 0.9).abs() < 1e-12,
        "{}",
        nn.coefficients[0]
    );
    assert_eq!(nn.active.len(), 1);
    assert_eq!(
        (nn.active[0].name.as_str(), nn.active[0].side),
        ("t1", BoundSide::Lower)
    );
    assert!(nn.solver.unwrap().polished);
}

/// Noise-free data with true θ = (2, 0): the bound θ₂ ≥ 0 is active with a zero
/// multiplier, where an interior-point method converges only like √μ. Without the polish
/// step θ₂ is left small but not zero (about 1e-5 here, even at tolerance 1e-10); with it
/// θ₂ is exactly 0 and θ₁ exact.
#[test]
fn polish_makes_a_zero_coefficient_exactly_zero() {
    let a: [&[f64]; 4] = [&[1.0, 0.3], &[2.0, 0.1], &[0.5, 0.9], &[1.5, 0.4]];
    let b: Vec<f64> = a.iter().map(|row| 2.0 * row[0]).collect();
    let r = from_rows(&a, &b);
    let rough = constrained(
        &r,
        Constraints::nonnegative(),
        SolverSettings {
            polish: false,
            ..SolverSettings::default()
        },
    );
    assert!(
        rough.coefficients[1] > 0.0 && rough.coefficients[1] < 1e-3,
        "{rough:?}"
    );
    let polished = constrained(&r, Constraints::nonnegative(), SolverSettings::default());
    assert_eq!(polished.coefficients[1], 0.0);
    assert!((polished.coefficients[0] - 2.0).abs() < 1e-13);
}

/// Upper bound active: A = I (2×2) plus a row, LS θ = (2, 1); with θ₁ ≤ 1.5 the answer
/// is θ₁ = 1.5 and θ₂ from the remaining rows. A = [[1,0],[0,1],[1,1]], b = [2,1,3]:
/// θ₁ = 1.5 ⇒ minimize (θ₂−1)² + (1.5+θ₂−3)² ⇒ θ₂ = 1.25.
#[test]
fn upper_bound_and_fixed_value() {
    let r = from_rows(&[&[1.0, 0.0], &[0.0, 1.0], &[1.0, 1.0]], &[2.0, 1.0, 3.0]);
    let bounded = Constraints {
        bounds: vec![Bound {
            name: "t0".into(),
            lower: None,
            upper: Some(1.5),
        }],
        ..Constraints::default()
    };
    let fit = constrained(&r, bounded, SolverSettings::default());
    assert_eq!(fit.coefficients[0], 1.5);
    assert!((fit.coefficients[1] - 1.25).abs() < 1e-12);
    assert_eq!(fit.active[0].side, BoundSide::Upper);

    // Fixing θ₂ = 0.5: minimize (θ₁−2)² + (θ₁+0.5−3)² ⇒ θ₁ = 2.25.
    let fixed = Constraints {
        fixed: vec![Fixed {
            name: "t1".into(),
            value: 0.5,
        }],
        ..Constraints::default()
    };
    let fit = constrained(&r, fixed, SolverSettings::default());
    assert_eq!(fit.coefficients[1], 0.5);
    assert!((fit.coefficients[0] - 2.25).abs() < 1e-12);
    assert_eq!(fit.active[0].side, BoundSide::Fixed);
}

/// Bounds that the solution does not touch leave the least-squares answer unchanged.
#[test]
fn inactive_bounds_equal_least_squares() {
    let r = from_rows(
        &[&[1.0, 0.2], &[0.3, 1.0], &[1.0, 1.0], &[0.7, 0.1]],
        &[1.1, 0.9, 2.2, 0.8],
    );
    let ls = fit::least_squares(&r, 1e-12).unwrap();
    let wide = Constraints {
        nonnegative: true,
        bounds: vec![Bound {
            name: "t0".into(),
            lower: Some(-10.0),
            upper: Some(10.0),
        }],
        ..Constraints::default()
    };
    let fit = constrained(&r, wide, SolverSettings::default());
    assert!(fit.active.is_empty());
    for (a, b) in fit.coefficients.iter().zip(&ls.coefficients) {
        assert!((a - b).abs() < 1e-9 * b.abs(), "{a} vs {b}");
    }
}

/// A solver stopped after one iteration says so, and the report warns in words.
#[test]
fn unconverged_solver_is_reported_not_hidden() {
    let r = from_rows(&[&[1.0, 0.0], &[0.0, 1.0], &[1.0, 1.0]], &[1.0, -0.2, 0.8]);
    let fit = constrained(
        &r,
        Constraints::nonnegative(),
        SolverSettings {
            max_iterations: 1,
            ..SolverSettings::default()
        },
    );
    assert_eq!(fit.status, FitStatus::MaxIterations);
    let report = FitReport::new(&r, fit.clone(), diagnose(&r, &fit, 1e-10));
    assert!(report.warnings.contains(&Warning::NotConverged {
        status: FitStatus::MaxIterations
    }));
    assert!(report.to_string().contains("not a solution"));
}

/// One column, A = [1,1,1,1]ᵀ, b = [1,2,3,4]: θ = 2.5, residuals (−1.5, −0.5, 0.5, 1.5),
/// s² = 5/3, Var θ = s²/4 = 5/12. Residual bias: mean 0.
#[test]
fn standard_error_of_a_mean() {
    let r = from_rows(&[&[1.0], &[1.0], &[1.0], &[1.0]], &[1.0, 2.0, 3.0, 4.0]);
    let fit = fit::least_squares(&r, 1e-12).unwrap();
    let d = diagnose(&r, &fit, 1e-12);
    assert!((fit.coefficients[0] - 2.5).abs() < 1e-14);
    assert!((d.std_errors[0].unwrap() - (5.0f64 / 12.0).sqrt()).abs() < 1e-14);
    assert_eq!((d.residual_bias.positive, d.residual_bias.negative), (2, 2));
    assert!(d.residual_bias.relative_mean.abs() < 1e-15);
    assert_eq!(d.rank, 1);
    assert!((d.condition_number - 1.0).abs() < 1e-14);
}

/// Two proportional columns cannot be told apart: rank 1, infinite condition number, and
/// the report says the values are not estimates.
#[test]
fn rank_deficient_regressor_is_flagged() {
    let r = from_rows(&[&[1.0, 2.0], &[2.0, 4.0], &[3.0, 6.0]], &[1.0, 2.0, 3.0]);
    let fit = fit::least_squares(&r, 1e-10).unwrap();
    let report = FitReport::new(&r, fit.clone(), diagnose(&r, &fit, 1e-10));
    assert_eq!(report.rank, 1);
    assert_eq!(report.condition_number, None);
    assert!(report.warnings.contains(&Warning::RankDeficient {
        rank: 1,
        coefficients: 2
    }));
    assert!(report.coefficients.iter().all(|c| c.std_error.is_none()));
    assert!(report.to_string().contains("cannot separate"));
}

/// The JSON report carries the keys the issue names.
#[test]
fn report_json_has_documented_keys() {
    let r = from_rows(&[&[1.0, 0.2], &[0.3, 1.0], &[1.0, 1.0]], &[1.1, 0.9, 2.2]);
    let fit = fit::least_squares(&r, 1e-12).unwrap();
    let report = FitReport::new(&r, fit.clone(), diagnose(&r, &fit, 1e-12));
    let json = serde_json::to_value(&report).unwrap();
    for key in [
        "status",
        "coefficients",
        "condition_number",
        "singular_values",
        "rank",
        "residuals",
        "relative_residual",
        "residual_bias",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    let first = &json["coefficients"][0];
    for key in ["name", "value", "std_error"] {
        assert!(first.get(key).is_some(), "coefficient missing {key}");
    }
    assert_eq!(json["status"], "solved");
}
