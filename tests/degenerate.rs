//! Degenerate data gets a typed error or a clearly flagged report: never a panic, a NaN
//! or a silent number. One test per class of degenerate data. Classes already covered
//! elsewhere are listed here and not repeated:
//!
//! | class | where | what the library gives |
//! |---|---|---|
//! | a DOF that never moves | here: `dof_that_never_moves_*`; tests/physics.rs, tests/errors/ (`physics`) | `Error::DeadMotionSensor` naming the record and the DOF (a dead sensor); declared held still (`Record::with_fixed_dofs`, `fixed_dofs` in a model file): `Warning::RankDeficient`, no standard errors, the moving DOF's coefficient still right |
//! | a constant signal | here: `constant_signal_*` | `Error::NoInputWork`: the DOFs the force acts on do not move |
//! | a dead force sensor (a zero force column, `forces = []`) | here: `dead_force_sensor_*`; tests/nonperiodic.rs: `dead_force_sensor_*`; tests/cli.rs: `dead_force_sensor_*` | `Error::NoInputWork` naming the record and the channels |
//! | a force that does no net work | here: `force_in_phase_*` | `Error::NoInputWork` for the window |
//! | data so small or large that their products leave double precision (work or damping work that underflows) | here: `underflowing_input_work_*`, `underflowing_damping_work_*`; tests/invariants.rs, tests/errors/physics.rs | `Error::DataScale` naming the record, the signal and the factor |
//! | an all-zero regressor (a zero matrix or weight for every term) | here: `zero_regressor_*`; tests/cli.rs | `Error::NoInformation` naming the coefficients |
//! | an all-zero regressor column | here: `all_zero_regressor_column_*`, `zero_element_weight_*` | `Warning::RankDeficient`, the coefficient "not determined"; the other coefficients still right |
//! | duplicated experiments | here: `duplicated_experiments_*` | `Warning::RankDeficient` (and `NoRedundancy`): copies add no information |
//! | NaN or Inf anywhere | tests/errors/: `record::nan_in_displacements_*`, `record::inf_in_force_signals_*`, `record::negative_inf_in_force_signals_*`, `record::nan_in_measured_velocities_*`, `record::nan_in_load_distribution_*`, `record::nan_start_time_*`, `record::nan_step_*`, `record::infinite_step_*`, `record::nonpositive_or_non_finite_period_*`, `model::nan_in_damping_matrix_*`, `regressor::custom_law_returning_nan_*`, `regressor::overflowing_regressor_column_*`, `regressor::regressor_parts_are_checked`, `fit::nan_bound_or_fixed_value_*`, `data_files::bad_data_cell_names_row_and_column` | `Error::NonFinite`, `Error::InvalidParameter` or `Error::Data` with the position |
//! | a record shorter than one period | tests/errors/: `prep::record_shorter_than_one_window_is_too_short`, `record::record_of_two_samples_is_too_short` | `Error::RecordTooShort` |
//! | more coefficients than equations | tests/errors/: `fit::fewer_windows_than_coefficients_is_too_few_equations`, `fit::constrained_fit_with_too_few_equations_*`, `fit::regressor_without_rows_*` | `Error::TooFewEquations` |
//! | a rank-deficient regressor | tests/fit.rs: `rank_deficient_regressor_is_flagged` (and every test here) | `Warning::RankDeficient`, `condition_number: None` |
//! | a solver that does not converge | tests/fit.rs: `unconverged_solver_is_reported_not_hidden` | `FitStatus::MaxIterations`, `Warning::NotConverged` |
//! | a force on a DOF that does not exist | tests/errors/: `record::force_channel_on_missing_dof_*`, `simulate::harmonic_force_on_missing_dof_*`; here: `force_on_missing_dof_in_a_model_file_*` (the model-file route) | `Error::DofOutOfRange`, inside `Error::ModelFile` for model files |
//!
//! Fixtures: pure harmonic motion on 2 DOFs with exact velocities (tests/support), one
//! equation per record, least squares unless a test says otherwise.

