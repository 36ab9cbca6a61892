//! The bootstrap of variable projection (src/varpro/bootstrap.rs): every replicate
//! refits the nonlinear parameters η and the linear coefficients θ on resampled
//! windows (records) or whole sweeps (stepped-sine tables), against simulated truth
//! with noise; deterministic across thread counts; force × λ scales the coefficients'
//! intervals by λ and leaves η's alone.
//!
//! Records: the four-mass chain with d|v|^1.7 sign(v) on every mass (as tests/varpro.rs),
//! four force levels, four periods each, 1 % displacement noise. Tables: the one-DOF
//! oscillator of tests/stepped_sine.rs with a residual receptance r_k = −2e-6 m/N per
//! sweep, five sweeps of 11 points.

mod support;
#[path = "support/stepped_sine_table.rs"]
mod table;

use std::sync::OnceLock;

use dampid::analysis::bootstrap::BootstrapSettings;
use dampid::analysis::bootstrap::{Bootstrap, Resampled};
use dampid::prelude::*;
use dampid::reference::{FOUR_MASS_C, four_mass_system, with_displacement_noise};
use dampid::report::{Estimation, FitReport};
use dampid::simulate::{SimSettings, chain_stiffness, simulate};
use dampid::terms::laws::PowerLaw;
use dampid::terms::{Coefficients, Term};
use dampid::varpro::{NonlinearParameter, ParametricModel, VarProSettings};
use faer::Mat;

const D: f64 = 0.10;
const EXPONENT: f64 = 1.7;
const AMPLITUDES: [f64; 4] = [0.25, 0.5, 1.0, 2.0];
const CYCLES: usize = 4;

/// C = c K and d|v|^p sign(v) on every mass.
fn model(exponent: f64) -> dampid::Result<DampingModel> {
    Ok(DampingModel::new()
        .with(Term::stiffness_proportional("c", chain_stiffness(4)))
        .with(Term::per_dof(
            PowerLaw::new(exponent)?,
            4,
            Coefficients::Shared("d".into()),
        )))
}

fn parametric() -> ParametricModel {
    ParametricModel::new(
        vec![NonlinearParameter::new("exponent", 1.0, 0.5, 4.0)],
        |eta| model(eta[0]),
    )
    .unwrap()
}

/// The chain driven at its first resonance at four force levels, `CYCLES` whole
/// periods recorded after 5000 steps, with 1 % displacement noise.
fn noisy() -> &'static [Record] {
    static RECORDS: OnceLock<Vec<Record>> = OnceLock::new();
    RECORDS.get_or_init(|| {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let settings = SimSettings {
            transient_steps: 5000,
            recorded_steps: (CYCLES as f64 * period / 0.1).ceil() as usize + 4,
            ..SimSettings::default()
        };
        let clean: Vec<Record> = AMPLITUDES
            .iter()
            .map(|&a| {
                let mut system = four_mass_system(a, false);
                system.damping = model(EXPONENT).unwrap();
                system.damping_coefficients = vec![FOUR_MASS_C, D];
                simulate(&system, &settings, &dampid::progress::silent).unwrap()
            })
            .collect();
        with_displacement_noise(&clean, 0.01, 20).unwrap()
    })
}

/// The noise-robust default pipeline, one equation per whole period.
fn settings() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = dampid::prep::window::WindowSpec::cycles(1).into();
    settings
}

fn boot(replicates: usize, seed: u64) -> BootstrapSettings {
    BootstrapSettings {
        replicates,
        seed,
        level: 0.95,
    }
}

/// The fit on `records` (without the profile intervals, which the bootstrap does not
/// read) and its bootstrap.
fn fit_and_boot(records: &[Record], settings: &BootstrapSettings) -> (FitReport, Bootstrap) {
    let identify_settings = IdentifySettings {
        estimation: VarProSettings {
            profile: false,
            ..VarProSettings::default()
        },
        bootstrap: Some(*settings),
        ..self::settings()
    };
    let found = identify(
        &ParametricRegressor::new(parametric(), records),
        &identify_settings,
        &silent,
    )
    .unwrap();
    assert!(found.report.is_estimate(), "{}", found.report);
    (found.report, found.bootstrap.expect("a bootstrap"))
}

/// The estimation of a report with estimated parameters.
fn estimation(report: &FitReport) -> &Estimation {
    report.estimation.as_ref().expect("estimated parameters")
}

fn records_bootstrap() -> &'static (FitReport, Bootstrap) {
    static RESULT: OnceLock<(FitReport, Bootstrap)> = OnceLock::new();
    RESULT.get_or_init(|| fit_and_boot(noisy(), &boot(100, 0)))
}

