//! The window bootstrap: coverage of its percentile intervals on noisy data, results
//! independent of the thread count, constrained fits, and bad settings.

use dampid::analysis::bootstrap::{BootstrapSettings, bootstrap};
use dampid::fit::{FitMethod, FitSettings};
use dampid::identify::{IdentifySettings, identify};
use dampid::prelude::*;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

mod support;
use support::regressors::row_labels;

/// True Rayleigh coefficients of the 2-DOF chain.
const C0: f64 = 0.05;
const C1: f64 = 0.05;

/// C = c0 I + c1 K on a 2-DOF chain (M = I, K = tridiag(−1, 2, −1), λ = 1, 3).
fn model() -> DampingModel {
    let k = Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 });
    DampingModel::new()
        .with(Term::mass_proportional("c0", Mat::identity(2, 2)))
        .with(Term::stiffness_proportional("c1", k))
}

/// Periods recorded per experiment (one window each).
const PERIODS: f64 = 30.0;

/// Noise-free records at both resonances (ω = 1 and √3), force on mass 1, [`PERIODS`]
/// periods each after 400 time units of transient (the slower mode decays at 0.05:
/// e^-20).
fn clean_records() -> Vec<Record> {
    [1.0f64, 3.0f64.sqrt()]
        .iter()
        .map(|&omega| {
            let system = System {
                mass: Mat::identity(2, 2),
                stiffness: Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 }),
                damping: model(),
                damping_coefficients: vec![C0, C1],
                conservative: Vec::new(),
                forcing: vec![HarmonicForce {
                    dof: 0,
                    amplitude: 1.0,
                    frequency: omega,
                    phase: 0.0,
                }],
            };
            let period = 2.0 * std::f64::consts::PI / omega;
            let settings = SimSettings {
                step: 0.1,
                substeps: 2,
                transient_steps: 4000,
                recorded_steps: (PERIODS * period / 0.1).ceil() as usize + 3,
            };
            simulate(&system, &settings, &dampid::progress::silent).unwrap()
        })
        .collect()
}

/// Each displacement channel plus white Gaussian noise of 1% of its RMS.
fn noisy(records: &[Record], seed: u64) -> Vec<Record> {
    let mut rng = StdRng::seed_from_u64(seed);
    records
        .iter()
        .map(|r| {
            let mut parts = r.parts().clone();
            let x = &mut parts.displacements;
            for j in 0..x.ncols() {
                let rms = (x.col(j).iter().map(|v| v * v).sum::<f64>() / x.nrows() as f64).sqrt();
                let noise = Normal::new(0.0, 0.01 * rms).unwrap();
                for i in 0..x.nrows() {
                    x[(i, j)] += noise.sample(&mut rng);
                }
            }
            parts.velocities = None;
            Record::new(parts).unwrap()
        })
        .collect()
}

/// One window per period; velocities from the displacements by projecting each window
/// on the fundamental (the motion of a linear system has no other harmonic), and the
/// spectral rule (exact for the resulting band-limited power). The plain pipeline
/// (ordinary least squares): these tests measure the window bootstrap itself. (With
/// the noise-robust pipeline's weights, refitted in every replicate, the same
/// repetitions gave a coverage of 0.8975 for c1, just under the 0.90 asked here; its
/// plug-in intervals are checked in tests/noise.rs.)
fn settings() -> IdentifySettings {
    IdentifySettings {
        regressor: RegressorSettings::plain(
            WindowSpec::cycles(1),
            Quadrature::Spectral,
            VelocitySource::HarmonicProjection { harmonics: Some(1) },
        ),
        ..IdentifySettings::default()
    }
}

/// With 1% displacement noise, the 95% percentile intervals of the window bootstrap
/// cover the true coefficients in 90–99% of 400 seeded repetitions (one noise draw and
/// one bootstrap of 1000 replicates each; 60 windows of one period). Noise-free, the
/// same pipeline recovers the truth to 1e-5, far inside the intervals' width (about
/// 0.3%), so coverage measures the intervals. Percentile intervals undercover a little
/// at this size: other seed sets of 200 gave 0.90–0.945.
#[test]
fn window_bootstrap_intervals_cover_the_truth() {
    let start = std::time::Instant::now();
    let clean = clean_records();
    let exact = identify(
        &ParametricRegressor::linear(&model(), &clean),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    for (name, truth) in [("c0", C0), ("c1", C1)] {
        let e = exact.coefficient(name).unwrap();
        assert!((e - truth).abs() < 1e-5 * truth, "noise-free {name} = {e}");
    }
    let repetitions = 400;
    let mut covered = [0usize; 2];
    let mut widths = [0.0f64; 2];
    for rep in 0..repetitions {
        let records = noisy(&clean, 1000 + rep as u64);
        let regressor =
            Regressor::build(&model(), &records, &settings().regressor).expect("regressor");
        let b = bootstrap(
            &regressor,
            &FitSettings::default(),
            &BootstrapSettings {
                replicates: 1000,
                seed: rep as u64,
                level: 0.95,
            },
            None,
            &silent,
        )
        .unwrap();
        assert_eq!(b.summary.used, 1000);
        for (k, truth) in [C0, C1].iter().enumerate() {
            let interval = &b.coefficients[k];
            if interval.contains(*truth) {
                covered[k] += 1;
            }
            widths[k] += (interval.upper - interval.lower) / truth / repetitions as f64;
        }
    }
    let coverage = covered.map(|c| c as f64 / repetitions as f64);
    eprintln!(
        "coverage of 95% intervals over {repetitions} repetitions: c0 {:.3}, c1 {:.3}; mean relative width c0 {:.4}, c1 {:.4}; {:.1?}",
        coverage[0],
        coverage[1],
        widths[0],
        widths[1],
        start.elapsed()
    );
    for (name, c) in ["c0", "c1"].iter().zip(coverage) {
        assert!((0.90..=0.99).contains(&c), "coverage of {name}: {c}");
    }
}

/// The same seed gives the same replicates on 1 thread and on 3.
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let records = noisy(&clean_records(), 7);
    let regressor = Regressor::build(&model(), &records, &settings().regressor).unwrap();
    let settings = BootstrapSettings {
        replicates: 300,
        seed: 42,
        level: 0.9,
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                bootstrap(
                    &regressor,
                    &FitSettings::default(),
                    &settings,
                    None,
                    &silent,
                )
                .unwrap()
            })
    };
    let (one, three) = (run(1), run(3));
    assert_eq!(one, three);
    let other_seed = bootstrap(
        &regressor,
        &FitSettings::default(),
        &BootstrapSettings {
            seed: 43,
            ..settings
        },
        None,
        &silent,
    )
    .unwrap();
    assert_ne!(one.samples, other_seed.samples);
}

