//! Real-file details (issue 16, item 8): a time column with clock jitter is read at its
//! mean step up to a documented tolerance and refused beyond it; `[identification]`
//! keys the non-periodic mode does not read are refused beside `[non_periodic]`; the
//! non-periodic window length reported is the one used (whole steps).

use std::path::{Path, PathBuf};

mod support;

use dampid::command::check;
use dampid::error::Error;
use dampid::model_file::{PERIODIC_ONLY, parse};
use dampid::record::Record;
use dampid::reference::drive::{DriveSettings, closed_loop_drive};

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid-real-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A closed-loop drive like models/drive_nonperiodic.toml's, at 1 ms, clean.
fn drive() -> Record {
    closed_loop_drive(&DriveSettings::default()).unwrap()
}

/// `record` as t, x, force, each time moved by `jitter(i)` steps.
fn write_csv(record: &Record, path: &Path, jitter: impl Fn(usize) -> f64) {
    let n = record.samples();
    support::write_scratch_csv(
        path,
        &["t".into(), "x".into(), "force".into()],
        &[
            (0..n)
                .map(|i| (i as f64 + jitter(i)) * record.step())
                .collect(),
            record.displacements().col(0).iter().copied().collect(),
            record.forcing().signals.col_as_slice(0).to_vec(),
        ],
    );
}

/// The drive's model file with `[identification]` lines `identification` and a
/// `[non_periodic]` window of `window` seconds.
fn model_file(identification: &str, window: f64) -> String {
    format!(
        r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "viscous"
[[terms]]
kind = "law"
law = "coulomb"
elements = "each_dof"
coefficient = "coulomb"
[identification]
nonnegative = true
{identification}
[non_periodic]
window = {window}
offsets = [1]
[[data.records]]
file = "drive.csv"
label = "drive"
time = "t"
displacements = ["x"]
forces = [{{ column = "force", dof = 1 }}]
"#
    )
}

/// A clock with 2.4e-5 jitter (a 1 kHz MATLAB export's) is read at the mean step, and
/// the summary and the check say so; 2e-3 is `TimeJitter` at the record's line, naming
/// the file, the column and the jitter, and suggesting `step = h`.
#[test]
fn a_jittery_time_column_is_read_at_its_mean_step() {
    let dir = scratch("jitter");
    let record = drive();
    let h = record.step();
    let wobble = |size: f64| move |i: usize| if i % 3 == 1 { size } else { 0.0 };
    write_csv(&record, &dir.join("drive.csv"), wobble(2.4e-5));
    let job = parse(&model_file("", 0.25), "m.toml", &dir, Default::default()).unwrap();
    let jitter = job.time_jitter[0].unwrap();
    assert!((jitter - 2.4e-5).abs() < 1e-7, "{jitter}");
    assert!((job.records[0].step() - h).abs() < 1e-9 * h);
    let preamble = job.preamble(None).to_string();
    assert!(preamble.contains("time column of 'drive'"), "{preamble}");
    assert!(preamble.contains("2.40e-5"), "{preamble}");
    let check = check::run(&job, Default::default()).unwrap();
    assert_eq!(check.time_jitter.len(), 1);
    assert!(check.to_string().contains("2.40e-5"), "{check}");

    // Clean times carry no jitter worth a line.
    write_csv(&record, &dir.join("drive.csv"), |_| 0.0);
    let job = parse(&model_file("", 0.25), "m.toml", &dir, Default::default()).unwrap();
    assert!(job.jittered().is_empty());
    assert!(!job.preamble(None).to_string().contains("time column"));

    write_csv(&record, &dir.join("drive.csv"), wobble(2e-3));
    let error = parse(&model_file("", 0.25), "m.toml", &dir, Default::default()).unwrap_err();
    match &error {
        Error::ModelFile {
            line,
            cause,
            message,
            ..
        } => {
            assert_eq!(*line, 18, "{message}");
            match cause.as_deref() {
                Some(Error::TimeJitter {
                    file,
                    column,
                    jitter,
                    ..
                }) => {
                    assert!(file.ends_with("drive.csv"), "{file}");
                    assert_eq!(column, "t");
                    assert!((jitter - 2e-3).abs() < 1e-6, "{jitter}");
                }
                other => panic!("{other:?}"),
            }
            assert!(message.contains("`step = 0.001`"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(dir).ok();
}

/// Each `[identification]` key that only windows of whole periods read is refused
/// beside `[non_periodic]`, at its own line, as `InvalidChoice` naming the key and the
/// reason; the same file without `[non_periodic]`'s companions is accepted.
#[test]
fn the_non_periodic_mode_refuses_keys_it_does_not_read() {
    let dir = scratch("keys");
    write_csv(&drive(), &dir.join("drive.csv"), |_| 0.0);
    let values = [
        ("cycles", "2"),
        ("windows", "3"),
        ("harmonics", "5"),
        ("noise", "\"ignore\""),
        ("max_energy_mismatch", "0.1"),
        ("max_state_mismatch", "0.1"),
        ("accept_transient", "true"),
    ];
    assert_eq!(values.len(), PERIODIC_ONLY.len());
    for (key, value) in values {
        let text = model_file(&format!("{key} = {value}"), 0.25);
        let error = parse(&text, "m.toml", &dir, Default::default()).unwrap_err();
        match &error {
            Error::ModelFile {
                line,
                cause,
                message,
                ..
            } => {
                assert_eq!(*line, 14, "{key}: {message}");
                assert!(message.contains("does not apply beside [non_periodic]"));
                match cause.as_deref() {
                    Some(Error::InvalidChoice { name, .. }) => assert_eq!(name, key),
                    other => panic!("{key}: {other:?}"),
                }
            }
            other => panic!("{key}: {other:?}"),
        }
    }
    // The keys both modes read are accepted.
    let text = model_file("skip = 10\nquadrature = \"trapezoid\"", 0.25);
    parse(&text, "m.toml", &dir, Default::default()).unwrap();
    std::fs::remove_dir_all(dir).ok();
}

/// A window of 0.25025 s at h = 1 ms is 250 whole steps, 0.25 s: the summary and the
/// check report 0.25 as used and 0.25025 as requested; 0.25 s itself is reported as is.
#[test]
fn the_window_length_used_is_reported() {
    let dir = scratch("window");
    write_csv(&drive(), &dir.join("drive.csv"), |_| 0.0);
    let job = parse(&model_file("", 0.25025), "m.toml", &dir, Default::default()).unwrap();
    let preamble = job.preamble(None).to_string();
    assert!(
        preamble.contains(
            "windows of 0.25 (250 steps of 0.001) time units (whole steps; 0.25025 requested)"
        ),
        "{preamble}"
    );
    let windows = dampid::prep::window::span_windows(&job.records[0], 0, 0.25025, 0).unwrap();
    assert!((windows[0].span - 0.25).abs() < 1e-12, "{:?}", windows[0]);
    let check = check::run(&job, Default::default()).unwrap();
    assert_eq!(check.non_periodic_window, Some(0.25025));
    assert_eq!(check.non_periodic_window_used.len(), 1);
    assert!((check.non_periodic_window_used[0] - 0.25).abs() < 1e-12);
    assert!(check.to_string().contains("0.25025 requested"), "{check}");

    let job = parse(&model_file("", 0.25), "m.toml", &dir, Default::default()).unwrap();
    let preamble = job.preamble(None).to_string();
    assert!(
        preamble.contains("windows of 0.25 time units,"),
        "{preamble}"
    );
    let check = check::run(&job, Default::default()).unwrap();
    assert!(check.non_periodic_window_used.is_empty());
    std::fs::remove_dir_all(dir).ok();
}
