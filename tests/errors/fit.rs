//! The fit: fewer equations than free coefficients is `TooFewEquations` (plain,
//! constrained, and without rows); constraints on a name the model lacks are
//! `UnknownCoefficient` (listing the names it has), bounds that admit no value
//! `InfeasibleBounds`, and NaN bounds and fit settings out of range `InvalidParameter`.

use dampid::fit::{self, SolverSettings};
use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;

/// One window of the fixture for the two coefficients of the per-DOF model.
const ONE_FOR_TWO: Error = Error::TooFewEquations {
    equations: 1,
    coefficients: 2,
};

// ---------------------------------------------------------------------------------
// Too few equations
// ---------------------------------------------------------------------------------

#[test]
fn fewer_windows_than_coefficients_is_too_few_equations() {
    // One window, two coefficients.
    let err = identify(
        &ParametricRegressor::linear(&per_dof_model(), &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert_eq!(err, ONE_FOR_TWO);
    let text = err.to_string();
    assert!(
        text.contains("1 windows") && text.contains("2 free"),
        "{text}"
    );

    // The same through the fit module directly.
    let regressor = Regressor::build(&per_dof_model(), &[record()], &measured().regressor).unwrap();
    assert_eq!(regressor.equations(), 1);
    assert_eq!(fit::least_squares(&regressor, 1e-10), Err(ONE_FOR_TWO));
}

#[test]
fn constrained_fit_with_too_few_equations_is_too_few_equations() {
    let mut settings = measured();
    settings.fit.constraints = Constraints::nonnegative();
    assert_eq!(
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &settings,
            &silent
        )
        .unwrap_err(),
        ONE_FOR_TWO
    );

    // Fixed coefficients are not free: three coefficients, one fixed, one equation
    // still leaves two free.
    let model = per_dof_model().with(Term::per_dof(
        Quadratic,
        2,
        Coefficients::Shared("d".into()),
    ));
    settings.fit.constraints = fixed("d", 0.0);
    assert_eq!(
        identify(
            &ParametricRegressor::linear(&model, &[record()]),
            &settings,
            &silent
        )
        .unwrap_err(),
        ONE_FOR_TWO
    );
}

#[test]
fn regressor_without_rows_is_too_few_equations() {
    let regressor =
        Regressor::from_parts(Mat::zeros(0, 1), Vec::new(), vec!["c".into()], Vec::new()).unwrap();
    assert_eq!(
        fit::solve(&regressor, &FitSettings::default()),
        Err(Error::TooFewEquations {
            equations: 0,
            coefficients: 1
        })
    );
}

// ---------------------------------------------------------------------------------
// Constraints
// ---------------------------------------------------------------------------------

#[test]
fn bound_on_unknown_coefficient_lists_the_known_names() {
    let settings = two_windows(bound("zeta", Some(0.0), None));
    let err = identify(
        &ParametricRegressor::linear(&per_dof_model(), &[record()]),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert_eq!(
        err,
        Error::UnknownCoefficient {
            name: "zeta".into(),
            known: "c[1], c[2]".into()
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("'zeta'") && text.contains("c[1], c[2]"),
        "{text}"
    );
}

#[test]
fn fixed_unknown_coefficient_is_unknown() {
    let settings = two_windows(fixed("c", 1.0));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&per_dof_model(), &[record()]), &settings, &silent),
        Err(Error::UnknownCoefficient { ref name, ref known })
            if name == "c" && known == "c[1], c[2]"
    ));
}