/// Rows that all satisfy b = Aθ exactly give θ in every replicate: the interval is the
/// point θ. A = [[1, 0], [0, 1], [1, 1], [2, 1]], θ = (2, 3).
#[test]
fn consistent_rows_give_a_point_interval() {
    let rows = [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 1.0], [1.0, 3.0]];
    let a = Mat::from_fn(5, 2, |i, j| rows[i][j]);
    let b = rows.iter().map(|r| 2.0 * r[0] + 3.0 * r[1]).collect();
    let labels = row_labels(5);
    let r = Regressor::from_parts(a, b, vec!["a".into(), "b".into()], labels).unwrap();
    let boot = bootstrap(
        &r,
        &FitSettings::default(),
        &BootstrapSettings::default(),
        None,
        &silent,
    )
    .unwrap();
    // No two rows are proportional, so only a replicate that draws one row five times
    // (probability 5·0.2⁵ = 0.0016) loses rank and is dropped.
    assert!(boot.summary.used >= 990, "{}", boot.summary.used);
    for (interval, truth) in boot.coefficients.iter().zip([2.0, 3.0]) {
        assert!((interval.lower - truth).abs() < 1e-12 && (interval.upper - truth).abs() < 1e-12);
    }
}

/// A constrained fit is bootstrapped with its constraints: with c1 fixed, every
/// replicate keeps c1 exactly and the report shows the interval beside the estimate.
#[test]
fn constrained_fits_are_bootstrapped_with_their_constraints() {
    let records = noisy(&clean_records(), 11);
    let mut s = settings();
    s.fit.constraints = Constraints {
        nonnegative: true,
        fixed: vec![Fixed {
            name: "c1".into(),
            value: C1,
        }],
        ..Constraints::default()
    };
    let report = identify(
        &ParametricRegressor::linear(&model(), &records),
        &IdentifySettings {
            bootstrap: Some(BootstrapSettings {
                replicates: 200,
                seed: 3,
                level: 0.95,
            }),
            ..s.clone()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let summary = report.bootstrap.unwrap();
    assert_eq!(summary.method, FitMethod::Constrained);
    let c1 = report.coefficients[1].interval.as_ref().unwrap();
    assert_eq!((c1.lower, c1.upper), (C1, C1));
    let c0 = report.coefficients[0].interval.as_ref().unwrap();
    assert!(c0.lower < c0.upper && c0.contains(report.coefficients[0].value));
    let text = report.to_string();
    assert!(
        text.contains("95% interval") && text.contains("seed 3"),
        "{text}"
    );
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["bootstrap"]["used"], summary.used);
    assert!(json["coefficients"][0]["interval"]["lower"].is_number());
}

#[test]
fn bad_bootstrap_settings_are_typed_errors() {
    let records = noisy(&clean_records(), 5);
    let regressor = Regressor::build(&model(), &records, &settings().regressor).unwrap();
    for (settings, name, value) in [
        (
            BootstrapSettings {
                replicates: 1,
                ..BootstrapSettings::default()
            },
            "replicates",
            1.0,
        ),
        (
            BootstrapSettings {
                level: 1.0,
                ..BootstrapSettings::default()
            },
            "confidence level",
            1.0,
        ),
    ] {
        match bootstrap(
            &regressor,
            &FitSettings::default(),
            &settings,
            None,
            &silent,
        ) {
            Err(Error::InvalidParameter {
                name: n, value: v, ..
            }) => {
                assert_eq!((n.as_str(), v), (name, value))
            }
            other => panic!("{other:?}"),
        }
    }
}

/// A regressor without equations is a typed error, not a panic.
#[test]
fn a_regressor_without_rows_is_too_few_equations() {
    let empty = Regressor::from_parts(
        Mat::zeros(0, 2),
        Vec::new(),
        vec!["a".into(), "b".into()],
        Vec::new(),
    )
    .unwrap();
    assert!(matches!(
        bootstrap(
            &empty,
            &FitSettings::default(),
            &BootstrapSettings::default(),
            None,
            &silent
        ),
        Err(Error::TooFewEquations {
            equations: 0,
            coefficients: 2
        })
    ));
}
