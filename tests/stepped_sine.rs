//! Stepped-sine tables from model files (`[stepped_sine]`): the weighted energy
//! equations, structural damping in closed form, equivalent damping versus amplitude,
//! resampling whole sweeps, the negative-damping warning, and the residual receptance
//! of out-of-band modes estimated per sweep with the damping.
//!
//! The truth is a one-DOF oscillator m ẍ + c ẋ + d |ẋ|^1.5 sign ẋ + k x = a cos ωt in
//! the harmonic (describing-function) approximation, solved here by hand: the power
//! law dissipates E_p = d ω^1.5 X^2.5 I per cycle, I = ∫₀^{2π} |sin θ|^2.5 dθ, i.e.
//! an equivalent viscous c_eq(X) = c + E_p/(πωX²) = c + d (ωX)^0.5 I/π, so
//!
//! ```text
//!   X |k − mω² + iω c_eq(X)| = a,     φ = atan2(ω c_eq(X), k − mω²)   (the lag),
//! ```
//!
//! X found by bisection (the left side grows with X). Energy balance per cycle, exact
//! under the approximation: π a X sin φ = π c ω X² + E_p(X), the equation dampid fits.
//!
//! The residual tables (as models/data/bolted_joint/generate.py) add the response of the
//! other modes, real and in phase with the force: Z = X e^{−iφ} + R(ω) a with
//! R(ω) = r_k − r_m/ω², and measure |Z| and −arg Z. Removing the true R gives the
//! mode's X and φ back exactly, so the noise-free fit is again exact.

mod support;
#[path = "support/stepped_sine_table.rs"]
mod table;

use dampid::progress::silent;
use dampid::regressor::ParametricRegressor;
use std::path::{Path, PathBuf};

use dampid::analysis::bootstrap::{BootstrapSettings, bootstrap};
use dampid::identify::Equivalent;
use dampid::identify::{IdentifySettings, identify};
use dampid::model::DampingModel;
use dampid::prep::harmonic::sweeps::{PointNoise, SweptTable};
use dampid::prep::harmonic::{HarmonicApproximation, SteppedSinePoint, SteppedSineTable};
use dampid::regressor::Regressor;
use dampid::regressor::SteppedSineSource;
use dampid::regressor::stepped_sine::StructuralTerm;
use dampid::report::{FitReport, Warning};
use table::*;