mod support;

use std::path::Path;

use dampid::prelude::*;
use dampid::report::Warning;
use faer::Mat;
use support::Harmonic;

/// Records of 2-DOF harmonic motion whose generalized forces balance linear damping
/// c = (0.3, 0.2) per DOF and a shared quadratic d = 0.1 exactly: r_j = c_j v_j + d v_j|v_j|.
fn balanced(amplitudes: [f64; 2], omega: f64) -> Record {
    balanced_with([0.3, 0.2], amplitudes, omega)
}

/// [`balanced`] with linear damping `c` per DOF.
fn balanced_with(c: [f64; 2], amplitudes: [f64; 2], omega: f64) -> Record {
    let h = Harmonic {
        amplitudes: amplitudes.to_vec(),
        phases: vec![0.0, 0.4],
        omega,
        per_period: 40.0,
        periods: 1.0,
        force: 1.0,
        force_phase: 0.0,
        force_dof: 0,
    };
    let parts = h.record().into_parts();
    let v = parts.velocities.clone().unwrap();
    let forces = Mat::from_fn(v.nrows(), 2, |i, j| {
        c[j] * v[(i, j)] + 0.1 * v[(i, j)] * v[(i, j)].abs()
    });
    Record::new(RecordParts {
        forcing: Forcing::generalized(forces),
        ..parts
    })
    .unwrap()
}

/// `model` plus the shared quadratic `d` on each DOF.
fn with_quadratic(model: DampingModel) -> DampingModel {
    model.with(Term::per_dof(
        Quadratic,
        2,
        Coefficients::Shared("d".into()),
    ))
}

fn per_dof_linear() -> DampingModel {
    DampingModel::new().with(Term::per_dof(
        Linear,
        2,
        Coefficients::PerElement("c".into()),
    ))
}

/// Spectral quadrature with measured (exact) velocities: the balanced forces identify
/// the true coefficients to round-off.
fn exact() -> IdentifySettings {
    support::identify_settings(
        WindowSpec::default(),
        Quadrature::Spectral,
        VelocitySource::Measured,
    )
}

fn rank_deficient(report: &FitReport) -> Option<(usize, usize)> {
    report.warnings.iter().find_map(|w| match w {
        Warning::RankDeficient { rank, coefficients } => Some((*rank, *coefficients)),
        _ => None,
    })
}

/// Every number in the report is finite or explicitly absent.
#[track_caller]
fn no_nan(report: &FitReport) {
    for c in &report.coefficients {
        assert!(c.value.is_finite(), "{}: {}", c.name, c.value);
        assert!(c.std_error.is_none_or(f64::is_finite), "{}", c.name);
    }
    assert!(report.relative_residual.is_finite());
    assert!(report.residuals.iter().all(|e| e.is_finite()));
    assert!(report.singular_values.iter().all(|s| s.is_finite()));
    assert!(report.residual_bias.relative_mean.is_finite());
    let text = report.to_string();
    assert!(!text.contains("NaN"), "{text}");
}

// ---------------------------------------------------------------------------------
// A DOF that never moves
// ---------------------------------------------------------------------------------

