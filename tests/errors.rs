//! Bad input gets a typed error that names the offending field and value: never a
//! panic, never a silently wrong number.
//!
//! Every variant of [`dampid::Error`] is produced here through the public API, except
//! `Error::SolverSetup`: dampid builds the clarabel problem itself (dimensions and cones
//! always consistent, settings fixed to the direct KKT solver with the default
//! `direct_solve_method`), so clarabel's set-up checks (`check_dimensions` and
//! `DefaultSettings::validate`) cannot fail from any input a caller can give. It is the
//! only variant not covered; see `every_variant_is_reachable`.
//!
//! Fixtures are small hand-built records: x_j = X_j cos(ωt + φ_j) on 2 DOFs, T = 1,
//! h = 0.01 (100 samples per period), 201 samples (two periods), with measured
//! velocities and generalized forces r = c v (c = 0.3), so that a linear model with
//! one shared coefficient identifies c = 0.3 (checked by `fixtures_are_valid`: every
//! other test changes exactly one thing).

use std::f64::consts::PI;
use std::sync::Arc;

use dampid::fit::{self, SolverSettings};
use dampid::prelude::*;
use dampid::record::LoadDistribution;
use dampid::regressor::RowLabel;
use dampid::simulate::{ConservativeForce, HarmonicForce, SimSettings, System, simulate};
use faer::Mat;

// ---------------------------------------------------------------------------------
// Fixtures
// ---------------------------------------------------------------------------------

/// Sampling step.
const H: f64 = 0.01;
/// Driving period.
const T: f64 = 1.0;
/// Samples in the fixture record (two periods plus the closing sample).
const N: usize = 201;
/// Samples one trapezoid window of one period reads: T/h + 1.
const WINDOW: usize = 101;
/// The linear damping coefficient the fixture forces balance.
const C_TRUE: f64 = 0.3;
/// Amplitudes and phases of the two DOFs.
const AMPLITUDE: [f64; 2] = [1.0, 0.5];
const PHASE: [f64; 2] = [0.0, 0.3];

fn omega() -> f64 {
    2.0 * PI / T
}

fn displacements(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| {
        AMPLITUDE[j] * (omega() * i as f64 * H + PHASE[j]).cos()
    })
}

fn velocities(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| {
        -omega() * AMPLITUDE[j] * (omega() * i as f64 * H + PHASE[j]).sin()
    })
}

/// Generalized forces r = c v: the input work balances linear damping c.
fn forces(samples: usize) -> Mat<f64> {
    Mat::from_fn(samples, 2, |i, j| C_TRUE * velocities(samples)[(i, j)])
}

fn parts(samples: usize) -> RecordParts {
    RecordParts {
        label: "fixture".into(),
        step: H,
        start_time: 0.0,
        displacements: displacements(samples),
        velocities: Some(velocities(samples)),
        forcing: Forcing::generalized(forces(samples)),
        period: T,
    }
}

fn record() -> Record {
    Record::new(parts(N)).expect("fixture record is valid")
}

/// Linear damping on each DOF to ground, one shared coefficient "c".
fn shared_model() -> DampingModel {
    DampingModel::new().with(Term::per_dof(Linear, 2, Coefficients::Shared("c".into())))
}

/// Linear damping on each DOF to ground, coefficients "c[1]" and "c[2]".
fn per_dof_model() -> DampingModel {
    DampingModel::new().with(Term::per_dof(
        Linear,
        2,
        Coefficients::PerElement("c".into()),
    ))
}

fn measured() -> IdentifySettings {
    IdentifySettings {
        regressor: RegressorSettings {
            velocity: VelocitySource::Measured,
            ..RegressorSettings::default()
        },
        ..IdentifySettings::default()
    }
}

/// A well-posed 2-DOF chain: M = I, K = tridiag(−1, 2, −1), linear damping 0.1,
/// a unit force at ω = 1 on DOF 1; 20 recorded steps of h = 0.1 (fast).
fn system() -> System {
    System {
        mass: Mat::identity(2, 2),
        stiffness: Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 }),
        damping: shared_model(),
        damping_coefficients: vec![0.1],
        conservative: Vec::new(),
        forcing: vec![HarmonicForce {
            dof: 1,
            amplitude: 1.0,
            frequency: 1.0,
            phase: 0.0,
        }],
    }
}

fn sim_settings() -> SimSettings {
    SimSettings {
        step: 0.1,
        substeps: 1,
        transient_steps: 0,
        recorded_steps: 20,
    }
}

fn row_labels(count: usize) -> Vec<RowLabel> {
    (0..count)
        .map(|r| RowLabel {
            record: "hand".into(),
            record_index: 0,
            window: r,
            start_time: 0.0,
            cycles: 1,
        })
        .collect()
}

