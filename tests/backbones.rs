//! Backbones of one mode from a ringdown and a stepped sine side by side
//! (`dampid backbones`, `dampid::analysis::backbones`): the shipped pair
//! (models/backbones_ringdown.toml, models/backbones_stepped.toml, data by NumPy in
//! models/data/backbones/make.py) against the closed-form ζ_eq(X) of their truth and
//! against each other; a table of a different law (made here) far from the ringdown;
//! the command line's text, JSON and page; and the refusals.

mod support;

use std::f64::consts::PI;
use std::path::Path;

use dampid::analysis::backbones::{Backbones, TestKind};
use dampid::command::backbones::{ComparedBackbones, run};
use dampid::model_file::{Job, Options, load, parse};
use dampid::progress::silent;

/// The truth of both shipped jobs: m = 1, 80 Hz, c = 2·0.001·ω, d = 5, p = 1.5.
const OMEGA: f64 = 2.0 * PI * 80.0;
const C: f64 = 2.0 * 0.001 * OMEGA;
const D: f64 = 5.0;

/// ∫₀^{2π} |sin t|^2.5 dt = 2√π Γ(1.75)/Γ(2.25), by the midpoint rule (independent of
/// the crate's own integral).
fn sine_integral() -> f64 {
    let n = 200_000;
    let h = 2.0 * PI / n as f64;
    (0..n)
        .map(|i| ((i as f64 + 0.5) * h).sin().abs().powf(2.5))
        .sum::<f64>()
        * h
}

/// ζ_eq(X) = (c + d √(ωX) I / π) / (2 m ω): the energy per cycle of the law under
/// x = X cos ωt over that of a viscous damper (the describing function).
fn truth(x: f64, d: f64) -> f64 {
    (C + d * (OMEGA * x).sqrt() * sine_integral() / PI) / (2.0 * OMEGA)
}

fn compared(jobs: Vec<(String, Job)>) -> ComparedBackbones {
    run(&jobs, &silent).unwrap()
}

fn shipped(file: &str) -> (String, Job) {
    (
        file.to_string(),
        load(Path::new(file), Options::default()).unwrap(),
    )
}

/// The shipped ringdown and table: each fitted backbone within 1 % of the closed form
/// over the common amplitudes (a 150× range), their ratio within 1 % of one, and inside
/// its 95 % interval; the ringdown's measured decrement within 2 % of the truth at the
/// median window of the common range.
#[test]
fn ringdown_and_stepped_sine_agree_with_the_truth_and_each_other() {
    let out = compared(vec![
        shipped("models/backbones_ringdown.toml"),
        shipped("models/backbones_stepped.toml"),
    ]);
    assert!(out.untrusted.is_empty());
    let Backbones { jobs, pairs } = &out.backbones;
    assert_eq!(jobs[0].kind, TestKind::FreeDecay);
    assert_eq!(jobs[1].kind, TestKind::SteppedSine);
    let pair = &pairs[0];
    let (lo, hi) = pair.common.unwrap();
    assert!(hi / lo > 100.0, "common range {lo:e} to {hi:e}");
    assert_eq!(pair.points.len(), dampid::analysis::backbones::GRID);
    for p in &pair.points {
        let z = truth(p.amplitude, D);
        for (which, zeta) in [("ringdown", p.first), ("stepped sine", p.second)] {
            assert!(
                (zeta / z - 1.0).abs() < 0.01,
                "{which} at X = {:e}: ζ = {zeta:e}, truth {z:e}",
                p.amplitude
            );
        }
        assert!((p.ratio - 1.0).abs() < 0.01, "ratio {}", p.ratio);
        let s = p.ratio_std.unwrap();
        assert!(
            (p.ratio - 1.0).abs() <= 1.96 * s,
            "ratio {} ± {}",
            p.ratio,
            1.96 * s
        );
    }
    assert!(pair.largest_deviation.unwrap() < 0.01);
    // The measured decrements in the common range: their median error is small (single
    // windows scatter with the noise; the edges of the record are not used).
    let mut errors: Vec<f64> = jobs[0]
        .measured
        .iter()
        .filter(|p| p.amplitude >= lo && p.amplitude <= hi)
        .map(|p| (p.damping_ratio / truth(p.amplitude, D) - 1.0).abs())
        .collect();
    errors.sort_by(f64::total_cmp);
    assert!(errors.len() > 300);
    assert!(
        errors[errors.len() / 2] < 0.02,
        "median error {}",
        errors[errors.len() / 2]
    );
    // The table's measured levels (phase slope) within 5 % of the truth.
    assert_eq!(jobs[1].measured.len(), 8);
    for p in &jobs[1].measured {
        let z = truth(p.amplitude, D);
        assert!(
            (p.damping_ratio / z - 1.0).abs() < 0.05,
            "level at {:e}",
            p.amplitude
        );
        assert!((p.frequency / 80.0 - 1.0).abs() < 1e-3);
    }
}

