//! Structural damping (src/terms/structural.rs): every refusal is typed and names what
//! it refuses. Modes without harmonics to rotate (non-periodic spans) and the RK4
//! simulator (the force is non-causal) refuse the term (the noise-robust rows take it:
//! tests/structural_noise.rs); a stiffness
//! that is not finite and > 0, or a stiffness list of the wrong length, is refused, in
//! a model file at the term's line.

use dampid::prelude::*;
use dampid::regressor::SpanWindows;
use dampid::simulate::simulate;

use crate::fixtures::*;

/// A loss factor on DOF 1 to ground beside linear damping.
fn structural_model(stiffness: Vec<f64>) -> DampingModel {
    shared_model().with(Term::structural(
        vec![Element::to_ground(0)],
        stiffness,
        Coefficients::Shared("eta".into()),
    ))
}

fn assert_refused(error: Error, mode: &str) {
    match error {
        Error::InvalidChoice { given, reason, .. } => {
            assert!(given.contains("structural"), "{given}");
            assert!(
                given.contains(mode) || reason.contains(mode),
                "{given}: {reason}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn periodic_windows_accept_structural_damping() {
    Regressor::build(
        &structural_model(vec![2.0]),
        &[record()],
        &measured().regressor,
    )
    .unwrap();
}

#[test]
fn non_periodic_spans_refuse_structural_damping() {
    let spans = IdentifySettings {
        regressor: RegressorSettings::non_periodic(SpanWindows::new(0.5)),
        ..IdentifySettings::default()
    };
    let error = identify(
        &ParametricRegressor::linear(&structural_model(vec![2.0]), &[record()]),
        &spans,
        &silent,
    )
    .unwrap_err();
    assert_refused(error, "non-periodic");
}

#[test]
fn the_simulator_refuses_structural_damping() {
    let mut system = system();
    system.damping = structural_model(vec![2.0]);
    system.damping_coefficients = vec![0.1, 0.02];
    let error = simulate(&system, &sim_settings(), &dampid::progress::silent).unwrap_err();
    assert_refused(error, "non-causal");
}

#[test]
fn bad_stiffness_is_refused() {
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let error = Regressor::build(
            &structural_model(vec![k]),
            &[record()],
            &measured().regressor,
        )
        .unwrap_err();
        match error {
            Error::InvalidParameter { name, .. } => {
                assert!(name.contains("stiffness") && name.contains("1"), "{name}")
            }
            other => panic!("{k}: {other:?}"),
        }
    }
    let error = Regressor::build(
        &structural_model(vec![1.0, 2.0]),
        &[record()],
        &measured().regressor,
    )
    .unwrap_err();
    assert!(
        matches!(error, Error::DimensionMismatch { .. }),
        "{error:?}"
    );
}

/// A model file with structural damping on two elements: the term at line 3, and a
/// `[simulation]` section (the records a model file needs; the simulator refuses the
/// term when it runs, `parse_model` does not run it).
fn model_file(stiffness: &str) -> String {
    format!(
        "dofs = 2\n\n[[terms]]\nkind = \"structural\"\nelements = [[1, 0], [1, 2]]\ncoefficient = \"eta\"\nstiffness = {stiffness}\n\n{SIMULATION}"
    )
}

const SIMULATION: &str = "[simulation]\nmass = \"identity\"\nstiffness = \"chain\"\ncoefficients = { eta = 0.01 }\nstep = 0.1\ntransient_steps = 0\nrecorded_steps = 10\nexperiments = [{ force_dof = 1, amplitude = 1.0, frequency = 1.0 }]\n";

#[test]
fn model_file_stiffness_is_checked_at_its_line() {
    let innermost = |text: String| match parse_model(&text, "m.toml") {
        Err(e @ Error::ModelFile { line, .. }) => {
            assert_eq!(line, 3, "{e}");
            e.innermost().clone()
        }
        other => panic!("{other:?}"),
    };
    match innermost(model_file("[1.0, -2.0]")) {
        Error::InvalidParameter { name, value, .. } => {
            assert!(name.contains("1-2"), "{name}");
            assert_eq!(value, -2.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        innermost(model_file("[1.0]")),
        Error::DimensionMismatch { .. }
    ));
    match innermost(model_file("0.0")) {
        Error::InvalidParameter { name, .. } => assert!(name.contains("stiffness"), "{name}"),
        other => panic!("{other:?}"),
    }
    let model = dampid::model_file::parse_model(&model_file("[1.0, 2.0]"), "m.toml").unwrap();
    assert_eq!(model.coefficient_names(), ["eta"]);
    dampid::model_file::parse_model(&model_file("3.0"), "m.toml").unwrap();
    // a job runs the simulation, which refuses the term at the [simulation] line
    match parse_model(&model_file("3.0"), "m.toml") {
        Err(e @ Error::ModelFile { line: 9, .. }) => {
            assert_refused(e.innermost().clone(), "non-causal")
        }
        other => panic!("{other:?}"),
    }
}
