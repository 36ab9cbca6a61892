//! Accelerometer records of the four-mass chain (models/four_mass.toml: M = I, K the
//! chain, C = 0.15 K, d = 0.10 ẋ|ẋ| on every mass, a force on mass 4 at ω = 0.618), as
//! a test lab saves them: four runs (force amplitudes 0.25 to 1), each 8 steady periods
//! at h = 0.1, every channel in volts. Accelerometers of 0.2 V per unit acceleration
//! (gain 5 units per volt) on all four masses, the force through an amplifier monitor
//! of 35.15 force units per volt; 0.5 % white noise on every channel.
//! The acceleration is the equation of motion's, a = f − K x − c K v − d v|v|.
//!
//! ```sh
//! cargo run --release --example accelerometer_records                # identify them
//! cargo run --release --example accelerometer_records -- --write models/data/four_mass_acc
//! ```
//!
//! With `--write DIR` it writes `DIR/run_1.csv` … `run_4.csv` (columns t, acc1 … acc4,
//! vir), which `models/four_mass_accelerometers.toml` reads.

use std::path::{Path, PathBuf};

use dampid::error::{Error, Result};
use dampid::io::output::Overwrite;
use dampid::prelude::*;
use dampid::prep::motion::Integration;
use dampid::reference::four_mass::{
    FOUR_MASS_C, FOUR_MASS_D, FOUR_MASS_OMEGA, four_mass_model, four_mass_records_with,
};
use dampid::simulate::SimSettings;
use faer::Mat;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// Units of acceleration per volt of the accelerometers.
const ACCELEROMETER_GAIN: f64 = 5.0;
/// Force units per volt of the force monitor.
const FORCE_GAIN: f64 = 35.15;

/// Per run: time, the four accelerations and the force, in volts, with noise.
fn runs() -> Result<Vec<(f64, Mat<f64>)>> {
    let period = 2.0 * std::f64::consts::PI / FOUR_MASS_OMEGA;
    let settings = SimSettings {
        transient_steps: 6000,
        recorded_steps: (8.0 * period / 0.1).ceil() as usize,
        ..SimSettings::default()
    };
    let mut rng = rand::rngs::StdRng::seed_from_u64(16);
    let mut runs = Vec::new();
    for record in four_mass_records_with(false, &settings)? {
        let (x, v) = (
            record.displacements(),
            record.velocities().expect("simulated"),
        );
        let f = record.forcing().signals.col_as_slice(0);
        let k = |m: faer::MatRef<f64>, i: usize, j: usize| {
            let left = if j > 0 { m[(i, j - 1)] } else { 0.0 };
            let right = if j < 3 { m[(i, j + 1)] } else { 0.0 };
            2.0 * m[(i, j)] - left - right
        };
        let n = record.samples();
        let mut volts = Mat::from_fn(n, 5, |i, j| match j {
            4 => f[i] / FORCE_GAIN,
            _ => {
                let force = if j == 3 { f[i] } else { 0.0 };
                let a = force
                    - k(x, i, j)
                    - FOUR_MASS_C * k(v, i, j)
                    - FOUR_MASS_D * v[(i, j)] * v[(i, j)].abs();
                a / ACCELEROMETER_GAIN
            }
        });
        // 0.5 % of the RMS of the accelerometers together, and of the force channel
        for columns in [0..4, 4..5] {
            let count = (columns.len() * n) as f64;
            let rms = (columns
                .clone()
                .flat_map(|j| (0..n).map(move |i| (i, j)))
                .map(|(i, j)| volts[(i, j)].powi(2))
                .sum::<f64>()
                / count)
                .sqrt();
            let normal = Normal::new(0.0, 0.005 * rms).expect("finite");
            for j in columns {
                for i in 0..n {
                    volts[(i, j)] += normal.sample(&mut rng);
                }
            }
        }
        runs.push((record.step(), volts));
    }
    Ok(runs)
}

fn write(folder: &Path, runs: &[(f64, Mat<f64>)]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(folder).map_err(|e| Error::Data {
        file: folder.display().to_string(),
        row: 0,
        column: String::new(),
        message: e.to_string(),
    })?;
    let headers: Vec<String> = ["t", "acc1", "acc2", "acc3", "acc4", "vir"]
        .map(String::from)
        .to_vec();
    let mut paths = Vec::new();
    for (k, (step, volts)) in runs.iter().enumerate() {
        let n = volts.nrows();
        let mut columns = vec![(0..n).map(|i| i as f64 * step).collect::<Vec<_>>()];
        columns.extend((0..5).map(|j| volts.col_as_slice(j).to_vec()));
        let path = folder.join(format!("run_{}.csv", k + 1));
        // Never replaces a file: regenerate into an empty folder.
        dampid::io::csv::write(&path, &headers, &columns, Overwrite::Refuse)?;
        paths.push(path);
    }
    Ok(paths)
}

fn main() -> Result<()> {
    let runs = runs()?;
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--write") {
        let folder = PathBuf::from(args.get(k + 1).map_or("models/data/four_mass_acc", |s| s));
        for path in write(&folder, &runs)? {
            println!("wrote {}", path.display());
        }
        return Ok(());
    }
    // The same records through the library: physical units, then sensors.
    let period = 2.0 * std::f64::consts::PI / FOUR_MASS_OMEGA;
    let records = runs
        .iter()
        .enumerate()
        .map(|(k, (step, volts))| {
            let n = volts.nrows();
            record_from_sensors(SensorParts {
                label: format!("run {}", k + 1),
                step: *step,
                start_time: 0.0,
                motion: Mat::from_fn(n, 4, |i, j| ACCELEROMETER_GAIN * volts[(i, j)]),
                sensors: vec![Sensor::Acceleration; 4],
                forcing: Forcing::on_dofs(
                    Mat::from_fn(n, 1, |i, _| FORCE_GAIN * volts[(i, 4)]),
                    vec![3],
                ),
                period,
                integration: Integration::WholePeriods,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let report = identify(
        &ParametricRegressor::linear(&four_mass_model(), &records),
        &IdentifySettings::default(),
        &silent,
    )?
    .report;
    println!("four-mass chain from accelerometers (truth c = {FOUR_MASS_C}, d = {FOUR_MASS_D})");
    for c in &report.coefficients {
        println!(
            "  {:<3} {:.5}  ± {:.5}",
            c.name,
            c.value,
            c.std_error.unwrap_or(f64::NAN)
        );
    }
    Ok(())
}
