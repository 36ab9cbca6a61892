//! Free decay (`dampid::prep::free_decay`, `Windows::Decay`): ringdowns of a one-DOF
//! oscillator simulated independently (tests/support/ringdown.rs), identified through the
//! one `identify`, against their true laws: coefficients, estimated exponents, the
//! backbone ζ(X) against its closed form, interval coverage over seeds, a second mode in
//! the signal, Coulomb friction, a hammer's impact; the shipped hammer example from its
//! model file; and a typed error for each kind of bad `[free_decay]`.

#[path = "support/ringdown.rs"]
mod ringdown;
mod support;

use dampid::identify::{IdentifySettings, identify};
use dampid::prep::free_decay::{DecaySettings, isolate};
use dampid::prep::motion::{Integration, SensorParts, record_from_sensors};
use dampid::prep::velocity::VelocitySource;
use dampid::progress::silent;
use dampid::record::{Forcing, Record, Sensor};
use dampid::regressor::{ParametricRegressor, RegressorSettings, Windows};
use faer::Mat;
use ringdown::{Ringdown, linear_mode_acceleration, with_noise};

/// A record of one sensor's `signal` (and the hammer's force when given).
fn record(label: &str, signal: &[f64], sensor: Sensor, step: f64, force: Option<&[f64]>) -> Record {
    let n = signal.len();
    let forcing = match force {
        Some(f) => Forcing::on_dofs(Mat::from_fn(n, 1, |i, _| f[i]), vec![0]),
        None => Forcing::on_dofs(Mat::zeros(n, 0), Vec::new()),
    };
    record_from_sensors(SensorParts {
        label: label.into(),
        step,
        start_time: 0.0,
        motion: Mat::from_fn(n, 1, |i, _| signal[i]),
        sensors: vec![sensor],
        forcing,
        period: 1.0 / 80.0,
        integration: Integration::HighPass { cutoff: 5.0 },
    })
    .unwrap()
}

fn settings(decay: DecaySettings) -> IdentifySettings {
    IdentifySettings {
        regressor: RegressorSettings {
            windows: Windows::Decay(decay),
            velocity: VelocitySource::Measured,
            ..RegressorSettings::default()
        },
        steady_state: None,
        ..IdentifySettings::default()
    }
}

/// The one `identify` of `law` on the modes' `records`, unit modal mass.
fn fitted(
    law: dampid::regressor::ParametricModel,
    records: &[Record],
) -> dampid::identify::Identification {
    identify(
        &ParametricRegressor::new(law, records),
        &settings(DecaySettings::unit_mass()),
        &silent,
    )
    .unwrap()
}

fn model(text: &str) -> dampid::model::DampingModel {
    dampid::model_file::parse_model(&format!("dofs = 1\n{text}"), "free_decay.toml").unwrap()
}

const VISCOUS_POWER: &str = r#"
[[terms]]
kind = "viscous"
coefficient = "c"
matrix = "identity"

[[terms]]
kind = "law"
law = "power"
exponent = 1.5
coefficient = "d"
elements = [[1, 0]]
"#;

/// Viscous ζ = 0.1 % plus 5|v|^1.5 sgn v at 80 Hz, m = 1, measured as an acceleration
/// with 1 % noise: c and d within 1 %.
#[test]
fn a_viscous_and_power_law_ringdown_from_accelerations() {
    let truth = Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        power: Some((5.0, 1.5)),
        x0: 2e-3,
        ..Ringdown::at_80_hz()
    };
    let [_, _, a, _] = truth.simulate();
    let a = with_noise(&a, 0.01, 11);
    let source = record("ringdown", &a, Sensor::Acceleration, truth.step, None);
    let decay = isolate(&source, &DecaySettings::unit_mass()).unwrap();
    eprintln!(
        "band {:?}, {} cycles, {} at edges, {} at floor, noise {:.3e}",
        decay.band,
        decay.cycles.len(),
        decay.dropped_at_edges,
        decay.dropped_at_floor,
        decay.noise_amplitude
    );
    let records = vec![decay.record.clone()];
    let model = model(VISCOUS_POWER);
    let result = fitted(
        dampid::regressor::Parametric::fixed(model.clone()),
        &records,
    );
    let (c, d) = (
        result.coefficient("c").unwrap(),
        result.coefficient("d").unwrap(),
    );
    eprintln!("c = {c} (truth {}), d = {d} (truth 5)", truth.viscous);
    assert!((c / truth.viscous - 1.0).abs() < 0.01, "c = {c}");
    assert!((d / 5.0 - 1.0).abs() < 0.01, "d = {d}");
}