/// Simulated truth at 1 % noise: the percentile intervals of the exponent, c and d
/// contain the truth, and their widths are of the order of the joint Wald intervals.
#[test]
fn records_intervals_cover_the_truth_and_match_the_joint_ones() {
    let (report, bootstrap) = records_bootstrap();
    println!("{report}");
    let summary = &bootstrap.summary;
    assert_eq!(summary.resampled, Resampled::Windows);
    assert_eq!(summary.groups, AMPLITUDES.len() * CYCLES);
    assert_eq!(summary.replicates, 100);
    assert_eq!(summary.used + summary.not_converged + summary.unusable, 100);
    assert_eq!(bootstrap.samples.len(), summary.used);
    let exponent = &bootstrap.parameters[0];
    assert_eq!(exponent.name, "exponent");
    let [wald_lo, wald_hi] = estimation(report).parameters[0].joint_interval.unwrap();
    let mut ratios = vec![(
        "exponent",
        (exponent.upper - exponent.lower) / (wald_hi - wald_lo),
    )];
    assert!(exponent.contains(EXPONENT), "{exponent:?}");
    for (truth, (interval, joint)) in [FOUR_MASS_C, D].into_iter().zip(
        bootstrap
            .coefficients
            .iter()
            .zip(&estimation(report).coefficients),
    ) {
        assert_eq!(interval.name, joint.name);
        assert!(interval.contains(truth), "{interval:?} truth {truth}");
        let width = joint.upper.unwrap() - joint.lower.unwrap();
        ratios.push((
            if joint.name == "c" { "c" } else { "d" },
            (interval.upper - interval.lower) / width,
        ));
    }
    println!("bootstrap / joint Wald interval widths: {ratios:?}");
    for (name, ratio) in ratios {
        assert!(
            (1.0 / 3.0..3.0).contains(&ratio),
            "{name}: width ratio {ratio}"
        );
    }
    // the standard error is the spread of the kept replicates
    let values: Vec<f64> = bootstrap.samples.iter().map(|s| s[0]).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let sd =
        (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (values.len() - 1) as f64).sqrt();
    assert!((sd - exponent.std_error).abs() <= 1e-12 * sd);
    // the text and the JSON carry it
    let text = report.to_string();
    assert!(text.contains("windows resampled"), "{text}");
    assert!(text.contains("95% percentile interval"), "{text}");
    let json = serde_json::to_value(report).unwrap();
    assert_eq!(json["bootstrap"]["resampled"], "windows");
    assert_eq!(
        json["estimation"]["parameters"][0]["bootstrap"]["name"],
        "exponent"
    );
    let back: FitReport = serde_json::from_value(json).unwrap();
    let intervals: Vec<_> = back
        .coefficients
        .iter()
        .map(|c| c.interval.clone().unwrap())
        .collect();
    assert_eq!(intervals, bootstrap.coefficients);
}

/// The same bits on 1 and 3 threads; the same seed twice gives the same result and
/// another seed another one.
#[test]
fn results_do_not_depend_on_the_thread_count_and_follow_the_seed() {
    let on = |threads: usize, seed: u64| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fit_and_boot(noisy(), &boot(12, seed)).1)
    };
    let bits = |b: &Bootstrap| -> Vec<Vec<u64>> {
        b.samples
            .iter()
            .map(|s| s.iter().map(|v| v.to_bits()).collect())
            .collect()
    };
    let (one, three) = (on(1, 7), on(3, 7));
    assert_eq!(bits(&one), bits(&three));
    assert_eq!(one, three);
    assert_eq!(on(1, 7), one);
    let other = on(3, 8);
    assert_ne!(other.drawn, one.drawn);
    assert_ne!(bits(&other), bits(&one));
}