/// Asserts `result` is `InvalidParameter` named `name` with value `value` (NaN-aware).
#[track_caller]
fn assert_invalid<T: std::fmt::Debug>(result: Result<T>, name: &str, value: f64) -> Error {
    match result {
        Err(
            ref e @ Error::InvalidParameter {
                name: ref n,
                value: v,
                ref reason,
            },
        ) => {
            assert_eq!(n, name, "{e}");
            assert!(
                v == value || (v.is_nan() && value.is_nan()),
                "value {v}, expected {value}: {e}"
            );
            assert!(!reason.is_empty(), "{e}");
            e.clone()
        }
        other => panic!("expected InvalidParameter '{name}' = {value}, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------
// The fixtures themselves are valid and identify the right number
// ---------------------------------------------------------------------------------

#[test]
fn fixtures_are_valid() {
    let report = identify(&shared_model(), &[record()], &measured()).unwrap();
    let c = report.coefficient("c").unwrap();
    assert!((c - C_TRUE).abs() < 1e-6 * C_TRUE, "c = {c}");

    let sim = simulate(&system(), &sim_settings()).unwrap();
    assert_eq!(sim.samples(), 20);
    assert_eq!(sim.dofs(), 2);
}

// ---------------------------------------------------------------------------------
// Record: non-finite values
// ---------------------------------------------------------------------------------

#[test]
fn nan_in_displacements_is_non_finite_with_position() {
    let mut p = parts(N);
    p.displacements[(17, 1)] = f64::NAN;
    let err = Record::new(p).unwrap_err();
    match &err {
        Error::NonFinite {
            what,
            row,
            column,
            value,
        } => {
            assert_eq!(what, "displacements");
            assert_eq!((*row, *column), (17, 1));
            assert!(value.is_nan());
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
    let text = err.to_string();
    for needle in ["displacements", "NaN", "row 17", "column 1"] {
        assert!(text.contains(needle), "'{needle}' missing from: {text}");
    }
}

#[test]
fn inf_in_force_signals_is_non_finite_with_position() {
    let mut p = parts(N);
    let mut signals = forces(N);
    signals[(5, 1)] = f64::INFINITY;
    p.forcing = Forcing::generalized(signals);
    let err = Record::new(p).unwrap_err();
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
    let mut p = parts(N);
    let mut signals = forces(N);
    signals[(200, 0)] = f64::NEG_INFINITY;
    p.forcing = Forcing::generalized(signals);
    assert!(matches!(
        Record::new(p),
        Err(Error::NonFinite { ref what, row: 200, column: 0, value })
            if what == "force signals" && value == f64::NEG_INFINITY
    ));
}

#[test]
fn nan_in_measured_velocities_is_non_finite_with_position() {
    let mut p = parts(N);
    let mut v = velocities(N);
    v[(0, 0)] = f64::NAN;
    p.velocities = Some(v);
    let err = Record::new(p).unwrap_err();
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
    let mut p = parts(N);
    let mut d = Mat::<f64>::identity(2, 2);
    d[(1, 0)] = f64::NAN;
    p.forcing = Forcing::distributed(forces(N), d);
    assert!(matches!(
        Record::new(p),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "load distribution" && value.is_nan()
    ));
}

#[test]
fn nan_start_time_is_invalid_parameter() {
    let mut p = parts(N);
    p.start_time = f64::NAN;
    assert_invalid(Record::new(p), "start_time", f64::NAN);
}

// ---------------------------------------------------------------------------------
// Record: shapes and DOFs
// ---------------------------------------------------------------------------------

#[test]
fn velocities_with_wrong_row_count_are_dimension_mismatch() {
    let mut p = parts(N);
    p.velocities = Some(velocities(N - 1));
    let err = Record::new(p).unwrap_err();
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
    let mut p = parts(N);
    p.velocities = Some(Mat::zeros(N, 3));
    assert!(matches!(
        Record::new(p),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("columns of velocities")
    ));
}

#[test]
fn force_signals_with_wrong_row_count_are_dimension_mismatch() {
    let mut p = parts(N);
    p.forcing = Forcing::generalized(forces(N + 4));
    assert!(matches!(
        Record::new(p),
        Err(Error::DimensionMismatch { ref what, expected: N, found: 205 })
            if what.contains("force signals")
    ));
}

#[test]
fn force_channel_on_missing_dof_is_dof_out_of_range() {
    let mut p = parts(N);
    p.forcing = Forcing::on_dofs(forces(N), vec![0, 5]);
    let err = Record::new(p).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::DofOutOfRange { what, dof: 5, dofs: 2 } if what == "force channel 1"
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("force channel 1") && text.contains("DOF 5") && text.contains("2 DOFs"),
        "{text}"
    );
}

#[test]
fn force_dof_list_length_mismatch_is_dimension_mismatch() {
    let mut p = parts(N);
    p.forcing = Forcing::on_dofs(forces(N), vec![0]);
    assert!(matches!(
        Record::new(p),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("force DOF list")
    ));
}

#[test]
fn load_distribution_of_wrong_size_is_dimension_mismatch() {
    let mut p = parts(N);
    p.forcing = Forcing::distributed(forces(N), Mat::identity(3, 2));
    assert!(matches!(
        Record::new(p),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("rows of load distribution")
    ));

    let mut p = parts(N);
    p.forcing = Forcing {
        signals: forces(N),
        distribution: LoadDistribution::Matrix(Mat::zeros(2, 1)),
    };
    assert!(matches!(
        Record::new(p),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("columns of load distribution")
    ));
}

#[test]
fn record_without_dofs_is_empty() {
    let mut p = parts(N);
    p.displacements = Mat::zeros(N, 0);
    p.velocities = None;
    p.forcing = Forcing::generalized(Mat::zeros(N, 0));
    assert!(matches!(
        Record::new(p),
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
// Record: step and period
// ---------------------------------------------------------------------------------

#[test]
fn nonpositive_step_is_invalid_parameter() {
    for step in [0.0, -0.01] {
        let mut p = parts(N);
        p.step = step;
        let err = assert_invalid(Record::new(p), "step", step);
        assert!(err.to_string().contains("step"), "{err}");
    }
}

#[test]
fn nan_step_is_invalid_parameter() {
    let mut p = parts(N);
    p.step = f64::NAN;
    let err = assert_invalid(Record::new(p), "step", f64::NAN);
    let text = err.to_string();
    assert!(text.contains("step") && text.contains("NaN"), "{text}");
}

#[test]
fn infinite_step_is_invalid_parameter() {
    let mut p = parts(N);
    p.step = f64::INFINITY;
    assert_invalid(Record::new(p), "step", f64::INFINITY);
}

#[test]
fn nonpositive_or_nan_period_is_invalid_parameter() {
    for period in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut p = parts(N);
        p.period = period;
        let err = assert_invalid(Record::new(p), "period", period);
        assert!(err.to_string().contains("period"), "{err}");
    }
}

// ---------------------------------------------------------------------------------
// Windows
// ---------------------------------------------------------------------------------

#[test]
fn record_shorter_than_one_window_is_too_short() {
    let mut p = parts(80);
    p.label = "short".into();
    let short = Record::new(p).unwrap();
    let err = identify(&shared_model(), &[short], &measured()).unwrap_err();
    assert_eq!(
        err,
        Error::RecordTooShort {
            record: "short".into(),
            needed: WINDOW,
            available: 80
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("'short'") && text.contains("101") && text.contains("80"),
        "{text}"
    );
}

#[test]
fn too_many_requested_windows_is_too_short() {
    let mut settings = measured();
    settings.regressor.windows = WindowSpec::cycles(1).first(3).into();
    // Window 2 starts at sample 200 and reads 101 samples.
    assert!(matches!(
        identify(&shared_model(), &[record()], &settings),
        Err(Error::RecordTooShort { ref record, needed: 301, available: N }) if record == "fixture"
    ));
}

#[test]
fn skip_beyond_record_is_too_short() {
    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().skip = 500;
    assert!(matches!(
        identify(&shared_model(), &[record()], &settings),
        Err(Error::RecordTooShort {
            needed: 601,
            available: N,
            ..
        })
    ));
}

/// A period so long against the step that span/h overflows to ∞ (6.4e288 over
/// 6.9e-311): every rule and velocity source reports the record too short. (The
/// `identify` fuzz target found that the rectangular rule took such a window as 0
/// samples long, from φ = ∞ − ∞ = NaN, and the harmonic-projection row then overflowed
/// a sample count.)
#[test]
fn period_beyond_any_record_is_too_short() {
    let mut p = parts(N);
    p.step = 6.9e-311;
    p.period = 6.4e288;
    let record = Record::new(p).unwrap();
    for quadrature in [
        Quadrature::Rectangular,
        Quadrature::Trapezoid,
        Quadrature::Spectral,
    ] {
        for velocity in [
            VelocitySource::Measured,
            VelocitySource::HarmonicProjection { harmonics: None },
        ] {
            let mut settings = measured();
            settings.regressor.quadrature = quadrature;
            settings.regressor.velocity = velocity;
            let result = identify(&shared_model(), std::slice::from_ref(&record), &settings);
            assert!(
                matches!(
                    result,
                    Err(Error::RecordTooShort {
                        needed: usize::MAX,
                        available: N,
                        ..
                    })
                ),
                "{quadrature:?}, {velocity:?}: {result:?}"
            );
        }
    }
}

#[test]
fn invalid_window_spec_is_invalid_parameter() {
    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().cycles = 0;
    assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "cycles",
        0.0,
    );

    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().count = Some(0);
    assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "count",
        0.0,
    );
}

#[test]
fn rectangular_window_under_two_samples_is_invalid_parameter() {
    // A period of half a step: the rectangular rule would sum round(0.5) = 1 sample.
    let mut p = parts(N);
    p.period = 0.5 * H;
    let record = Record::new(p).unwrap();
    let mut settings = measured();
    settings.regressor.quadrature = Quadrature::Rectangular;
    assert_invalid(
        identify(&shared_model(), &[record], &settings),
        "window span",
        0.5 * H,
    );
}

// ---------------------------------------------------------------------------------
// Fit: too few equations
// ---------------------------------------------------------------------------------

#[test]
fn fewer_windows_than_coefficients_is_too_few_equations() {
    // One window, two coefficients.
    let err = identify(&per_dof_model(), &[record()], &measured()).unwrap_err();
    assert_eq!(
        err,
        Error::TooFewEquations {
            equations: 1,
            coefficients: 2
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("1 windows") && text.contains("2 free"),
        "{text}"
    );

    // The same through the fit module directly.
    let regressor = Regressor::build(&per_dof_model(), &[record()], &measured().regressor).unwrap();
    assert_eq!(regressor.equations(), 1);
    assert_eq!(
        fit::least_squares(&regressor, 1e-10),
        Err(Error::TooFewEquations {
            equations: 1,
            coefficients: 2
        })
    );
}

#[test]
fn constrained_fit_with_too_few_equations_is_too_few_equations() {
    let mut settings = measured();
    settings.fit.constraints = Constraints::nonnegative();
    assert_eq!(
        identify(&per_dof_model(), &[record()], &settings).unwrap_err(),
        Error::TooFewEquations {
            equations: 1,
            coefficients: 2
        }
    );

    // Fixed coefficients are not free: three coefficients, one fixed, one equation
    // still leaves two free.
    let model = per_dof_model().with(Term::per_dof(
        Quadratic,
        2,
        Coefficients::Shared("d".into()),
    ));
    settings.fit.constraints = Constraints {
        fixed: vec![Fixed {
            name: "d".into(),
            value: 0.0,
        }],
        ..Constraints::default()
    };
    assert_eq!(
        identify(&model, &[record()], &settings).unwrap_err(),
        Error::TooFewEquations {
            equations: 1,
            coefficients: 2
        }
    );
}

#[test]
fn regressor_without_rows_is_too_few_equations() {
    let regressor =
        Regressor::from_parts(Mat::zeros(0, 1), Vec::new(), vec!["c".into()], Vec::new()).unwrap();
    assert_eq!(
        fit::solve(&regressor, &FitSettings::default()),
        Err(Error::TooFewEquations {
            equations: 0,
            coefficients: 1
        })
    );
}

// ---------------------------------------------------------------------------------
// Model
// ---------------------------------------------------------------------------------

#[test]
fn element_on_missing_dof_is_dof_out_of_range() {
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        vec![Element::to_ground(0), Element::between(0, 3)],
        Coefficients::PerElement("dashpot".into()),
    ));
    let err = identify(&model, &[record()], &measured()).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::DofOutOfRange { what, dof: 3, dofs: 2 }
                if what.contains("linear") && what.contains("[1-4]")
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(text.contains("DOF 3") && text.contains("1-4"), "{text}");

    // The first DOF of an element is checked as well.
    let model = DampingModel::new().with(Term::on_elements(
        Quadratic,
        vec![Element::to_ground(7)],
        Coefficients::Shared("d".into()),
    ));
    assert!(matches!(
        model.validate(2),
        Err(Error::DofOutOfRange { ref what, dof: 7, dofs: 2 }) if what.contains("quadratic")
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
        identify(&model, &[record()], &measured()),
        Err(Error::Empty { ref what }) if what.contains("element list")
    ));
}

#[test]
fn matrix_term_of_wrong_size_is_dimension_mismatch() {
    let model = DampingModel::new().with(Term::viscous("c", Mat::identity(3, 3)));
    let err = identify(&model, &[record()], &measured()).unwrap_err();
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
        identify(&model, &[record()], &measured()),
        Err(Error::NonFinite { ref what, row: 0, column: 1, value })
            if what == "matrix of term 'm'" && value.is_nan()
    ));
}

#[test]
fn empty_model_is_empty() {
    let err = identify(&DampingModel::new(), &[record()], &measured()).unwrap_err();
    assert!(
        matches!(&err, Error::Empty { what } if what == "damping model"),
        "{err:?}"
    );
    assert!(err.to_string().contains("damping model"), "{err}");
}

#[test]
fn empty_record_list_is_empty() {
    let err = identify(&shared_model(), &[], &measured()).unwrap_err();
    assert!(
        matches!(&err, Error::Empty { what } if what == "record list"),
        "{err:?}"
    );
    assert!(
        matches!(
            Regressor::build(&shared_model(), &[], &RegressorSettings::default()),
            Err(Error::Empty { ref what }) if what == "record list"
        ),
        "Regressor::build"
    );
}

#[test]
fn two_terms_with_the_same_coefficient_name_are_duplicate() {
    let model = DampingModel::new()
        .with(Term::viscous("c", Mat::identity(2, 2)))
        .with(Term::per_dof(Linear, 2, Coefficients::Shared("c".into())));
    let err = identify(&model, &[record()], &measured()).unwrap_err();
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

// ---------------------------------------------------------------------------------
// Constraints
// ---------------------------------------------------------------------------------

/// Two windows (count: None) so that the per-DOF model passes the equation count.
fn two_windows(constraints: Constraints) -> IdentifySettings {
    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().count = None;
    settings.fit.constraints = constraints;
    settings
}

#[test]
fn bound_on_unknown_coefficient_lists_the_known_names() {
    let settings = two_windows(Constraints {
        bounds: vec![Bound {
            name: "zeta".into(),
            lower: Some(0.0),
            upper: None,
        }],
        ..Constraints::default()
    });
    let err = identify(&per_dof_model(), &[record()], &settings).unwrap_err();
    assert_eq!(
        err,
        Error::UnknownCoefficient {
            name: "zeta".into(),
            known: "c[1], c[2]".into()
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("'zeta'") && text.contains("c[1], c[2]"),
        "{text}"
    );
}

#[test]
fn fixed_unknown_coefficient_is_unknown() {
    let settings = two_windows(Constraints {
        fixed: vec![Fixed {
            name: "c".into(),
            value: 1.0,
        }],
        ..Constraints::default()
    });
    assert!(matches!(
        identify(&per_dof_model(), &[record()], &settings),
        Err(Error::UnknownCoefficient { ref name, ref known })
            if name == "c" && known == "c[1], c[2]"
    ));
}

#[test]
fn lower_bound_above_upper_bound_is_infeasible() {
    let settings = two_windows(Constraints {
        bounds: vec![Bound {
            name: "c[2]".into(),
            lower: Some(2.0),
            upper: Some(1.0),
        }],
        ..Constraints::default()
    });
    let err = identify(&per_dof_model(), &[record()], &settings).unwrap_err();
    assert_eq!(
        err,
        Error::InfeasibleBounds {
            name: "c[2]".into(),
            lower: 2.0,
            upper: 1.0
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("c[2]") && text.contains('2') && text.contains('1'),
        "{text}"
    );
}

#[test]
fn negative_upper_bound_with_nonnegativity_is_infeasible() {
    let settings = two_windows(Constraints {
        nonnegative: true,
        bounds: vec![Bound {
            name: "c[1]".into(),
            lower: None,
            upper: Some(-0.5),
        }],
        ..Constraints::default()
    });
    assert_eq!(
        identify(&per_dof_model(), &[record()], &settings).unwrap_err(),
        Error::InfeasibleBounds {
            name: "c[1]".into(),
            lower: 0.0,
            upper: -0.5
        }
    );
}

#[test]
fn fixed_value_outside_its_bounds_is_infeasible() {
    let settings = two_windows(Constraints {
        bounds: vec![Bound {
            name: "c[1]".into(),
            lower: Some(0.0),
            upper: Some(1.0),
        }],
        fixed: vec![Fixed {
            name: "c[1]".into(),
            value: 2.0,
        }],
        ..Constraints::default()
    });
    assert!(matches!(
        identify(&per_dof_model(), &[record()], &settings),
        Err(Error::InfeasibleBounds { ref name, lower, upper })
            if name == "c[1]" && lower == 2.0 && upper == 1.0
    ));

    // A negative fixed value under nonnegativity.
    let settings = two_windows(Constraints {
        nonnegative: true,
        fixed: vec![Fixed {
            name: "c[2]".into(),
            value: -0.1,
        }],
        ..Constraints::default()
    });
    assert!(matches!(
        identify(&per_dof_model(), &[record()], &settings),
        Err(Error::InfeasibleBounds { ref name, lower, upper })
            if name == "c[2]" && lower == 0.0 && upper == -0.1
    ));
}

#[test]
fn nan_bound_or_fixed_value_is_invalid_parameter() {
    let settings = two_windows(Constraints {
        bounds: vec![Bound {
            name: "c[1]".into(),
            lower: None,
            upper: Some(f64::NAN),
        }],
        ..Constraints::default()
    });
    assert_invalid(
        identify(&per_dof_model(), &[record()], &settings),
        "upper bound of 'c[1]'",
        f64::NAN,
    );

    let settings = two_windows(Constraints {
        fixed: vec![Fixed {
            name: "c[2]".into(),
            value: f64::INFINITY,
        }],
        ..Constraints::default()
    });
    assert_invalid(
        identify(&per_dof_model(), &[record()], &settings),
        "fixed value of 'c[2]'",
        f64::INFINITY,
    );
}

// ---------------------------------------------------------------------------------
// Velocities
// ---------------------------------------------------------------------------------

#[test]
fn measured_velocities_on_record_without_them_are_missing() {
    let mut p = parts(N);
    p.label = "no-v".into();
    p.velocities = None;
    let record = Record::new(p).unwrap();
    let err = identify(&shared_model(), &[record], &measured()).unwrap_err();
    assert_eq!(
        err,
        Error::MissingVelocities {
            record: "no-v".into()
        }
    );
    assert!(err.to_string().contains("'no-v'"), "{err}");
}

#[test]
fn spectral_velocities_with_too_many_harmonics_are_invalid_parameter() {
    // A one-period trapezoid window reads 101 samples: at most 50 harmonics fit.
    let mut settings = measured();
    settings.regressor.velocity = VelocitySource::Spectral {
        harmonics: Some(80),
    };
    let err = assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "harmonics",
        80.0,
    );
    assert!(err.to_string().contains("80"), "{err}");

    // 50 harmonics fit the samples but reach the Nyquist frequency (T/2h = 50).
    settings.regressor.velocity = VelocitySource::Spectral {
        harmonics: Some(50),
    };
    let err = assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "harmonics",
        50.0,
    );
    assert!(err.to_string().contains("Nyquist"), "{err}");

    settings.regressor.velocity = VelocitySource::Spectral { harmonics: Some(0) };
    assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "harmonics",
        0.0,
    );
}

// ---------------------------------------------------------------------------------
// Laws
// ---------------------------------------------------------------------------------

#[test]
fn negative_or_nan_power_law_exponent_is_invalid_parameter() {
    let err = assert_invalid(PowerLaw::new(-1.0), "exponent", -1.0);
    let text = err.to_string();
    assert!(text.contains("exponent") && text.contains("-1"), "{text}");
    assert_invalid(PowerLaw::new(f64::NAN), "exponent", f64::NAN);
    assert_invalid(PowerLaw::new(f64::INFINITY), "exponent", f64::INFINITY);
    assert!(PowerLaw::new(0.0).is_ok());
}

#[test]
fn custom_law_returning_nan_names_the_regressor_column() {
    let model = shared_model().with(Term::per_dof(
        Custom::new("broken", |_x, _v| f64::NAN),
        2,
        Coefficients::Shared("bad".into()),
    ));
    let err = Regressor::build(&model, &[record()], &measured().regressor).unwrap_err();
    match &err {
        Error::NonFinite {
            what,
            row,
            column,
            value,
        } => {
            assert_eq!(what, "regressor column 'bad'");
            assert_eq!((*row, *column), (0, 1));
            assert!(value.is_nan());
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
    assert!(err.to_string().contains("'bad'"), "{err}");
    // The same through identify: no report with NaN coefficients.
    assert!(matches!(
        identify(&model, &[record()], &measured()),
        Err(Error::NonFinite { ref what, .. }) if what == "regressor column 'bad'"
    ));
}

#[test]
fn overflowing_regressor_column_is_non_finite_not_a_number() {
    // Finite but huge displacements: ∫ v² overflows to inf.
    let mut p = parts(N);
    p.displacements = Mat::from_fn(N, 2, |i, j| 1e200 * displacements(N)[(i, j)]);
    p.velocities = Some(Mat::from_fn(N, 2, |i, j| 1e200 * velocities(N)[(i, j)]));
    let record = Record::new(p).unwrap();
    assert!(matches!(
        identify(&shared_model(), &[record], &measured()),
        Err(Error::NonFinite { ref what, row: 0, column: 0, value })
            if what == "regressor column 'c'" && value == f64::INFINITY
    ));
}

// ---------------------------------------------------------------------------------
// Regressor from parts
// ---------------------------------------------------------------------------------

#[test]
fn regressor_parts_are_checked() {
    let names = || vec!["a".to_string(), "b".to_string()];
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(3, 2), vec![0.0; 2], names(), row_labels(2)),
        Err(Error::DimensionMismatch { ref what, expected: 3, found: 2 })
            if what.contains("right-hand side")
    ));
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(2, 3), vec![0.0; 2], names(), row_labels(2)),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("coefficient names")
    ));
    assert!(matches!(
        Regressor::from_parts(Mat::zeros(2, 2), vec![0.0; 2], names(), row_labels(1)),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("row labels")
    ));
    assert!(matches!(
        Regressor::from_parts(
            Mat::identity(2, 2),
            vec![1.0, f64::NAN],
            names(),
            row_labels(2)
        ),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "input work b" && value.is_nan()
    ));
    let mut a = Mat::<f64>::identity(2, 2);
    a[(1, 1)] = f64::NEG_INFINITY;
    assert!(matches!(
        Regressor::from_parts(a, vec![1.0, 1.0], names(), row_labels(2)),
        Err(Error::NonFinite { ref what, row: 1, column: 1, value })
            if what == "regressor column 'b'" && value == f64::NEG_INFINITY
    ));
}

