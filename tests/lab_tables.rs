//! Stepped-sine tables as labs hand them over (issue 30, items 3 and 4): sweeps
//! labelled by text (`FC1`, `RC3`) rather than numbers, and a near-resonance selection
//! that leaves a sweep with two points, which takes the pooled scatter of the others
//! under either weighting instead of needing dummy noise columns.
//!
//! The truth is the one-DOF oscillator of `support/stepped_sine_table.rs` (viscous c plus
//! a power law d|ẋ|^1.5 sign ẋ, solved in the harmonic approximation by hand).

mod support;
#[path = "support/stepped_sine_table.rs"]
mod table;

use std::path::{Path, PathBuf};

use dampid::identify::identify;
use dampid::model_file::SteppedSineSummary;
use dampid::progress::silent;
use table::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_lab_tables_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Rows (level, f_hz, force, x, phase_deg) of five force levels × 15 frequencies over
/// ±3 % of f_n; relative noise `noise.1` on force and amplitude, `noise.2` rad on the
/// phase.
fn rows(noise: Option<(u64, f64, f64)>) -> Vec<[f64; 5]> {
    let fn_hz = K.sqrt() / (2.0 * std::f64::consts::PI);
    let mut rng = Normal(noise.map_or(0, |n| n.0));
    let mut rows = Vec::new();
    for (l, force) in [0.05, 0.2, 0.5, 1.0, 2.0].into_iter().enumerate() {
        for i in 0..15 {
            let f_hz = fn_hz * (0.97 + 0.06 * i as f64 / 14.0);
            let (x, phi) = response(2.0 * std::f64::consts::PI * f_hz, force, C, D);
            let (mut a, mut x, mut phi) = (force, x, phi);
            if let Some((_, relative, phase)) = noise {
                a *= 1.0 + relative * rng.sample();
                x *= 1.0 + relative * rng.sample();
                phi += phase * rng.sample();
            }
            rows.push([l as f64 + 1.0, f_hz, a, x, phi.to_degrees()]);
        }
    }
    rows
}

/// Writes `rows` as CSV with the level column written by `label`.
fn write(name: &str, rows: &[[f64; 5]], label: impl Fn(f64) -> String) -> PathBuf {
    let file = scratch(name);
    let mut text = headers().join(",") + "\n";
    for r in rows {
        text.push_str(&format!(
            "{},{:e},{:e},{:e},{:e}\n",
            label(r[0]),
            r[1],
            r[2],
            r[3],
            r[4]
        ));
    }
    std::fs::write(&file, text).unwrap();
    file
}

