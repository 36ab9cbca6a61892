//! Cycle extraction: the driving period detected from the force, and the steady-state
//! check of every window (state and stored energy at its end against its start).

use std::f64::consts::PI;
use std::path::Path;

use dampid::model_file::{load, parse};
use dampid::prelude::*;
use dampid::prep::period::detect_period;
use faer::Mat;

mod support;
use support::cli::dampid;

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
    let job = parse(
        &from_rest(0, false),
        "rest.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap();
    let report = job.steady_state().unwrap().expect("a periodic model file");
    assert!(report.energy_known);
    let window = &report.windows[0];
    assert!(!window.steady);
    let mismatch = window.energy_mismatch.unwrap();
    assert!(mismatch > 0.1, "{mismatch}");
    match report.enforce().unwrap_err() {
        err @ Error::NotSteady { .. } => {
            let text = err.to_string();
            for needle in ["a=1 ω=1 on DOF 2", "window 0", "t = 0", "exceeds"] {
                assert!(text.contains(needle), "'{needle}' not in: {text}");
            }
            let Error::NotSteady {
                mismatch: reported,
                threshold,
                ..
            } = err
            else {
                unreachable!()
            };
            assert_eq!(reported, mismatch);
            // The threshold is max(1%, 4 σ of the noise): the transient itself raises
            // the out-of-band noise estimate, but not to its own size.
            assert!(
                threshold >= 0.01 && threshold < mismatch / 4.0,
                "{threshold}"
            );
        }
        other => panic!("{other:?}"),
    }
    // Accepted: reported, not rejected, and the fit runs.
    let accepted = parse(
        &from_rest(0, true),
        "rest.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap();
    assert!(
        accepted
            .steady_state()
            .unwrap()
            .expect("a periodic model file")
            .enforce()
            .is_ok()
    );

    // 2500 samples in, the transient (decaying at c/2 = 0.025) is down to e^-6.25.
    let steady = parse(
        &from_rest(2500, false),
        "rest.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap();
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
    let fit = dampid::identify(
        &ParametricRegressor::linear(&steady.model, &steady.records),
        &steady.settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!((fit.coefficient("c").unwrap() - 0.05).abs() < 0.05 * 0.01);
}

/// The state criterion (M and K unknown) sees the same transient.
#[test]
fn state_criterion_sees_the_transient_too() {
    let job = parse(
        &from_rest(0, false),
        "rest.toml",
        Path::new("."),
        Default::default(),
    )
    .unwrap();
    let without_energy = dampid::prep::steady_state::check(
        &job.source_records,
        job.source_windows.windows.cycles().unwrap(),
        job.source_windows.quadrature,
        None,
        job.settings.steady_state.as_ref().unwrap(),
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
    let job = load(Path::new("models/four_mass.toml"), Default::default()).unwrap();
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
    let job = parse(text, "detect.toml", Path::new("models"), Default::default()).unwrap();
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

/// The 3-DOF chain (M = I, K = chain, c = 0.05 on every DOF) driven on DOF 1 at its
/// first mode, ω = 2 sin(π/8), after 4000 steps (e^{-10} of the transient left),
/// `cycles` periods recorded.
fn chain3(cycles: usize) -> Vec<Record> {
    let omega = 2.0 * (PI / 8.0).sin();
    let system = System {
        mass: Mat::identity(3, 3),
        stiffness: chain_stiffness(3),
        damping: DampingModel::new().with(Term::per_dof(
            Linear,
            3,
            Coefficients::Shared("c".into()),
        )),
        damping_coefficients: vec![0.05],
        conservative: vec![],
        forcing: vec![HarmonicForce {
            dof: 0,
            amplitude: 1.0,
            frequency: omega,
            phase: 0.0,
        }],
    };
    let settings = SimSettings {
        transient_steps: 4000,
        recorded_steps: (cycles as f64 * 2.0 * PI / omega / 0.1).ceil() as usize + 4,
        ..SimSettings::default()
    };
    vec![simulate(&system, &settings, &dampid::progress::silent).unwrap()]
}

/// Steady responses with 1% displacement noise and 1% force noise: at most 5% of the
/// windows flagged, for the four-mass chain (40 cycles, windows of 1 and 4 periods,
/// with and without M and K) and the 3-DOF chain (30 windows of one period; also at
/// 0.3% and 0.1%, where the old central-difference check flagged 20 and 10 of 30),
/// over several seeds. Today's check flagged all 36 and 29 of 30.
#[test]
fn one_percent_noise_on_steady_responses_flags_at_most_five_percent() {
    let four = four_mass(1000, 40);
    let energy = chain_energy(4);
    for seed in [1u64, 2, 3] {
        let records = noisy(&four, 0.01, 0.01, seed);
        for cycles in [1usize, 4] {
            for e in [Some(&energy), None] {
                let report = checked(&records, cycles, e);
                let share = flagged(&report) as f64 / report.windows.len() as f64;
                assert!(
                    share <= 0.05,
                    "seed {seed}, cycles {cycles}, {share}:\n{report}"
                );
                assert!(report.windows.len() >= 40);
            }
        }
    }
    let three = chain3(31);
    let energy = chain_energy(3);
    for level in [0.01, 0.003, 0.001] {
        for seed in [11u64, 12, 13, 14] {
            let records = noisy(&three, level, level, seed);
            for e in [Some(&energy), None] {
                let report = checked(&records, 1, e);
                assert!(report.windows.len() >= 30);
                let share = flagged(&report) as f64 / report.windows.len() as f64;
                assert!(
                    share <= 0.05,
                    "level {level}, seed {seed}, {share}:\n{report}"
                );
            }
        }
    }
}

/// The four-mass chain after only 200 transient steps is still rejected at 0%, 1% and
/// 3% noise: the first window of every record (the model file's one equation per
/// record), for windows of 1 and 4 periods, with and without M and K, and the report
/// says why in σ of the noise (without noise: that the records carry none to measure). One exception is measured and allowed: without M and K
/// at 3% noise, the first window of a=1 (the record that settles fastest) differs from
/// its neighbour by about 5% of its velocity amplitude, 3.3–3.5 σ of the noise, and
/// may pass; the other three records' first windows are rejected, so the job is.
#[test]
fn transient_four_mass_is_rejected_at_every_noise_level() {
    let transient = four_mass(200, 40);
    let energy = chain_energy(4);
    for level in [0.0, 0.01, 0.03] {
        for seed in [5u64, 6] {
            let records = noisy(&transient, level, level, seed);
            for cycles in [1usize, 4] {
                for e in [Some(&energy), None] {
                    let report = checked(&records, cycles, e);
                    let first: Vec<_> = report.windows.iter().filter(|w| w.window == 0).collect();
                    let rejected: Vec<_> = first.iter().filter(|w| !w.steady).collect();
                    let allowed = usize::from(e.is_none() && level > 0.02);
                    assert!(
                        rejected.len() + allowed >= first.len(),
                        "level {level}, cycles {cycles}:\n{report}"
                    );
                    for w in rejected {
                        assert!(w.reason.starts_with("not steady"), "{}", w.reason);
                        // noise-free records have none to measure against (the record's
                        // noise is its steady spans', round-off)
                        let said = if level == 0.0 {
                            "no measurable noise"
                        } else {
                            "σ of the noise"
                        };
                        assert!(w.reason.contains(said), "{}", w.reason);
                        assert!(w.noise_sigmas().unwrap() > 4.0, "{w:?}");
                    }
                    assert!(report.enforce().is_err());
                    // Late windows, long after the transient, are steady.
                    let late = report.windows.iter().filter(|w| w.start_time > 300.0);
                    let (count, rejected) =
                        late.fold((0, 0), |(c, r), w| (c + 1, r + usize::from(!w.steady)));
                    assert!(rejected * 20 <= count, "{rejected} of {count} late windows");
                }
            }
        }
    }
}

/// The 3-DOF chain of [`chain3`], integrated here by RK4 (h = 0.1), with a force
/// cos φ(t) on DOF 1 whose frequency jumps from ω₁ to 1.25 ω₁ (phase-continuous) after
/// `before` periods of T₁ from the record's start; `total` periods recorded.
fn frequency_change(before: usize, total: usize) -> Record {
    let omega = 2.0 * (PI / 8.0).sin();
    let (h, c) = (0.1, 0.05);
    let period = 2.0 * PI / omega;
    let skip = 4000usize;
    let switch = skip as f64 * h + before as f64 * period;
    let phase = |t: f64| {
        if t < switch {
            omega * t
        } else {
            omega * switch + 1.25 * omega * (t - switch)
        }
    };
    let k = chain_stiffness(3);
    let rate = |t: f64, y: &[f64; 6]| {
        let mut d = [0.0; 6];
        for i in 0..3 {
            d[i] = y[3 + i];
            let kx: f64 = (0..3).map(|j| k[(i, j)] * y[j]).sum();
            let f = if i == 0 { phase(t).cos() } else { 0.0 };
            d[3 + i] = f - c * y[3 + i] - kx;
        }
        d
    };
    let samples = (total as f64 * period / h).ceil() as usize + 4;
    let (mut x, mut f) = (Mat::zeros(samples, 3), Mat::zeros(samples, 1));
    let mut y = [0.0; 6];
    for step in 0..skip + samples {
        let t = step as f64 * h;
        if step >= skip {
            for i in 0..3 {
                x[(step - skip, i)] = y[i];
            }
            f[(step - skip, 0)] = phase(t).cos();
        }
        let add = |y: &[f64; 6], d: &[f64; 6], s: f64| std::array::from_fn(|i| y[i] + s * d[i]);
        let k1 = rate(t, &y);
        let k2 = rate(t + h / 2.0, &add(&y, &k1, h / 2.0));
        let k3 = rate(t + h / 2.0, &add(&y, &k2, h / 2.0));
        let k4 = rate(t + h, &add(&y, &k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    Record::new(RecordParts {
        label: "switch".into(),
        step: h,
        start_time: 0.0,
        displacements: x,
        velocities: None,
        forcing: Forcing::on_dofs(f, vec![0]),
        period,
    })
    .unwrap()
}

/// A record whose forcing frequency changes halfway is rejected at 0%, 1% and 3%
/// noise: every window from the change on is flagged, while the windows before it are
/// steady (at most one flagged).
#[test]
fn frequency_change_halfway_is_rejected_at_every_noise_level() {
    let clean = frequency_change(20, 40);
    let switch = 20.0 * clean.period();
    let energy = chain_energy(3);
    for level in [0.0, 0.01, 0.03] {
        for seed in [21u64, 22] {
            let records = noisy(std::slice::from_ref(&clean), level, level, seed);
            for cycles in [1usize, 2] {
                for e in [Some(&energy), None] {
                    let report = checked(&records, cycles, e);
                    assert!(report.enforce().is_err());
                    let span = cycles as f64 * clean.period();
                    let mut before = 0;
                    for w in &report.windows {
                        if w.start_time + span > switch + 0.1 {
                            assert!(
                                !w.steady,
                                "level {level}, cycles {cycles}, window {}:\n{report}",
                                w.window
                            );
                        } else {
                            before += usize::from(!w.steady);
                        }
                    }
                    assert!(before <= 1, "level {level}, cycles {cycles}:\n{report}");
                }
            }
        }
    }
}

/// Writes `records` (displacements x1.., force f on DOF 4) as CSV files in `dir` and a
/// model file that reads them with M and K known; returns its path.
fn model_file_of(dir: &std::path::Path, records: &[Record]) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let mut toml = String::from(
        r#"title = "four masses, measured"
dofs = 4

[[terms]]
kind = "stiffness_proportional"
coefficient = "c"
matrix = "chain"

[[terms]]
kind = "law"
law = "quadratic"
elements = "each_dof"
coefficient = "d"

[identification]
cycles = 1

[system]
mass = "identity"
stiffness = "chain"
"#,
    );
    for (k, r) in records.iter().enumerate() {
        let mut csv = String::from("t,x1,x2,x3,x4,f\n");
        let x = r.displacements();
        for i in 0..r.samples() {
            csv.push_str(&format!("{:.10e}", i as f64 * r.step()));
            for j in 0..4 {
                csv.push_str(&format!(",{:.17e}", x[(i, j)]));
            }
            csv.push_str(&format!(",{:.17e}\n", r.forcing().signals[(i, 0)]));
        }
        std::fs::write(dir.join(format!("rec{k}.csv")), csv).unwrap();
        toml.push_str(&format!(
            "\n[[data.records]]\nfile = \"rec{k}.csv\"\ntime = \"t\"\nfrequency = 0.618\ndisplacements = [\"x1\", \"x2\", \"x3\", \"x4\"]\nforces = [{{ column = \"f\", dof = 4 }}]\n"
        ));
    }
    let path = dir.join("measured.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

/// `dampid check` on files with 1% noise: steady records pass and the table gives the
/// mismatch in σ of the noise; records 200 steps after rest exit with 2, and the
/// windows are explained in words.
#[test]
fn check_explains_in_words_and_in_noise_sigmas() {
    let dir = std::env::temp_dir().join(format!("dampid-steady-cli-{}", std::process::id()));
    let steady = noisy(&four_mass(1000, 6), 0.01, 0.01, 31);
    let path = model_file_of(&dir.join("steady"), &steady);
    let out = dampid(&["check", path.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needle in ["|ΔE|/|W| within max(1%, 4 σ of its noise)", " σ ", "steady"] {
        assert!(stdout.contains(needle), "'{needle}' not in {stdout}");
    }
    assert!(!stdout.contains("NOT STEADY"), "{stdout}");

    let transient = noisy(&four_mass(200, 6), 0.01, 0.01, 32);
    let path = model_file_of(&dir.join("transient"), &transient);
    let out = dampid(&["check", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    // The report, with every window's verdict, on stdout; the refusal on stderr.
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    for needle in [
        "NOT STEADY",
        "window 0: not steady: the stored energy at the end differs from the start",
        "σ of the noise",
    ] {
        assert!(stdout.contains(needle), "'{needle}' not in {stdout}");
    }
    for needle in ["skip more of the transient", "--accept-transient"] {
        assert!(stderr.contains(needle), "'{needle}' not in {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