// ---------------------------------------------------------------------------------
// Fit settings
// ---------------------------------------------------------------------------------

#[test]
fn invalid_rank_tolerance_is_invalid_parameter() {
    for tolerance in [0.0, 1.0, -1e-3, f64::NAN] {
        let mut settings = measured();
        settings.fit.rank_tolerance = tolerance;
        let err = assert_invalid(
            identify(&shared_model(), &[record()], &settings),
            "rank_tolerance",
            tolerance,
        );
        assert!(err.to_string().contains("rank_tolerance"), "{err}");
    }
}

#[test]
fn invalid_solver_tolerance_is_invalid_parameter() {
    for tolerance in [0.0, -1.0, 0.5, f64::NAN] {
        let mut settings = measured();
        settings.fit.solver.tolerance = tolerance;
        assert_invalid(
            identify(&shared_model(), &[record()], &settings),
            "solver tolerance",
            tolerance,
        );
    }
    // Also when the constrained solver is called directly.
    let regressor = Regressor::build(&shared_model(), &[record()], &measured().regressor).unwrap();
    let solver = SolverSettings {
        tolerance: 0.0,
        ..SolverSettings::default()
    };
    assert_invalid(
        fit::constrained(&regressor, &Constraints::nonnegative(), &solver),
        "solver tolerance",
        0.0,
    );
}