/// A second mode at 3.7 × the frequency with 3 × the amplitude in the signal changes
/// mode 1's coefficients by less than 2 %.
#[test]
fn a_second_mode_in_the_signal_is_filtered_out() {
    let truth = Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        power: Some((5.0, 1.5)),
        x0: 2e-3,
        ..Ringdown::at_80_hz()
    };
    let [_, _, a, _] = truth.simulate();
    let second = linear_mode_acceleration(a.len(), truth.step, 3.7 * 80.0, 0.002, 3.0 * 2e-3);
    let both: Vec<f64> = a.iter().zip(&second).map(|(a, b)| a + b).collect();
    let model = model(VISCOUS_POWER);
    let mut found = Vec::new();
    for signal in [&a, &both] {
        let source = record("ringdown", signal, Sensor::Acceleration, truth.step, None);
        let decay = isolate(&source, &DecaySettings::unit_mass()).unwrap();
        let records = vec![decay.record];
        let result = fitted(
            dampid::regressor::Parametric::fixed(model.clone()),
            &records,
        );
        found.push((
            result.coefficient("c").unwrap(),
            result.coefficient("d").unwrap(),
        ));
    }
    eprintln!("{found:?}");
    assert!((found[1].0 / found[0].0 - 1.0).abs() < 0.02);
    assert!((found[1].1 / found[0].1 - 1.0).abs() < 0.02);
}

const VISCOUS_POWER_ESTIMATED: &str = r#"
[[terms]]
kind = "viscous"
coefficient = "c"
matrix = "identity"

[[terms]]
kind = "law"
law = "power"
exponent = { estimate = true, initial = 2.0, lower = 1.05, upper = 3.5 }
coefficient = "d"
elements = [[1, 0]]
"#;

/// mean of |cos θ|^q over a period: Γ((q+1)/2) / (√π Γ(q/2 + 1)).
fn mean_abs_cos(q: f64) -> f64 {
    use statrs::function::gamma::gamma;
    gamma(0.5 * (q + 1.0)) / (std::f64::consts::PI.sqrt() * gamma(0.5 * q + 1.0))
}

/// ζ_eq(X) of c v + d|v|^p sgn v at amplitude X and frequency ω, unit mass, by hand:
/// E_d = π c ω X² + d (ωX)^{p+1} (2π/ω) M_{p+1}, ζ = E_d / (2π ω² X²).
fn zeta_by_hand(c: f64, d: f64, p: f64, x: f64, omega: f64) -> f64 {
    let dissipated = std::f64::consts::PI * c * omega * x * x
        + d * (omega * x).powf(p + 1.0) * 2.0 * std::f64::consts::PI / omega
            * mean_abs_cos(p + 1.0);
    dissipated / (2.0 * std::f64::consts::PI * omega * omega * x * x)
}

/// Two accelerometer ringdowns whose starts span 10× and whose decays together span
/// more than 50× in amplitude, 1 % noise.
fn two_ringdowns(truth: &Ringdown, seed: u64) -> Vec<Record> {
    [truth.x0, 0.1 * truth.x0]
        .iter()
        .enumerate()
        .map(|(k, &x0)| {
            let run = Ringdown { x0, ..*truth };
            let [_, _, a, _] = run.simulate();
            let a = with_noise(&a, 0.01, seed * 2 + k as u64);
            let source = record(
                &format!("x0 = {x0}"),
                &a,
                Sensor::Acceleration,
                run.step,
                None,
            );
            isolate(&source, &DecaySettings::unit_mass())
                .unwrap()
                .record
        })
        .collect()
}

fn power_truth(d: f64, p: f64) -> Ringdown {
    Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        power: Some((d, p)),
        x0: 3e-3,
        ..Ringdown::at_80_hz()
    }
}

