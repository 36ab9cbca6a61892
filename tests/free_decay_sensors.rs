//! Free decay of several sensors (`dampid::prep::free_decay::modal_filter`): a 3-DOF
//! chain rings down with modal damping (tests/support/modal_chain.rs, independent of
//! dampid), mode 1 under c q̇ + 5|q̇|^1.5 sgn q̇; three accelerometers with 0.5 % noise
//! (of each sensor's RMS, which modes 2 and 3 dominate).
//! Projected with the given mode shape or the record's own POD, mode 1's coefficients
//! are within 2 % of the truth and within 1 % of the single-mode result (mode 1's own
//! acceleration through the one-sensor pipeline); through a model file too.

#[path = "support/modal_chain.rs"]
mod modal_chain;
#[path = "support/ringdown.rs"]
mod ringdown;

use dampid::identify::{IdentifySettings, identify};
use dampid::prep::free_decay::{
    Band, BandChoice, DecaySettings, ModalFilter, isolate, isolate_with,
};
use dampid::prep::motion::{Integration, SensorParts, record_from_sensors};
use dampid::prep::velocity::VelocitySource;
use dampid::progress::silent;
use dampid::record::{Forcing, Record, Sensor};
use dampid::regressor::{Parametric, ParametricRegressor, RegressorSettings, Windows};
use faer::Mat;
use modal_chain::{chain_ringdown, csv};

const SAMPLES: usize = 65_536;