/// DOF 2 is still (amplitude 0). Undeclared, that is a dead sensor: an error naming the
/// record and the DOF. Declared held still, its damper does no work in any record, so
/// its column is zero: the report says the data cannot determine c[2]; c[1] is still
/// right.
#[test]
fn dof_that_never_moves_is_flagged_and_the_other_coefficient_is_right() {
    let undeclared = [balanced([1.0, 0.0], 1.0)];
    match identify(
        &ParametricRegressor::linear(&with_quadratic(per_dof_linear()), &undeclared),
        &exact(),
        &silent,
    ) {
        Err(dampid::Error::DeadMotionSensor { dof, .. }) => assert_eq!(dof, 2),
        other => panic!("{other:?}"),
    }
    let records: Vec<Record> = [(1.0, 1.0), (0.5, 1.3), (1.5, 0.8)]
        .iter()
        .map(|&(a, w)| balanced([a, 0.0], w).with_fixed_dofs(vec![1]).unwrap())
        .collect();
    let report = identify(
        &ParametricRegressor::linear(&with_quadratic(per_dof_linear()), &records),
        &exact(),
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(rank_deficient(&report), Some((2, 3)), "{report}");
    assert_eq!(report.condition_number, None);
    assert!(report.coefficients.iter().all(|c| c.std_error.is_none()));
    assert!(report.to_string().contains("cannot separate"), "{report}");
    // The moving DOF's coefficients are determined by the data and come out right.
    let c1 = report.coefficient("c[1]").unwrap();
    let d = report.coefficient("d").unwrap();
    assert!(
        (c1 - 0.3).abs() < 1e-9 && (d - 0.1).abs() < 1e-9,
        "{report}"
    );
}

/// The same with θ ≥ 0: the interior-point solver puts the undetermined c[2] anywhere
/// in [0, ∞), and the report must say that it is not an estimate.
#[test]
fn dof_that_never_moves_is_flagged_in_a_nonnegative_fit() {
    let records: Vec<Record> = [(1.0, 1.0), (0.5, 1.3), (1.5, 0.8)]
        .iter()
        .map(|&(a, w)| balanced([a, 0.0], w).with_fixed_dofs(vec![1]).unwrap())
        .collect();
    let mut settings = exact();
    settings.fit.constraints = Constraints::nonnegative();
    let report = identify(
        &ParametricRegressor::linear(&with_quadratic(per_dof_linear()), &records),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(report.status, FitStatus::Solved);
    assert_eq!(rank_deficient(&report), Some((2, 3)), "{report}");
    assert!(report.coefficients.iter().all(|c| c.std_error.is_none()));
    let c1 = report.coefficient("c[1]").unwrap();
    let d = report.coefficient("d").unwrap();
    assert!(
        (c1 - 0.3).abs() < 1e-6 && (d - 0.1).abs() < 1e-6,
        "{report}"
    );
}

/// A still DOF whose sensor reads a constant offset (0.3, not 0): estimated velocities
/// must come out exactly zero, not as round-off that column scaling would inflate into
/// a "determined" coefficient of any size (spectral velocities once gave c[2] ≈ 0.01
/// "± 1e-18" here, central differences 9e14 on a record with no motion at all).
#[test]
fn dof_that_never_moves_at_an_offset_is_flagged_with_estimated_velocities() {
    let records: Vec<Record> = [(1.0, 1.0), (0.5, 1.3), (1.5, 0.8)]
        .iter()
        .map(|&(a, w)| {
            let mut parts = balanced([a, 0.0], w).into_parts();
            for i in 0..parts.displacements.nrows() {
                parts.displacements[(i, 1)] = 0.3;
            }
            parts.velocities = None;
            Record::new(parts)
                .unwrap()
                .with_fixed_dofs(vec![1])
                .unwrap()
        })
        .collect();
    for velocity in [
        VelocitySource::CentralDifference,
        VelocitySource::Spectral { harmonics: None },
        VelocitySource::HarmonicProjection { harmonics: None },
    ] {
        let mut settings = exact();
        settings.regressor.velocity = velocity;
        let report = identify(
            &ParametricRegressor::linear(&with_quadratic(per_dof_linear()), &records),
            &settings,
            &silent,
        )
        .unwrap()
        .report;
        no_nan(&report);
        assert_eq!(
            rank_deficient(&report),
            Some((2, 3)),
            "{velocity:?}: {report}"
        );
        // Minimum norm: zero along the null direction, up to round-off.
        let c2 = report.coefficient("c[2]").unwrap();
        assert!(c2.abs() < 1e-12, "{velocity:?}: c[2] = {c2}");
        let c1 = report.coefficient("c[1]").unwrap();
        assert!((c1 - 0.3).abs() < 1e-2, "{velocity:?}: c[1] = {c1}");
    }
}

// ---------------------------------------------------------------------------------
// A constant signal
// ---------------------------------------------------------------------------------

/// Displacements that never change (a stuck sensor, or no motion at all) and a constant
/// force: every step x_{i+1} − x_i is zero, so the gross work ∫|vᵀr| dt of each window is
/// zero and no work goes in. Every equation would read 0 = 0 (it used to come out as a
/// rank-0 "fit" with status Solved): it is `NoInputWork`, naming the record, the window,
/// the channel and the DOFs that do not move.
#[test]
fn constant_signal_is_no_input_work() {
    let samples = 120;
    let record = Record::new(RecordParts {
        label: "stuck".into(),
        step: 0.05,
        start_time: 0.0,
        displacements: Mat::from_fn(samples, 2, |_, j| [0.3, -0.2][j]),
        velocities: None,
        forcing: Forcing::on_dofs(Mat::from_fn(samples, 1, |_, _| 1.0), vec![0]),
        period: 2.0,
    })
    .unwrap();
    for velocity in [
        VelocitySource::CentralDifference,
        VelocitySource::Spectral { harmonics: None },
    ] {
        // As many one-period windows as fit: 2 equations.
        let settings =
            support::identify_settings(WindowSpec::cycles(1), Quadrature::Trapezoid, velocity);
        let err = identify(
            &ParametricRegressor::linear(&per_dof_linear(), std::slice::from_ref(&record)),
            &settings,
            &silent,
        )
        .unwrap_err();
        match &err {
            Error::NoInputWork {
                record,
                window,
                channels,
                reason,
            } => {
                assert_eq!(record, "stuck");
                assert_eq!(*window, Some(0));
                assert_eq!(channels, "force channel 1 (on DOF 1)");
                assert!(reason.contains("do not move"), "{err}");
            }
            other => panic!("{velocity:?}: expected NoInputWork, got {other:?}"),
        }
    }
}

// ---------------------------------------------------------------------------------
// A dead force sensor
// ---------------------------------------------------------------------------------

/// The balanced records with their force channels replaced by `signals` (N × c) on
/// `dofs`.
fn with_forcing(record: &Record, signals: Mat<f64>, dofs: Vec<usize>) -> Record {
    Record::new(RecordParts {
        forcing: Forcing::on_dofs(signals, dofs),
        ..record.parts().clone()
    })
    .unwrap()
}

/// An unplugged load cell reads zero: b_r = ∫ vᵀr dt = 0 in every window, and least
/// squares would report c = 0 as "determined" (it did, with status Solved). With one
/// dead channel of two, or with no channel at all, the record takes no work in either.
/// Each is `NoInputWork` naming the record and every channel, numbered from 1, with its
/// DOF, for every velocity source (the noise-robust rows included).
#[test]
fn dead_force_sensor_is_no_input_work() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3)]
        .iter()
        .map(|&(a, w)| balanced(a, w))
        .collect();
    let n = records[0].samples();
    let cases = [
        (
            Mat::zeros(n, 1),
            vec![1],
            "force channel 1 (on DOF 2)",
            "reads zero",
        ),
        (
            Mat::zeros(n, 2),
            vec![0, 1],
            "force channels 1 (on DOF 1) and 2 (on DOF 2)",
            "reads zero",
        ),
        (
            Mat::zeros(n, 0),
            vec![],
            "no force channel",
            "lists no force",
        ),
    ];
    for velocity in [
        VelocitySource::Measured,
        VelocitySource::Spectral { harmonics: None },
        VelocitySource::HarmonicProjection { harmonics: None },
    ] {
        let mut settings = exact();
        settings.regressor.velocity = velocity;
        for (signals, dofs, channels, reason) in &cases {
            let mut dead = records.clone();
            dead[1] = with_forcing(&records[1], signals.clone(), dofs.clone());
            let err = identify(
                &ParametricRegressor::linear(&per_dof_linear(), &dead),
                &settings,
                &silent,
            )
            .unwrap_err();
            let Error::NoInputWork {
                record,
                window,
                channels: named,
                reason: why,
            } = &err
            else {
                panic!("{velocity:?}: expected NoInputWork, got {err:?}");
            };
            assert_eq!(record, "harmonic");
            assert_eq!(*window, None, "{err}");
            assert_eq!(named, channels);
            assert!(why.contains(reason), "{err}");
            assert!(err.to_string().contains("no input work"), "{err}");
        }
    }
}

