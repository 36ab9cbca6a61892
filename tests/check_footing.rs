//! `dampid check` judges the data on the equations `identify` solves
//! (`analysis::solved`): the same rows, weighted by the propagated noise model in the
//! noise-robust pipeline, so the two agree on the rank, the condition number and what
//! is determined; and the ± of a determined combination matches its scatter over noise
//! draws.

use dampid::analysis::check::RegressorCheck;
use dampid::analysis::diagnostics::diagnose;
use dampid::fit;
use dampid::prelude::*;
use dampid::reference::with_displacement_noise;
use dampid::regressor::NoiseTreatment;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use faer::Mat;

const N: usize = 6;

fn chain(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2.0,
        1 => -1.0,
        _ => 0.0,
    })
}

/// λ_k = 2 − 2cos(kπ/7), the k-th eigenvalue of the 6-DOF chain.
fn lambda(k: usize) -> f64 {
    2.0 - 2.0 * (k as f64 * std::f64::consts::PI / (N as f64 + 1.0)).cos()
}

/// C = c0 I + c1 K on the 6-DOF chain with unit masses and springs.
fn rayleigh() -> DampingModel {
    DampingModel::new()
        .with(Term::mass_proportional("c0", Mat::identity(N, N)))
        .with(Term::stiffness_proportional("c1", chain(N)))
}

/// Steady response to a force of `amplitude` on mass 3 at the `mode`-th natural
/// frequency, 128 samples per period, `cycles` periods recorded.
fn record(mode: usize, amplitude: f64, cycles: usize) -> Record {
    let omega = lambda(mode).sqrt();
    let step = 2.0 * std::f64::consts::PI / omega / 128.0;
    let system = System {
        mass: Mat::identity(N, N),
        stiffness: chain(N),
        damping: rayleigh(),
        damping_coefficients: vec![0.02, 0.03],
        conservative: Vec::new(),
        forcing: vec![HarmonicForce {
            dof: 2,
            amplitude,
            frequency: omega,
            phase: 0.0,
        }],
    };
    // The slowest mode decays like exp(−(c0 + c1 λ_1) t / 2): 40 time constants.
    let transient = 80.0 / (0.02 + 0.03 * lambda(1));
    let settings = SimSettings {
        step,
        substeps: 2,
        transient_steps: (transient / step).ceil() as usize,
        recorded_steps: 128 * cycles + 1,
    };
    simulate(&system, &settings, &dampid::progress::silent).unwrap()
}

/// The noise-robust pipeline: harmonic projection, bias-corrected columns, propagated
/// weights; windows of 2 periods.
fn robust() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(2).into();
    settings.regressor.velocity = VelocitySource::HarmonicProjection { harmonics: None };
    settings.regressor.noise = NoiseTreatment::Correct;
    settings.fit.weighting = fit::Weighting::Propagated;
    settings
}

