//! The damping model, checked against the records' DOFs by `DampingModel::validate`
//! (which `identify` calls): elements on missing DOFs are `DofOutOfRange`, an element
//! from a DOF to itself and a bad power-law exponent `InvalidParameter`, a model or
//! term without content `Empty`, matrix terms of the wrong size `DimensionMismatch` and
//! with NaN `NonFinite`, and two coefficients of one name `DuplicateCoefficient`.

use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;

#[test]
fn element_on_missing_dof_is_dof_out_of_range() {
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        vec![Element::to_ground(0), Element::between(0, 3)],
        Coefficients::PerElement("dashpot".into()),
    ));
    let err = identify(
        &ParametricRegressor::linear(&model, &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(
            &err,
            Error::DofOutOfRange { what, dof: 4, dofs: 2 }
                if what.contains("linear") && what.contains("[1-4]")
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(text.contains("DOF 4") && text.contains("1-4"), "{text}");

    // The first DOF of an element is checked as well.
    let model = DampingModel::new().with(Term::on_elements(
        Quadratic,
        vec![Element::to_ground(7)],
        Coefficients::Shared("d".into()),
    ));
    assert!(matches!(
        model.validate(2),
        Err(Error::DofOutOfRange { ref what, dof: 8, dofs: 2 }) if what.contains("quadratic")
    ));
}

#[test]
fn element_joining_a_dof_to_itself_is_invalid_parameter() {
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        vec![Element::between(1, 1)],
        Coefficients::Shared("c".into()),
    ));
    assert_invalid(model.validate(2), "element", 1.0);
}

#[test]
fn term_without_elements_is_empty() {
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        Vec::new(),
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&model, &[record()]), &measured(), &silent),
        Err(Error::Empty { ref what }) if what.contains("element list")
    ));
}

#[test]
fn matrix_term_of_wrong_size_is_dimension_mismatch() {
    let model = DampingModel::new().with(Term::viscous("c", Mat::identity(3, 3)));
    let err = identify(
        &ParametricRegressor::linear(&model, &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(
            &err,
            Error::DimensionMismatch { what, expected: 2, found: 3 }
                if what.contains("rows of matrix of term 'c'")
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("term 'c'"), "{err}");

    let model = DampingModel::new().with(Term::stiffness_proportional("k", Mat::zeros(2, 1)));
    assert!(matches!(
        model.validate(2),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("columns of matrix of term 'k'")
    ));
}

#[test]
fn nan_in_damping_matrix_is_non_finite() {
    let mut c0 = Mat::<f64>::identity(2, 2);
    c0[(0, 1)] = f64::NAN;
    let model = DampingModel::new().with(Term::mass_proportional("m", c0));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&model, &[record()]), &measured(), &silent),
        Err(Error::NonFinite { ref what, row: 0, column: 1, value })
            if what == "matrix of term 'm'" && value.is_nan()
    ));
}

#[test]
fn empty_model_is_empty() {
    let err = identify(
        &ParametricRegressor::linear(&DampingModel::new(), &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::Empty { what } if what == "damping model"),
        "{err:?}"
    );
    assert!(err.to_string().contains("damping model"), "{err}");
}

#[test]
fn two_terms_with_the_same_coefficient_name_are_duplicate() {
    let model = DampingModel::new()
        .with(Term::viscous("c", Mat::identity(2, 2)))
        .with(Term::per_dof(Linear, 2, Coefficients::Shared("c".into())));
    let err = identify(
        &ParametricRegressor::linear(&model, &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert_eq!(err, Error::DuplicateCoefficient { name: "c".into() });
    assert!(err.to_string().contains("'c'"), "{err}");
}

#[test]
fn per_element_labels_that_collide_are_duplicate() {
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        vec![Element::to_ground(0), Element::to_ground(1).labelled("1")],
        Coefficients::PerElement("d".into()),
    ));
    assert_eq!(
        model.validate(2),
        Err(Error::DuplicateCoefficient {
            name: "d[1]".into()
        })
    );
}

#[test]
fn negative_or_non_finite_power_law_exponent_is_invalid_parameter() {
    let err = assert_invalid(PowerLaw::new(-1.0), "exponent", -1.0);
    let text = err.to_string();
    assert!(text.contains("exponent") && text.contains("-1"), "{text}");
    assert_invalid(PowerLaw::new(f64::NAN), "exponent", f64::NAN);
    assert_invalid(PowerLaw::new(f64::INFINITY), "exponent", f64::INFINITY);
    assert!(PowerLaw::new(0.0).is_ok());
}

/// A coefficient without a name is `InvalidChoice`: reports, bounds and JSON refer to
/// coefficients by name.
#[test]
fn empty_coefficient_name_is_invalid_choice() {
    let model =
        DampingModel::new().with(Term::per_dof(Linear, 2, Coefficients::Shared(" ".into())));
    let err = model.validate(2).unwrap_err();
    assert_eq!(err.kind(), "invalid_choice");
    assert!(err.to_string().contains("coefficient name"), "{err}");
}

/// A negative element weight would make a dashpot supply energy (c came out −0.111
/// before): `InvalidParameter` naming the element, from 1, and the value.
#[test]
fn negative_element_weight_is_invalid_parameter() {
    let model = DampingModel::new().with(Term::weighted(
        Linear,
        vec![Element::to_ground(0), Element::to_ground(1)],
        vec![1.0, -2.0],
        Coefficients::Shared("c".into()),
    ));
    let err = model.validate(2).unwrap_err();
    assert_eq!(err.kind(), "invalid_parameter");
    let message = err.to_string();
    assert!(
        message.contains("element 2") && message.contains("-2"),
        "{message}"
    );
}