/// Force × λ: b scales by λ, A(η) does not, so every replicate (the same draws) finds
/// the same η* and λ θ*: the coefficients' intervals scale by λ, the exponent's stays.
/// The outer loop stops at a relative change of its cost of 10⁻⁸, not at round-off (a
/// power-of-two λ = 1024 still moves η* by about 10⁻⁶ of its bootstrap se): the
/// intervals agree to 10⁻⁴ of the standard errors.
#[test]
fn force_scale_scales_the_coefficients_intervals_and_leaves_the_exponent() {
    let lambda = 1024.0;
    let scaled: Vec<Record> = noisy()
        .iter()
        .map(|r| {
            let parts = r.parts().clone();
            let signals = &parts.forcing.signals;
            let forcing = Forcing {
                signals: Mat::from_fn(signals.nrows(), signals.ncols(), |i, j| {
                    lambda * signals[(i, j)]
                }),
                distribution: parts.forcing.distribution.clone(),
            };
            Record::new(RecordParts { forcing, ..parts }).unwrap()
        })
        .collect();
    let (_, base) = fit_and_boot(noisy(), &boot(16, 3));
    let (_, other) = fit_and_boot(&scaled, &boot(16, 3));
    assert_eq!(base.drawn, other.drawn);
    assert_eq!(base.summary.used, other.summary.used);
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-4 * scale;
    for (a, b) in base.parameters.iter().zip(&other.parameters) {
        for (x, y) in [
            (a.lower, b.lower),
            (a.upper, b.upper),
            (a.std_error, b.std_error),
        ] {
            assert!(close(x, y, a.std_error), "{}: {x} vs {y}", a.name);
        }
    }
    for (a, b) in base.coefficients.iter().zip(&other.coefficients) {
        for (x, y) in [
            (a.lower, b.lower),
            (a.upper, b.upper),
            (a.std_error, b.std_error),
        ] {
            assert!(
                close(lambda * x, y, lambda * a.std_error),
                "{}: {x} × λ vs {y}",
                a.name
            );
        }
    }
}

/// A stepped-sine table with its residual receptance estimated per sweep: a replicate
/// draws whole sweeps (every drawn index a sweep, five per replicate), and the
/// intervals of c and d cover the truth of the generated table. (The sweeps' r_k keep
/// their points in every replicate, so their bootstrap spread is that of c and d alone:
/// the report says to read their joint intervals.)
#[test]
fn whole_sweeps_are_resampled_and_cover_the_truth() {
    let levels = [0.1, 0.5, 1.0, 2.0, 3.0];
    let columns = table::residual_columns_at(
        &levels,
        11,
        table::R_K,
        0.0,
        1.0,
        Some((20, 0.005, 0.3f64.to_radians())),
    );
    let file = std::env::temp_dir().join(format!(
        "dampid_varpro_bootstrap_{}_sweeps.csv",
        std::process::id()
    ));
    support::write_scratch_csv(&file, &table::headers(), &columns);
    let job = dampid::model_file::parse(
        &table::model_text(&file, "residual = \"stiffness\""),
        "test.toml",
        std::path::Path::new("."),
        Default::default(),
    )
    .unwrap();
    let problem = job.problem();
    let sweeps = problem.groups().unwrap();
    assert_eq!(sweeps.len(), levels.len() * 11);
    let settings = IdentifySettings {
        bootstrap: Some(boot(40, 1)),
        ..job.settings.clone()
    };
    let found = identify(&problem, &settings, &silent).unwrap();
    let report = &found.report;
    assert!(report.is_estimate(), "{report}");
    let bootstrap = found.bootstrap.clone().expect("a bootstrap");
    let text = report.to_string();
    println!("{text}");
    assert!(text.contains("whole sweeps resampled"), "{text}");
    assert!(text.contains("read its joint interval"), "{text}");
    assert_eq!(bootstrap.summary.resampled, Resampled::Sweeps);
    assert_eq!(bootstrap.summary.groups, levels.len());
    assert_eq!(bootstrap.drawn.len(), 40);
    for drawn in &bootstrap.drawn {
        assert_eq!(drawn.len(), levels.len());
        assert!(drawn.iter().all(|&g| g < levels.len()));
    }
    // whole sweeps, with replacement: some replicate repeats a sweep
    assert!(bootstrap.drawn.iter().any(|d| {
        let mut d = d.clone();
        d.sort();
        d.dedup();
        d.len() < levels.len()
    }));
    assert!(bootstrap.summary.used * 2 >= 40);
    assert_eq!(bootstrap.parameters.len(), levels.len());
    for (name, truth) in [("c", table::C), ("d", table::D)] {
        let interval = bootstrap
            .coefficients
            .iter()
            .find(|i| i.name == name)
            .unwrap();
        let joint = estimation(report)
            .coefficients
            .iter()
            .find(|c| c.name == name)
            .unwrap();
        println!(
            "{name}: bootstrap [{}, {}], joint [{}, {}]",
            interval.lower,
            interval.upper,
            joint.lower.unwrap(),
            joint.upper.unwrap()
        );
        assert!(interval.contains(truth), "{interval:?} truth {truth}");
        assert!(
            interval.upper - interval.lower < 0.5 * truth,
            "{interval:?}"
        );
    }
}
