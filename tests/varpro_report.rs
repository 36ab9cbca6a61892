//! The reports of a variable-projection fit: `dampid identify --report` on jobs with
//! estimated law parameters or residual receptances, the page of a fit that is not an
//! estimate, and the equivalent damping at η̂ with intervals from the joint covariance
//! against the closed form of the true law.

mod support;

use dampid::progress::silent;
use dampid::regressor::ParametricRegressor;
use std::path::Path;

use dampid::analysis::equivalent::equivalent_damping;
use dampid::identify::Equivalent;
use dampid::identify::{IdentifySettings, identify};
use dampid::report::html::HtmlReport;
use dampid::varpro::VarProSettings;
use support::cli::{dampid_json, dampid_ok};

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_varpro_report_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The page holds no non-finite number a reader could take for a value: no "NaN", and
/// "inf" only inside words ("infinite", "information").
fn assert_finite(page: &str) {
    assert!(!page.contains("NaN"), "the page shows NaN");
    let bytes = page.as_bytes();
    for (i, _) in page.match_indices("inf") {
        let before = i.checked_sub(1).map(|j| bytes[j]);
        let after = bytes.get(i + 3).copied();
        let letter = |b: Option<u8>| b.is_some_and(|b| b.is_ascii_alphabetic());
        assert!(
            letter(before) || letter(after),
            "the page shows a bare inf: {}",
            &page[i.saturating_sub(60)..(i + 20).min(page.len())]
        );
    }
}