/// A force in phase with the displacement of the DOF it drives, F cos ωt on
/// x = X cos ωt, does no net work over whole periods (∮ F cos ωt · (−ωX sin ωt) dt = 0)
/// while its gross work ∮ |F v| dt = 4FX is not: the spectral rule gives |b| at
/// round-off, far below 1e-9 of the gross work. A spring force read in place of the
/// drive is `NoInputWork` for the window, not "no damping".
#[test]
fn force_in_phase_with_the_displacement_is_no_input_work() {
    let record = Harmonic {
        amplitudes: vec![1.0, 0.5],
        phases: vec![0.0, 0.4],
        omega: 1.0,
        per_period: 40.0,
        periods: 1.0,
        force: 2.0,
        force_phase: 0.0,
        force_dof: 0,
    }
    .record();
    let err = identify(
        &ParametricRegressor::linear(&per_dof_linear(), &[record]),
        &exact(),
        &silent,
    )
    .unwrap_err();
    match &err {
        Error::NoInputWork { window, reason, .. } => {
            assert_eq!(*window, Some(0));
            assert!(reason.contains("net input work"), "{err}");
            assert!(reason.contains("gross work"), "{err}");
        }
        other => panic!("expected NoInputWork, got {other:?}"),
    }
}

/// Data in units so small that force times displacement underflows: x and r scaled by
/// 1e-170 give products near 1e-340, below the smallest f64 (4.9e-324), so b would be 0
/// although the force reads and the DOFs move. The record is refused before any product
/// is formed (`prep::data_scale`), naming its displacements and the factor to bring them
/// to order one. (Before that check, `NoInputWork` said the work underflows.)
#[test]
fn underflowing_input_work_is_refused_as_out_of_scale() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3)]
        .iter()
        .map(|&(a, w)| {
            let parts = balanced(a, w).into_parts();
            let scale =
                |m: &Mat<f64>| Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * 1e-170);
            Record::new(RecordParts {
                displacements: scale(&parts.displacements),
                velocities: parts.velocities.as_ref().map(scale),
                forcing: Forcing::generalized(scale(&parts.forcing.signals)),
                ..parts
            })
            .unwrap()
        })
        .collect();
    let err = identify(
        &ParametricRegressor::linear(&per_dof_linear(), &records),
        &exact(),
        &silent,
    )
    .unwrap_err();
    match &err {
        Error::DataScale {
            signal,
            factor_exponent,
            ..
        } => {
            assert_eq!(signal, "displacement");
            assert!((168..=172).contains(factor_exponent), "{err}");
        }
        other => panic!("expected DataScale, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------
// A regressor that is zero
// ---------------------------------------------------------------------------------

/// A model whose only term dissipates nothing on any motion (a zero damping matrix, or
/// an element weight of zero) gives A = 0 while the input work is there. Every
/// coefficient would be "determined" at 0 (the identifiability threshold tol·σ_1 was 0):
/// it is `NoInformation` naming the coefficients, for `identify` and for the check.
#[test]
fn zero_regressor_is_no_information() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3), ([1.1, 0.9], 0.7)]
        .iter()
        .map(|&(a, w)| balanced(a, w))
        .collect();
    let zero_weights = DampingModel::new().with(Term::weighted(
        Linear,
        Element::each_dof(2),
        vec![0.0, 0.0],
        Coefficients::PerElement("c".into()),
    ));
    let zero_matrix = DampingModel::new().with(Term::viscous("zero", Mat::zeros(2, 2)));
    for (model, names) in [(zero_weights, "c[1] and c[2]"), (zero_matrix, "zero")] {
        let err = identify(
            &ParametricRegressor::linear(&model, &records),
            &exact(),
            &silent,
        )
        .unwrap_err();
        match &err {
            Error::NoInformation {
                coefficients,
                reason,
            } => {
                assert_eq!(coefficients, names);
                assert!(reason.contains("every column"), "{err}");
            }
            other => panic!("expected NoInformation, got {other:?}"),
        }
        assert!(
            err.to_string()
                .starts_with("these data carry no information on"),
            "{err}"
        );
        let regressor = Regressor::build(&model, &records, &exact().regressor).unwrap();
        let check = dampid::analysis::check::RegressorCheck::new(&regressor, &exact().fit);
        assert!(
            matches!(check, Err(Error::NoInformation { .. })),
            "{check:?}"
        );
    }
}

