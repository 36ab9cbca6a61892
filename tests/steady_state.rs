//! Cycle extraction: the driving period detected from the force, and the steady-state
//! check of every window (state and stored energy at its end against its start).

use std::f64::consts::PI;
use std::path::Path;

use dampid::Error;
use dampid::model_file::{load, parse};
use dampid::prep::period::detect_period;
use faer::Mat;

/// A clean sinusoid with 37.29 samples per period (not a whole number) over 26.8
/// periods, with an offset: the period is recovered to 1e-6 (in fact to ~1e-10).
#[test]
fn period_of_a_clean_sinusoid_with_fractional_samples_per_period() {
    let per_period = 37.29;
    let period = 2.7;
    let h = period / per_period;
    let force = Mat::from_fn(1000, 1, |i, _| {
        0.3 + 1.7 * (2.0 * PI * i as f64 * h / period + 0.4).cos()
    });
    let estimate = detect_period(force.as_ref(), h, "clean").unwrap();
    let error = (estimate.period - period).abs() / period;
    assert!(error < 1e-6, "relative error {error:e}");
    assert!(estimate.explained > 0.999_999, "{}", estimate.explained);
    assert!((estimate.cycles - 999.0 / per_period).abs() < 1e-4);
}

/// With noise and a third harmonic the fundamental is still found, to the accuracy
/// the noise allows.
#[test]
fn period_with_noise_and_a_harmonic() {
    let (period, h) = (2.0 * PI / 0.618, 0.1);
    let mut state = 12345u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let force = Mat::from_fn(2000, 1, |i, _| {
        let phase = 2.0 * PI * i as f64 * h / period;
        phase.cos() + 0.3 * (3.0 * phase).cos() + 0.1 * uniform()
    });
    let estimate = detect_period(force.as_ref(), h, "noisy").unwrap();
    assert!((estimate.period - period).abs() < 1e-4 * period);
}

/// Under two periods, or under eight samples, the record is too short; pure noise
/// shows no period.
#[test]
fn too_short_or_aperiodic_force_is_rejected() {
    let h = 0.1;
    let short = Mat::from_fn(15, 1, |i, _| (i as f64 * h).cos());
    assert!(matches!(
        detect_period(short.as_ref(), h, "short"),
        Err(Error::RecordTooShort { ref record, available: 15, .. }) if record == "short"
    ));
    let tiny = Mat::from_fn(5, 1, |i, _| (i as f64).cos());
    assert!(matches!(
        detect_period(tiny.as_ref(), h, "tiny"),
        Err(Error::RecordTooShort { available: 5, .. })
    ));
    let mut state = 7u64;
    let noise = Mat::from_fn(4000, 1, |_, _| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    });
    match detect_period(noise.as_ref(), h, "noise") {
        Err(Error::NoPeriod { explained, .. }) => assert!(explained < 0.1, "{explained}"),
        other => panic!("{other:?}"),
    }
}