/// Viscous ζ = 0.1 % plus a power law with p = 1.5 and with p = 2.5, the exponent
/// estimated: c, d and p within 1 %, and the fitted ζ(X) within 1 % of the closed form
/// over the whole amplitude range (over 50×).
#[test]
fn power_laws_with_estimated_exponents_and_their_backbones() {
    let model = dampid::model_file::parse_parametric_model(
        &format!("dofs = 1\n{VISCOUS_POWER_ESTIMATED}"),
        "free_decay.toml",
    )
    .unwrap()
    .1;
    for (d, p) in [(5.0, 1.5), (2.0, 2.5)] {
        let truth = power_truth(d, p);
        let records = two_ringdowns(&truth, 1);
        let found = fitted(model.clone(), &records);
        let (c, d_hat) = (
            found.coefficient("c").unwrap(),
            found.coefficient("d").unwrap(),
        );
        let p_hat = found.report.parameter("d.exponent").unwrap();
        eprintln!("p = {p}: c = {c}, d = {d_hat}, p̂ = {p_hat}");
        assert!((c / truth.viscous - 1.0).abs() < 0.01, "c = {c}");
        assert!((d_hat / d - 1.0).abs() < 0.01, "d = {d_hat}");
        assert!((p_hat / p - 1.0).abs() < 0.01, "p = {p_hat}");
        let backbone = found.backbone.as_ref().unwrap();
        let (lo, hi) = backbone.amplitude_range().unwrap();
        assert!(hi / lo > 50.0, "amplitudes {lo}..{hi}");
        for point in &backbone.points {
            let omega = 2.0 * std::f64::consts::PI * point.frequency;
            let expected = zeta_by_hand(truth.viscous, d, p, point.amplitude, omega);
            assert!(
                (point.fitted / expected - 1.0).abs() < 0.01,
                "ζ at X = {}: {} vs {expected}",
                point.amplitude,
                point.fitted
            );
        }
    }
}

/// The 95 % intervals of c and d (exponent estimated, joint errors) cover the truth in
/// at least 90 % of 40 seeds.
#[test]
fn intervals_cover_the_truth_over_seeds() {
    let model = dampid::model_file::parse_parametric_model(
        &format!("dofs = 1\n{VISCOUS_POWER_ESTIMATED}"),
        "free_decay.toml",
    )
    .unwrap()
    .1;
    let truth = power_truth(5.0, 1.5);
    let mut covered = [0; 3];
    let seeds = 40;
    for seed in 0..seeds {
        let records = two_ringdowns(&truth, 100 + seed);
        let found = fitted(model.clone(), &records);
        let estimation = found.report.estimation.as_ref().unwrap();
        for (k, (name, value)) in [("c", truth.viscous), ("d", 5.0)].iter().enumerate() {
            let joint = estimation
                .coefficients
                .iter()
                .find(|c| c.name == *name)
                .unwrap();
            let (lo, hi) = (joint.lower.unwrap(), joint.upper.unwrap());
            covered[k] += usize::from(lo <= *value && *value <= hi);
        }
        let profile = estimation.parameters[0].interval.as_ref().unwrap();
        let (lo, hi) = (profile.lower.unwrap(), profile.upper.unwrap());
        covered[2] += usize::from(lo <= 1.5 && 1.5 <= hi);
    }
    eprintln!("covered {covered:?} of {seeds}");
    for k in covered {
        assert!(k * 10 >= seeds as usize * 9, "{covered:?} of {seeds}");
    }
}

/// Coulomb friction μ sgn v beside viscous ζ = 0.1 % (the envelope decays linearly at
/// small amplitude), accelerations with 1 % noise: μ and c within 1 %.
#[test]
fn coulomb_and_viscous() {
    let truth = Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        coulomb: 0.1,
        x0: 2e-3,
        ..Ringdown::at_80_hz()
    };
    let [_, _, a, _] = truth.simulate();
    let a = with_noise(&a, 0.01, 5);
    let source = record("coulomb", &a, Sensor::Acceleration, truth.step, None);
    let decay = isolate(&source, &DecaySettings::unit_mass()).unwrap();
    let records = vec![decay.record];
    let model = model(
        r#"
[[terms]]
kind = "viscous"
coefficient = "c"
matrix = "identity"

[[terms]]
kind = "law"
law = "coulomb"
coefficient = "mu"
elements = [[1, 0]]
"#,
    );
    let found = fitted(
        dampid::regressor::Parametric::fixed(model.clone()),
        &records,
    );
    let (c, mu) = (
        found.coefficient("c").unwrap(),
        found.coefficient("mu").unwrap(),
    );
    eprintln!("c = {c} (truth {}), μ = {mu} (truth 0.1)", truth.viscous);
    assert!((c / truth.viscous - 1.0).abs() < 0.01, "c = {c}");
    assert!((mu / 0.1 - 1.0).abs() < 0.01, "μ = {mu}");
}