/// The stepped-sine table of the shipped mode with the power law's coefficient `d`:
/// the harmonic balance X |k − mω² + iω c_eq(X)| = a solved by bisection, eight levels
/// of 21 frequencies, 0.5 % amplitude noise, 0.3° phase noise (seeded), written as
/// `dir/table.csv`; the job reads it with the shipped table's model file.
fn stepped_job(dir: &Path, d: f64) -> (String, Job) {
    let integral = sine_integral();
    let mut rng = support_normal(31);
    let (mut level, mut f_hz, mut force, mut x_m, mut phase) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for l in 0..8 {
        let a = 0.01 * 300f64.powf(l as f64 / 7.0);
        for i in 0..21 {
            let f = 80.0 * (1.0 - 0.012 + 0.024 * i as f64 / 20.0);
            let w = 2.0 * PI * f;
            let c_eq = |x: f64| C + d * (w * x).sqrt() * integral / PI;
            let stiff = OMEGA * OMEGA - w * w;
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid * (stiff.powi(2) + (w * c_eq(mid)).powi(2)).sqrt() > a {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let x = 0.5 * (lo + hi);
            level.push((l + 1) as f64);
            f_hz.push(f);
            force.push(a * (1.0 + 0.005 * rng()));
            x_m.push(x * (1.0 + 0.005 * rng()));
            phase.push(((w * c_eq(x)).atan2(stiff) + 0.3f64.to_radians() * rng()).to_degrees());
        }
    }
    let headers: Vec<String> = ["level", "f_hz", "force_n", "x_m", "phase_deg"]
        .map(String::from)
        .to_vec();
    support::write_scratch_csv(
        &dir.join("table.csv"),
        &headers,
        &[level, f_hz, force, x_m, phase],
    );
    let text = std::fs::read_to_string("models/backbones_stepped.toml")
        .unwrap()
        .replace("data/backbones/stepped.csv", "table.csv");
    let file = dir.join("stepped.toml").display().to_string();
    (
        file.clone(),
        parse(&text, &file, dir, Options::default()).unwrap(),
    )
}

/// Standard normal draws (splitmix64, Box–Muller), seeded.
fn support_normal(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    let mut uniform = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    move || {
        let (u, v) = (uniform().max(1e-300), uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    }
}

/// A table of a joint twice as lossy (d = 10) against the shipped ringdown (d = 5): its
/// own backbone within 1 % of its own truth, and the ratio to the ringdown far from one
/// (the truth's ratio, within 1 %), outside its 95 % interval at every common amplitude.
#[test]
fn a_different_law_shows_a_ratio_far_from_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = compared(vec![
        shipped("models/backbones_ringdown.toml"),
        stepped_job(dir.path(), 2.0 * D),
    ]);
    let pair = &out.backbones.pairs[0];
    assert_eq!(pair.points.len(), dampid::analysis::backbones::GRID);
    for p in &pair.points {
        let expected = truth(p.amplitude, 2.0 * D) / truth(p.amplitude, D);
        assert!((p.second / truth(p.amplitude, 2.0 * D) - 1.0).abs() < 0.01);
        assert!(
            (p.ratio / expected - 1.0).abs() < 0.01,
            "ratio {} vs {expected}",
            p.ratio
        );
        assert!((p.ratio - 1.0).abs() > 3.0 * p.ratio_std.unwrap());
    }
    let largest = pair.points.last().unwrap().ratio;
    assert!(
        largest > 1.6,
        "ratio at the largest common amplitude {largest}"
    );
    assert!(pair.largest_deviation.unwrap() > 0.6);
}

/// The same table made here with the shipped law (d = 5) agrees with the shipped table
/// (a third job: each later job against the first).
#[test]
fn three_jobs_each_against_the_first() {
    let dir = tempfile::tempdir().unwrap();
    let out = compared(vec![
        shipped("models/backbones_stepped.toml"),
        shipped("models/backbones_ringdown.toml"),
        stepped_job(dir.path(), D),
    ]);
    let pairs = &out.backbones.pairs;
    assert_eq!(pairs.len(), 2);
    assert_eq!((pairs[0].first, pairs[0].second), (0, 1));
    assert_eq!((pairs[1].first, pairs[1].second), (0, 2));
    for pair in pairs {
        assert!(pair.largest_deviation.unwrap() < 0.015, "{pair:?}");
    }
}

/// The command line: text with the common range and the ratio table, JSON with every
/// job's points and the ratios, and the page with both charts.
#[test]
fn the_command_line_prints_and_writes_the_page() {
    let args = [
        "backbones",
        "models/backbones_ringdown.toml",
        "models/backbones_stepped.toml",
    ];
    let json = support::cli::dampid_json(&[&args[..], &["--json"]].concat());
    let jobs = json["jobs"].as_array().unwrap();
    assert_eq!(jobs.len(), 2);
    assert_eq!(jobs[0]["kind"], "free_decay");
    assert_eq!(jobs[1]["kind"], "stepped_sine");
    assert!(jobs[0]["measured"].as_array().unwrap().len() > 300);
    let ratios = json["pairs"][0]["points"].as_array().unwrap();
    assert!(
        ratios
            .iter()
            .all(|p| (p["ratio"].as_f64().unwrap() - 1.0).abs() < 0.01)
    );
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().display().to_string();
    let output = support::cli::dampid_ok(&[&args[..], &["--report", &folder]].concat());
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(
        text.contains("[2] stepped sine against [1] free decay"),
        "{text}"
    );
    assert!(text.contains("largest |ratio − 1|"));
    let page = std::fs::read_to_string(dir.path().join("backbones.html")).unwrap();
    assert!(page.contains("Damping ratio ζ(X) of each job"));
    assert!(page.contains("Frequency f(X) of each job"));
    assert!(page.contains("models/backbones_stepped.toml"));
    // An existing page is not replaced without --force.
    let again = support::cli::dampid(&[&args[..], &["--report", &folder]].concat());
    assert_eq!(again.status.code(), Some(2));
}
