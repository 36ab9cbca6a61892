//! `Record::new` checks its parts: every value finite (`NonFinite` names the array,
//! row and column), the arrays of one size (`DimensionMismatch`), force channels on
//! existing DOFs (`DofOutOfRange`), at least one DOF (`Empty`) and three samples
//! (`RecordTooShort`), and a positive finite step and period and a finite start time
//! (`InvalidParameter`).

use dampid::prelude::*;
use dampid::record::LoadDistribution;
use faer::Mat;

use crate::fixtures::*;

// ---------------------------------------------------------------------------------
// Non-finite values
// ---------------------------------------------------------------------------------

#[test]
fn nan_in_displacements_is_non_finite_with_position() {
    let err = record_with(|p| p.displacements[(17, 1)] = f64::NAN).unwrap_err();
    assert_nan_at(&err, "displacements", 17, 1);
    let text = err.to_string();
    for needle in ["displacements", "NaN", "row 17", "column 1"] {
        assert!(text.contains(needle), "'{needle}' missing from: {text}");
    }
}

#[test]
fn inf_in_force_signals_is_non_finite_with_position() {
    let mut signals = forces(N);
    signals[(5, 1)] = f64::INFINITY;
    let err = record_with(|p| p.forcing = Forcing::generalized(signals)).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::NonFinite { what, row: 5, column: 1, value }
                if what == "force signals" && *value == f64::INFINITY
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("force signals") && text.contains("inf"),
        "{text}"
    );
}

#[test]
fn negative_inf_in_force_signals_is_non_finite() {
    let mut signals = forces(N);
    signals[(200, 0)] = f64::NEG_INFINITY;
    assert!(matches!(
        record_with(|p| p.forcing = Forcing::generalized(signals)),
        Err(Error::NonFinite { ref what, row: 200, column: 0, value })
            if what == "force signals" && value == f64::NEG_INFINITY
    ));
}

#[test]
fn nan_in_measured_velocities_is_non_finite_with_position() {
    let mut v = velocities(N);
    v[(0, 0)] = f64::NAN;
    let err = record_with(|p| p.velocities = Some(v)).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::NonFinite { what, row: 0, column: 0, value }
                if what == "velocities" && value.is_nan()
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("velocities"), "{err}");
}

#[test]
fn nan_in_load_distribution_is_non_finite() {
    let mut d = Mat::<f64>::identity(2, 2);
    d[(1, 0)] = f64::NAN;
    assert!(matches!(
        record_with(|p| p.forcing = Forcing::distributed(forces(N), d)),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "load distribution" && value.is_nan()
    ));
}

#[test]
fn nan_start_time_is_invalid_parameter() {
    assert_invalid(
        record_with(|p| p.start_time = f64::NAN),
        "start_time",
        f64::NAN,
    );
}

// ---------------------------------------------------------------------------------
// Shapes and DOFs
// ---------------------------------------------------------------------------------

#[test]
fn velocities_with_wrong_row_count_are_dimension_mismatch() {
    let err = record_with(|p| p.velocities = Some(velocities(N - 1))).unwrap_err();
    match &err {
        Error::DimensionMismatch {
            what,
            expected,
            found,
        } => {
            assert!(what.contains("rows of velocities"), "{what}");
            assert_eq!((*expected, *found), (N, N - 1));
        }
        other => panic!("expected DimensionMismatch, got {other:?}"),
    }
    let text = err.to_string();
    assert!(text.contains("201") && text.contains("200"), "{text}");
}

#[test]
fn velocities_with_wrong_column_count_are_dimension_mismatch() {
    assert!(matches!(
        record_with(|p| p.velocities = Some(Mat::zeros(N, 3))),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("columns of velocities")
    ));
}

#[test]
fn force_signals_with_wrong_row_count_are_dimension_mismatch() {
    assert!(matches!(
        record_with(|p| p.forcing = Forcing::generalized(forces(N + 4))),
        Err(Error::DimensionMismatch { ref what, expected: N, found: 205 })
            if what.contains("force signals")
    ));
}

#[test]
fn force_channel_on_missing_dof_is_dof_out_of_range() {
    let err = record_with(|p| p.forcing = Forcing::on_dofs(forces(N), vec![0, 5])).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::DofOutOfRange { what, dof: 6, dofs: 2 } if what == "force channel 2"
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("force channel 2")
            && text.contains("DOF 6")
            && text.contains("numbered 1..2"),
        "{text}"
    );
}

#[test]
fn force_dof_list_length_mismatch_is_dimension_mismatch() {
    assert!(matches!(
        record_with(|p| p.forcing = Forcing::on_dofs(forces(N), vec![0])),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("force DOF list")
    ));
}

