//! Variable projection's own input: a parametric model's parameter specs (finite, ordered
//! bounds with the initial value inside, unique names, at least one), its settings, and a
//! `[simulation] parameters` name that is not an estimated parameter.

use dampid::prelude::*;
use dampid::varpro::{NonlinearParameter, ParametricModel, VarProSettings};

use crate::fixtures::parse_model;

fn model(_: &[f64]) -> dampid::Result<DampingModel> {
    Ok(DampingModel::new())
}

#[test]
fn parameter_specs_are_checked() {
    let bad = [
        (
            NonlinearParameter::new("p", 1.0, 2.0, 0.5),
            "lower bound",
            2.0,
        ),
        (
            NonlinearParameter::new("p", 5.0, 0.5, 4.0),
            "initial value",
            5.0,
        ),
        (
            NonlinearParameter::new("p", 1.0, f64::NEG_INFINITY, 4.0),
            "lower bound",
            f64::NEG_INFINITY,
        ),
    ];
    for (spec, what, given) in bad {
        match ParametricModel::new(vec![spec], model) {
            Err(Error::InvalidParameter { name, value, .. }) => {
                assert!(name.contains(what) && name.contains("'p'"), "{name}");
                assert_eq!(value, given);
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(matches!(
        ParametricModel::new(Vec::new(), model),
        Err(Error::Empty { .. })
    ));
    let twice = vec![
        NonlinearParameter::new("p", 1.0, 0.5, 4.0),
        NonlinearParameter::new("p", 1.0, 0.5, 4.0),
    ];
    assert!(matches!(
        ParametricModel::new(twice, model),
        Err(Error::InvalidChoice { .. })
    ));
    let one =
        ParametricModel::new(vec![NonlinearParameter::new("p", 1.0, 0.5, 4.0)], model).unwrap();
    assert!(matches!(
        one.at(&[1.0, 2.0]),
        Err(Error::DimensionMismatch {
            expected: 1,
            found: 2,
            ..
        })
    ));
}

#[test]
fn outer_settings_are_checked() {
    for settings in [
        VarProSettings {
            tolerance: 0.0,
            ..VarProSettings::default()
        },
        VarProSettings {
            max_iterations: 0,
            ..VarProSettings::default()
        },
        VarProSettings {
            level: 1.0,
            ..VarProSettings::default()
        },
    ] {
        assert!(matches!(
            settings.validate(),
            Err(Error::InvalidParameter { .. })
        ));
    }
}

/// `[simulation] parameters` may name only estimated parameters.
#[test]
fn simulated_parameters_must_be_estimated_ones() {
    let text = "dofs = 2

[[terms]]
kind = \"law\"
law = \"power\"
exponent = { estimate = true, initial = 1.0, lower = 0.5, upper = 4.0 }
elements = \"each_dof\"
coefficient = \"d\"

[simulation]
mass = \"identity\"
stiffness = \"chain\"
coefficients = { d = 0.1 }
parameters = { \"d.exponnent\" = 1.7 }
step = 0.1
transient_steps = 10
recorded_steps = 100
experiments = [{ force_dof = 1, amplitude = 1.0, frequency = 1.0 }]
";
    let error = parse_model(text, "sim.toml").unwrap_err();
    assert!(
        matches!(&error, Error::ModelFile { line: 10, .. }),
        "{error:?}"
    );
    match error.innermost() {
        Error::UnknownName { name, known, .. } => {
            assert_eq!(name, "d.exponnent");
            assert!(known.contains("d.exponent"), "{known}");
        }
        other => panic!("{other:?}"),
    }
}