/// The table's columns: level, frequency (Hz), force, amplitude, phase (degrees, lag).
/// Relative noise `noise.0` on force and amplitude, `noise.1` rad on the phase.
fn table_columns(c: f64, d: f64, noise: Option<(u64, f64, f64)>) -> Vec<Vec<f64>> {
    let levels = [0.05, 0.2, 0.5, 1.0, 2.0];
    let fn_hz = K.sqrt() / (2.0 * std::f64::consts::PI);
    let mut columns = vec![Vec::new(); 5];
    let mut rng = Normal(noise.map_or(0, |n| n.0));
    for (l, &force) in levels.iter().enumerate() {
        for i in 0..15 {
            let f_hz = fn_hz * (0.97 + 0.06 * i as f64 / 14.0);
            let (x, phi) = response(2.0 * std::f64::consts::PI * f_hz, force, c, d);
            let (mut a, mut x, mut phi) = (force, x, phi);
            if let Some((_, relative, phase)) = noise {
                a *= 1.0 + relative * rng.sample();
                x *= 1.0 + relative * rng.sample();
                phi += phase * rng.sample();
            }
            columns[0].push(l as f64 + 1.0);
            columns[1].push(f_hz);
            columns[2].push(a);
            columns[3].push(x);
            columns[4].push(phi.to_degrees());
        }
    }
    columns
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_stepped_sine_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn job_of(name: &str, columns: &[Vec<f64>], extra: &str) -> dampid::model_file::Job {
    let file = scratch(name);
    support::write_scratch_csv(&file, &headers(), columns);
    dampid::model_file::parse(
        &model_text(&file, extra),
        "test.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap()
}

/// Noise-free: the energy equations are exact under the approximation, so c and d come
/// back to quadrature accuracy (N = 512 samples per synthesized period).
#[test]
fn viscous_and_power_law_come_back_noise_free() {
    let job = job_of("clean.csv", &table_columns(C, D, None), "");
    let regressor = job.initial_regressor().unwrap();
    assert_eq!(regressor.equations(), 75);
    assert!(
        regressor.noise().is_some(),
        "the equations carry a noise model"
    );
    let report = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings {
            fit: job.settings.fit.clone(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let c = report.coefficient("c").unwrap();
    let d = report.coefficient("d").unwrap();
    assert!((c - C).abs() < 1e-4 * C, "c = {c}");
    assert!((d - D).abs() < 1e-4 * D, "d = {d}");
}

/// 0.5 % amplitude and force noise, 0.005 rad phase noise, estimated from the scatter
/// along each sweep: the weighted fit's χ² check accepts the model, and the truth lies
/// within four calibrated standard errors of each estimate.
#[test]
fn noisy_table_is_weighted_and_calibrated() {
    let job = job_of(
        "noisy.csv",
        &table_columns(C, D, Some((7, 0.005, 0.005))),
        "",
    );
    let regressor = job.initial_regressor().unwrap();
    let report = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings {
            fit: job.settings.fit.clone(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let noise = report.noise.as_ref().expect("weighted fit");
    assert!(
        noise.p_value.unwrap() > 1e-3,
        "χ² = {} for {} dof",
        noise.chi_square,
        noise.degrees_of_freedom
    );
    for (name, truth) in [("c", C), ("d", D)] {
        let estimate = report.coefficients.iter().find(|c| c.name == name).unwrap();
        let se = estimate.std_error.unwrap();
        assert!(
            (estimate.value - truth).abs() < 4.0 * se,
            "{name} = {} ± {se}, truth {truth}",
            estimate.value
        );
        assert!(
            se < 0.2 * truth,
            "{name}: se {se} too large to mean anything"
        );
    }
    // Whole sweeps resampled: five groups, intervals that contain the estimate.
    let problem = job.problem();
    let sweeps = problem.groups().unwrap();
    let boot = bootstrap(
        &regressor,
        &job.settings.fit,
        &BootstrapSettings {
            replicates: 200,
            ..Default::default()
        },
        Some(sweeps),
        &dampid::progress::silent,
    )
    .unwrap();
    assert!(boot.summary.used >= 100);
    for (interval, c) in boot.coefficients.iter().zip(&report.coefficients) {
        assert!(interval.lower < interval.upper);
        assert!(interval.std_error > 0.0);
        assert_eq!(interval.name, c.name);
    }
}

/// One sweep cannot be resampled as a whole: an error, not a degenerate interval.
#[test]
fn one_sweep_cannot_be_resampled() {
    let job = job_of("one_sweep.csv", &table_columns(C, D, None), "");
    let regressor = job.initial_regressor().unwrap();
    let e = bootstrap(
        &regressor,
        &job.settings.fit,
        &BootstrapSettings::default(),
        Some(&vec![0; regressor.equations()]),
        &dampid::progress::silent,
    )
    .unwrap_err();
    assert!(matches!(e, dampid::Error::InvalidChoice { .. }), "{e}");
}

/// Pure viscous damping: ζ_eq = c/(2√(km)) at every amplitude, η = 2ζ. With [system]
/// the modal mass is the given one; without it Re(a/Z) = k − mω² holds exactly for the
/// viscous oscillator, so the lowest level's FRF gives m and k back.
#[test]
fn equivalent_damping_of_a_viscous_oscillator() {
    let columns = table_columns(C, 0.0, None);
    let zeta = C / (2.0 * (K * M).sqrt());
    for extra in [
        "[system]\nmass = [[1.0]]\nstiffness = [[98696.0440108936]]",
        "",
    ] {
        let job = job_of("viscous.csv", &columns, extra);
        let found = identify(&job.problem(), &job.settings, &silent).unwrap();
        let Some(Equivalent::Computed(equivalent)) = found.equivalent else {
            panic!("no equivalent damping: {:?}", found.equivalent)
        };
        assert!(
            (equivalent.modal.mass - M).abs() < 1e-6,
            "{:?}",
            equivalent.modal
        );
        assert!((equivalent.modal.stiffness - K).abs() < 1e-6 * K);
        for p in &equivalent.points {
            assert!((p.damping_ratio - zeta).abs() < 1e-4 * zeta, "{p:?}");
            assert!((p.loss_factor - 2.0 * p.damping_ratio).abs() < 1e-15);
            assert!(p.damping_ratio_std.is_some());
        }
        let text = equivalent.to_string();
        assert!(text.contains(if extra.is_empty() {
            "lowest level"
        } else {
            "[system]"
        }));
    }
}

/// Structural damping in closed form. A one-DOF oscillator with complex stiffness
/// k(1 + iη) driven by a cos ωt has Z = a/(k − mω² + iηk), so
/// X = a/|k − mω² + iηk| and sin φ = ηk/|k − mω² + iηk|; the input work per cycle is
/// π a X sin φ = π a X · ηk X/a = π η k X², which is the structural column π k X²
/// times η: the fit returns η exactly (to round-off), at any frequency.
#[test]
fn structural_damping_closed_form() {
    let eta: f64 = 0.012;
    let k: f64 = 2.0e5;
    let m: f64 = 3.0;
    let points: Vec<SteppedSinePoint> = [0.8f64, 0.95, 1.0, 1.07, 1.3]
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let omega = r * (k / m).sqrt();
            let a = 1.0 + i as f64;
            let (re, im) = (k - m * omega * omega, eta * k);
            let modulus = (re * re + im * im).sqrt();
            SteppedSinePoint {
                label: format!("p{i}"),
                frequency: omega,
                force_dof: 0,
                force_amplitude: a,
                amplitudes: vec![a / modulus],
                phases: vec![im.atan2(re)],
            }
        })
        .collect();
    let n = points.len();
    let swept = SweptTable::with_noise(
        SteppedSineTable::new(points.clone()).unwrap(),
        vec![0; n],
        vec!["all".into()],
        vec![
            PointNoise {
                force: 0.0,
                amplitudes: vec![0.0],
                phases: vec![1e-3],
            };
            n
        ],
    )
    .unwrap();
    let structural = [StructuralTerm {
        coefficient: "eta".into(),
        stiffness: k,
        from: Some(0),
        to: None,
    }];
    let mut table = SteppedSineSource::new(swept, HarmonicApproximation::default());
    table.structural = structural.to_vec();
    let regressor = Regressor::build(
        &DampingModel::new(),
        &table,
        &dampid::regressor::RegressorSettings::default(),
    )
    .unwrap();
    for (r, p) in points.iter().enumerate() {
        let x = p.amplitudes[0];
        let expected = std::f64::consts::PI * k * x * x;
        assert!((regressor.matrix()[(r, 0)] - expected).abs() < 1e-12 * expected);
    }
    let report = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings::default(),
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let estimate = report.coefficient("eta").unwrap();
    assert!((estimate - eta).abs() < 1e-12, "η = {estimate}");
}

/// An unconstrained fit with a negative coefficient warns and names it; the same
/// rows fitted with nonnegative bounds do not. Rows (1, 1), (1, 2), (1, 3) with
/// b = (1, 0.5, 0) are consistent: θ = (1.5, −0.5) exactly.
#[test]
fn negative_damping_is_a_warning() {
    use dampid::fit::{Constraints, FitSettings};
    let a = faer::Mat::from_fn(3, 2, |r, k| [[1.0, 1.0], [1.0, 2.0], [1.0, 3.0]][r][k]);
    let labels = (0..3)
        .map(|r| dampid::regressor::RowLabel {
            record: format!("r{r}"),
            record_index: r,
            window: 0,
            start_time: 0.0,
            cycles: 1,
            frequency: None,
        })
        .collect();
    let regressor = Regressor::from_parts(
        a,
        vec![1.0, 0.5, 0.0],
        vec!["c".into(), "friction".into()],
        labels,
    )
    .unwrap();
    let report = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings {
            fit: FitSettings::default(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let warning = report
        .warnings
        .iter()
        .find(|w| matches!(w, Warning::NegativeDamping { .. }))
        .expect("a negative-damping warning");
    let text = warning.to_string();
    assert!(text.contains("friction = -5.0000e-1"), "{text}");
    assert!(text.contains("nonnegative"), "{text}");
    assert!(!text.contains("c = "), "{text}");
    let json = serde_json::to_value(warning).unwrap();
    assert_eq!(json["kind"], "negative_damping");
    let bounded = FitSettings {
        constraints: Constraints::nonnegative(),
        ..FitSettings::default()
    };
    let report = identify(
        &ParametricRegressor::rows(&regressor),
        &IdentifySettings {
            fit: bounded.clone(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    assert!(
        !report
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::NegativeDamping { .. }))
    );
}

/// The variable-projection fit of a table with estimated residuals or law parameters,
/// as `dampid identify` runs it.
fn fit_residual(job: &dampid::model_file::Job) -> FitReport {
    let problem = job.problem();
    assert!(!problem.is_linear(), "something estimated");
    let report = identify(&problem, &job.settings, &silent).unwrap().report;
    assert!(report.is_estimate(), "{report}");
    report
}

fn coefficient(report: &FitReport, name: &str) -> f64 {
    report.coefficient(name).unwrap()
}

/// The estimated parameters of a report.
fn parameters(report: &FitReport) -> &[dampid::varpro::NonlinearEstimate] {
    &report.estimation.as_ref().expect("estimated").parameters
}

/// Coefficient `name` of a report with estimated parameters, with its joint interval.
fn joint<'a>(report: &'a FitReport, name: &str) -> &'a dampid::varpro::JointEstimate {
    let estimation = report.estimation.as_ref().expect("estimated");
    estimation
        .coefficients
        .iter()
        .find(|c| c.name == name)
        .unwrap()
}

/// Noise-free, R = −2e-6 m/N in every sweep: with `residual = "stiffness"` the fit
/// removes it, c and d come back within 1 % and every sweep's r_k within 5 %; without
/// it the damping columns read |Z| instead of |Z − R a| and the same fit is measurably
/// worse (docs/stepped_sine.md quotes the numbers this prints with --nocapture).
#[test]
fn residual_stiffness_comes_back_noise_free_and_its_neglect_biases() {
    let columns = residual_columns(R_K, 0.0, 1.0, None);
    let job = job_of("residual_clean.csv", &columns, "residual = \"stiffness\"");
    let report = fit_residual(&job);
    let (c, d) = (coefficient(&report, "c"), coefficient(&report, "d"));
    println!(
        "with the residual: c = {c}, d = {d}, relative residual {:.3e}",
        report.relative_residual
    );
    assert!((c - C).abs() < 0.01 * C, "c = {c}");
    assert!((d - D).abs() < 0.01 * D, "d = {d}");
    assert_eq!(parameters(&report).len(), LEVELS.len());
    for p in parameters(&report) {
        println!("{} = {:e}", p.name, p.value);
        assert!(p.name.starts_with("r_k (level = "), "{}", p.name);
        assert!(
            (p.value - R_K).abs() < 0.05 * R_K.abs(),
            "{} = {}",
            p.name,
            p.value
        );
    }
    // The residual ignored: the same table, the ordinary weighted fit.
    let plain = job_of("residual_ignored.csv", &columns, "");
    assert!(plain.problem().is_linear());
    let biased = identify(
        &ParametricRegressor::rows(&plain.initial_regressor().unwrap()),
        &IdentifySettings {
            fit: plain.settings.fit.clone(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap();
    let (cb, db) = (
        biased.coefficient("c").unwrap(),
        biased.coefficient("d").unwrap(),
    );
    println!(
        "without: c = {cb} ({:+.2} %), d = {db} ({:+.2} %), relative residual {:.3e}",
        100.0 * (cb / C - 1.0),
        100.0 * (db / D - 1.0),
        biased.relative_residual
    );
    let error = |c: f64, d: f64| ((c / C - 1.0).abs()).max((d / D - 1.0).abs());
    assert!(
        error(cb, db) > 10.0 * error(c, d),
        "neglected: {} vs {}",
        error(cb, db),
        error(c, d)
    );
    assert!(
        biased.relative_residual > 10.0 * report.relative_residual,
        "relative residual {} neglected vs {} estimated",
        biased.relative_residual,
        report.relative_residual
    );
}

/// R(ω) = r_k − r_m/ω² with a residual mass too: `mass_and_stiffness` gives R back
/// within 5 % over each sweep's band (r_k and r_m/ω² are nearly collinear over ±3 %,
/// so the pair is checked through R at the band's ends), and c, d within 1 %.
#[test]
fn residual_mass_and_stiffness_noise_free() {
    let w0 = 2.0 * std::f64::consts::PI * 50.0;
    // r_m/ω₀² = 1e-6: R(ω₀) = −3e-6
    let r_m = 1e-6 * w0 * w0;
    let columns = residual_columns(-2.0e-6, r_m, 1.0, None);
    let job = job_of(
        "residual_mass.csv",
        &columns,
        "residual = \"mass_and_stiffness\"",
    );
    let report = fit_residual(&job);
    let (c, d) = (coefficient(&report, "c"), coefficient(&report, "d"));
    assert!((c - C).abs() < 0.01 * C, "c = {c}");
    assert!((d - D).abs() < 0.01 * D, "d = {d}");
    assert_eq!(parameters(&report).len(), 2 * LEVELS.len());
    for pair in parameters(&report).chunks(2) {
        assert!(pair[0].name.starts_with("r_k") && pair[1].name.starts_with("r_m"));
        for f in [0.97, 1.03] {
            let w = f * w0;
            let truth = -2.0e-6 - r_m / (w * w);
            let r = pair[0].value - pair[1].value / (w * w);
            assert!(
                (r - truth).abs() < 0.05 * truth.abs(),
                "R({f} ω₀) = {r:e}, truth {truth:e}"
            );
        }
    }
}

/// With the noise of the committed generator (0.5 % on force and amplitude, 0.3° on
/// the phase, estimated from the scatter along each sweep): the joint 95 % intervals of
/// c and d cover the truth, and so do those of the sweeps' r_k (at least six of
/// seven: each is a 95 % interval).
#[test]
fn residual_intervals_cover_the_truth_with_noise() {
    let columns = residual_columns(R_K, 0.0, 1.0, Some((20, 0.005, 0.3f64.to_radians())));
    let job = job_of("residual_noisy.csv", &columns, "residual = \"stiffness\"");
    let report = fit_residual(&job);
    for (name, truth) in [("c", C), ("d", D)] {
        let e = joint(&report, name);
        let (lower, upper) = (e.lower.unwrap(), e.upper.unwrap());
        println!("{name} = {} [{lower}, {upper}]", e.value);
        assert!(
            lower <= truth && truth <= upper,
            "{name}: [{lower}, {upper}], truth {truth}"
        );
        assert!(
            upper - lower < 0.2 * truth,
            "{name}: interval too wide to mean anything"
        );
    }
    let mut covered = 0;
    for p in parameters(&report) {
        let [lower, upper] = p.joint_interval.expect("joint interval");
        println!("{} = {:e} [{lower:e}, {upper:e}]", p.name, p.value);
        assert!(
            p.interval.is_none(),
            "residuals are nuisance parameters: no profile"
        );
        covered += usize::from(lower <= R_K && R_K <= upper);
    }
    assert!(covered >= 6, "{covered} of 7 intervals cover r_k");
}

/// Units: the force column × k (a force in other units) multiplies every energy
/// π a X sin φ and so every damping coefficient by k, and divides the receptance
/// X/a and so every residual by k. The default bounds scale with it, so the outer
/// loop sees the same problem in its unit box.
#[test]
fn force_scale_scales_coefficients_and_residuals() {
    let k = 1000.0;
    let base = job_of(
        "residual_unit.csv",
        &residual_columns(R_K, 0.0, 1.0, Some((3, 0.005, 0.3f64.to_radians()))),
        "residual = \"stiffness\"",
    );
    let scaled = job_of(
        "residual_scaled.csv",
        &residual_columns(R_K, 0.0, k, Some((3, 0.005, 0.3f64.to_radians()))),
        "residual = \"stiffness\"",
    );
    let (a, b) = (fit_residual(&base), fit_residual(&scaled));
    for (ca, cb) in a.coefficients.iter().zip(&b.coefficients) {
        assert!(
            (cb.value - k * ca.value).abs() < 1e-6 * k * ca.value.abs(),
            "{} {} vs {}",
            ca.name,
            ca.value,
            cb.value
        );
    }
    // The outer loop stops at a relative change of its cost of 10⁻⁸, not at round-off:
    // the residuals agree to a thousandth of their standard error.
    for (pa, pb) in parameters(&a).iter().zip(parameters(&b)) {
        let se = pa.std_error.unwrap() / k;
        assert!(
            (pb.value - pa.value / k).abs() < 1e-3 * se,
            "{} {:e} vs {:e}",
            pa.name,
            pa.value,
            pb.value
        );
        assert!((pb.std_error.unwrap() - se).abs() < 1e-3 * se);
    }
}

/// Law parameters and residuals together: the power law's exponent estimated from 1.0
/// (η = exponent, then the seven r_k), noise-free: the exponent within 1 %, c and d
/// within 1 %, every r_k within 5 %.
#[test]
fn estimated_exponent_and_residual_together() {
    let file = scratch("residual_exponent.csv");
    support::write_scratch_csv(&file, &headers(), &residual_columns(R_K, 0.0, 1.0, None));
    let text = model_text(&file, "residual = \"stiffness\"").replace(
        "exponent = 1.5",
        "exponent = { estimate = true, initial = 1.0, lower = 0.2, upper = 3.0 }",
    );
    let job =
        dampid::model_file::parse(&text, "test.toml", Path::new("."), Default::default()).unwrap();
    let report = fit_residual(&job);
    assert_eq!(parameters(&report)[0].name, "d.exponent");
    let exponent = parameters(&report)[0].value;
    assert!((exponent - 1.5).abs() < 0.015, "exponent {exponent}");
    let (c, d) = (coefficient(&report, "c"), coefficient(&report, "d"));
    assert!((c - C).abs() < 0.01 * C, "c = {c}");
    assert!((d - D).abs() < 0.01 * D, "d = {d}");
    for p in &parameters(&report)[1..] {
        assert!(
            (p.value - R_K).abs() < 0.05 * R_K.abs(),
            "{} = {}",
            p.name,
            p.value
        );
    }
}

/// With noise, an estimated exponent and the seven r_k: the exponent, a law parameter,
/// gets a profile-likelihood interval (each end a nested fit of the residuals), which
/// covers the truth and agrees with its joint Wald interval to within a factor 1.5 in
/// width; the residuals, nuisance parameters, get their joint intervals only.
#[test]
fn exponent_profile_with_residuals_as_nuisance() {
    let file = scratch("residual_exponent_noisy.csv");
    let columns = residual_columns(R_K, 0.0, 1.0, Some((20, 0.005, 0.3f64.to_radians())));
    support::write_scratch_csv(&file, &headers(), &columns);
    let text = model_text(&file, "residual = \"stiffness\"").replace(
        "exponent = 1.5",
        "exponent = { estimate = true, initial = 1.0, lower = 0.2, upper = 3.0 }",
    );
    let job =
        dampid::model_file::parse(&text, "test.toml", Path::new("."), Default::default()).unwrap();
    let report = fit_residual(&job);
    let exponent = &parameters(&report)[0];
    let profile = exponent.interval.as_ref().expect("a profile interval");
    let (lower, upper) = (profile.lower.unwrap(), profile.upper.unwrap());
    let [wald_lower, wald_upper] = exponent.joint_interval.unwrap();
    println!(
        "exponent {} profile [{lower}, {upper}] joint [{wald_lower}, {wald_upper}]",
        exponent.value
    );
    assert!(lower <= 1.5 && 1.5 <= upper, "[{lower}, {upper}]");
    assert!(lower < exponent.value && exponent.value < upper);
    let ratio = (upper - lower) / (wald_upper - wald_lower);
    assert!((1.0 / 1.5..1.5).contains(&ratio), "width ratio {ratio}");
    for p in &parameters(&report)[1..] {
        assert!(
            p.interval.is_none() && p.joint_interval.is_some(),
            "{}",
            p.name
        );
    }
}

/// An estimated exponent on a noisy table without residuals is still fitted on the
/// table's equations with their noise model: the fit is weighted by each point's
/// propagated variance (it once ran on the synthesized periods, unweighted, and put the
/// exponent at 1.56 on the shipped table), and the exponent's profile interval covers
/// the truth.
#[test]
fn estimated_exponent_on_a_table_is_weighted() {
    let file = scratch("exponent_weighted.csv");
    support::write_scratch_csv(
        &file,
        &headers(),
        &table_columns(C, D, Some((7, 0.005, 0.005))),
    );
    let text = model_text(&file, "").replace(
        "exponent = 1.5",
        "exponent = { estimate = true, initial = 1.0, lower = 0.2, upper = 3.0 }",
    );
    let job =
        dampid::model_file::parse(&text, "test.toml", Path::new("."), Default::default()).unwrap();
    let report = fit_residual(&job);
    assert!(
        report.estimation.as_ref().unwrap().weighted,
        "the table's noise model weights the fit"
    );
    let exponent = &parameters(&report)[0];
    let profile = exponent.interval.as_ref().expect("a profile interval");
    let (lower, upper) = (profile.lower.unwrap(), profile.upper.unwrap());
    assert!(lower <= 1.5 && 1.5 <= upper, "exponent [{lower}, {upper}]");
    for (name, truth) in [("c", C), ("d", D)] {
        let e = joint(&report, name);
        let (l, u) = (e.lower.unwrap(), e.upper.unwrap());
        assert!(
            l <= truth && truth <= u,
            "{name}: [{l}, {u}], truth {truth}"
        );
    }
}

/// ζ at the measured levels, against the closed form. The residual table (seven
/// force levels, R = r_k estimated per sweep) is noise-free, so each sweep's phase lag
/// less the estimated residual crosses π/2 at ω_n, where the fitted law must give
/// ζ_eq(X_c) = c_eq(X_c)/(2 m ω_n), c_eq(X) = c + d (ω_n X)^½ I/π, I = ∫|sin θ|^2.5,
/// to 1 %. The modal mass comes from the lowest level less its residual (1 kg to 1 %;
/// the response as measured would not give it), and the table's own phase-slope
/// estimate at each crossing sits beside the fit, within 10 %.
#[test]
fn damping_at_the_measured_levels_matches_the_closed_form() {
    let columns = residual_columns(R_K, 0.0, 1.0, None);
    let job = job_of("levels.csv", &columns, "residual = \"stiffness\"");
    let found = identify(&job.problem(), &job.settings, &silent).unwrap();
    let Some(Equivalent::Computed(equivalent)) = found.equivalent else {
        panic!("no equivalent damping: {:?}", found.equivalent)
    };
    let modal = &equivalent.modal;
    assert!((modal.mass - M).abs() < 0.01 * M, "{modal:?}");
    assert!(
        equivalent
            .to_string()
            .contains("less the estimated residual")
    );
    assert_eq!(equivalent.levels.len(), LEVELS.len(), "{equivalent}");
    let omega_n = (K / M).sqrt();
    let integral = sine_power_integral(2.5);
    for level in &equivalent.levels {
        let x = level.amplitude;
        let c_eq = C + D * (omega_n * x).sqrt() * integral / std::f64::consts::PI;
        let zeta = c_eq / (2.0 * M * omega_n);
        println!(
            "{}: X_c = {x:.4e}, ζ fitted {:.5e}, closed form {zeta:.5e}, phase slope {:?}",
            level.sweep, level.fitted, level.measured
        );
        assert!((level.frequency / omega_n - 1.0).abs() < 1e-3, "{level:?}");
        assert!(
            (level.fitted / zeta - 1.0).abs() < 0.01,
            "{level:?} vs {zeta}"
        );
        let measured = level.measured.expect("a positive phase slope");
        // Below ζ(X_c) by 2–5 %: along a force-controlled sweep X, and so ζ, falls off
        // the peak between the two points that bracket the crossing.
        assert!((measured / zeta - 1.0).abs() < 0.1, "{level:?} vs {zeta}");
        assert_eq!(level.ratio, Some(level.fitted / measured));
    }
}