/// Unit modal mass, mode 1's peak looked for between 50 and 150 Hz.
fn mode_1() -> DecaySettings {
    DecaySettings {
        band: BandChoice::PeakIn(Band {
            low: 50.0,
            high: 150.0,
        }),
        ..DecaySettings::unit_mass()
    }
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

/// A record of accelerometer `channels` (one column each), no force.
fn record(channels: &[&[f64]], step: f64) -> Record {
    let n = channels[0].len();
    record_from_sensors(SensorParts {
        label: "chain".into(),
        step,
        start_time: 0.0,
        motion: Mat::from_fn(n, channels.len(), |i, j| channels[j][i]),
        sensors: vec![Sensor::Acceleration; channels.len()],
        forcing: Forcing::on_dofs(Mat::zeros(n, 0), Vec::new()),
        period: 1.0 / 80.0,
        integration: Integration::HighPass { cutoff: 5.0 },
    })
    .unwrap()
}

/// (c, d) fitted to the modes' `records`, unit modal mass, exponent 1.5.
fn fitted(records: &[Record]) -> (f64, f64) {
    let model =
        dampid::model_file::parse_model(&format!("dofs = 1\n{VISCOUS_POWER}"), "m.toml").unwrap();
    let settings = IdentifySettings {
        regressor: RegressorSettings {
            windows: Windows::Decay(DecaySettings::unit_mass()),
            velocity: VelocitySource::Measured,
            ..RegressorSettings::default()
        },
        steady_state: None,
        ..IdentifySettings::default()
    };
    let result = identify(
        &ParametricRegressor::new(Parametric::fixed(model), records),
        &settings,
        &silent,
    )
    .unwrap();
    (
        result.coefficient("c").unwrap(),
        result.coefficient("d").unwrap(),
    )
}

fn within(found: f64, truth: f64, tolerance: f64, what: &str) {
    assert!(
        (found / truth - 1.0).abs() < tolerance,
        "{what}: {found} against {truth}"
    );
}

/// The given shape and the POD both recover mode 1's law from three sensors that also
/// see modes 2 and 3 (224 and 324 Hz, each 3× mode 1's amplitude), and agree with the
/// single-mode result.
#[test]
fn three_sensors_give_mode_1s_law() {
    let chain = chain_ringdown(SAMPLES, 1.0, 0.005, 7);
    let truth = (chain.mode_1.viscous, 5.0);
    let step = chain.mode_1.step;
    let single = {
        let a = ringdown::with_noise(&chain.modal_acceleration, 0.01, 99);
        let decay = isolate(&record(&[&a], step), &mode_1()).unwrap();
        fitted(&[decay.record])
    };
    within(single.0, truth.0, 0.02, "single-mode c");
    within(single.1, truth.1, 0.02, "single-mode d");
    let sensors = record(
        &[&chain.sensors[0], &chain.sensors[1], &chain.sensors[2]],
        step,
    );
    for filter in [
        ModalFilter::Shape(chain.shapes[0].to_vec()),
        ModalFilter::Pod,
    ] {
        let decay = isolate_with(&sensors, Some(&filter), &mode_1()).unwrap();
        let band = decay.band;
        assert!(
            band.low < 80.0 && band.high > 80.0 && band.high < 224.0,
            "{band:?}"
        );
        let (c, d) = fitted(&[decay.record]);
        eprintln!("{filter:?}: c = {c}, d = {d}; single mode {single:?}");
        within(c, truth.0, 0.02, &format!("{filter:?}: c"));
        within(d, truth.1, 0.02, &format!("{filter:?}: d"));
        within(
            c,
            single.0,
            0.01,
            &format!("{filter:?}: c against the single mode"),
        );
        within(
            d,
            single.1,
            0.01,
            &format!("{filter:?}: d against the single mode"),
        );
    }
}

/// A shape that is not orthogonal to another mode (mode 1's plus half of mode 3's)
/// leaves mode 3 in the coordinate; at 324 Hz it lies above 1.5 × the band's top
/// (160 Hz), so the band-pass still isolates mode 1 (modal_filter.rs: "else the
/// band-pass that follows must remove it").
#[test]
fn a_shape_that_is_not_orthogonal_relies_on_the_band() {
    let chain = chain_ringdown(SAMPLES, 1.0, 0.005, 11);
    let step = chain.mode_1.step;
    let sensors = record(
        &[&chain.sensors[0], &chain.sensors[1], &chain.sensors[2]],
        step,
    );
    let mixed: Vec<f64> = (0..3)
        .map(|k| chain.shapes[0][k] + 0.5 * chain.shapes[2][k])
        .collect();
    let decay = isolate_with(&sensors, Some(&ModalFilter::Shape(mixed)), &mode_1()).unwrap();
    let (c, d) = fitted(&[decay.record]);
    // q = φᵀy/φᵀφ with φ = φ₁ + φ₃/2 (orthonormal φ_r): mode 1's coordinate × 1/1.25.
    let scale: f64 = 1.0 / 1.25;
    within(c, chain.mode_1.viscous, 0.02, "c");
    // d|q̇|^p: in the scaled coordinate d' = d × scale^(1−p).
    within(d, 5.0 * scale.powf(1.0 - 1.5), 0.02, "d");
}

/// The same through a model file: three acceleration columns and `mode_shape`.
#[test]
fn a_model_file_with_three_sensors() {
    let chain = chain_ringdown(SAMPLES, 1.0, 0.005, 5);
    let dir =
        std::env::temp_dir().join(format!("dampid-free-decay-sensors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("chain.csv"), csv(&chain.sensors)).unwrap();
    let shape = chain.shapes[0];
    let text = format!(
        "dofs = 1\n{VISCOUS_POWER}\n[data]\nrecords = [\n  {{ file = \"chain.csv\", step = {}, accelerations = [\"a1\", \"a2\", \"a3\"] }},\n]\n\n[free_decay]\nmass = 1.0\npeak_in = [50.0, 150.0]\nmode_shape = [{}, {}, {}]\n",
        chain.mode_1.step, shape[0], shape[1], shape[2]
    );
    let job = dampid::model_file::parse(&text, "chain.toml", &dir, Default::default()).unwrap();
    let result = identify(&job.problem(), &job.settings, &silent).unwrap();
    within(
        result.coefficient("c").unwrap(),
        chain.mode_1.viscous,
        0.02,
        "c",
    );
    within(result.coefficient("d").unwrap(), 5.0, 0.02, "d");
    let pod = text.replace(
        &format!("mode_shape = [{}, {}, {}]", shape[0], shape[1], shape[2]),
        "modal_filter = \"pod\"",
    );
    let job = dampid::model_file::parse(&pod, "chain.toml", &dir, Default::default()).unwrap();
    let result = identify(&job.problem(), &job.settings, &silent).unwrap();
    // The POD's shape is of unit length, as Φ's columns are: the same coordinate.
    within(
        result.coefficient("c").unwrap(),
        chain.mode_1.viscous,
        0.02,
        "POD c",
    );
    within(result.coefficient("d").unwrap(), 5.0, 0.02, "POD d");
    std::fs::remove_dir_all(&dir).ok();
}
