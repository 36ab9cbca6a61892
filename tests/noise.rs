//! The noise-robust pipeline (issue #8) on the 6-DOF chain of
//! src/reference/noisy_chain.rs: simulated, made noisy, identified; never compared with
//! anything but the truth the simulation used.

use std::sync::OnceLock;

use dampid::fit::{Constraints, Weighting};
use dampid::prelude::*;
use dampid::reference::{
    FOUR_MASS_AMPLITUDES, four_mass_model, four_mass_system, noise_study, noise_study_settings,
    noisy_chain_model, noisy_chain_records, noisy_chain_truth, with_displacement_noise,
};
use dampid::regressor::NoiseTreatment;
use dampid::simulate::{SimSettings, simulate};

/// The 24 clean experiments, 8 recorded cycles each (a study of c cycles reads the
/// first c), simulated once for every test here.
fn clean() -> &'static [Record] {
    static RECORDS: OnceLock<Vec<Record>> = OnceLock::new();
    RECORDS.get_or_init(|| noisy_chain_records(8).unwrap())
}

/// 1% displacement noise, 2 recorded cycles, 160 draws: the worst coefficient's RMS
/// error is at most 2%, its bias at most 0.5%, the plug-in 95% intervals cover the
/// truth in 93–97% of the 1280 (coefficient, draw) pairs, and ordinary least squares on
/// 15-harmonic velocities is more than twice as far off.
#[test]
fn one_percent_noise_reaches_the_targets_and_beats_ordinary_least_squares() {
    let robust = noise_study(clean(), 0.01, 160, &noise_study_settings(2, true)).unwrap();
    let plain = noise_study(clean(), 0.01, 160, &noise_study_settings(2, false)).unwrap();
    assert!(robust.worst_rms() <= 0.02, "{robust:?}");
    assert!(robust.worst_bias() <= 0.005, "{robust:?}");
    assert!(
        (0.93..=0.97).contains(&robust.coverage),
        "coverage {}",
        robust.coverage
    );
    assert!(
        plain.worst_rms() > 2.0 * robust.worst_rms(),
        "OLS {} vs robust {}",
        plain.worst_rms(),
        robust.worst_rms()
    );
    // near the first-order optimum: RMS within 15% of the mean plug-in standard error
    for (rms, se) in robust.rms.iter().zip(&robust.mean_std_error) {
        assert!(rms / se < 1.15 && rms / se > 0.85, "rms {rms} vs se {se}");
    }
}

/// The error is about linear in the noise level (0.3% → 3%: ×10) and falls about like
/// 1/√cycles (2 → 8 cycles: ÷2).
#[test]
fn error_scales_with_noise_and_cycles_as_theory_says() {
    let worst = |level, cycles| {
        noise_study(clean(), level, 40, &noise_study_settings(cycles, true))
            .unwrap()
            .worst_rms()
    };
    let noise_ratio = worst(0.03, 2) / worst(0.003, 2);
    assert!(
        (7.0..14.0).contains(&noise_ratio),
        "noise ratio {noise_ratio}"
    );
    let cycles_ratio = worst(0.01, 2) / worst(0.01, 8);
    assert!(
        (1.5..2.8).contains(&cycles_ratio),
        "cycles ratio {cycles_ratio}"
    );
}

fn plain_projection() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.velocity = VelocitySource::HarmonicProjection { harmonics: None };
    settings.regressor.noise = NoiseTreatment::Ignore;
    settings.fit.weighting = Weighting::Ordinary;
    settings
}

fn robust_projection() -> IdentifySettings {
    let mut settings = plain_projection();
    settings.regressor.noise = NoiseTreatment::Correct;
    settings.fit.weighting = Weighting::Propagated;
    settings
}

/// On clean data the corrections vanish and the weights only rebalance exact
/// equations: the same estimates as the plain pipeline to 0.05%, on the paper's
/// four-mass chain (simulated 5000 steps into its steady state; after the paper's 1000
/// the smallest amplitude still carries a transient of 3·10⁻⁵, which the weights rightly
/// discount) and on the noise chain. The four-mass records hold one period of 101.67
/// samples, which the spectral rule integrates exactly.
#[test]
fn clean_data_give_the_plain_estimates() {
    let steady = SimSettings {
        transient_steps: 5000,
        ..SimSettings::default()
    };
    let four_mass: Vec<Record> = FOUR_MASS_AMPLITUDES
        .iter()
        .map(|&a| {
            simulate(
                &four_mass_system(a, false),
                &steady,
                &dampid::progress::silent,
            )
            .unwrap()
        })
        .collect();
    let chain = clean();
    let mut chain_settings = (plain_projection(), robust_projection());
    for s in [&mut chain_settings.0, &mut chain_settings.1] {
        s.regressor.windows.cycles_mut().unwrap().cycles = 2;
    }
    let mut four_mass_settings = (plain_projection(), robust_projection());
    for s in [&mut four_mass_settings.0, &mut four_mass_settings.1] {
        s.regressor.quadrature = Quadrature::Spectral;
    }
    for (model, records, (plain, robust)) in [
        (four_mass_model(), &four_mass[..], four_mass_settings),
        (noisy_chain_model(), chain, chain_settings),
    ] {
        let a = identify(
            &ParametricRegressor::linear(&model, records),
            &plain,
            &silent,
        )
        .unwrap()
        .report;
        let b = identify(
            &ParametricRegressor::linear(&model, records),
            &robust,
            &silent,
        )
        .unwrap()
        .report;
        assert!(b.noise.is_some() && a.noise.is_none());
        for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
            assert!(
                (x.value - y.value).abs() <= 5e-4 * x.value.abs(),
                "{}: {} vs {}",
                x.name,
                x.value,
                y.value
            );
        }
    }
}

