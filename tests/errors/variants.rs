//! Every variant of `dampid::Error` is reachable through the public API: one input per
//! variant, checked against `dampid::error::KINDS`, the list of every variant (which
//! the crate keeps complete with an exhaustive match in `Error::kind`): a new variant
//! fails this test until an input here produces it. Every message names something.

use dampid::io::output::Overwrite;
use dampid::prelude::*;
use dampid::regressor::SpanWindows;
use dampid::simulate::simulate;
use faer::Mat;

use crate::fixtures::*;

#[test]
fn every_variant_is_reachable() {
    let mut singular = system();
    singular.mass = Mat::zeros(2, 2);
    let unknown = two_windows(fixed("nope", 0.0));
    let infeasible = two_windows(bound("c[1]", Some(1.0), Some(0.0)));
    let duplicate = shared_model().with(Term::viscous("c", Mat::identity(2, 2)));
    let no_v = record_with(|p| p.velocities = None).unwrap();

    let errors = [
        record_with(|p| p.displacements[(0, 0)] = f64::NAN).unwrap_err(),
        record_with(|p| p.velocities = Some(velocities(3))).unwrap_err(),
        record_with(|p| p.step = 0.0).unwrap_err(),
        Record::new(parts(2)).unwrap_err(),
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        record_with(|p| p.forcing = Forcing::on_dofs(forces(N), vec![0, 2])).unwrap_err(),
        identify(
            &ParametricRegressor::linear(&DampingModel::new(), &[record()]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&duplicate, &[record()]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &unknown,
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &infeasible,
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&shared_model(), &[no_v]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        simulate(&singular, &sim_settings(), &dampid::progress::silent).unwrap_err(),
        dampid::terms::laws::Expression::parse("abs(v)*q").unwrap_err(),
        parse_model("dofs = ", "bad.toml").unwrap_err(),
        dampid::io::csv::parse("t,x\n0,1\n", "t.csv")
            .unwrap()
            .column("y")
            .unwrap_err(),
        dampid::io::csv::parse("t,x\n0,abc\n", "t.csv").unwrap_err(),
        dampid::io::csv::parse("t,x\n0,1\n1,1\n2.1,1\n3,1\n", "t.csv")
            .unwrap()
            .uniform_step("t")
            .unwrap_err(),
        dampid::prep::period::detect_period(Mat::<f64>::zeros(N, 1).as_ref(), H, "still")
            .unwrap_err(),
        growing_record_is_not_steady(),
        {
            let spectral = IdentifySettings {
                regressor: RegressorSettings {
                    quadrature: Quadrature::Spectral,
                    ..RegressorSettings::non_periodic(SpanWindows::new(0.5))
                },
                ..IdentifySettings::default()
            };
            identify(
                &ParametricRegressor::linear(&shared_model(), &[record()]),
                &spectral,
                &silent,
            )
            .unwrap_err()
        },
        dampid::terms::laws::by_name("power", &dampid::terms::laws::LawParameters::new())
            .unwrap_err(),
        {
            let dead = record_with(|p| p.forcing = Forcing::generalized(Mat::zeros(N, 2)));
            identify(
                &ParametricRegressor::linear(&shared_model(), &[dead.unwrap()]),
                &measured(),
                &silent,
            )
            .unwrap_err()
        },
        {
            let zero = DampingModel::new().with(Term::viscous("zero", Mat::zeros(2, 2)));
            identify(
                &ParametricRegressor::linear(&zero, &[record()]),
                &measured(),
                &silent,
            )
            .unwrap_err()
        },
        existing_output(),
        identify(
            &ParametricRegressor::linear(&crate::history::bouc_wen_model(1), &[record()]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        // A flag of the caller's own: the process-wide one would stop the other tests.
        dampid::cancel::check_flag(&std::sync::atomic::AtomicBool::new(true), "the simulation")
            .unwrap_err(),
        {
            let mut huge = sim_settings();
            huge.recorded_steps = 1_000_000_000_000_000;
            simulate(&system(), &huge, &dampid::progress::silent).unwrap_err()
        },
        {
            let contradictory = Constraints {
                linear: vec![
                    LinearConstraint::equal("c[1]", "c[2]"),
                    LinearConstraint::new(&[("c[1]", 1.0), ("c[2]", -1.0)], Relation::AtLeast, 1.0),
                ],
                ..Constraints::default()
            };
            identify(
                &ParametricRegressor::linear(&per_dof_model(), &[record()]),
                &two_windows(contradictory),
                &silent,
            )
            .unwrap_err()
        },
        dampid::io::records::write_record(
            std::path::Path::new("/nonexistent-dampid-folder/record_1.csv"),
            &record(),
            Overwrite::Refuse,
        )
        .unwrap_err(),
        parse_model(
            &chain3_with_motion("displacements = [\"x1\", \"x2\"]"),
            "m.toml",
        )
        .unwrap_err()
        .innermost()
        .clone(),
        identify(
            &ParametricRegressor::linear(&shared_model(), &[crate::physics::inverted()]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&shared_model(), &[crate::physics::still(0)]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        identify(
            &ParametricRegressor::linear(&shared_model(), &[crate::physics::scaled(1e200)]),
            &measured(),
            &silent,
        )
        .unwrap_err(),
        incomparable_units(),
    ];
    let mut seen: Vec<&str> = errors.iter().map(Error::kind).collect();
    seen.sort_unstable();
    seen.dedup();
    let mut expected = dampid::error::KINDS.to_vec();
    expected.sort_unstable();
    assert_eq!(seen, expected);
    // Every message is non-empty and names something.
    for e in &errors {
        assert!(e.to_string().len() > 10, "{e:?}");
    }
}

/// Two backbones whose length units differ.
fn incomparable_units() -> Error {
    use dampid::analysis::backbones::{JobBackbone, JobLabel, TestKind, compare};
    let job = |file: &str, length: &str| JobBackbone {
        label: JobLabel {
            file: file.into(),
            length: Some(length.into()),
            ..Default::default()
        },
        kind: TestKind::FreeDecay,
        modal_mass: 1.0,
        measured: Vec::new(),
        fitted: Vec::new(),
    };
    compare(vec![job("a.toml", "m"), job("b.toml", "mm")]).unwrap_err()
}

/// Writing a record twice to one path without `Replace`.
fn existing_output() -> Error {
    let path = std::env::temp_dir().join(format!("dampid-variants-{}.csv", std::process::id()));
    std::fs::remove_file(&path).ok();
    dampid::io::records::write_record(&path, &record(), Overwrite::Refuse).unwrap();
    let error = dampid::io::records::write_record(&path, &record(), Overwrite::Refuse).unwrap_err();
    std::fs::remove_file(&path).ok();
    error
}