/// The 6-DOF chain at its first resonance only (two amplitudes: only c0 + λ_1 c1 is
/// determined) or at its first two (both are), 8 periods per record.
fn sets() -> [(&'static str, Vec<Record>); 2] {
    [
        (
            "first resonance",
            vec![record(1, 0.5, 8), record(1, 1.0, 8)],
        ),
        ("two resonances", vec![record(1, 0.5, 8), record(2, 1.0, 8)]),
    ]
}

/// On noisy data the check reports the identify report's condition number, rank,
/// practical rank, undetermined coefficients and determined combinations, for the
/// propagated weights and for ordinary least squares; the weighted condition number is
/// not the unweighted one (so the agreement is not an accident of equal rows), and the
/// text says which matrix it is of.
#[test]
fn check_and_identify_agree_on_noisy_data() {
    let model = rayleigh();
    for (name, clean) in sets() {
        for level in [0.01, 0.03] {
            let noisy = with_displacement_noise(&clean, level, 7).unwrap();
            for weighting in [fit::Weighting::Propagated, fit::Weighting::Ordinary] {
                let mut settings = robust();
                settings.fit.weighting = weighting;
                let regressor = Regressor::build(&model, &noisy, &settings.regressor).unwrap();
                let report = identify(
                    &ParametricRegressor::rows(&regressor),
                    &IdentifySettings {
                        fit: settings.fit.clone(),
                        ..Default::default()
                    },
                    &silent,
                )
                .map(|i| i.report)
                .unwrap();
                let check = RegressorCheck::new(&regressor, &settings.fit).unwrap();
                let case = format!("{name}, noise {level}, {weighting:?}");
                assert_eq!(check.condition_number, report.condition_number, "{case}");
                assert_eq!(check.singular_values, report.singular_values, "{case}");
                assert_eq!(check.rank, report.rank, "{case}");
                assert_eq!(check.identifiability, report.identifiability, "{case}");
                assert_eq!(
                    check.weighted,
                    weighting == fit::Weighting::Propagated,
                    "{case}"
                );
                let separable = name == "two resonances";
                assert_eq!(check.identifiability.separable(), separable, "{case}");
                assert_eq!(report.identifiability.separable(), separable, "{case}");
                let text = check.to_string();
                let weighted_text = text.contains("rows weighted by their propagated noise");
                assert_eq!(weighted_text, check.weighted, "{text}");
                let wanted = format!(
                    "condition number σ₁/σₚ of the column-scaled regressor{}",
                    if check.weighted {
                        ", rows weighted"
                    } else {
                        ":"
                    }
                );
                assert!(report.to_string().contains(&wanted), "{report}");
            }
            // The unweighted rows, which check used to read, are conditioned differently
            // (3.65 weighted against 5.22 on the two resonances).
            if name != "two resonances" {
                continue;
            }
            let settings = robust();
            let regressor = Regressor::build(&model, &noisy, &settings.regressor).unwrap();
            let weighted = RegressorCheck::new(&regressor, &settings.fit).unwrap();
            let ordinary = diagnose(
                &regressor,
                &fit::least_squares(&regressor, 1e-10).unwrap(),
                1e-10,
            );
            let (a, b) = (
                weighted.condition_number.unwrap(),
                ordinary.condition_number,
            );
            assert!((a / b - 1.0).abs() > 0.1, "{name}: κ {a} vs {b}");
        }
    }
}

/// The ± of the determined combination c0 + λ_1 c1 on the noisy first-resonance set
/// is its scatter over 60 noise draws (1% displacement noise): the ratio of the
/// empirical standard deviation to the mean reported standard error lies in
/// [0.75, 1.35] (the sampling error of a 60-draw standard deviation is about 9%). The
/// ordinary least-squares ± the check used to print is reported below it for contrast.
#[test]
fn a_determined_combination_error_matches_its_scatter() {
    let settings = robust();
    let model = rayleigh();
    let clean = vec![record(1, 0.5, 8), record(1, 1.0, 8)];
    let (mut values, mut errors, mut ordinary_errors) = (vec![], vec![], vec![]);
    for seed in 0..60 {
        let noisy = with_displacement_noise(&clean, 0.01, 100 + seed).unwrap();
        let regressor = Regressor::build(&model, &noisy, &settings.regressor).unwrap();
        let check = RegressorCheck::new(&regressor, &settings.fit).unwrap();
        // A draw can make both coefficients determined (a wide, noisy second direction).
        let Some(d) = check.identifiability.determined.first() else {
            continue;
        };
        assert_eq!(d.combination.terms.len(), 2, "{:?}", d.combination);
        values.push(d.value);
        errors.push(d.std_error.unwrap());
        let ordinary = diagnose(
            &regressor,
            &fit::least_squares(&regressor, 1e-10).unwrap(),
            1e-10,
        );
        if let Some(d) = ordinary.identifiability.determined.first() {
            ordinary_errors.push(d.std_error.unwrap());
        }
    }
    assert!(values.len() >= 55, "{} draws rank 1", values.len());
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let scatter = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let reported = errors.iter().sum::<f64>() / n;
    let ratio = scatter / reported;
    let ordinary = ordinary_errors.iter().sum::<f64>() / ordinary_errors.len() as f64;
    assert!(
        (0.75..=1.35).contains(&ratio),
        "scatter {scatter:.3e}, mean ± {reported:.3e} (ordinary ± {ordinary:.3e})"
    );
}