#[test]
fn load_distribution_of_wrong_size_is_dimension_mismatch() {
    assert!(matches!(
        record_with(|p| p.forcing = Forcing::distributed(forces(N), Mat::identity(3, 2))),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("rows of load distribution")
    ));

    let forcing = Forcing {
        signals: forces(N),
        distribution: LoadDistribution::Matrix(Mat::zeros(2, 1)),
    };
    assert!(matches!(
        record_with(|p| p.forcing = forcing),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("columns of load distribution")
    ));
}

#[test]
fn record_without_dofs_is_empty() {
    let result = record_with(|p| {
        p.displacements = Mat::zeros(N, 0);
        p.velocities = None;
        p.forcing = Forcing::generalized(Mat::zeros(N, 0));
    });
    assert!(matches!(
        result,
        Err(Error::Empty { ref what }) if what.contains("DOFs")
    ));
}

#[test]
fn record_of_two_samples_is_too_short() {
    let mut p = parts(2);
    p.label = "tiny".into();
    assert_eq!(
        Record::new(p).unwrap_err(),
        Error::RecordTooShort {
            record: "tiny".into(),
            needed: 3,
            available: 2
        }
    );
}

// ---------------------------------------------------------------------------------
// Step and period
// ---------------------------------------------------------------------------------

#[test]
fn nonpositive_step_is_invalid_parameter() {
    for step in [0.0, -0.01] {
        let err = assert_invalid(record_with(|p| p.step = step), "step", step);
        assert!(err.to_string().contains("step"), "{err}");
    }
}

#[test]
fn nan_step_is_invalid_parameter() {
    let err = assert_invalid(record_with(|p| p.step = f64::NAN), "step", f64::NAN);
    let text = err.to_string();
    assert!(text.contains("step") && text.contains("NaN"), "{text}");
}

#[test]
fn infinite_step_is_invalid_parameter() {
    assert_invalid(
        record_with(|p| p.step = f64::INFINITY),
        "step",
        f64::INFINITY,
    );
}

#[test]
fn nonpositive_or_non_finite_period_is_invalid_parameter() {
    for period in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = assert_invalid(record_with(|p| p.period = period), "period", period);
        assert!(err.to_string().contains("period"), "{err}");
    }
}

// ---------------------------------------------------------------------------------
// Motion sensors (model files): per DOF exactly one kind of motion column
// ---------------------------------------------------------------------------------

/// A DOF with no motion column, or with two kinds, is `MotionSensors` naming the record
/// and the DOF from 1; displacements and velocities of every DOF are measured velocities.
#[test]
fn a_dof_needs_exactly_one_kind_of_motion_column() {
    let cases = [
        ("displacements = [\"x1\", \"x2\"]", 3, "no motion column"),
        (
            "displacements = [\"x1\", \"x2\", \"x3\"]\naccelerations = [{ column = \"v2\", dof = 2 }]",
            2,
            "2 kinds of motion column (displacement 'x2', acceleration 'v2')",
        ),
        (
            "displacements = [\"x1\", \"x2\"]\nvelocities = [{ column = \"v1\", dof = 1 }]",
            1,
            "2 kinds",
        ),
    ];
    for (motion, dof, found) in cases {
        let err = parse_model(&chain3_with_motion(motion), "m.toml").unwrap_err();
        match err.innermost() {
            Error::MotionSensors {
                record,
                dof: d,
                found: f,
            } => {
                assert!(record.ends_with("record_1.csv"), "{err}");
                assert_eq!(*d, dof, "{err}");
                assert!(f.contains(found), "{err}");
            }
            other => panic!("{motion}: {other:?}"),
        }
        assert!(err.to_string().contains(&format!("DOF {dof}")), "{err}");
    }
    // the same DOF twice in one list points at the second entry's line (line 11)
    let err = parse_model(
        &chain3_with_motion(
            "displacements = [\"x1\", \"x2\", \"x3\"]\naccelerations = [\n  { column = \"v2\", dof = 2 },\n  { column = \"v3\", dof = 2 },\n]\nvelocities = [\"v1\"]",
        ),
        "m.toml",
    )
    .unwrap_err();
    assert!(matches!(err, Error::ModelFile { line: 13, .. }), "{err}");
    assert!(
        err.to_string().contains("two acceleration columns"),
        "{err}"
    );
    // a motion column on a DOF the model does not have
    let err = parse_model(
        &chain3_with_motion("displacements = [\"x1\", \"x2\", \"x3\", \"v1\"]"),
        "m.toml",
    )
    .unwrap_err();
    assert!(
        matches!(
            err.innermost(),
            Error::DofOutOfRange {
                dof: 4,
                dofs: 3,
                ..
            }
        ),
        "{err}"
    );
    // displacements and velocities of every DOF: measured velocities, as before
    let job = parse_model(
        &chain3_with_motion(
            "displacements = [\"x1\", \"x2\", \"x3\"]\nvelocities = [\"v1\", \"v2\", \"v3\"]",
        ),
        "m.toml",
    )
    .unwrap();
    assert!(job.records[0].velocities().is_some());
    assert!(job.records[0].measured_motion().is_none());
}
