//! The regressor: no records is `Empty`; a column that is not finite, from a law
//! returning NaN or from integrals that overflow, is `NonFinite` named after its
//! coefficient (never a report with NaN coefficients); and `Regressor::from_parts`
//! checks sizes (`DimensionMismatch`) and values (`NonFinite`). A record whose force
//! does no work is `NoInputWork`; a regressor whose every column is zero is
//! `NoInformation`, also when built by hand.

use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;
use crate::support::regressors::row_labels;

#[test]
fn empty_record_list_is_empty() {
    let err = identify(
        &ParametricRegressor::linear(&shared_model(), &[]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::Empty { what } if what == "record list"),
        "{err:?}"
    );
    assert!(
        matches!(
            Regressor::build(&shared_model(), &[], &RegressorSettings::default()),
            Err(Error::Empty { ref what }) if what == "record list"
        ),
        "Regressor::build"
    );
}

#[test]
fn custom_law_returning_nan_names_the_regressor_column() {
    let model = shared_model().with(Term::per_dof(
        Custom::new("broken", |_x, _v| f64::NAN),
        2,
        Coefficients::Shared("bad".into()),
    ));
    let err = Regressor::build(&model, &[record()], &measured().regressor).unwrap_err();
    assert_nan_at(&err, "regressor column 'bad'", 0, 1);
    assert!(err.to_string().contains("'bad'"), "{err}");
    // The same through identify: no report with NaN coefficients.
    assert!(matches!(
        identify(&ParametricRegressor::linear(&model, &[record()]), &measured(), &silent),
        Err(Error::NonFinite { ref what, .. }) if what == "regressor column 'bad'"
    ));
}

#[test]
fn overflowing_regressor_column_is_non_finite_not_a_number() {
    // A law whose force is finite but huge on ordinary data: ∫ g v overflows to inf.
    let model = DampingModel::new().with(Term::per_dof(
        Custom::new("huge", |_x, v| 1e307 * v),
        2,
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&model, &[record()]), &measured(), &silent),
        Err(Error::NonFinite { ref what, row: 0, column: 0, value })
            if what == "regressor column 'c'" && value == f64::INFINITY
    ));
    // Huge data are refused before any product is formed, naming the units.
    let record = record_with(|p| {
        p.displacements = Mat::from_fn(N, 2, |i, j| 1e200 * displacements(N)[(i, j)]);
        p.velocities = Some(Mat::from_fn(N, 2, |i, j| 1e200 * velocities(N)[(i, j)]));
    })
    .unwrap();
    assert!(matches!(
        identify(&ParametricRegressor::linear(&shared_model(), &[record]), &measured(), &silent),
        Err(Error::DataScale { ref signal, .. }) if signal == "displacement"
    ));
}

#[test]
fn regressor_parts_are_checked() {
    let names = || vec!["a".to_string(), "b".to_string()];
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(3, 2), vec![0.0; 2], names(), row_labels(2)),
        Err(Error::DimensionMismatch { ref what, expected: 3, found: 2 })
            if what.contains("right-hand side")
    ));
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(2, 3), vec![0.0; 2], names(), row_labels(2)),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("coefficient names")
    ));
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(2, 2), vec![0.0; 2], names(), row_labels(1)),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("row labels")
    ));
    assert!(matches!(
        Regressor::from_parts(
            Mat::identity(2, 2),
            vec![1.0, f64::NAN],
            names(),
            row_labels(2)
        ),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "input work b" && value.is_nan()
    ));
    let mut a = Mat::<f64>::identity(2, 2);
    a[(1, 1)] = f64::NEG_INFINITY;
    assert!(matches!(
        Regressor::from_parts(a, vec![1.0, 1.0], names(), row_labels(2)),
        Err(Error::NonFinite { ref what, row: 1, column: 1, value })
            if what == "regressor column 'b'" && value == f64::NEG_INFINITY
    ));
}

/// The fixture with its generalized forces zeroed: b = ∫ vᵀr dt = 0 in every window, so
/// the fit would give c = 0 "determined". `NoInputWork` names the record and both
/// channels, numbered from 1 with their DOFs, and what to check.
#[test]
fn zero_force_is_no_input_work() {
    let dead = record_with(|p| p.forcing = Forcing::generalized(Mat::zeros(N, 2))).unwrap();
    let err = identify(
        &ParametricRegressor::linear(&shared_model(), &[dead]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::NoInputWork { record, window: None, channels, .. }
            if record == "fixture" && channels == "force channels 1 (on DOF 1) and 2 (on DOF 2)"),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "record 'fixture', force channels 1 (on DOF 1) and 2 (on DOF 2): no input work: every \
         sample reads zero (an unplugged or dead load cell); check the force sensor and its \
         column in the model file"
    );
}

/// A regressor of zeros, built by hand (A = 0, b ≠ 0) and fitted at the middle level:
/// σ_1 of the column-scaled regressor is 0, so the identifiability threshold was 0 and
/// both coefficients were "determined". `NoInformation` names them.
#[test]
fn zero_regressor_is_no_information() {
    let names = vec!["a".to_string(), "b".to_string()];
    let regressor =
        Regressor::from_parts(Mat::zeros(3, 2), vec![1.0, 2.0, 3.0], names, row_labels(3)).unwrap();
    let err = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings {
            fit: FitSettings::default(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap_err();
    assert!(
        matches!(&err, Error::NoInformation { coefficients, .. } if coefficients == "a and b"),
        "{err:?}"
    );
    assert!(
        err.to_string()
            .starts_with("these data carry no information on a and b: every column"),
        "{err}"
    );
}
