//! Free decay (`dampid::prep::free_decay`, `Windows::Decay`): ringdowns of a one-DOF
//! oscillator simulated independently (tests/support/ringdown.rs), identified through the
//! one `identify`, against their true laws.

#[path = "support/ringdown.rs"]
mod ringdown;

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
    let result = identify(
        &ParametricRegressor::linear(&model, records.as_slice()),
        &settings(DecaySettings::unit_mass()),
        &silent,
    )
    .unwrap();
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
        let result = identify(
            &ParametricRegressor::linear(&model, records.as_slice()),
            &settings(DecaySettings::unit_mass()),
            &silent,
        )
        .unwrap();
        found.push((
            result.coefficient("c").unwrap(),
            result.coefficient("d").unwrap(),
        ));
    }
    eprintln!("{found:?}");
    assert!((found[1].0 / found[0].0 - 1.0).abs() < 0.02);
    assert!((found[1].1 / found[0].1 - 1.0).abs() < 0.02);
}
