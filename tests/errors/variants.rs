//! Every variant of `dampid::Error` is reachable through the public API: one input per
//! variant, and an exhaustive match that stops compiling when a variant is added until
//! an input here produces it. Every message names something.

use dampid::prelude::*;
use dampid::simulate::simulate;
use faer::Mat;

use crate::fixtures::*;

/// The variant's name. An exhaustive match: a new variant fails to compile here until
/// a test produces it.
fn variant(e: &Error) -> &'static str {
    match e {
        Error::NonFinite { .. } => "NonFinite",
        Error::DimensionMismatch { .. } => "DimensionMismatch",
        Error::InvalidParameter { .. } => "InvalidParameter",
        Error::RecordTooShort { .. } => "RecordTooShort",
        Error::TooFewEquations { .. } => "TooFewEquations",
        Error::DofOutOfRange { .. } => "DofOutOfRange",
        Error::Empty { .. } => "Empty",
        Error::DuplicateCoefficient { .. } => "DuplicateCoefficient",
        Error::UnknownCoefficient { .. } => "UnknownCoefficient",
        Error::InfeasibleBounds { .. } => "InfeasibleBounds",
        Error::MissingVelocities { .. } => "MissingVelocities",
        Error::Numerical { .. } => "Numerical",
        Error::Expression { .. } => "Expression",
        Error::ModelFile { .. } => "ModelFile",
        Error::UnknownName { .. } => "UnknownName",
        Error::Data { .. } => "Data",
        Error::NoPeriod { .. } => "NoPeriod",
        Error::NotSteady { .. } => "NotSteady",
    }
}

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
        identify(&per_dof_model(), &[record()], &measured()).unwrap_err(),
        record_with(|p| p.forcing = Forcing::on_dofs(forces(N), vec![0, 2])).unwrap_err(),
        identify(&DampingModel::new(), &[record()], &measured()).unwrap_err(),
        identify(&duplicate, &[record()], &measured()).unwrap_err(),
        identify(&per_dof_model(), &[record()], &unknown).unwrap_err(),
        identify(&per_dof_model(), &[record()], &infeasible).unwrap_err(),
        identify(&shared_model(), &[no_v], &measured()).unwrap_err(),
        simulate(&singular, &sim_settings()).unwrap_err(),
        dampid::terms::laws::Expression::parse("abs(v)*q").unwrap_err(),
        parse_model("dofs = ", "bad.toml").unwrap_err(),
        dampid::io::csv::parse("t,x\n0,1\n", "t.csv")
            .unwrap()
            .column("y")
            .unwrap_err(),
        dampid::io::csv::parse("t,x\n0,abc\n", "t.csv").unwrap_err(),
        dampid::prep::period::detect_period(Mat::<f64>::zeros(N, 1).as_ref(), H, "still")
            .unwrap_err(),
        growing_record_is_not_steady(),
    ];
    let mut seen: Vec<&str> = errors.iter().map(variant).collect();
    seen.sort_unstable();
    seen.dedup();
    let mut expected = vec![
        "NonFinite",
        "DimensionMismatch",
        "InvalidParameter",
        "RecordTooShort",
        "TooFewEquations",
        "DofOutOfRange",
        "Empty",
        "DuplicateCoefficient",
        "UnknownCoefficient",
        "InfeasibleBounds",
        "MissingVelocities",
        "Numerical",
        "Expression",
        "ModelFile",
        "UnknownName",
        "Data",
        "NoPeriod",
        "NotSteady",
    ];
    expected.sort_unstable();
    assert_eq!(seen, expected);
    // Every message is non-empty and names something.
    for e in &errors {
        assert!(e.to_string().len() > 10, "{e:?}");
    }
}