/// A hammer's half-sine of 0.5 ms on the oscillator at rest, its force recorded: the
/// automatic start lies after the impact, and the coefficients equal those of the same
/// ringdown recorded from the end of the impact on, without the force.
#[test]
fn an_impact_starts_the_decay_after_the_force() {
    let quiet = 512;
    let truth = Ringdown {
        viscous: 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0,
        power: Some((5.0, 1.5)),
        hammer: Some((400.0, 0.5e-3)),
        quiet,
        ..Ringdown::at_80_hz()
    };
    let [_, _, a, f] = truth.simulate();
    let a = with_noise(&a, 0.005, 3);
    let hit = record("hit", &a, Sensor::Acceleration, truth.step, Some(&f));
    let decay = isolate(&hit, &DecaySettings::unit_mass()).unwrap();
    let impact_end = quiet as f64 * truth.step + 0.5e-3;
    assert!(
        decay.record.start_time() > impact_end,
        "the decay starts at {} s, the impact ends at {impact_end} s",
        decay.record.start_time()
    );
    let after = (impact_end / truth.step).ceil() as usize + 1;
    let cut = record("cut", &a[after..], Sensor::Acceleration, truth.step, None);
    let model = model(VISCOUS_POWER);
    let mut found = Vec::new();
    for source in [&hit, &cut] {
        let records = vec![isolate(source, &DecaySettings::unit_mass()).unwrap().record];
        let result = fitted(
            dampid::regressor::Parametric::fixed(model.clone()),
            &records,
        );
        found.push([
            result.coefficient("c").unwrap(),
            result.coefficient("d").unwrap(),
        ]);
    }
    eprintln!("impact {:?}, cut {:?}", found[0], found[1]);
    for k in 0..2 {
        assert!((found[0][k] / found[1][k] - 1.0).abs() < 0.01, "{found:?}");
    }
    assert!(
        (found[0][0] / truth.viscous - 1.0).abs() < 0.01,
        "{found:?}"
    );
    assert!((found[0][1] / 5.0 - 1.0).abs() < 0.01, "{found:?}");
}