#[test]
fn zero_max_iterations_is_invalid_parameter() {
    let mut settings = measured();
    settings.fit.solver.max_iterations = 0;
    assert_invalid(
        identify(&shared_model(), &[record()], &settings),
        "max_iterations",
        0.0,
    );
}

// ---------------------------------------------------------------------------------
// Simulator
// ---------------------------------------------------------------------------------

#[test]
fn singular_mass_matrix_is_numerical() {
    for mass in [Mat::<f64>::zeros(2, 2), Mat::from_fn(2, 2, |_, _| 1.0)] {
        let mut sys = system();
        sys.mass = mass;
        let err = simulate(&sys, &sim_settings()).unwrap_err();
        assert!(
            matches!(
                &err,
                Error::Numerical { stage, detail }
                    if stage == "simulation" && detail.contains("singular")
            ),
            "{err:?}"
        );
        assert!(err.to_string().contains("singular"), "{err}");
    }
}

#[test]
fn diverging_simulation_is_numerical_not_nan() {
    // Stiff K = 1e6 I with a step h = 1: h √k = 1000, far beyond RK4's stability limit.
    let mut sys = system();
    sys.stiffness = Mat::from_fn(2, 2, |i, j| if i == j { 1e6 } else { 0.0 });
    let settings = SimSettings {
        step: 1.0,
        substeps: 1,
        transient_steps: 0,
        recorded_steps: 200,
    };
    let err = simulate(&sys, &settings).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::Numerical { stage, detail }
                if stage == "simulation" && detail.contains("diverged")
        ),
        "{err:?}"
    );
}

