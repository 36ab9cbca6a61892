//! The non-periodic mode on a closed-loop linear drive (`dampid::reference::drive`): a
//! 2 kg carriage with viscous friction 8 N s/m, Coulomb friction 3 N and a constant
//! 4.9 N load, moved by a PD position controller through random point-to-point moves
//! with dwells. Nothing in the record is periodic. The encoder position carries 1 µm
//! and the motor force 0.05 N of white noise.
//!
//! The energy balance over consecutive 0.25 s windows has the damping columns ∫ v² dt
//! and ∫ |v| dt, the kinetic column ½[v²] (unknown mass) and the offset column [x]
//! (unknown constant force), with central-difference velocities. The mass comes out as
//! a nuisance estimate: a check on the data.
//!
//! ```sh
//! cargo run --release --example nonperiodic_drive
//! cargo run --release --example nonperiodic_drive -- --write models/data/drive
//! ```
//!
//! With `--write DIR` it also writes the record as `DIR/drive.csv` (columns t, x, force),
//! the file `models/drive_nonperiodic.toml` reads.

use std::path::PathBuf;

use dampid::error::Result;
use dampid::identify::{IdentifySettings, identify};
use dampid::record::Record;
use dampid::reference::drive::{DriveSettings, closed_loop_drive, drive_model};
use dampid::regressor::RegressorSettings;
use dampid::regressor::SpanWindows;
use dampid::regressor::nonperiodic::StorageModel;

/// The drive of the bundled record: 20 s at h = 2 ms, with sensor noise.
fn drive() -> DriveSettings {
    DriveSettings {
        step: 2e-3,
        substeps: 20,
        samples: 10_001,
        position_noise: 1e-6,
        force_noise: 0.05,
        ..DriveSettings::default()
    }
}

fn write_csv(record: &Record, folder: &PathBuf) -> Result<PathBuf> {
    std::fs::create_dir_all(folder).map_err(|e| dampid::error::Error::Data {
        file: folder.display().to_string(),
        row: 0,
        column: String::new(),
        message: e.to_string(),
    })?;
    let path = folder.join("drive.csv");
    let n = record.samples();
    let time = (0..n).map(|i| i as f64 * record.step()).collect();
    let x = record.displacements().col(0).iter().copied().collect();
    let force = record.forcing().signals.col_as_slice(0).to_vec();
    dampid::io::csv::write(
        &path,
        &["t".into(), "x".into(), "force".into()],
        &[time, x, force],
        dampid::io::output::Overwrite::Replace, // this example's own scratch file
    )?;
    Ok(path)
}

fn main() -> Result<()> {
    let settings = drive();
    let record = closed_loop_drive(&settings)?;
    let model = drive_model();
    // 0.25 s windows; an unknown mass and an unknown constant force on the carriage.
    let balance = IdentifySettings {
        regressor: RegressorSettings::non_periodic(SpanWindows {
            storage: StorageModel {
                offsets: vec![0],
                ..StorageModel::default()
            },
            ..SpanWindows::new(0.25)
        }),
        ..IdentifySettings::default()
    };
    let report = identify(
        &dampid::regressor::ParametricRegressor::linear(&model, std::slice::from_ref(&record)),
        &balance,
        &dampid::progress::silent,
    )?
    .report;
    println!("{report}");
    println!("against the simulation:");
    for (name, truth) in settings.truth() {
        let estimate = report.coefficient(&name).unwrap_or(f64::NAN);
        println!(
            "  {name:<10} true {truth:<6} estimate {estimate:<10.5} error {:+.3}%",
            100.0 * (estimate - truth) / truth
        );
    }
    let mut args = std::env::args().skip(1);
    if let (Some(flag), Some(folder)) = (args.next(), args.next())
        && flag == "--write"
    {
        let path = write_csv(&record, &PathBuf::from(folder))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