#[test]
fn lower_bound_above_upper_bound_is_infeasible() {
    let settings = two_windows(bound("c[2]", Some(2.0), Some(1.0)));
    let err = identify(
        &ParametricRegressor::linear(&per_dof_model(), &[record()]),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert_eq!(
        err,
        Error::InfeasibleBounds {
            name: "c[2]".into(),
            lower: 2.0,
            upper: 1.0
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("c[2]") && text.contains('2') && text.contains('1'),
        "{text}"
    );
}

#[test]
fn negative_upper_bound_with_nonnegativity_is_infeasible() {
    let settings = two_windows(Constraints {
        nonnegative: true,
        ..bound("c[1]", None, Some(-0.5))
    });
    assert_eq!(
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &settings,
            &silent
        )
        .unwrap_err(),
        Error::InfeasibleBounds {
            name: "c[1]".into(),
            lower: 0.0,
            upper: -0.5
        }
    );
}

#[test]
fn fixed_value_outside_its_bounds_is_infeasible() {
    let settings = two_windows(Constraints {
        fixed: fixed("c[1]", 2.0).fixed,
        ..bound("c[1]", Some(0.0), Some(1.0))
    });
    let error = identify(
        &ParametricRegressor::linear(&per_dof_model(), &[record()]),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidParameter { name, value, .. }
            if name == "fixed value of 'c[1]'" && *value == 2.0),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("outside its bounds [0, 1]"),
        "{error}"
    );

    // A negative fixed value under nonnegativity says that nonnegative is the conflict
    // (issue 29, item 10), not "infeasible bounds: lower 0 > upper -0.1".
    let settings = two_windows(Constraints {
        nonnegative: true,
        ..fixed("c[2]", -0.1)
    });
    let error = identify(
        &ParametricRegressor::linear(&per_dof_model(), &[record()]),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidParameter { name, value, .. }
            if name == "fixed value of 'c[2]'" && *value == -0.1),
        "{error:?}"
    );
    assert!(error.to_string().contains("nonnegative = true"), "{error}");
}

#[test]
fn nan_bound_or_fixed_value_is_invalid_parameter() {
    assert_invalid(
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &two_windows(bound("c[1]", None, Some(f64::NAN))),
            &silent,
        ),
        "upper bound of 'c[1]'",
        f64::NAN,
    );
    assert_invalid(
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &two_windows(fixed("c[2]", f64::INFINITY)),
            &silent,
        ),
        "fixed value of 'c[2]'",
        f64::INFINITY,
    );
}

// ---------------------------------------------------------------------------------
// Fit settings
// ---------------------------------------------------------------------------------

#[test]
fn invalid_rank_tolerance_is_invalid_parameter() {
    for tolerance in [0.0, 1.0, -1e-3, f64::NAN] {
        let mut settings = measured();
        settings.fit.rank_tolerance = tolerance;
        let err = assert_invalid(
            identify(
                &ParametricRegressor::linear(&shared_model(), &[record()]),
                &settings,
                &silent,
            ),
            "rank_tolerance",
            tolerance,
        );
        assert!(err.to_string().contains("rank_tolerance"), "{err}");
    }
}

#[test]
fn invalid_solver_tolerance_is_invalid_parameter() {
    for tolerance in [0.0, -1.0, 0.5, f64::NAN] {
        let mut settings = measured();
        settings.fit.solver.tolerance = tolerance;
        assert_invalid(
            identify(
                &ParametricRegressor::linear(&shared_model(), &[record()]),
                &settings,
                &silent,
            ),
            "solver tolerance",
            tolerance,
        );
    }
    // Also when the constrained solver is called directly.
    let regressor = Regressor::build(&shared_model(), &[record()], &measured().regressor).unwrap();
    let solver = SolverSettings {
        tolerance: 0.0,
        ..SolverSettings::default()
    };
    assert_invalid(
        fit::constrained(&regressor, &Constraints::nonnegative(), &solver),
        "solver tolerance",
        0.0,
    );
}

#[test]
fn zero_max_iterations_is_invalid_parameter() {
    let mut settings = measured();
    settings.fit.solver.max_iterations = 0;
    assert_invalid(
        identify(
            &ParametricRegressor::linear(&shared_model(), &[record()]),
            &settings,
            &silent,
        ),
        "max_iterations",
        0.0,
    );
}