/// A stepped-sine table with residual receptances: the page lists every sweep's r_k
/// with its joint interval, the coefficients with joint intervals, the energy per cycle
/// against amplitude and the equivalent-damping table; the JSON carries the joint
/// covariance and the equivalent damping at η̂.
#[test]
fn report_of_a_residual_job() {
    let folder = scratch("residual");
    std::fs::remove_dir_all(&folder).ok();
    let json = dampid_json(&[
        "identify",
        "models/bolted_joint_stepped_sine_residual.toml",
        "--json",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    for needle in [
        "estimated 7 nonlinear parameters",
        "Estimated nonlinear parameters",
        "r_k (level = 1)",
        "r_k (level = 7)",
        "joint (Wald)",
        "levenberg_marquardt",
        "joint 95% interval",
        "std error with η fixed",
        "The intervals shown are <b>joint</b>",
        "Dissipated energy per cycle",
        "Equivalent damping",
        "Identified damping laws",
    ] {
        assert!(page.contains(needle), "missing {needle}");
    }
    assert!(!page.contains("Not an estimate"));
    assert_finite(&page);
    // 7 residuals + c, d: a 9 × 9 covariance whose diagonal gives the standard errors.
    let covariance = json["report"]["estimation"]["covariance"]
        .as_array()
        .unwrap();
    assert_eq!(covariance.len(), 9);
    let se = json["report"]["estimation"]["coefficients"][0]["std_error"]
        .as_f64()
        .unwrap();
    let c00 = covariance[0][0].as_f64().unwrap();
    assert!((c00.sqrt() - se).abs() < 1e-12 * se, "{c00} vs {se}²");
    let points = json["equivalent_damping"]["points"].as_array().unwrap();
    assert_eq!(points.len(), 12);
    assert!(
        points
            .iter()
            .all(|p| p["damping_ratio_std"].as_f64().is_some())
    );
    // The text report prints the equivalent damping too.
    let text = dampid_ok(&["identify", "models/bolted_joint_stepped_sine_residual.toml"]).stdout;
    let text = String::from_utf8(text).unwrap();
    assert!(text.contains("equivalent damping at ω_n"), "{text}");
}

/// Records with an estimated exponent: the exponent with its profile interval, the
/// coefficients with joint intervals, the law plots at η̂; no stepped-sine sections.
#[test]
fn report_of_an_estimated_exponent() {
    let folder = scratch("power");
    std::fs::remove_dir_all(&folder).ok();
    dampid_ok(&[
        "identify",
        "models/four_mass_power.toml",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    for needle in [
        "estimated 1 nonlinear parameter",
        "d.exponent",
        "profile likelihood",
        "brent",
        "joint 95% interval",
        "power(1.7",
    ] {
        assert!(page.contains(needle), "missing {needle}");
    }
    assert!(!page.contains("Equivalent damping"));
    assert_finite(&page);
}

/// An outer loop stopped after one iteration is not an estimate: the page says so,
/// labels the values as the last trial and shows no interval, fitted curve or standard
/// error.
#[test]
fn a_fit_that_is_not_an_estimate_shows_no_estimates() {
    let job =
        dampid::model_file::load(Path::new("models/four_mass_power.toml"), Default::default())
            .unwrap();
    let settings = IdentifySettings {
        estimation: VarProSettings {
            max_iterations: 1,
            ..job.settings.estimation
        },
        ..job.settings.clone()
    };
    let found = identify(&job.problem(), &settings, &silent).unwrap();
    let report = &found.report;
    assert!(!report.is_estimate(), "{report}");
    let page = HtmlReport {
        title: &job.title,
        model: &found.model,
        source: (&job.records).into(),
        regressor: &found.regressor,
        report,
        truth: job.truth.as_deref(),
        pod: None,
        steady: None,
        equivalent: None,
        backbone: None,
        provenance: None,
        units: None,
    }
    .render()
    .unwrap();
    assert!(page.contains("<b>Not an estimate</b>"));
    assert!(page.contains("last trial (not an estimate)"));
    for absent in [
        "<th>estimate</th>",
        "profile likelihood",
        "joint (Wald)",
        "joint 95% interval",
        "<svg",
        "Identified damping laws",
    ] {
        assert!(!page.contains(absent), "the page shows {absent}");
    }
    // The standard-error and interval cells are dashes.
    let table = &page[page.find("Estimated nonlinear parameters").unwrap()..];
    let row = &table[table.find("<td>d.exponent</td>").unwrap()..];
    let row = &row[..row.find("</tr>").unwrap()];
    assert_eq!(row.matches("<td>–</td>").count(), 3, "{row}");
}

// ---- equivalent damping of an estimated power law against its closed form ----

const K: f64 = 98_696.044_010_893_6; // (2π·50)², modal mass 1
const C: f64 = 1.2566;
const D: f64 = 5.0;
const P: f64 = 1.5;

/// ∫₀^{2π} |sin θ|^{q} dθ = 4 ∫₀^{π/2} cos^{q} θ dθ = 2 B((q + 1)/2, 1/2), with
/// ∫₀^{π/2} cos^{q} θ dθ = ½ B((q + 1)/2, ½) (the Beta integral with t = cos²θ).
fn sine_power_integral(q: f64) -> f64 {
    2.0 * statrs::function::beta::beta((q + 1.0) / 2.0, 0.5)
}

/// The closed form of the true law's ζ_eq at amplitude X and ω: a force
/// c v + d |v|^p sign v on x = X cos ωt, v = −Xω sin ωt dissipates per cycle
///
/// ```text
///   E_d = ∫₀^{2π/ω} (c v² + d |v|^{p+1}) dt
///       = π c ω X² + d (Xω)^{p+1} ω⁻¹ ∫₀^{2π} |sin θ|^{p+1} dθ
///       = π c ω X² + d X^{p+1} ω^p · 2 B((p + 2)/2, 1/2),
/// ```
///
/// and ζ_eq = E_d / (2π k X²).
fn true_damping_ratio(x: f64, omega: f64) -> f64 {
    let energy = std::f64::consts::PI * C * omega * x * x
        + D * x.powf(P + 1.0) * omega.powf(P) * sine_power_integral(P + 1.0);
    energy / (2.0 * std::f64::consts::PI * K * x * x)
}

/// (X, lag φ) of the oscillator m = 1, k = K driven at `omega` with amplitude `force`
/// under the harmonic balance: c_eq(X) = E_d(X)/(π ω X²).
fn response(omega: f64, force: f64) -> (f64, f64) {
    let c_eq = |x: f64| {
        C + D * (omega * x).powf(P - 1.0) * sine_power_integral(P + 1.0) / std::f64::consts::PI
    };
    let stiff = K - omega * omega;
    let h = |x: f64| x * (stiff.powi(2) + (omega * c_eq(x)).powi(2)).sqrt() - force;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if h(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let x = 0.5 * (lo + hi);
    (x, (omega * c_eq(x)).atan2(stiff))
}

/// A deterministic normal generator (splitmix64, Box–Muller).
struct Normal(u64);
impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// Five force levels, 15 points over ±3 % of 50 Hz, 0.5 % amplitude and force noise
/// and 0.3° phase noise: level, frequency (Hz), force, amplitude, phase (degrees).
fn noisy_table(seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Normal(seed);
    let mut columns = vec![Vec::new(); 5];
    for (l, force) in [0.05, 0.2, 0.5, 1.0, 2.0].into_iter().enumerate() {
        for i in 0..15 {
            let f_hz = 50.0 * (0.97 + 0.06 * i as f64 / 14.0);
            let (x, phi) = response(2.0 * std::f64::consts::PI * f_hz, force);
            columns[0].push(l as f64 + 1.0);
            columns[1].push(f_hz);
            columns[2].push(force * (1.0 + 0.005 * rng.sample()));
            columns[3].push(x * (1.0 + 0.005 * rng.sample()));
            columns[4].push((phi + 0.3f64.to_radians() * rng.sample()).to_degrees());
        }
    }
    columns
}

fn model_text(file: &Path, exponent: &str) -> String {
    format!(
        r#"
dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[terms]]
kind = "law"
law = "power"
exponent = {exponent}
elements = "each_dof"
coefficient = "d"
[stepped_sine]
file = "{}"
frequency = {{ column = "f_hz", scale = 6.283185307179586 }}
force = "force"
amplitudes = ["x"]
phases = [{{ column = "phase_deg", scale = 0.017453292519943295 }}]
sweep = "level"
[system]
mass = [[1.0]]
stiffness = [[98696.0440108936]]
"#,
        file.display()
    )
}

/// The Beta form of ∫|sin|^q against the midpoint rule, so the closed form the next
/// test checks against is itself checked.
#[test]
fn beta_form_of_the_sine_power_integral() {
    for q in [1.0, 2.0, 2.5, 3.7] {
        let n = 200_000;
        let h = 2.0 * std::f64::consts::PI / n as f64;
        let midpoint: f64 = (0..n)
            .map(|i| ((i as f64 + 0.5) * h).sin().abs().powf(q))
            .sum::<f64>()
            * h;
        let beta = sine_power_integral(q);
        assert!(
            (beta - midpoint).abs() < 1e-9 * midpoint,
            "{q}: {beta} vs {midpoint}"
        );
    }
    // q = 2: ∫ sin² = π.
    assert!((sine_power_integral(2.0) - std::f64::consts::PI).abs() < 1e-12);
}

/// A one-DOF table of c v + d |v|^1.5 sign v with noise, the exponent estimated from
/// 1.0: ζ_eq(X) at η̂ matches the closed form of the true law within its 95 % interval
/// at every amplitude, and that interval (joint: θ and η) is wider than the one of the
/// linear fit at the same exponent held fixed.
#[test]
fn equivalent_damping_with_an_estimated_exponent() {
    let file = scratch("power_table.csv");
    let headers: Vec<String> = ["level", "f_hz", "force", "x", "phase_deg"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    support::write_scratch_csv(&file, &headers, &noisy_table(7));
    let estimated = model_text(
        &file,
        "{ estimate = true, initial = 1.0, lower = 0.5, upper = 3.0 }",
    );
    let job =
        dampid::model_file::parse(&estimated, "test.toml", Path::new("."), Default::default())
            .unwrap();
    let fit = identify(&job.problem(), &job.settings, &silent).unwrap();
    let report = &fit.report;
    assert!(report.is_estimate(), "{report}");
    let exponent = report.parameter("d.exponent").unwrap();
    println!("exponent {exponent}");
    assert!((exponent - P).abs() < 0.1, "exponent {exponent}");
    let Some(Equivalent::Computed(joint)) = fit.equivalent.clone() else {
        panic!("no equivalent damping: {:?}", fit.equivalent)
    };
    // The same table with the exponent fixed at its estimate: the conditional fit.
    let fixed_text = model_text(&file, &format!("{exponent:?}"));
    let fixed_job =
        dampid::model_file::parse(&fixed_text, "test.toml", Path::new("."), Default::default())
            .unwrap();
    let fixed_found = identify(&fixed_job.problem(), &fixed_job.settings, &silent).unwrap();
    let fixed_report = &fixed_found.report;
    let Some(Equivalent::Computed(fixed)) = fixed_found.equivalent.clone() else {
        panic!("no equivalent damping: {:?}", fixed_found.equivalent)
    };
    // The fixed fit at η̂ is the varpro fit's inner fit: the same coefficients.
    for (a, b) in fixed_report.coefficients.iter().zip(&report.coefficients) {
        assert!(
            (a.value - b.value).abs() < 1e-9 * b.value.abs(),
            "{} {}",
            a.value,
            b.value
        );
    }
    let omega = joint.modal.natural_frequency;
    assert!((omega - K.sqrt()).abs() < 1e-9 * omega);
    for (j, f) in joint.points.iter().zip(&fixed.points) {
        let truth = true_damping_ratio(j.amplitude, omega);
        let (sj, sf) = (j.damping_ratio_std.unwrap(), f.damping_ratio_std.unwrap());
        println!(
            "X = {:.3e}: ζ = {:.6e} ± {:.2e} (joint), ± {:.2e} (η fixed); truth {truth:.6e}",
            j.amplitude,
            j.damping_ratio,
            1.96 * sj,
            1.96 * sf
        );
        assert!((j.damping_ratio - f.damping_ratio).abs() < 1e-9 * f.damping_ratio);
        assert!(
            (j.damping_ratio - truth).abs() <= 1.96 * sj,
            "X = {:e}: {} vs truth {truth}, ± {}",
            j.amplitude,
            j.damping_ratio,
            1.96 * sj
        );
        assert!(
            sj > sf,
            "X = {:e}: joint {sj} not wider than fixed {sf}",
            j.amplitude
        );
    }
    // η fixed at η̂ in the varpro model: the formula with u = g alone is the linear
    // path's, bit for bit.
    let fixed_model = ParametricRegressor::linear(&fit.model, job.stepped_sine.as_ref().unwrap());
    let conditional = equivalent_damping(
        &fixed_model,
        &[],
        &report
            .coefficients
            .iter()
            .map(|c| c.value)
            .collect::<Vec<_>>(),
        None,
    )
    .unwrap()
    .unwrap();
    for (a, b) in conditional.points.iter().zip(&joint.points) {
        assert_eq!(a.dissipated_energy, b.dissipated_energy);
    }
}