/// Motion so small that the damping work underflows while the input work does not:
/// x and v scaled by 1e-170 make every v·f(v) near 1e-340, zero in f64, while r scaled by
/// 1e+170 keeps vᵀr of order one. Such motion is refused before any product is formed
/// (`prep::data_scale`), naming the displacements: a fit would see A = 0 exactly.
#[test]
fn underflowing_damping_work_is_refused_as_out_of_scale() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3), ([1.1, 0.9], 0.7)]
        .iter()
        .map(|&(a, w)| {
            let parts = balanced(a, w).into_parts();
            let scale =
                |m: &Mat<f64>, k: f64| Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * k);
            Record::new(RecordParts {
                displacements: scale(&parts.displacements, 1e-170),
                velocities: parts.velocities.as_ref().map(|v| scale(v, 1e-170)),
                forcing: Forcing::generalized(scale(&parts.forcing.signals, 1e170)),
                ..parts
            })
            .unwrap()
        })
        .collect();
    let err = identify(
        &ParametricRegressor::linear(&per_dof_linear(), &records),
        &exact(),
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::DataScale { signal, .. } if signal == "displacement"),
        "{err:?}"
    );
}

// ---------------------------------------------------------------------------------
// An all-zero regressor column
// ---------------------------------------------------------------------------------

