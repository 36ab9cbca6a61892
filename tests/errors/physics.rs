//! Physically impossible data (issue 29): input work that a passive structure cannot
//! take in, and a motion sensor that never moves. The fixture's forces balance linear
//! damping, r = c v; inverted, r = −c v gives b = −c ∮ vᵀv dt, every equation's net
//! work is minus its gross work.

use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;

/// The fixture with its forces inverted (a load cell mounted the other way round).
pub fn inverted() -> Record {
    record_with(|p| {
        let f = forces(N);
        p.forcing = Forcing::generalized(Mat::from_fn(N, 2, |i, j| -f[(i, j)]));
    })
    .unwrap()
}

/// The fixture with the displacement channel of DOF `dof` (0-based) all zero.
pub fn still(dof: usize) -> Record {
    record_with(|p| {
        for i in 0..N {
            p.displacements[(i, dof)] = 0.0;
        }
    })
    .unwrap()
}

/// The fixture with every displacement, velocity and force × `s`.
pub fn scaled(s: f64) -> Record {
    record_with(|p| {
        p.displacements = Mat::from_fn(N, 2, |i, j| s * p.displacements[(i, j)]);
        p.velocities = p
            .velocities
            .as_ref()
            .map(|v| Mat::from_fn(N, 2, |i, j| s * v[(i, j)]));
        let f = forces(N);
        p.forcing = Forcing::generalized(Mat::from_fn(N, 2, |i, j| s * f[(i, j)]));
    })
    .unwrap()
}

/// Data beyond 2^±505 are refused naming the record, the signal and its magnitude, with
/// the factor that brings them to order one; data at 1e±100 fit, with the coefficient
/// unchanged (x and f scale alike).
#[test]
fn data_beyond_double_precision_are_refused_with_units_advice() {
    let fit = |s: f64| {
        identify(
            &ParametricRegressor::linear(&shared_model(), &[scaled(s)]),
            &measured(),
            &silent,
        )
    };
    let base = fit(1.0).unwrap().report.coefficients[0].value;
    for s in [1e-100, 1e100] {
        let c = fit(s).unwrap().report.coefficients[0].value;
        assert!(
            (c - base).abs() <= 1e-9 * base.abs(),
            "{s:e}: {c} vs {base}"
        );
    }
    for (s, signal) in [
        (1e160, "displacement"),
        (1e300, "displacement"),
        (1e-160, "displacement"),
        (1e-300, "displacement"),
    ] {
        let e = fit(s).unwrap_err();
        match &e {
            Error::DataScale {
                record,
                signal: named,
                magnitude,
                ..
            } => {
                assert_eq!((record.as_str(), named.as_str()), ("fixture", signal));
                assert!(*magnitude > 1e-3 * s && *magnitude < 1e3 * s, "{e}");
                let text = e.to_string();
                assert!(
                    text.contains("other units") && text.contains("`scale`"),
                    "{e}"
                );
                let factor = format!("by about 1e{}", -(magnitude.log10().round() as i32));
                assert!(text.contains(&factor), "{text} lacks {factor}");
            }
            other => panic!("{s:e}: {other}"),
        }
    }
}

#[test]
fn inverted_forces_are_refused_with_the_share_and_the_record() {
    let e = identify(
        &ParametricRegressor::linear(&shared_model(), &[inverted()]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    match &e {
        Error::NegativeInputWork {
            unit,
            groups,
            total,
            share,
            reason,
        } => {
            assert_eq!((unit.as_str(), groups.len(), *total), ("record", 1, 1));
            assert!(groups[0].contains("'fixture'"), "{e}");
            assert_eq!(*share, 1.0, "{e}");
            assert!(reason.contains("accept_negative_work"), "{e}");
        }
        other => panic!("{other}"),
    }
    // Accepted, the fit runs and gives the negative coefficient the data ask for.
    let mut settings = measured();
    settings.fit.accept_negative_work = true;
    let report = identify(
        &ParametricRegressor::linear(&shared_model(), &[inverted()]),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!((report.coefficients[0].value + C_TRUE).abs() < 1e-3);
}

#[test]
fn a_dead_displacement_channel_names_the_record_and_the_dof() {
    for dof in 0..2 {
        let e = identify(
            &ParametricRegressor::linear(&shared_model(), &[still(dof)]),
            &measured(),
            &silent,
        )
        .unwrap_err();
        match &e {
            Error::DeadMotionSensor {
                record,
                dof: named,
                sensor,
                ..
            } => {
                assert_eq!(
                    (record.as_str(), *named, sensor.as_str()),
                    ("fixture", dof + 1, "displacement")
                );
                assert!(e.to_string().contains("never moves"), "{e}");
            }
            other => panic!("{other}"),
        }
    }
    // Declared held still, the channel is not refused (the fit is then the user's call).
    let fixed = still(1).with_fixed_dofs(vec![1]).unwrap();
    assert!(!matches!(
        identify(
            &ParametricRegressor::linear(&shared_model(), &[fixed]),
            &measured(),
            &silent,
        ),
        Err(Error::DeadMotionSensor { .. })
    ));
    // A fixed DOF out of range is an error naming it from 1.
    let e = record().with_fixed_dofs(vec![2]).unwrap_err();
    assert!(e.to_string().contains("DOF 3"), "{e}");
}