/// The shipped hammer test (models/ringdown.toml, made by NumPy in
/// models/data/ringdown/make.py) runs as is and recovers its truth: c = 1.00531,
/// d = 5, p = 1.5, each inside its 95 % interval and within 1 %.
#[test]
fn the_shipped_hammer_example() {
    let json = support::cli::dampid_json(&["identify", "models/ringdown.toml", "--json"]);
    let estimation = &json["report"]["estimation"];
    let exponent = &estimation["parameters"][0];
    let p = exponent["value"].as_f64().unwrap();
    assert!((p / 1.5 - 1.0).abs() < 0.01, "p = {p}");
    assert!(exponent["interval"]["lower"].as_f64().unwrap() <= 1.5);
    assert!(exponent["interval"]["upper"].as_f64().unwrap() >= 1.5);
    for (name, truth) in [
        ("c", 2.0 * 0.001 * 2.0 * std::f64::consts::PI * 80.0),
        ("d", 5.0),
    ] {
        let joint = estimation["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap();
        let value = joint["value"].as_f64().unwrap();
        assert!((value / truth - 1.0).abs() < 0.01, "{name} = {value}");
        assert!(
            joint["lower"].as_f64().unwrap() <= truth && joint["upper"].as_f64().unwrap() >= truth
        );
    }
    let backbone = json["backbone"]["points"].as_array().unwrap();
    assert!(backbone.len() > 300);
    let decay = &json["free_decay"][0];
    assert!(decay["start_time"].as_f64().unwrap() > 0.02 + 0.5e-3);
    assert!(decay["largest"].as_f64().unwrap() / decay["smallest"].as_f64().unwrap() > 50.0);
}

/// The shipped hammer model with `edit` applied, parsed beside models/.
fn hammer_job(edit: impl Fn(String) -> String) -> dampid::Result<dampid::model_file::Job> {
    let text = std::fs::read_to_string("models/ringdown.toml").unwrap();
    dampid::model_file::parse(
        &edit(text),
        "ringdown.toml",
        std::path::Path::new("models"),
        dampid::model_file::Options::default(),
    )
}

/// Each kind of bad `[free_decay]` is a typed error that names the key, its line and
/// what to give instead.
#[test]
fn bad_free_decay_sections_are_typed_errors() {
    let replace = |from: &'static str, to: &'static str| {
        move |text: String| {
            assert!(text.contains(from), "{from}");
            text.replacen(from, to, 1)
        }
    };
    type Edit = Box<dyn Fn(String) -> String>;
    let cases: Vec<(Edit, &[&str])> = vec![
        (
            Box::new(replace("mass = 1.0 ", "# no mass ")),
            &[
                "ringdown.toml:35:",
                "[free_decay] needs the modal mass",
                "mass = 1.0",
            ],
        ),
        (
            Box::new(replace("peak_in = [50.0, 150.0]", "band = [150.0, 50.0]")),
            &["ringdown.toml:37:", "band", "0 < low < high"],
        ),
        (
            Box::new(replace(
                "peak_in = [50.0, 150.0]",
                "band = [50.0, 150.0]\npeak_in = [50.0, 150.0]",
            )),
            &["`band`", "`peak_in`", "not both"],
        ),
        (
            Box::new(replace("peak_in = [50.0, 150.0]", "start = \"after\"")),
            &["ringdown.toml:37:", "start", "\"auto\""],
        ),
        (
            Box::new(replace("peak_in = [50.0, 150.0]", "floor = 1e9")),
            &[
                "record 'hit 1' has no whole cycle",
                "below 1000000000 × the noise amplitude",
            ],
        ),
        (
            Box::new(replace(
                "[free_decay]",
                "[identification]\ncycles = 2\n\n[free_decay]",
            )),
            &["cycles", "does not apply beside [free_decay]"],
        ),
        (
            Box::new(replace(
                "peak_in = [50.0, 150.0]",
                "peak_in = [50.0, 150.0]\n\n[non_periodic]\nwindow = 0.1",
            )),
            &["[free_decay] reads ringdowns from [data]", "[non_periodic]"],
        ),
        (
            Box::new(replace(
                "peak_in = [50.0, 150.0]",
                "peak_in = [5000.0, 8000.0]",
            )),
            &["ringdown.toml:37:", "peak_in", "Nyquist"],
        ),
    ];
    for (edit, expected) in cases {
        let Err(error) = hammer_job(edit) else {
            panic!("an error expected");
        };
        let error = error.to_string();
        for e in expected {
            assert!(error.contains(e), "'{e}' not in: {error}");
        }
    }
}

/// A record of two motion channels is not one sensor of a mode: the error names it.
#[test]
fn a_record_of_two_channels_is_refused() {
    let a = vec![0.0; 4096];
    let source = record_from_sensors(SensorParts {
        label: "two".into(),
        step: 1e-3,
        start_time: 0.0,
        motion: Mat::from_fn(a.len(), 2, |i, j| ((i * (j + 1)) as f64 * 0.3).sin()),
        sensors: vec![Sensor::Acceleration; 2],
        forcing: Forcing::on_dofs(Mat::zeros(a.len(), 0), Vec::new()),
        period: 1.0,
        integration: Integration::HighPass { cutoff: 1.0 },
    })
    .unwrap();
    let error = isolate(&source, &DecaySettings::unit_mass()).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("record 'two' has 2 motion channels"),
        "{error}"
    );
}

/// A force that acts until the record's end leaves no decay: the error says so, and a
/// sensor that reads nothing has no mode to isolate.
#[test]
fn a_force_to_the_end_or_a_silent_sensor_is_refused() {
    let n = 4096;
    let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.04).sin()).collect();
    let force: Vec<f64> = (0..n).map(|i| (i as f64 * 0.04).cos()).collect();
    let driven = record("driven", &a, Sensor::Acceleration, 1e-3, Some(&force));
    let error = isolate(&driven, &DecaySettings::unit_mass()).unwrap_err();
    assert!(
        matches!(error, dampid::Error::RecordTooShort { needed: 64, .. }),
        "{error}"
    );
    assert!(error.to_string().contains("its free decay"), "{error}");
    let silent = record("silent", &vec![0.0; n], Sensor::Acceleration, 1e-3, None);
    let error = isolate(&silent, &DecaySettings::unit_mass()).unwrap_err();
    assert!(error.to_string().contains("no spectral peak"), "{error}");
}