/// A term that dissipates nothing on these data (a zero damping matrix) gives an
/// all-zero column. Column scaling must not divide by its zero norm; the report flags
/// it and the other coefficients are unaffected.
#[test]
fn all_zero_regressor_column_is_flagged_and_the_others_are_right() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3), ([1.1, 0.9], 0.7)]
        .iter()
        .map(|&(a, w)| balanced(a, w))
        .collect();
    let model = with_quadratic(per_dof_linear()).with(Term::viscous("zero", Mat::zeros(2, 2)));
    let mut records = records;
    records.push(balanced([0.7, 0.3], 1.6));
    let report = identify(
        &ParametricRegressor::linear(&model, &records),
        &exact(),
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(rank_deficient(&report), Some((3, 4)), "{report}");
    assert_eq!(report.coefficient("zero"), Some(0.0));
    // Not determined, never "determined".
    assert_not_determined(&report, "zero");
    for (name, truth) in [("c[1]", 0.3), ("c[2]", 0.2), ("d", 0.1)] {
        let value = report.coefficient(name).unwrap();
        assert!((value - truth).abs() < 1e-9, "{name} = {value}: {report}");
    }
}

/// The column of `name` is not determined: the report says so by name, and does not
/// say that every coefficient is determined.
#[track_caller]
fn assert_not_determined(report: &FitReport, name: &str) {
    let estimate = report.coefficients.iter().find(|c| c.name == name).unwrap();
    assert!(!estimate.determined, "{report}");
    assert!(!report.identifiability.is_identifiable(name), "{report}");
    assert!(!report.identifiability.separable(), "{report}");
    let text = report.to_string();
    assert!(
        text.contains(&format!("{name} is not determined")),
        "{text}"
    );
    assert!(!text.contains("every coefficient is determined"), "{text}");
}

