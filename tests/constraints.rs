//! Linear constraints between coefficients (clarabel's zero and nonnegative cones), by
//! hand, with their typed errors and their model-file form.

use std::path::Path;

use dampid::fit::{self, LinearConstraint, LinearTerm, Relation, SolverSettings};
use dampid::model_file::parse;
use dampid::prelude::*;
use faer::Mat;

mod support;
use support::regressors::row_labels;

/// A = [[1, 0], [0, 1], [1, 1]], b = [2, 1, 3]: least squares θ = (2, 1).
fn regressor() -> Regressor {
    let rows = [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    let labels = row_labels(3);
    Regressor::from_parts(
        Mat::from_fn(3, 2, |i, j| rows[i][j]),
        vec![2.0, 1.0, 3.0],
        vec!["a".into(), "b".into()],
        labels,
    )
    .unwrap()
}

fn fit_with(linear: Vec<LinearConstraint>) -> Result<Fit> {
    fit::constrained(
        &regressor(),
        &Constraints {
            linear,
            ..Constraints::default()
        },
        &SolverSettings::default(),
    )
}

/// θ_a = θ_b = t minimises (t − 2)² + (t − 1)² + (2t − 3)²: 12t = 18, t = 1.5. The polish
/// knows only bounds, so it is skipped.
#[test]
fn equality_between_two_coefficients() {
    let fit = fit_with(vec![LinearConstraint::equal("a", "b")]).unwrap();
    assert_eq!(fit.status, FitStatus::Solved);
    for value in &fit.coefficients {
        assert!((value - 1.5).abs() < 1e-8, "{fit:?}");
    }
    assert!(!fit.solver.unwrap().polished);
}

/// θ_a ≤ 1.5 θ_b is violated by (2, 1); on the boundary θ = (1.5t, t):
/// (1.5t − 2)² + (t − 1)² + (2.5t − 3)² is least at 19t = 23. θ_a ≤ 3 θ_b holds at
/// (2, 1): inactive, the least-squares answer. θ_a + θ_b ≥ 3.5 is violated (sum 3): on
/// θ_a + θ_b = 3.5 with θ_b = 3.5 − θ_a, (θ_a − 2)² + (2.5 − θ_a)² + 0.25 is least at
/// θ_a = 2.25.
#[test]
fn inequalities_active_and_inactive() {
    let fit = fit_with(vec![LinearConstraint::at_most_multiple("a", 1.5, "b")]).unwrap();
    let t = 23.0 / 19.0;
    assert!((fit.coefficients[0] - 1.5 * t).abs() < 1e-8, "{fit:?}");
    assert!((fit.coefficients[1] - t).abs() < 1e-8);

    let fit = fit_with(vec![LinearConstraint::at_most_multiple("a", 3.0, "b")]).unwrap();
    assert!((fit.coefficients[0] - 2.0).abs() < 1e-8 && (fit.coefficients[1] - 1.0).abs() < 1e-8);

    let fit = fit_with(vec![LinearConstraint::new(
        &[("a", 1.0), ("b", 1.0)],
        Relation::AtLeast,
        3.5,
    )])
    .unwrap();
    assert!((fit.coefficients[0] - 2.25).abs() < 1e-8, "{fit:?}");
    assert!((fit.coefficients[1] - 1.25).abs() < 1e-8);
}

/// θ_a = θ_b together with θ_a ≥ θ_b + 1 cannot hold: bad input, a typed error that
/// lists the constraints (not a failed fit).
#[test]
fn contradictory_constraints_are_an_error() {
    let error = fit_with(vec![
        LinearConstraint::equal("a", "b"),
        LinearConstraint::new(&[("a", 1.0), ("b", -1.0)], Relation::AtLeast, 1.0),
    ])
    .unwrap_err();
    assert_eq!(error.kind(), "infeasible_constraints");
    let message = error.to_string();
    assert!(
        message.contains("a = b") || message.contains("a − b"),
        "{message}"
    );
}

#[test]
fn bad_linear_constraints_are_typed_errors() {
    assert!(matches!(
        fit_with(vec![LinearConstraint::equal("a", "nope")]),
        Err(Error::UnknownCoefficient { name, .. }) if name == "nope"
    ));
    assert!(matches!(
        fit_with(vec![LinearConstraint::new(&[("a", 1.0), ("a", -1.0)], Relation::Equal, 0.0)]),
        Err(Error::DuplicateCoefficient { name }) if name == "a"
    ));
    assert!(matches!(
        fit_with(vec![LinearConstraint {
            terms: Vec::new(),
            relation: Relation::Equal,
            value: 0.0
        }]),
        Err(Error::Empty { .. })
    ));
    assert!(matches!(
        fit_with(vec![LinearConstraint::new(&[("a", f64::NAN)], Relation::AtMost, 0.0)]),
        Err(Error::InvalidParameter { value, .. }) if value.is_nan()
    ));
    assert!(matches!(
        fit_with(vec![LinearConstraint::new(&[("a", 1.0)], Relation::AtMost, f64::INFINITY)]),
        Err(Error::InvalidParameter { value, .. }) if value == f64::INFINITY
    ));
    assert!(matches!(
        fit_with(vec![LinearConstraint::new(&[("a", 0.0), ("b", 0.0)], Relation::Equal, 0.0)]),
        Err(Error::InvalidParameter { value, .. }) if value == 0.0
    ));
}

#[test]
fn linear_constraints_print_as_relations() {
    let c = LinearConstraint {
        terms: vec![
            LinearTerm {
                name: "dashpot[0-1]".into(),
                coefficient: 1.0,
            },
            LinearTerm {
                name: "dashpot[4-5]".into(),
                coefficient: -2.5,
            },
        ],
        relation: Relation::AtMost,
        value: 0.0,
    };
    assert_eq!(c.to_string(), "dashpot[0-1] − 2.5 dashpot[4-5] ≤ 0");
}

const MODEL: &str = r#"
dofs = 2
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "dashpot"
[identification]
constraints = [
  { terms = { "dashpot[0-1]" = 1, "dashpot[2-3]" = -1 }, relation = "=", value = 0 },
  { terms = { "dashpot[1-2]" = 1, "dashpot[0-1]" = -2 }, relation = "<=" },
]
[simulation]
mass = "identity"
stiffness = "chain"
coefficients = { "dashpot[0-1]" = 0.1, "dashpot[1-2]" = 0.15, "dashpot[2-3]" = 0.1 }
step = 0.1
transient_steps = 3000
recorded_steps = 200
[[simulation.experiments]]
force_dof = 1
amplitude = 1.0
frequency = 1.0
[[simulation.experiments]]
force_dof = 2
amplitude = 1.0
frequency = 1.7320508
"#;

/// Model-file constraints: symmetric walls' dashpots equal, the middle one at most twice
/// the wall ones; the simulated truth satisfies both, so the fit returns it.
#[test]
fn constraints_in_a_model_file() {
    let job = parse(
        MODEL,
        "constraints.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap();
    let linear = &job.settings.fit.constraints.linear;
    assert_eq!(linear.len(), 2);
    assert_eq!(linear[0].relation, Relation::Equal);
    assert_eq!(linear[1].relation, Relation::AtMost);
    assert_eq!(linear[1].value, 0.0);
    let mut settings = job.settings.clone();
    settings.regressor.windows.cycles_mut().unwrap().count = None;
    let report = identify(&job.problem(), &settings, &silent).unwrap().report;
    assert_eq!(report.status, FitStatus::Solved);
    let (d01, d23) = (
        report.coefficient("dashpot[0-1]").unwrap(),
        report.coefficient("dashpot[2-3]").unwrap(),
    );
    assert!((d01 - d23).abs() < 1e-9 * d01, "{report}");
    for (name, truth) in [("dashpot[0-1]", 0.1), ("dashpot[1-2]", 0.15)] {
        let value = report.coefficient(name).unwrap();
        assert!((value - truth).abs() < 1e-2 * truth, "{name} = {value}");
    }

    let bad = MODEL.replace(r#"relation = "=""#, r#"relation = "==""#);
    match parse(&bad, "constraints.toml", Path::new("."), Default::default()).unwrap_err() {
        Error::ModelFile { line, .. } => assert_eq!(line, 10, "the first constraint"),
        other => panic!("{other:?}"),
    }
}
