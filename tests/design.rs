//! Experiment design: the greedy search adds the candidate that separates the
//! coefficients, reports the conditioning after each addition, and stops at a target.

use std::path::Path;

use dampid::analysis::design::{Criterion, DesignSettings, design, select, simulate_candidates};
use dampid::model_file::parse;
use dampid::prelude::*;
use dampid::simulate::{HarmonicForce, SimSettings, System};
use faer::Mat;

mod support;
use support::cli::dampid_json;

fn chain2() -> Mat<f64> {
    Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 })
}

/// C = c0 I + c1 K on a 2-DOF chain (λ = 1, 3).
fn model() -> DampingModel {
    DampingModel::new()
        .with(Term::mass_proportional("c0", Mat::identity(2, 2)))
        .with(Term::stiffness_proportional("c1", chain2()))
}

fn nominal() -> System {
    System {
        mass: Mat::identity(2, 2),
        stiffness: chain2(),
        damping: model(),
        damping_coefficients: vec![0.05, 0.05],
        conservative: Vec::new(),
        forcing: Vec::new(),
    }
}

fn force(amplitude: f64, frequency: f64) -> HarmonicForce {
    HarmonicForce {
        dof: 0,
        amplitude,
        frequency,
        phase: 0.0,
    }
}

/// Candidates 0 and 1: the first resonance at two amplitudes (a linear system: the
/// same row scaled, no new direction); candidate 2: the second resonance.
fn candidates() -> Vec<HarmonicForce> {
    vec![force(1.0, 1.0), force(0.5, 1.0), force(1.0, 3f64.sqrt())]
}

fn simulation() -> SimSettings {
    SimSettings {
        step: 0.1,
        substeps: 2,
        transient_steps: 4000,
        recorded_steps: 200,
    }
}

fn regressor_settings() -> RegressorSettings {
    support::settings(
        WindowSpec::cycles(1),
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    )
}

/// From the first resonance, both criteria add the second resonance, not another
/// amplitude; the practical rank goes from 1 to 2 (the first resonance alone has
/// σ_2/σ_1 of round-off size) and the condition number falls by orders of magnitude;
/// log det = 2 Σ ln σ_i of the singular values reported.
#[test]
fn greedy_step_adds_the_experiment_that_separates_the_coefficients() {
    for criterion in [Criterion::DOptimal, Criterion::Condition] {
        let report = design(
            &nominal(),
            &model(),
            &candidates(),
            &simulation(),
            &regressor_settings(),
            &DesignSettings {
                criterion,
                start: vec![0],
                picks: 1,
                ..DesignSettings::default()
            },
        )
        .unwrap();
        assert_eq!(report.chosen, [2], "{report}");
        assert_eq!(report.selected(), [0, 2]);
        let (start, added) = (&report.steps[0], &report.steps[1]);
        assert_eq!(start.rank, 1);
        assert!(start.condition_number.is_none_or(|k| k > 1e6), "{report}");
        assert_eq!(added.rank, 2);
        assert!(added.condition_number.unwrap() < 10.0, "{report}");
        let s = &added.singular_values;
        assert!((added.condition_number.unwrap() - s[0] / s[1]).abs() < 1e-9);
        assert!((added.log_det.unwrap() - 2.0 * (s[0].ln() + s[1].ln())).abs() < 1e-12);
        assert!(report.succeeded());
        assert!(report.to_string().contains("a=1 ω=1.7321 on DOF 1"));
    }
}

/// A start set that already meets the target adds nothing; an unreachable target is
/// reported as not reached.
#[test]
fn the_search_stops_at_the_target_condition() {
    let records = simulate_candidates(&nominal(), &candidates(), &simulation()).unwrap();
    let met = select(
        &model(),
        &records,
        &regressor_settings(),
        &DesignSettings {
            start: vec![0, 2],
            target_condition: Some(1e3),
            ..DesignSettings::default()
        },
        &dampid::progress::silent,
    )
    .unwrap();
    assert!(met.chosen.is_empty());
    assert!(met.succeeded());
    let missed = select(
        &model(),
        &records,
        &regressor_settings(),
        &DesignSettings {
            start: vec![0],
            picks: 5,
            target_condition: Some(1.0 + 1e-9),
            ..DesignSettings::default()
        },
        &dampid::progress::silent,
    )
    .unwrap();
    assert_eq!(missed.chosen.len(), 2, "runs out of candidates");
    assert!(!missed.succeeded());
    assert!(missed.to_string().contains("not reached"));
}

