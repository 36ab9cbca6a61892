//! The lack-of-fit test of unweighted fits (`analysis::lack_of_fit`,
//! `Warning::LackOfFit`, `StandardErrorBasis::BetweenRecords`): by hand on three records
//! of three windows, and on the physics fuzz target's finding 4ae7ed… (velocities given
//! as displacements in every record of a 2-DOF chain, spectral velocities, an
//! unweighted nonnegative fit: c[0-1] = 0.021 ± 0.0099 for a truth of 0.19, "every
//! coefficient is determined", no warning).

use dampid::analysis::diagnostics::{Diagnostics, StandardErrorBasis, diagnose};
use dampid::fit;
use dampid::prelude::*;
use dampid::prep::velocity::VelocitySource;
use dampid::regressor::{NoiseTreatment, RegressorSettings, RowLabel, Windows};
use dampid::report::Warning;
use faer::Mat;

mod support;
use support::fuzz_chain::{self, amplitude, detune};

/// Labels of `records` records of `windows` one-period windows each.
fn replicate_labels(records: usize, windows: usize) -> Vec<RowLabel> {
    (0..records * windows)
        .map(|i| RowLabel {
            frequency: None,
            record: format!("r{}", i / windows + 1),
            record_index: i / windows,
            window: i % windows,
            start_time: 0.0,
            cycles: 1,
        })
        .collect()
}

fn lack_of_fit_warnings(report: &FitReport) -> Vec<&Warning> {
    report
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::LackOfFit { .. }))
        .collect()
}

/// One column of ones with right-hand side `b`, records of `windows` windows each, its
/// least-squares fit and the fit's diagnostics.
fn ones_fit(b: &[f64], windows: usize) -> (Regressor, dampid::fit::Fit, Diagnostics) {
    let regressor = Regressor::from_parts(
        Mat::from_fn(b.len(), 1, |_, _| 1.0),
        b.to_vec(),
        vec!["c".into()],
        replicate_labels(b.len() / windows, windows),
    )
    .unwrap();
    let fit = fit::least_squares(&regressor, 1e-10).unwrap();
    let diagnostics = diagnose(&regressor, &fit, 1e-10);
    (regressor, fit, diagnostics)
}

/// One column of ones, three records of three windows: b = (1, 1.1, 0.9), (2, 2.1, 1.9),
/// (3, 3.1, 2.9). Then θ = 2, the record means of e are −1, 0, 1, so SS_lof = 3·2 = 6
/// on 3 − 1 = 2 degrees of freedom and SS_pe = 3·0.02 = 0.06 on 6: F = 3/0.01 = 300,
/// P = (1 + 2F/6)^(−3) = 101⁻³ (the F tail with 2 numerator degrees), s² = 6.06/8,
/// scale = √(3/s²), se = √(3/9) instead of √(s²/9), and the misfit √6/‖b‖,
/// ‖b‖² = 3·14 + 6·0.01.
#[test]
fn the_test_and_the_scaled_errors_match_the_analysis_of_variance_by_hand() {
    let b = [1.0, 1.1, 0.9, 2.0, 2.1, 1.9, 3.0, 3.1, 2.9];
    let (regressor, fit, diagnostics) = ones_fit(&b, 3);
    let l = diagnostics
        .lack_of_fit
        .clone()
        .expect("the test has degrees of freedom");
    assert_eq!(
        (l.degrees_of_freedom, l.pure_error_degrees_of_freedom),
        (2, 6)
    );
    let f = l.f_statistic.unwrap();
    assert!((f - 300.0).abs() < 1e-9 * 300.0, "F = {f}");
    let p = 101f64.powi(-3);
    assert!((l.p_value - p).abs() < 1e-9 * p, "P = {}", l.p_value);
    let s2: f64 = 6.06 / 8.0;
    assert!((l.scale - (3.0 / s2).sqrt()).abs() < 1e-12);
    let misfit = 6f64.sqrt() / (42.06f64).sqrt();
    assert!((l.relative_misfit - misfit).abs() < 1e-12);
    assert!(l.rejects());
    // The records' shares of SS_lof: r1 and r3 half each, r2 none.
    assert_eq!(l.records[0].1 + l.records[1].1, 1.0);
    let se = diagnostics.std_errors[0].unwrap();
    assert!((se - (3.0f64 / 9.0).sqrt()).abs() < 1e-12, "se = {se}");
    assert!(matches!(
        diagnostics.std_error_basis,
        StandardErrorBasis::BetweenRecords { .. }
    ));
    let report = FitReport::new(&regressor, fit, diagnostics);
    assert_eq!(lack_of_fit_warnings(&report).len(), 1);
    assert!(!report.strict_failures().is_empty());
    let text = report.to_string();
    assert!(text.contains("lack of fit"), "{text}");
    assert!(
        text.contains("'r1' (50 %)") && text.contains("'r3' (50 %)"),
        "{text}"
    );
}