/// Scaling every force by k scales every coefficient by k, noise and weights included
/// (the noise estimate of the force scales with it).
#[test]
fn scaling_the_forces_scales_the_robust_estimates() {
    let noisy = with_displacement_noise(clean(), 0.01, 7).unwrap();
    let scaled: Vec<Record> = noisy
        .iter()
        .map(|r| {
            let mut parts = r.parts().clone();
            parts.forcing.signals = &parts.forcing.signals * faer::Scale(3.0);
            Record::new(parts).unwrap()
        })
        .collect();
    let settings = noise_study_settings(2, true);
    let a = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    let b = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &scaled),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
        assert!(
            (3.0 * x.value - y.value).abs() <= 1e-9 * y.value.abs(),
            "{}: {} vs {}",
            x.name,
            x.value,
            y.value
        );
    }
}

/// The nonnegative fit works on the weighted rows: with every coefficient well inside
/// its bound it equals the unconstrained weighted fit, and the report still carries the
/// noise summary.
#[test]
fn nonnegative_fit_on_the_weighted_system_equals_the_free_fit_when_inactive() {
    let noisy = with_displacement_noise(clean(), 0.01, 3).unwrap();
    let free = noise_study_settings(2, true);
    let mut nonnegative = free.clone();
    nonnegative.fit.constraints = Constraints {
        nonnegative: true,
        ..Constraints::default()
    };
    let a = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &free,
        &silent,
    )
    .unwrap()
    .report;
    let b = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &nonnegative,
        &silent,
    )
    .unwrap()
    .report;
    assert!(b.active_constraints.is_empty());
    assert!(b.noise.is_some());
    for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
        assert!(
            (x.value - y.value).abs() <= 1e-6 * x.value.abs(),
            "{}: {} vs {}",
            x.name,
            x.value,
            y.value
        );
    }
}

/// The report says what was estimated: noise per channel near the truth, the harmonics
/// kept, χ² near its degrees of freedom, plug-in standard errors and their intervals.
#[test]
fn report_carries_the_noise_estimates_and_the_model_check() {
    let noisy = with_displacement_noise(clean(), 0.01, 11).unwrap();
    let report = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &noise_study_settings(2, true),
        &silent,
    )
    .unwrap()
    .report;
    let noise = report.noise.as_ref().expect("noise summary");
    assert_eq!(noise.windows.len(), 24);
    for (window, record) in noise.windows.iter().zip(clean()) {
        assert_eq!(window.harmonics[0], 1);
        // the noise added was 1% of the record's RMS displacement
        let x = record.displacements();
        let rms = (x.squared_norm_l2() / (x.nrows() * x.ncols()) as f64).sqrt();
        for sigma in &window.displacement_noise {
            assert!(
                (sigma / (0.01 * rms) - 1.0).abs() < 0.3,
                "{sigma} vs {}",
                0.01 * rms
            );
        }
    }
    assert_eq!(noise.degrees_of_freedom, 24 - 8);
    assert!(noise.p_value.unwrap() > 0.01, "χ² {}", noise.chi_square);
    let truth = noisy_chain_truth();
    for (c, t) in report.coefficients.iter().zip(&truth) {
        let se = c.std_error.expect("plug-in se");
        assert!(se > 0.0 && se < 0.05 * t, "{}: se {se}", c.name);
        assert!(c.residual_std_error.is_some());
    }
    let text = report.to_string();
    assert!(
        text.contains("95% plug-in interval") && text.contains("χ²"),
        "{text}"
    );
    let json = serde_json::to_value(&report).unwrap();
    assert!(json["noise"]["windows"][0]["harmonics"].is_array());
}

/// A model that misses a mechanism (no friction term) leaves residuals far above the
/// noise: the χ² check says so.
#[test]
fn missing_friction_fails_the_model_check() {
    let noisy = with_displacement_noise(clean(), 0.01, 5).unwrap();
    let viscous_only = DampingModel::new().with(Term::on_elements(
        Linear,
        Element::chain_fixed_both_ends(6),
        Coefficients::PerElement("c".into()),
    ));
    let report = identify(
        &ParametricRegressor::linear(&viscous_only, &noisy),
        &noise_study_settings(2, true),
        &silent,
    )
    .unwrap()
    .report;
    assert!(
        report
            .warnings
            .iter()
            .any(|w| matches!(w, dampid::report::Warning::ModelInadequate { .. })),
        "{report}"
    );
}

/// Settings that cannot work are typed errors naming the field.
#[test]
fn noise_correction_needs_projected_velocities_and_weights_need_a_noise_model() {
    let noisy = with_displacement_noise(clean(), 0.01, 1).unwrap();
    let mut settings = noise_study_settings(2, true);
    settings.regressor.velocity = VelocitySource::CentralDifference;
    let error = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidChoice { name, given, .. } if name == "noise" && given == "correct"),
        "{error}"
    );
    settings.regressor.noise = NoiseTreatment::Ignore;
    settings.fit.weighting = Weighting::Propagated;
    let error = identify(
        &ParametricRegressor::linear(&noisy_chain_model(), &noisy),
        &settings,
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidChoice { name, .. } if name == "weighting"),
        "{error}"
    );
}