#[test]
fn bad_design_settings_are_typed_errors() {
    let records = simulate_candidates(&nominal(), &candidates(), &simulation()).unwrap();
    let run = |settings: DesignSettings| {
        select(
            &model(),
            &records,
            &regressor_settings(),
            &settings,
            &dampid::progress::silent,
        )
        .unwrap_err()
    };
    for (settings, name, value) in [
        (
            DesignSettings {
                start: vec![3],
                ..DesignSettings::default()
            },
            "start experiment",
            3.0,
        ),
        (
            DesignSettings {
                start: vec![1, 1],
                ..DesignSettings::default()
            },
            "start experiment",
            1.0,
        ),
        (
            DesignSettings {
                target_condition: Some(0.5),
                ..DesignSettings::default()
            },
            "target_condition",
            0.5,
        ),
    ] {
        match run(settings) {
            Error::InvalidParameter {
                name: n, value: v, ..
            } => assert_eq!((n.as_str(), v), (name, value)),
            other => panic!("{other:?}"),
        }
    }
    assert!(matches!(
        select(
            &model(),
            &[],
            &regressor_settings(),
            &DesignSettings::default(),
            &dampid::progress::silent
        ),
        Err(Error::Empty { .. })
    ));
}

const HEAD: &str = r#"
dofs = 2
[[terms]]
kind = "mass_proportional"
coefficient = "c0"
matrix = "identity"
[[terms]]
kind = "stiffness_proportional"
coefficient = "c1"
matrix = "chain"
"#;

const SIMULATION: &str = r#"
[simulation]
mass = "identity"
stiffness = "chain"
coefficients = { c0 = 0.05, c1 = 0.05 }
step = 0.1
transient_steps = 4000
recorded_steps = 200
[[simulation.experiments]]
force_dof = 1
amplitude = 1.0
frequency = 1.0
[[simulation.experiments]]
force_dof = 1
amplitude = 1.0
frequency = 1.7320508
"#;

/// `[design]` in a model file: 1-based start indices; it needs a `[simulation]`.
#[test]
fn design_section_in_a_model_file() {
    let text = format!(
        "{HEAD}{SIMULATION}[design]\ncriterion = \"condition\"\nstart = [1]\npicks = 1\ntarget_condition = 50.0\n"
    );
    let job = parse(&text, "design.toml", Path::new("."), Default::default()).unwrap();
    let settings = job.design.unwrap();
    assert_eq!(settings.criterion, Criterion::Condition);
    assert_eq!((settings.start.clone(), settings.picks), (vec![0], 1));
    assert_eq!(settings.target_condition, Some(50.0));

    let bad_start = format!("{HEAD}{SIMULATION}[design]\nstart = [3]\n");
    match parse(
        &bad_start,
        "design.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap_err()
    {
        Error::ModelFile { line, message, .. } => {
            assert!(
                line > 0 && message.contains("experiments are numbered 1..2"),
                "{message}"
            )
        }
        other => panic!("{other:?}"),
    }
    let unknown_key = format!("{HEAD}{SIMULATION}[design]\npick = 1\n");
    assert!(matches!(
        parse(
            &unknown_key,
            "design.toml",
            Path::new("."),
            Default::default()
        )
        .unwrap_err(),
        Error::ModelFile { .. }
    ));
}

/// `dampid design` on the 6-DOF Rayleigh chain: one experiment added, full rank and a
/// condition number below 100 after it.
#[test]
fn design_command_adds_one_experiment() {
    let json = dampid_json(&["design", "models/rayleigh_chain6_design.toml", "--json"]);
    assert_eq!(json["chosen"].as_array().unwrap().len(), 1);
    let last = &json["steps"][1];
    assert_eq!(last["rank"], 2);
    assert!(last["condition_number"].as_f64().unwrap() < 100.0);
}