#[test]
fn custom_law_returning_nan_in_simulation_is_numerical() {
    let mut sys = system();
    sys.damping = DampingModel::new().with(Term::per_dof(
        Custom::new("broken", |_x, _v| f64::NAN),
        2,
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::Numerical { ref stage, .. }) if stage == "simulation"
    ));

    let mut sys = system();
    sys.conservative = vec![ConservativeForce::Custom(Arc::new(|_x, out| {
        out[0] += f64::NAN
    }))];
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::Numerical { ref stage, .. }) if stage == "simulation"
    ));
}

#[test]
fn invalid_sim_settings_are_invalid_parameter() {
    let mut settings = sim_settings();
    settings.substeps = 0;
    let err = assert_invalid(simulate(&system(), &settings), "substeps", 0.0);
    assert!(err.to_string().contains("substeps"), "{err}");

    for step in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let mut settings = sim_settings();
        settings.step = step;
        assert_invalid(simulate(&system(), &settings), "step", step);
    }

    let mut settings = sim_settings();
    settings.recorded_steps = 2;
    assert_invalid(simulate(&system(), &settings), "recorded_steps", 2.0);
}

#[test]
fn cubic_spring_on_missing_dof_is_dof_out_of_range() {
    let mut sys = system();
    sys.conservative = vec![ConservativeForce::Cubic {
        dof: 2,
        coefficient: 1.0,
    }];
    let err = simulate(&sys, &sim_settings()).unwrap_err();
    assert_eq!(
        err,
        Error::DofOutOfRange {
            what: "cubic spring".into(),
            dof: 2,
            dofs: 2
        }
    );
    assert!(err.to_string().contains("cubic spring"), "{err}");

    let mut sys = system();
    sys.conservative = vec![ConservativeForce::Cubic {
        dof: 0,
        coefficient: f64::NAN,
    }];
    assert_invalid(
        simulate(&sys, &sim_settings()),
        "cubic spring coefficient",
        f64::NAN,
    );
}