/// A two-mass chain driven on mass 2 and simulated from rest, 3000 steps of 0.1
/// (≈ 48 periods), identified from one window `skip` samples in.
fn from_rest(skip: usize, accept: bool) -> String {
    format!(
        r#"
title = "two masses from rest"
dofs = 2

[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"

[identification]
quadrature = "trapezoid"
velocity = "measured"
cycles = 1
windows = 1
skip = {skip}
accept_transient = {accept}

[simulation]
mass = "identity"
stiffness = "chain"
coefficients = {{ c = 0.05 }}
step = 0.1
transient_steps = 0
recorded_steps = 3000

[[simulation.experiments]]
force_dof = 2
amplitude = 1.0
frequency = 1.0
"#
    )
}

/// From rest with no transient skipped, the first window is rejected, with the record,
/// window, start time and mismatch in the error; skipping the transient passes.
#[test]
fn transient_from_rest_is_rejected_and_skipping_it_passes() {
    let job = parse(&from_rest(0, false), "rest.toml", Path::new(".")).unwrap();
    let report = job.steady_state().unwrap().expect("a periodic model file");
    assert!(report.energy_known);
    let window = &report.windows[0];
    assert!(!window.steady);
    let mismatch = window.energy_mismatch.unwrap();
    assert!(mismatch > 0.1, "{mismatch}");
    match report.enforce().unwrap_err() {
        err @ Error::NotSteady { .. } => {
            let text = err.to_string();
            for needle in ["a=1 ω=1 on DOF 2", "window 0", "t = 0", "exceeds 1.000e-2"] {
                assert!(text.contains(needle), "'{needle}' not in: {text}");
            }
            let Error::NotSteady {
                mismatch: reported, ..
            } = err
            else {
                unreachable!()
            };
            assert_eq!(reported, mismatch);
        }
        other => panic!("{other:?}"),
    }
    // Accepted: reported, not rejected, and the fit runs.
    let accepted = parse(&from_rest(0, true), "rest.toml", Path::new(".")).unwrap();
    assert!(
        accepted
            .steady_state()
            .unwrap()
            .expect("a periodic model file")
            .enforce()
            .is_ok()
    );

    // 2500 samples in, the transient (decaying at c/2 = 0.025) is down to e^-6.25.
    let steady = parse(&from_rest(2500, false), "rest.toml", Path::new(".")).unwrap();
    let report = steady
        .steady_state()
        .unwrap()
        .expect("a periodic model file");
    assert!(report.enforce().is_ok(), "{report}");
    let late = report.windows[0].energy_mismatch.unwrap();
    assert!(
        late < 0.01 && late < mismatch / 100.0,
        "{late} vs {mismatch}"
    );
    let fit = dampid::identify(&steady.model, &steady.records, &steady.settings).unwrap();
    assert!((fit.coefficient("c").unwrap() - 0.05).abs() < 0.05 * 0.01);
}

/// The state criterion (M and K unknown) sees the same transient.
#[test]
fn state_criterion_sees_the_transient_too() {
    let job = parse(&from_rest(0, false), "rest.toml", Path::new(".")).unwrap();
    let without_energy = dampid::prep::steady_state::check(
        &job.source_records,
        job.source_windows.windows.cycles().unwrap(),
        job.source_windows.quadrature,
        None,
        &job.steady_state,
    )
    .unwrap();
    assert!(!without_energy.energy_known);
    assert!(without_energy.windows[0].state_mismatch() > 0.02);
    assert!(matches!(
        without_energy.enforce(),
        Err(Error::NotSteady { ref measure, .. }) if measure.contains("state")
    ));
}

/// The shipped four-mass model passes unchanged: every window is steady to well under
/// 1% of its input work.
#[test]
fn four_mass_default_passes() {
    let job = load(Path::new("models/four_mass.toml")).unwrap();
    let report = job.steady_state().unwrap().expect("a periodic model file");
    assert!(report.enforce().is_ok(), "{report}");
    assert_eq!(report.windows.len(), 4);
    for w in &report.windows {
        assert!(w.energy_mismatch.unwrap() < 0.005, "{w:?}");
    }
}

/// A data file without `period` or `frequency` gets its period from the force, close
/// to the true 2π/ω; a `[system]` section turns on the energy criterion.
#[test]
fn model_file_detects_the_period_of_a_data_file() {
    let text = r#"
dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "dashpot"

[identification]
velocity = "spectral"
cycles = 2

[system]
mass = "identity"
stiffness = "chain"

[[data.records]]
file = "data/chain3/record_1.csv"
time = "t"
displacements = ["x1", "x2", "x3"]
forces = [{ column = "f1", dof = 1 }]
"#;
    let job = parse(text, "detect.toml", Path::new("models")).unwrap();
    let detected = job.detected_periods[0].unwrap();
    let truth = 2.0 * PI / 0.765367;
    assert!(
        (detected.period - truth).abs() < 1e-6 * truth,
        "{} vs {truth}",
        detected.period
    );
    assert_eq!(job.records[0].period(), detected.period);
    let report = job.steady_state().unwrap().expect("a periodic model file");
    assert!(report.energy_known);
    assert!(report.enforce().is_ok(), "{report}");
}

/// Windows of a few samples, as many as fit, up to the record's last sample: every
/// window is checked (no index leaves the record), and clean periodic motion is steady
/// for every rule.
#[test]
fn short_windows_up_to_the_end_of_a_short_record() {
    use dampid::prelude::*;
    let (h, period, samples) = (0.1, 1.05, 40);
    let omega = 2.0 * PI / period;
    let x = Mat::from_fn(samples, 1, |i, _| (omega * i as f64 * h).cos());
    let v = Mat::from_fn(samples, 1, |i, _| -omega * (omega * i as f64 * h).sin());
    let f = Mat::from_fn(samples, 1, |i, _| (omega * i as f64 * h).sin());
    let record = Record::new(RecordParts {
        label: "short".into(),
        step: h,
        start_time: 0.0,
        displacements: x,
        velocities: Some(v),
        forcing: Forcing::on_dofs(f, vec![0]),
        period,
    })
    .unwrap();
    for quadrature in [
        Quadrature::Rectangular,
        Quadrature::Trapezoid,
        Quadrature::Spectral,
    ] {
        let report = dampid::prep::steady_state::check(
            std::slice::from_ref(&record),
            &WindowSpec::cycles(1),
            quadrature,
            None,
            &Default::default(),
        )
        .unwrap();
        assert!(report.windows.len() >= 3, "{quadrature:?}");
        for w in &report.windows {
            assert!(w.state_mismatch() < 0.02, "{quadrature:?}: {w:?}");
        }
    }
    // 1.5 samples per window: the last window's interpolation stencil starts before the
    // window does. Too coarse to judge, but checked without leaving the record.
    let mut parts = record.into_parts();
    parts.period = 0.15;
    let coarse = Record::new(parts).unwrap();
    let report = dampid::prep::steady_state::check(
        &[coarse],
        &WindowSpec::cycles(1),
        Quadrature::Rectangular,
        None,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(
        report.windows.last().unwrap().window,
        report.windows.len() - 1
    );
    assert!(report.windows.len() > 20);
}

// ---------------------------------------------------------------------------------
// Noise (issue 16, item 2): steady records with measurement noise pass; transients
// are still rejected. Every record is simulated; noise is drawn with fixed seeds.
// ---------------------------------------------------------------------------------

use dampid::prelude::*;
use dampid::prep::steady_state::{SteadyStateReport, SteadyStateSettings, StoredEnergy, check};
use dampid::reference::{four_mass_records_with, with_displacement_noise};
use dampid::simulate::{HarmonicForce, SimSettings, System, chain_stiffness, simulate};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// `records` with Gaussian noise of `x_level` × the RMS displacement on every
/// displacement (velocities dropped) and `f_level` × the RMS force on every force
/// channel, per record.
fn noisy(records: &[Record], x_level: f64, f_level: f64, seed: u64) -> Vec<Record> {
    let records = with_displacement_noise(records, x_level, seed).unwrap();
    let mut rng = StdRng::seed_from_u64(seed ^ 0x5eed);
    records
        .iter()
        .map(|r| {
            let mut parts = r.parts().clone();
            let s = &mut parts.forcing.signals;
            let (rows, cols) = s.shape();
            for c in 0..cols {
                let rms = ((0..rows).map(|i| s[(i, c)].powi(2)).sum::<f64>() / rows as f64).sqrt();
                let normal = Normal::new(0.0, f_level * rms).unwrap();
                for i in 0..rows {
                    s[(i, c)] += normal.sample(&mut rng);
                }
            }
            Record::new(parts).unwrap()
        })
        .collect()
}

/// The four-mass chain (M = I, K = chain) over `cycles` recorded periods after
/// `transient` steps.
fn four_mass(transient: usize, cycles: usize) -> Vec<Record> {
    let period = 2.0 * PI / 0.618;
    let settings = SimSettings {
        transient_steps: transient,
        recorded_steps: (cycles as f64 * period / 0.1).ceil() as usize + 4,
        ..SimSettings::default()
    };
    four_mass_records_with(false, &settings).unwrap()
}

fn chain_energy(n: usize) -> StoredEnergy {
    StoredEnergy {
        mass: Mat::identity(n, n),
        stiffness: chain_stiffness(n),
        cubic_springs: vec![],
    }
}

fn checked(records: &[Record], cycles: usize, energy: Option<&StoredEnergy>) -> SteadyStateReport {
    check(
        records,
        &WindowSpec::cycles(cycles),
        Quadrature::Trapezoid,
        energy,
        &SteadyStateSettings::default(),
    )
    .unwrap()
}

fn flagged(report: &SteadyStateReport) -> usize {
    report.rejected().count()
}

#[test]
fn explore() {
    let clean = four_mass(1000, 40);
    let records = noisy(&clean, 0.01, 0.01, 1);
    let e = chain_energy(4);
    let with = checked(&records[3..], 4, Some(&e));
    let without = checked(&records[3..], 4, None);
    println!("{with}{without}");
    let transient = four_mass(200, 40);
    for level in [0.0, 0.01, 0.03] {
        let records = noisy(&transient, level, level, 7);
        for cycles in [1usize, 4] {
            let with = checked(&records, cycles, Some(&e));
            let without = checked(&records, cycles, None);
            println!(
                "transient {level} cycles {cycles}: energy {}/{} state {}/{}",
                flagged(&with), with.windows.len(), flagged(&without), without.windows.len()
            );
            if cycles == 1 {
                let first: Vec<String> = with.windows.iter().filter(|w| w.window < 3).map(|w| format!("{} {} {}", w.record, w.window, w.reason)).collect();
                println!("{}", first.join("\n"));
                let first: Vec<String> = without.windows.iter().filter(|w| w.window < 3).map(|w| format!("{} {} {}", w.record, w.window, w.reason)).collect();
                println!("{}", first.join("\n"));
            }
        }
    }
}