/// An element weight of zero for one dashpot of two (per-element coefficients): that
/// element's column is zero among nonzero ones. With forces that balance c = (0.3, 0)
/// and d = 0.1, c[2] is not determined (never "determined"), and c[1] and d are still
/// right.
#[test]
fn zero_element_weight_is_not_determined() {
    let records: Vec<Record> = [([1.0, 0.5], 1.0), ([0.4, 1.2], 1.3), ([1.1, 0.9], 0.7)]
        .iter()
        .map(|&(a, w)| balanced_with([0.3, 0.0], a, w))
        .collect();
    let model = with_quadratic(DampingModel::new().with(Term::weighted(
        Linear,
        Element::each_dof(2),
        vec![1.0, 0.0],
        Coefficients::PerElement("c".into()),
    )));
    let report = identify(
        &ParametricRegressor::linear(&model, &records),
        &exact(),
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(rank_deficient(&report), Some((2, 3)), "{report}");
    assert_not_determined(&report, "c[2]");
    for (name, truth) in [("c[1]", 0.3), ("d", 0.1)] {
        let value = report.coefficient(name).unwrap();
        assert!((value - truth).abs() < 1e-9, "{name} = {value}: {report}");
    }
}

// ---------------------------------------------------------------------------------
// Duplicated experiments
// ---------------------------------------------------------------------------------

/// The same experiment given twice is two equal equations: as many equations as
/// coefficients, but rank 1. The report says the data cannot separate them, instead of
/// fitting the copies exactly and calling it a solution.
#[test]
fn duplicated_experiments_are_rank_deficient() {
    let record = balanced([1.0, 0.5], 1.0);
    let report = identify(
        &ParametricRegressor::linear(&per_dof_linear(), &[record.clone(), record]),
        &exact(),
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(rank_deficient(&report), Some((1, 2)), "{report}");
    assert!(
        report
            .warnings
            .contains(&Warning::NoRedundancy { equations: 2 }),
        "{report}"
    );
    assert!(report.coefficients.iter().all(|c| c.std_error.is_none()));
}

/// Copies of an experiment whose motion is only rescaled (the same shape at another
/// amplitude) carry no new information about a linear model either.
#[test]
fn duplicated_experiments_at_another_amplitude_are_rank_deficient() {
    let records = [
        balanced([1.0, 0.5], 1.0),
        balanced([2.0, 1.0], 1.0),
        balanced([0.5, 0.25], 1.0),
    ];
    let report = identify(
        &ParametricRegressor::linear(&per_dof_linear(), &records),
        &exact(),
        &silent,
    )
    .unwrap()
    .report;
    no_nan(&report);
    assert_eq!(rank_deficient(&report), Some((1, 2)), "{report}");
    assert!(report.coefficients.iter().all(|c| c.std_error.is_none()));
}

// ---------------------------------------------------------------------------------
// A force on a DOF that does not exist (the model-file route)
// ---------------------------------------------------------------------------------

fn model_file_error(forces: &str) -> Error {
    let text = format!(
        r#"
dofs = 2

[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"

[[data.records]]
file = "data/chain3/record_1.csv"
time = "t"
displacements = ["x1", "x2"]
forces = [{forces}]
frequency = 0.765367
"#
    );
    dampid::model_file::parse(&text, "force.toml", Path::new("models"), Default::default())
        .unwrap_err()
}

/// Model files number DOFs from 1 (0 is ground): a force column on DOF 3 of a 2-DOF
/// model, or on DOF 0, is `DofOutOfRange`, reported at the force column's line.
#[test]
fn force_on_missing_dof_in_a_model_file_is_dof_out_of_range() {
    for (dof, needle) in [(3, "DOF 3"), (0, "DOF 0")] {
        let err = model_file_error(&format!(r#"{{ column = "f1", dof = {dof} }}"#));
        match &err {
            Error::ModelFile {
                file,
                line,
                message,
                ..
            } => {
                assert_eq!(file, "force.toml");
                assert_eq!(*line, 14, "{err}");
                assert!(message.contains(needle), "{err}");
                assert!(message.contains("numbered 1..2"), "{err}");
            }
            other => panic!("expected a model-file error, got {other:?}"),
        }
    }
}