#[test]
fn harmonic_force_on_missing_dof_is_dof_out_of_range() {
    let mut sys = system();
    sys.forcing[0].dof = 9;
    assert_eq!(
        simulate(&sys, &sim_settings()).unwrap_err(),
        Error::DofOutOfRange {
            what: "harmonic force".into(),
            dof: 9,
            dofs: 2
        }
    );
}

#[test]
fn harmonic_forces_at_two_frequencies_are_invalid_parameter() {
    let mut sys = system();
    sys.forcing.push(HarmonicForce {
        dof: 0,
        amplitude: 0.5,
        frequency: 1.5,
        phase: 0.0,
    });
    let err = assert_invalid(simulate(&sys, &sim_settings()), "forcing frequency", 1.5);
    assert!(err.to_string().contains("1.5"), "{err}");
}

#[test]
fn invalid_harmonic_force_is_invalid_parameter() {
    for frequency in [0.0, -1.0, f64::NAN] {
        let mut sys = system();
        sys.forcing[0].frequency = frequency;
        assert_invalid(
            simulate(&sys, &sim_settings()),
            "forcing frequency",
            frequency,
        );
    }
    let mut sys = system();
    sys.forcing[0].amplitude = f64::INFINITY;
    assert_invalid(
        simulate(&sys, &sim_settings()),
        "forcing amplitude",
        f64::INFINITY,
    );
}

#[test]
fn system_without_forcing_or_dofs_is_empty() {
    let mut sys = system();
    sys.forcing.clear();
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::Empty { ref what }) if what == "forcing"
    ));

    let mut sys = system();
    sys.mass = Mat::zeros(0, 0);
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::Empty { ref what }) if what == "mass matrix"
    ));
}

#[test]
fn system_matrices_and_coefficients_are_checked() {
    let mut sys = system();
    sys.stiffness = Mat::identity(3, 3);
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("stiffness")
    ));

    let mut sys = system();
    sys.mass[(1, 0)] = f64::NAN;
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "mass" && value.is_nan()
    ));

    let mut sys = system();
    sys.damping_coefficients = vec![0.1, 0.2];
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::DimensionMismatch { ref what, expected: 1, found: 2 })
            if what.contains("damping coefficients")
    ));

    let mut sys = system();
    sys.damping_coefficients = vec![f64::NAN];
    assert_invalid(
        simulate(&sys, &sim_settings()),
        "damping coefficient 0",
        f64::NAN,
    );

    let mut sys = system();
    sys.damping = DampingModel::new().with(Term::on_elements(
        Linear,
        vec![Element::between(0, 2)],
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        simulate(&sys, &sim_settings()),
        Err(Error::DofOutOfRange {
            dof: 2,
            dofs: 2,
            ..
        })
    ));
}

/// A force that does not change has no period; a zero force neither.
#[test]
fn constant_force_has_no_period() {
    for level in [0.0, 2.5] {
        let force = Mat::from_fn(N, 1, |_, _| level);
        match dampid::prep::period::detect_period(force.as_ref(), H, "still") {
            Err(Error::NoPeriod {
                record, explained, ..
            }) => {
                assert_eq!(record, "still");
                assert_eq!(explained, 0.0);
            }
            other => panic!("{other:?}"),
        }
    }
}

/// The fixture record with its amplitude growing by half over its two periods: the
/// state at the end of the first window differs from its start by about a quarter of
/// the amplitude, and the steady-state check names record, window and mismatch.
fn growing_record_is_not_steady() -> Error {
    let mut p = parts(N);
    let grow = |i: usize| 1.0 + 0.5 * i as f64 / N as f64;
    let x = p.displacements.clone();
    let v = p.velocities.clone().unwrap();
    p.displacements = Mat::from_fn(N, 2, |i, j| grow(i) * x[(i, j)]);
    p.velocities = Some(Mat::from_fn(N, 2, |i, j| grow(i) * v[(i, j)]));
    p.label = "growing".into();
    let record = Record::new(p).unwrap();
    let settings = measured().regressor;
    let report = dampid::prep::steady_state::check(
        &[record],
        settings.windows.cycles().unwrap(),
        settings.quadrature,
        None,
        &dampid::prep::steady_state::SteadyStateSettings::default(),
    )
    .unwrap();
    report.enforce().unwrap_err()
}

#[test]
fn growing_motion_is_not_steady_with_its_mismatch() {
    match growing_record_is_not_steady() {
        Error::NotSteady {
            record,
            window,
            mismatch,
            threshold,
            ..
        } => {
            assert_eq!((record.as_str(), window), ("growing", 0));
            assert!(mismatch > 0.2 && mismatch < 0.3, "{mismatch}");
            assert_eq!(threshold, 0.02);
        }
        other => panic!("{other:?}"),
    }
}

