//! History terms (Bouc–Wen, Dahl, Iwan): every refusal is typed and names what it
//! refuses. A window whose state does not repeat within the cap is `NoPeriodicOrbit`
//! naming the record and window; modes without an orbit (non-periodic spans, the
//! noise-robust rows) and the RK4 simulator refuse the term; shape parameters out of
//! range, and model files with unknown or missing ones, are refused at construction.

use std::sync::Arc;

use dampid::prelude::*;
use dampid::regressor::SpanWindows;
use dampid::simulate::simulate;
use dampid::terms::history::{BoucWen, Dahl, HistoryTerm, Iwan};

use crate::fixtures::*;

/// Bouc–Wen on DOF 1 to ground beside linear damping, at most `passes` passes.
pub fn bouc_wen_model(passes: usize) -> DampingModel {
    shared_model().with(Term::History(
        HistoryTerm::new(
            Arc::new(BoucWen::new(1.0, 0.5, 1.0).unwrap()),
            vec![Element::to_ground(0)],
            Coefficients::Shared("alpha".into()),
        )
        .with_max_passes(passes),
    ))
}

#[test]
fn a_state_that_does_not_repeat_names_the_record_and_window() {
    // One pass from z = 0 at x = 1 cannot end where it started.
    match identify(
        &ParametricRegressor::linear(&bouc_wen_model(1), &[record()]),
        &measured(),
        &silent,
    ) {
        Err(Error::NoPeriodicOrbit {
            record,
            window,
            term,
            passes,
            change,
            tolerance,
        }) => {
            assert_eq!((record.as_str(), window, passes), ("fixture", 1, 1));
            assert_eq!(term, "bouc_wen [1]");
            assert!(change > tolerance, "{change} vs {tolerance}");
        }
        other => panic!("{other:?}"),
    }
    // the default cap reaches it
    Regressor::build(&bouc_wen_model(200), &[record()], &measured().regressor).unwrap();
}

#[test]
fn zero_passes_are_refused() {
    let error = identify(
        &ParametricRegressor::linear(&bouc_wen_model(0), &[record()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidParameter { name, .. } if name.contains("max_passes")),
        "{error:?}"
    );
}

fn assert_refused(error: Error, mode: &str) {
    match error {
        Error::InvalidChoice { given, reason, .. } => {
            assert!(given.contains("bouc_wen"), "{given}");
            assert!(
                given.contains(mode) || reason.contains(mode),
                "{given}: {reason}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn non_periodic_spans_refuse_history_terms() {
    let spans = IdentifySettings {
        regressor: RegressorSettings::non_periodic(SpanWindows::new(0.5)),
        ..IdentifySettings::default()
    };
    let error = identify(
        &ParametricRegressor::linear(&bouc_wen_model(200), &[record()]),
        &spans,
        &silent,
    )
    .unwrap_err();
    assert_refused(error, "non-periodic");
}

#[test]
fn noise_robust_rows_refuse_history_terms() {
    // the default pipeline: harmonic projection with noise = auto
    let error = identify(
        &ParametricRegressor::linear(&bouc_wen_model(200), &[record()]),
        &IdentifySettings::default(),
        &silent,
    )
    .unwrap_err();
    assert_refused(error, "noise-robust");
}

#[test]
fn the_simulator_refuses_history_terms() {
    let mut system = system();
    system.damping = bouc_wen_model(200);
    system.damping_coefficients = vec![0.1, 1.0];
    let error = simulate(&system, &sim_settings(), &dampid::progress::silent).unwrap_err();
    assert_refused(error, "not simulated");
}

#[test]
fn shape_parameters_out_of_range_are_refused() {
    let named = |error: Error, expected: &str| match error {
        Error::InvalidParameter { name, .. } => assert!(name.contains(expected), "{name}"),
        other => panic!("{other:?}"),
    };
    named(BoucWen::new(0.5, -0.5, 1.0).unwrap_err(), "beta");
    named(BoucWen::new(1.0, 0.0, 0.5).unwrap_err(), "'n'");
    named(Dahl::new(0.0, 1.0).unwrap_err(), "x_c");
    named(Dahl::new(0.1, -1.0).unwrap_err(), "exponent");
    named(Iwan::new(-1.0, 0.0, 0.0).unwrap_err(), "phi_max");
    named(Iwan::new(0.1, -1.0, 0.0).unwrap_err(), "chi");
    named(Iwan::new(0.1, 0.0, -0.1).unwrap_err(), "beta");
}

fn model_file(parameters: &str) -> String {
    format!(
        "dofs = 2\n\n[[terms]]\nkind = \"iwan\"\nelements = [[1, 0]]\ncoefficient = \"k_t\"\nparameters = {parameters}\n"
    )
}

#[test]
fn model_file_history_parameters_are_checked_at_their_line() {
    let innermost = |text: String| match parse_model(&text, "m.toml") {
        Err(e @ Error::ModelFile { line, .. }) => {
            // At the term's table, or at its `parameters` key when the error names it.
            assert!(line == 3 || line == 7, "{e}");
            e.innermost().clone()
        }
        other => panic!("{other:?}"),
    };
    match innermost(model_file(
        "{ phi_max = 0.1, chi = -0.5, beta = 1, gamma = 2 }",
    )) {
        Error::UnknownName { name, known, .. } => {
            assert_eq!(name, "gamma");
            assert!(known.contains("phi_max"), "{known}");
        }
        other => panic!("{other:?}"),
    }
    match innermost(model_file("{ phi_max = 0.1, beta = 1 }")) {
        Error::Missing { name, .. } => assert!(name.contains("chi"), "{name}"),
        other => panic!("{other:?}"),
    }
    match innermost(model_file("{ phi_max = 0.1, chi = -2, beta = 1 }")) {
        Error::InvalidParameter { name, .. } => assert!(name.contains("chi"), "{name}"),
        other => panic!("{other:?}"),
    }
    match innermost(model_file(
        "{ phi_max = { estimate = true, initial = 0.1 }, chi = -0.5, beta = 1 }",
    )) {
        Error::Missing { name, .. } => assert!(name.contains("lower"), "{name}"),
        other => panic!("{other:?}"),
    }
}

/// Bouc–Wen's run time does not grow with β (issue 29, item 6): β = 10⁶ and 10²⁵⁰ (a
/// saturation displacement z_max = 1/β far below the motion) build in bounded work and
/// give finite columns; β = 10³⁰⁰ (z_max below 1e-280) is refused naming β.
#[test]
fn a_huge_bouc_wen_beta_runs_in_bounded_time_or_is_refused() {
    let with_beta = |beta: f64| -> Result<DampingModel> {
        Ok(shared_model().with(Term::History(HistoryTerm::new(
            Arc::new(BoucWen::new(beta, 0.5, 1.0)?),
            vec![Element::to_ground(0)],
            Coefficients::Shared("alpha".into()),
        ))))
    };
    for beta in [1e6, 1e250] {
        let regressor = Regressor::build(
            &with_beta(beta).unwrap(),
            &[record()],
            &measured().regressor,
        )
        .unwrap();
        let column = regressor.matrix().col(1);
        assert!(
            column.iter().all(|a| a.is_finite() && *a != 0.0),
            "β = {beta}"
        );
    }
    let error = with_beta(1e300).unwrap_err();
    assert!(
        matches!(&error, Error::InvalidParameter { name, .. } if name.contains("beta")),
        "{error:?}"
    );
    assert!(error.to_string().contains("z_max"), "{error}");
}