fn job(file: &Path, extra: &str) -> dampid::model_file::Job {
    dampid::model_file::parse(
        &model_text(file, extra),
        "lab.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap()
}

/// The error message of the model file on `file` with `extra`.
fn parse_error(file: &Path, extra: &str) -> String {
    dampid::model_file::parse(
        &model_text(file, extra),
        "lab.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap_err()
    .to_string()
}

/// Sweeps labelled `FC1` … `FC5` are named as written and give the same fit, bit for
/// bit, as the same table with numeric labels (only the names differ).
#[test]
fn text_sweep_labels_name_the_sweeps_as_written() {
    let rows = rows(Some((3, 0.005, 0.005)));
    let text = job(&write("text.csv", &rows, |l| format!("FC{l}")), "");
    let numeric = job(&write("numeric.csv", &rows, |l| format!("{l}")), "");
    let names = |job: &dampid::model_file::Job| {
        job.stepped_sine.as_ref().unwrap().table.sweep_names.clone()
    };
    assert_eq!(names(&text), ["FC1", "FC2", "FC3", "FC4", "FC5"]);
    assert_eq!(names(&numeric)[0], "level = 1");
    let fit = |job: &dampid::model_file::Job| {
        identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report
    };
    let (a, b) = (fit(&text), fit(&numeric));
    for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
        assert_eq!(x.value.to_bits(), y.value.to_bits(), "{}", x.name);
    }
    let shares: Vec<&str> = a.records.iter().map(|r| r.record.as_str()).collect();
    assert_eq!(shares, ["FC1", "FC2", "FC3", "FC4", "FC5"]);
    // An empty label is an error naming the file, its row and the column.
    let mut broken = std::fs::read_to_string(scratch("text.csv")).unwrap();
    broken = broken.replacen("\nFC1,", "\n,", 1);
    let file = scratch("empty_label.csv");
    std::fs::write(&file, broken).unwrap();
    let message = parse_error(&file, "");
    assert!(
        message.contains("empty_label.csv") && message.contains("level"),
        "{message}"
    );
}

/// A near-resonance selection leaves level 3 with two points: it takes the pooled
/// scatter of the other four sweeps (the summary names it), and the fit runs under the
/// weighted default and under `weighting = "ordinary"`, each within four standard errors
/// of the truth. The sweeps with their own scatter keep exactly the noise they had.
#[test]
fn a_two_point_sweep_takes_the_pooled_scatter() {
    let all = rows(Some((11, 0.005, 0.005)));
    let mut kept = 0;
    let selected: Vec<[f64; 5]> = all
        .iter()
        .filter(|r| {
            if r[0] != 3.0 {
                return true;
            }
            kept += 1;
            (7..9).contains(&kept)
        })
        .copied()
        .collect();
    assert_eq!(selected.len(), 4 * 15 + 2);
    let file = write("selected.csv", &selected, |l| format!("{l}"));
    let whole = job(&write("whole.csv", &all, |l| format!("{l}")), "");
    for weighting in ["", "[identification]\nweighting = \"ordinary\""] {
        let job = job(&file, weighting);
        let source = job.stepped_sine.as_ref().unwrap();
        assert_eq!(source.table.pooled, [2]);
        let summary = SteppedSineSummary::of(source).to_string();
        assert!(
            summary.contains("level = 3: fewer than 3 points"),
            "{summary}"
        );
        // Sweeps 1, 2, 4, 5 keep their own noise, bit for bit.
        let before = &whole.stepped_sine.as_ref().unwrap().table;
        for (k, p) in source.table.table.points().iter().enumerate() {
            if source.table.sweeps[k] == 2 {
                continue;
            }
            let i = before
                .table
                .points()
                .iter()
                .position(|q| q.frequency == p.frequency && q.force_amplitude == p.force_amplitude)
                .unwrap();
            assert_eq!(before.noise[i], source.table.noise[k], "point {k}");
        }
        let report = identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report;
        for (name, truth) in [("c", C), ("d", D)] {
            let c = report.coefficients.iter().find(|c| c.name == name).unwrap();
            let se = c.std_error.expect("a standard error");
            assert!(
                (c.value - truth).abs() < 4.0 * se,
                "{weighting}: {name} = {} ± {se}, truth {truth}",
                c.value
            );
        }
    }
    // No sweep with three points: refused, saying what to give.
    let two_each: Vec<[f64; 5]> = all.chunks(15).flat_map(|s| s[6..8].to_vec()).collect();
    let message = parse_error(&write("two_each.csv", &two_each, |l| format!("{l}")), "");
    assert!(message.contains("force_std"), "{message}");
}

/// `keep` selects points as a lab would, without editing the file: the points within
/// 0.6 rad of resonance (|φ − π/2| ≤ 0.6, which leaves most sweeps one point),
/// a frequency band, some sweeps; each kept set is exactly the rows the condition
/// names, counted from the generator, and the selection fits under both weightings.
/// An unknown sweep, an empty band and a selection of nothing are errors naming `keep`.
#[test]
fn keep_selects_points_near_resonance_a_band_or_sweeps() {
    let all = rows(Some((5, 0.005, 0.005)));
    let file = write("keep.csv", &all, |l| format!("FC{l}"));
    let half_pi = std::f64::consts::FRAC_PI_2;
    let near: Vec<usize> = (0..all.len())
        .filter(|&r| (all[r][4].to_radians() - half_pi).abs() <= 0.6)
        .collect();
    // About seven of the 75 (the points lie 0.43 % apart, the resonances are 0.6–1.5 %
    // wide): most sweeps keep one point and take the pooled scatter of the last.
    assert!(near.len() >= 5 && near.len() < all.len(), "{}", near.len());
    for weighting in ["", "[identification]\nweighting = \"ordinary\""] {
        let extra = format!(
            "keep = {{ lag = [{}, {}] }}\n{weighting}",
            half_pi - 0.6,
            half_pi + 0.6
        );
        let job = job(&file, &extra);
        let table = &job.stepped_sine.as_ref().unwrap().table;
        let labels: Vec<String> = table
            .table
            .points()
            .iter()
            .map(|p| p.label.clone())
            .collect();
        let expected: Vec<String> = near.iter().map(|r| format!("row {}", r + 1)).collect();
        assert_eq!(labels, expected);
        let report = identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report;
        assert!(report.is_usable(), "{report}");
    }
    // A band of ±0.5 % of f_n in Hz, and two sweeps by name.
    let fn_hz = K.sqrt() / std::f64::consts::TAU;
    let (lo, hi) = (0.995 * fn_hz, 1.005 * fn_hz);
    let band = job(&file, &format!("keep = {{ frequency_hz = [{lo}, {hi}] }}"));
    let in_band = all.iter().filter(|r| lo <= r[1] && r[1] <= hi).count();
    assert_eq!(
        band.stepped_sine
            .as_ref()
            .unwrap()
            .table
            .table
            .points()
            .len(),
        in_band
    );
    let two = job(&file, "keep = { sweeps = [\"FC2\", \"FC4\"] }");
    let table = &two.stepped_sine.as_ref().unwrap().table;
    assert_eq!(table.sweep_names, ["FC2", "FC4"]);
    assert_eq!(table.table.points().len(), 30);
    // Errors at `keep`.
    for (extra, needle) in [
        ("keep = { sweeps = [\"FC9\"] }", "FC9"),
        (
            "keep = { frequency_hz = [60.0, 50.0] }",
            "keep.frequency_hz",
        ),
        (
            "keep = { frequency_hz = [1.0, 2.0] }",
            "none of the 75 points",
        ),
    ] {
        let message = parse_error(&file, extra);
        assert!(
            message.contains(needle) && message.contains("lab.toml"),
            "{message}"
        );
    }
}