// ---------------------------------------------------------------------------------
// Coverage of the variants
// ---------------------------------------------------------------------------------

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
    let mut nan_x = parts(N);
    nan_x.displacements[(0, 0)] = f64::NAN;
    let mut bad_step = parts(N);
    bad_step.step = 0.0;
    let mut no_v = parts(N);
    no_v.velocities = None;
    let mut short_velocities = parts(N);
    short_velocities.velocities = Some(velocities(3));
    let mut bad_dof = parts(N);
    bad_dof.forcing = Forcing::on_dofs(forces(N), vec![0, 2]);
    let mut singular = system();
    singular.mass = Mat::zeros(2, 2);
    let unknown = two_windows(Constraints {
        fixed: vec![Fixed {
            name: "nope".into(),
            value: 0.0,
        }],
        ..Constraints::default()
    });
    let infeasible = two_windows(Constraints {
        bounds: vec![Bound {
            name: "c[1]".into(),
            lower: Some(1.0),
            upper: Some(0.0),
        }],
        ..Constraints::default()
    });
    let duplicate = shared_model().with(Term::viscous("c", Mat::identity(2, 2)));

    let errors = [
        Record::new(nan_x).unwrap_err(),
        Record::new(short_velocities).unwrap_err(),
        Record::new(bad_step).unwrap_err(),
        Record::new(parts(2)).unwrap_err(),
        identify(&per_dof_model(), &[record()], &measured()).unwrap_err(),
        Record::new(bad_dof).unwrap_err(),
        identify(&DampingModel::new(), &[record()], &measured()).unwrap_err(),
        identify(&duplicate, &[record()], &measured()).unwrap_err(),
        identify(&per_dof_model(), &[record()], &unknown).unwrap_err(),
        identify(&per_dof_model(), &[record()], &infeasible).unwrap_err(),
        identify(&shared_model(), &[Record::new(no_v).unwrap()], &measured()).unwrap_err(),
        simulate(&singular, &sim_settings()).unwrap_err(),
        dampid::terms::laws::Expression::parse("abs(v)*q").unwrap_err(),
        dampid::model_file::parse("dofs = ", "bad.toml", std::path::Path::new(".")).unwrap_err(),
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

// ---------------------------------------------------------------------------------
// Regressions: inputs that once panicked or gave a wrong number, each with the typed
// error (or right number) the library gives now.
// ---------------------------------------------------------------------------------

#[test]
fn huge_period_is_too_short_not_a_panic() {
    // A window of T = 1e20 needs 1e22 samples: more than usize holds. The window
    // length saturates to usize::MAX in Quadrature::length and `whole + 1` overflows.
    let mut p = parts(N);
    p.period = 1e20;
    let record = Record::new(p).unwrap();
    assert!(matches!(
        identify(&shared_model(), &[record], &measured()),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_skip_is_too_short_not_a_panic() {
    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().skip = usize::MAX;
    assert!(matches!(
        identify(&shared_model(), &[record()], &settings),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_window_count_is_too_short_not_a_panic() {
    let mut settings = measured();
    settings.regressor.windows.cycles_mut().unwrap().count = Some(usize::MAX);
    assert!(matches!(
        identify(&shared_model(), &[record()], &settings),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_transient_is_invalid_not_a_panic() {
    let mut settings = sim_settings();
    settings.transient_steps = usize::MAX;
    assert!(matches!(
        simulate(&system(), &settings),
        Err(Error::InvalidParameter { ref name, .. }) if name.contains("steps")
    ));
}

#[test]
fn singular_mass_with_roundoff_pivot_is_numerical() {
    // M = [[1,2,3],[4,5,6],[7,8,9]] has rank 2; partial-pivot LU leaves a last pivot
    // of order 1e-16, so M⁻¹ is finite (entries ~1e16) and the check that looks for
    // non-finite entries of M⁻¹ misses it. With 3 recorded steps the state has not
    // overflowed yet, so no divergence error either.
    let mut sys = system();
    sys.mass = Mat::from_fn(3, 3, |i, j| (3 * i + j + 1) as f64);
    sys.stiffness = Mat::identity(3, 3);
    sys.damping =
        DampingModel::new().with(Term::per_dof(Linear, 3, Coefficients::Shared("c".into())));
    let mut settings = sim_settings();
    settings.recorded_steps = 3;
    let result = simulate(&sys, &settings);
    assert!(
        matches!(
            &result,
            Err(Error::Numerical { stage, detail })
                if stage == "simulation" && detail.contains("singular")
        ),
        "{:?}",
        result.map(|r| r.displacements().norm_max())
    );
}

#[test]
fn large_but_finite_records_give_the_right_number() {
    // The fixture scaled by 1e80 in displacement, velocity and force: every value is
    // finite and the regressor entries (~1e160) are finite, but Σ b_r² = inf. The
    // energy balance is scale-free, so c is still 0.3.
    let mut p = parts(N);
    p.displacements = Mat::from_fn(N, 2, |i, j| 1e80 * displacements(N)[(i, j)]);
    p.velocities = Some(Mat::from_fn(N, 2, |i, j| 1e80 * velocities(N)[(i, j)]));
    p.forcing = Forcing::generalized(Mat::from_fn(N, 2, |i, j| 1e80 * forces(N)[(i, j)]));
    let record = Record::new(p).unwrap();
    match identify(&shared_model(), &[record], &measured()) {
        Ok(report) => {
            let c = report.coefficient("c").unwrap();
            assert!((c - C_TRUE).abs() < 1e-6, "c = {c}");
        }
        Err(e) => assert!(matches!(e, Error::Numerical { .. }), "{e:?}"),
    }

    // The same through a hand-built regressor: A = b = 1e160 · [1, 1] gives θ = 1.
    let regressor = Regressor::from_parts(
        Mat::from_fn(2, 1, |_, _| 1e160),
        vec![1e160, 1e160],
        vec!["c".into()],
        row_labels(2),
    )
    .unwrap();
    match fit::solve(&regressor, &FitSettings::default()) {
        Ok(fit) => assert!(
            (fit.coefficients[0] - 1.0).abs() < 1e-12,
            "θ = {:?}",
            fit.coefficients
        ),
        Err(e) => assert!(matches!(e, Error::Numerical { .. }), "{e:?}"),
    }
}

/// Entries near f64::MAX are finite, but a column's or the right-hand side's norm can
/// overflow. The fit's scaling then falls back to the largest entry, so that a
/// bound 0 (nonnegativity) or ±∞ (none) stays 0 or ±∞ instead of 0 · ∞ = NaN (the
/// `identify` fuzz target found the panic this caused in the constrained fit). The
/// system is consistent, and plain and nonnegative fits give θ = 1.
#[test]
fn regressor_whose_column_norm_overflows_fits_or_fails_cleanly() {
    let huge = 1.5e308;
    for (column, rhs) in [
        (vec![huge, huge, huge], vec![huge, huge, huge]),
        (vec![huge, huge, 1.0], vec![huge, huge, 1.0]),
        (vec![1.0, 2.0, 3.0], vec![1.0, 2.0, 3.0]),
    ] {
        let regressor = Regressor::from_parts(
            Mat::from_fn(3, 1, |i, _| column[i]),
            rhs,
            vec!["c".into()],
            row_labels(3),
        )
        .unwrap();
        for constraints in [Constraints::default(), Constraints::nonnegative()] {
            let settings = FitSettings {
                constraints,
                ..FitSettings::default()
            };
            let fit = fit::solve(&regressor, &settings).unwrap();
            let theta = fit.coefficients[0];
            assert!(
                fit.status.is_usable() && (theta - 1.0).abs() < 1e-9,
                "{column:?}: θ = {theta}, {:?}",
                fit.status
            );
        }
    }
}

#[test]
fn infinite_bounds_that_admit_no_value_are_rejected() {
    // [inf, inf] passes `lower > upper` and would count as fixed (lower == upper);
    // [−inf, −inf] likewise from above.
    for (lower, upper) in [(Some(f64::INFINITY), None), (None, Some(f64::NEG_INFINITY))] {
        let settings = two_windows(Constraints {
            bounds: vec![Bound {
                name: "c[1]".into(),
                lower,
                upper,
            }],
            ..Constraints::default()
        });
        let result = identify(&per_dof_model(), &[record()], &settings);
        assert!(
            matches!(
                &result,
                Err(Error::InfeasibleBounds { name, .. } | Error::InvalidParameter { name, .. })
                    if name.contains("c[1]")
            ),
            "bounds {lower:?}..{upper:?}: {result:?}"
        );
    }
}

#[test]
fn nan_phase_is_reported_with_its_value() {
    let mut sys = system();
    sys.forcing[0].phase = f64::NAN;
    assert_invalid(simulate(&sys, &sim_settings()), "forcing phase", f64::NAN);
}

// ---------------------------------------------------------------------------------
// Expressions, model files and data files (more cases in tests/model_file.rs)
// ---------------------------------------------------------------------------------

#[test]
fn expression_with_unknown_identifier_names_it() {
    match dampid::terms::laws::Expression::parse("x^2*vel") {
        Err(Error::Expression {
            expression,
            message,
        }) => {
            assert_eq!(expression, "x^2*vel");
            assert!(message.contains("'vel'"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn malformed_model_file_names_file_line_and_column() {
    match dampid::model_file::parse("dofs = 2\nterms = 3\n", "m.toml", std::path::Path::new(".")) {
        Err(Error::ModelFile {
            file,
            line,
            column,
            message,
        }) => {
            assert_eq!((file.as_str(), line), ("m.toml", 2));
            assert!(column >= 1);
            assert!(!message.is_empty());
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn missing_column_lists_the_columns() {
    let table = dampid::io::csv::parse("t,x1\n0,1\n", "d.csv").unwrap();
    match table.column("x2") {
        Err(Error::UnknownName { what, name, known }) => {
            assert!(what.contains("d.csv"));
            assert_eq!((name.as_str(), known.as_str()), ("x2", "t, x1"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_data_cell_names_row_and_column() {
    match dampid::io::csv::parse("t,x1\n0,1\n0.1,inf\n", "d.csv") {
        Err(Error::Data {
            file, row, column, ..
        }) => assert_eq!((file.as_str(), row, column.as_str()), ("d.csv", 2, "x1")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn element_weights_that_do_not_match_the_elements_are_checked() {
    // Two elements, one weight: accumulating the second element's column once indexed
    // past the end of the weights and panicked.
    let model = DampingModel::new().with(Term::weighted(
        Linear,
        Element::each_dof(2),
        vec![0.5],
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        identify(&model, &[record()], &measured()),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("element weights")
    ));
    // The same through a model file.
    let text = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\nweights = [1.0, 2.0, 3.0]\n[simulation]\nmass = \"identity\"\nstiffness = \"chain\"\ncoefficients = { c = 0.1 }\nstep = 0.1\ntransient_steps = 0\nrecorded_steps = 10\nexperiments = [{ force_dof = 1, amplitude = 1.0, frequency = 1.0 }]\n";
    match dampid::model_file::parse(text, "w.toml", std::path::Path::new(".")) {
        Err(Error::ModelFile { line, message, .. }) => {
            assert_eq!(line, 2, "{message}");
            assert!(message.contains("element weights"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // A non-finite weight names its position.
    let model = DampingModel::new().with(Term::weighted(
        Linear,
        Element::each_dof(2),
        vec![0.5, f64::NAN],
        Coefficients::Shared("c".into()),
    ));
    assert!(matches!(
        identify(&model, &[record()], &measured()),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what.contains("element weights") && value.is_nan()
    ));
}

#[test]
fn window_shorter_than_one_step_is_invalid_not_an_endless_loop() {
    // Found by the `identify` fuzz target: with a period of a tiny fraction of a step
    // and as many windows as fit (`count: None`), round(j·T/h) stayed 0, every window
    // "fit" at sample 0, and cutting windows ran until memory ran out.
    for quadrature in [
        Quadrature::Rectangular,
        Quadrature::Trapezoid,
        Quadrature::Spectral,
    ] {
        let mut p = parts(N);
        p.period = 1e-30;
        let record = Record::new(p).unwrap();
        let mut settings = measured();
        settings.regressor.quadrature = quadrature;
        settings.regressor.windows.cycles_mut().unwrap().count = None;
        assert_invalid(
            identify(&shared_model(), &[record], &settings),
            "window span",
            1e-30,
        );
    }
}

#[test]
fn mat_file_whose_dimensions_overflow_is_a_data_error() {
    // Found by the `mat` fuzz target: a numeric matrix of 65536 × 65536 makes the MAT
    // parser (matfile 0.5) multiply its dimensions as i32, a panic under overflow checks.
    let mut bytes = vec![b' '; 116];
    bytes.extend_from_slice(&[0; 8]); // subsystem data offset
    bytes.extend_from_slice(&[0x00, 0x01]); // version
    bytes.extend_from_slice(b"IM"); // little endian
    let tag = |kind: u32, size: u32| [kind.to_le_bytes(), size.to_le_bytes()].concat();
    bytes.extend(tag(14, 56)); // miMATRIX of 56 bytes:
    bytes.extend(tag(6, 8)); // array flags (miUINT32): class 6 = double, nzmax 0
    bytes.extend_from_slice(&[6, 0, 0, 0, 0, 0, 0, 0]);
    bytes.extend(tag(5, 8)); // dimensions (miINT32): 65536 × 65536
    bytes.extend_from_slice(&[65536i32.to_le_bytes(), 65536i32.to_le_bytes()].concat());
    bytes.extend(tag(1, 1)); // name (miINT8) "x", padded to 8
    bytes.extend_from_slice(b"x\0\0\0\0\0\0\0");
    bytes.extend(tag(9, 0)); // real part (miDOUBLE), empty
    let path = std::env::temp_dir().join(format!("dampid-dims-{}.mat", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    let result = dampid::io::mat::read_mat(&path);
    std::fs::remove_file(&path).unwrap();
    assert!(
        matches!(&result, Err(Error::Data { file, row: 0, .. }) if file.ends_with(".mat")),
        "{result:?}"
    );
}

#[test]
fn mat_file_whose_element_size_overflows_is_a_data_error() {
    // Found by the `mat` fuzz target: a data element claiming 0xFFFFFFFF bytes made the
    // MAT parser (matfile 0.5) overflow while rounding the size up to its padding, a
    // panic under overflow checks. A 128-byte level-5 header, then that one tag.
    let mut bytes = vec![b' '; 116];
    bytes.extend_from_slice(&[0; 8]); // subsystem data offset
    bytes.extend_from_slice(&[0x00, 0x01]); // version
    bytes.extend_from_slice(b"IM"); // little endian
    bytes.extend_from_slice(&[0x0f, 0, 0, 0, 0xff, 0xff, 0xff, 0xff]); // miCOMPRESSED
    let path = std::env::temp_dir().join(format!("dampid-overflow-{}.mat", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    let result = dampid::io::mat::read_mat(&path);
    std::fs::remove_file(&path).unwrap();
    assert!(
        matches!(&result, Err(Error::Data { file, row: 0, message, .. })
            if file.ends_with(".mat") && message.contains("MAT")),
        "{result:?}"
    );
}