/// The same records with the record means on the fit (b = 2 ± 0.1 in every record): the
/// scatter is all within records, F = 0, and the errors are the residual-variance ones.
#[test]
fn records_that_agree_leave_the_errors_as_they_are() {
    let b = [2.0, 2.1, 1.9, 2.1, 2.0, 1.9, 1.9, 2.0, 2.1];
    let (regressor, fit, diagnostics) = ones_fit(&b, 3);
    let l = diagnostics.lack_of_fit.clone().unwrap();
    assert!(!l.rejects());
    assert_eq!(
        diagnostics.std_error_basis,
        StandardErrorBasis::ResidualVariance
    );
    let s2: f64 = 0.06 / 8.0;
    assert!((diagnostics.std_errors[0].unwrap() - (s2 / 9.0f64).sqrt()).abs() < 1e-12);
    let report = FitReport::new(&regressor, fit, diagnostics);
    assert!(lack_of_fit_warnings(&report).is_empty());
}

/// The test rejects at the χ² check's level.
#[test]
fn the_test_and_the_chi_square_check_reject_at_one_level() {
    assert_eq!(
        dampid::analysis::lack_of_fit::REJECTION_P_VALUE,
        dampid::analysis::diagnostics::REJECTION_P_VALUE
    );
}

/// Records of one window each have no pure error, and as many records as coefficients
/// no lack-of-fit degrees of freedom: no test.
#[test]
fn without_degrees_of_freedom_there_is_no_test() {
    let one_window = Regressor::from_parts(
        Mat::from_fn(3, 1, |_, _| 1.0),
        vec![1.0, 2.0, 3.0],
        vec!["c".into()],
        replicate_labels(3, 1),
    )
    .unwrap();
    let fit = fit::least_squares(&one_window, 1e-10).unwrap();
    assert!(diagnose(&one_window, &fit, 1e-10).lack_of_fit.is_none());
    let one_record = Regressor::from_parts(
        Mat::from_fn(3, 1, |_, _| 1.0),
        vec![1.0, 2.0, 3.0],
        vec!["c".into()],
        replicate_labels(1, 3),
    )
    .unwrap();
    let fit = fit::least_squares(&one_record, 1e-10).unwrap();
    assert!(diagnose(&one_record, &fit, 1e-10).lack_of_fit.is_none());
}

