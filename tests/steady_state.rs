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
    assert!((estimate.cycles - 1000.0 / per_period).abs() < 1e-4);
    assert_eq!(estimate.whole_periods, None);
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

/// Under two periods, or under eight samples, no period can be detected, and the
/// error asks for one; pure noise shows no period.
#[test]
fn too_short_or_aperiodic_force_is_rejected() {
    let h = 0.1;
    let short = Mat::from_fn(15, 1, |i, _| (i as f64 * h).cos());
    let error = detect_period(short.as_ref(), h, "short").unwrap_err();
    assert!(
        matches!(error, Error::NoPeriod { ref record, .. } if record == "short"),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("`period` or `frequency`"),
        "{error}"
    );
    let tiny = Mat::from_fn(5, 1, |i, _| (i as f64).cos());
    let error = detect_period(tiny.as_ref(), h, "tiny").unwrap_err();
    assert!(matches!(error, Error::NoPeriod { .. }), "{error:?}");
    assert!(error.to_string().contains("5 samples"), "{error}");
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