/// The fuzz finding's records: a 2-DOF chain with dashpots (12, 1, 14)/64, four records
/// (on DOF 1 near mode 1, on DOF 2 near mode 2 twice, on DOF 2 near mode 1), no noise;
/// `corrupt` puts the velocities in the displacement channels of every record.
fn fuzz_4ae7(corrupt: bool, velocity: VelocitySource, noise: f64) -> (FitReport, [f64; 3]) {
    let n = 2;
    let truth = [12.0 / 64.0, 1.0 / 64.0, 14.0 / 64.0];
    let experiments = [
        (0, 1, detune(255.0), amplitude(97.0)),
        (1, 2, detune(255.0), amplitude(255.0)),
        (1, 2, detune(17.0), amplitude(255.0)),
        (1, 1, detune(255.0), amplitude(255.0)),
    ];
    let mut rng = fuzz_chain::Noise(0);
    let records: Vec<Record> = experiments
        .iter()
        .enumerate()
        .map(|(k, &(dof, mode, d, a))| {
            let mut raw = fuzz_chain::raw(n, &truth, dof, mode, d, a, noise, &mut rng);
            if corrupt {
                raw.x = raw.v.clone();
            }
            raw.into_record(&format!("r{}", k + 1))
        })
        .collect();
    let regressor = RegressorSettings {
        windows: Windows::Cycles(WindowSpec::cycles(1)),
        quadrature: Quadrature::Trapezoid,
        velocity,
        noise: NoiseTreatment::Ignore,
        ..RegressorSettings::default()
    };
    let mut settings = IdentifySettings {
        regressor,
        ..IdentifySettings::default()
    };
    settings.fit.constraints = Constraints::nonnegative();
    let report = identify(
        &ParametricRegressor::linear(&fuzz_chain::model(n), &records),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    (report, truth)
}

/// Velocities as displacements in every record: each record's four windows agree to
/// round-off, but the records' means leave 6.8 % of the input work, so the test rejects
/// the fit, `--strict` fails, and the standard errors come from the records' means.
#[test]
fn velocities_given_as_displacements_in_every_record_fail_the_lack_of_fit_test() {
    let (report, truth) = fuzz_4ae7(true, VelocitySource::Spectral { harmonics: None }, 0.0);
    let found = lack_of_fit_warnings(&report);
    assert_eq!(found.len(), 1, "{report}");
    let Warning::LackOfFit {
        relative_misfit,
        scale,
        records,
        ..
    } = found[0]
    else {
        unreachable!()
    };
    assert!(*relative_misfit > 0.01, "{report}");
    assert!(*scale > 1.0);
    assert_eq!(records.len(), 3);
    assert!(!report.strict_failures().is_empty());
    let StandardErrorBasis::BetweenRecords { scale: basis, .. } = report.std_error_basis else {
        panic!("{report}")
    };
    assert_eq!(basis, *scale);
    // With the records' disagreement as the noise level, the three dashpots are not
    // separated, and the advice is to correct the records or the model, not only to
    // add experiments.
    assert!(
        report
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::Unidentifiable { misfit: true, .. })),
        "{report}"
    );
    assert!(report.to_string().contains("correct the model"), "{report}");
    // The estimate is still wrong (nothing in these data says where the truth is): the
    // warnings are what the report owes.
    let c01 = &report.coefficients[0];
    assert!((c01.value - truth[0]).abs() > 0.1, "{report}");
}

/// The same records uncorrupted, with every velocity source and with noise: the test
/// never rejects them (clean records differ between records by round-off or
/// discretisation error, noisy ones by noise).
#[test]
fn clean_and_noisy_records_of_the_fuzz_case_pass() {
    for velocity in [
        VelocitySource::Spectral { harmonics: None },
        VelocitySource::CentralDifference,
        VelocitySource::Measured,
    ] {
        for noise in [0.0, 1e-3] {
            let (report, truth) = fuzz_4ae7(false, velocity, noise);
            assert!(
                lack_of_fit_warnings(&report).is_empty(),
                "{velocity:?}, noise {noise}:\n{report}"
            );
            if noise == 0.0 {
                for (c, t) in report.coefficients.iter().zip(truth) {
                    assert!((c.value - t).abs() < 1e-2 * t, "{velocity:?}:\n{report}");
                }
            }
        }
    }
}

/// The shipped measured chain fitted without its friction term (measured velocities,
/// unweighted): the records disagree by 2.3 % of the input work, far beyond their
/// windows' scatter. `identify --json` carries the warning and the between-records
/// basis, `--strict` exits 1, and `check` says so above its identifiability analysis;
/// with the friction term the test passes.
#[test]
fn the_chain_fitted_without_its_friction_fails_the_test_from_the_command_line() {
    let json = support::cli::dampid_json(&[
        "identify",
        "models/measured_chain_no_friction.toml",
        "--json",
    ]);
    let warnings = json["report"]["warnings"].as_array().unwrap();
    let found = warnings
        .iter()
        .find(|w| w["kind"] == "lack_of_fit")
        .unwrap_or_else(|| panic!("{warnings:?}"));
    let misfit = found["relative_misfit"].as_f64().unwrap();
    assert!((0.01..0.05).contains(&misfit), "{misfit}");
    assert_eq!(
        json["report"]["std_error_basis"]["basis"],
        "between_records"
    );
    let strict = support::cli::dampid(&[
        "identify",
        "models/measured_chain_no_friction.toml",
        "--strict",
    ]);
    assert_eq!(strict.status.code(), Some(1));
    let check = support::cli::dampid_ok(&["check", "models/measured_chain_no_friction.toml"]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(text.contains("lack of fit:"), "{text}");
    let with_friction =
        support::cli::dampid_json(&["identify", "models/measured_chain.toml", "--json"]);
    assert!(
        !with_friction["report"]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["kind"] == "lack_of_fit"),
        "{with_friction}"
    );
    assert_eq!(
        with_friction["report"]["std_error_basis"]["basis"],
        "residual_variance"
    );
}
