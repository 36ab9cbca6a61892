//! The Rust side of the Python overhead benchmark (`examples/python/overhead.py` runs
//! this and the same calls through the Python package, and prints both): the wall time
//! of the same identification in-process, best of `repeats` runs, and the mean CPU time
//! per run (user + system, all threads: the work done, whatever the machine's load).
//!
//! - `four_mass`: `models/four_mass.toml` loaded, steady-state checked, identified and
//!   its text report written (what `dampid identify` and Python's `dampid.identify_file`
//!   do).
//! - `large DOFS SAMPLES`: one synthetic record, x_j(t) = (1 + j/n) sin(ω t + 0.01 j)
//!   (j = 0..n−1), a force cos(ω t) on DOF 1, ω = 0.618, h = 0.05, with viscous and
//!   quadratic damping on every DOF (shared c, d) and the `[identification]` defaults
//!   (one-period windows as many as fit, harmonic projection, noise-robust rows): the
//!   steady-state check of the windows and `identify`, which is what Python's
//!   `dampid.identify` runs (and `dampid identify`), on the data already in the library's
//!   layout, as a Rust caller holds it; and the same with `Record::new` of a copy of the
//!   parts inside the timing (Python's `dampid.Record` is in its timing).
//!
//! - `small RECORDS SAMPLES REPEATS PER_PERIOD`: RECORDS records of 4 DOFs × SAMPLES
//!   samples (defaults 200 and 1000; the same signals as `large` at ω = 0.55 … 0.70,
//!   about five periods at h = 0.05, or exactly PER_PERIOD samples per period), one
//!   `identify` of the list with the defaults (steady-state check included): records
//!   per second, the fixed cost of small records (issue 32); then each record's rows
//!   alone (`campaign::rows`, what a campaign's map and Python's `regressor_rows` run per
//!   record).
//! - `map RECORDS SAMPLES REPEATS PER_PERIOD`: the same records, the map alone (no
//!   `identify` of the list: what a profile of the per-record cost runs).
//!
//! `cargo run --release --example python_overhead -- large 100 100000 5`

use std::path::Path;
use std::time::Instant;

use dampid::prelude::*;
use faer::Mat;

// As the `dampid` binary and the Python package allocate (with the `cli` feature, the
// default): the map's per-window vectors cost a fifth of its instructions in the
// system allocator.
#[cfg(feature = "cli")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// CPU time of this process so far, user + system over all threads, in seconds: from
/// /proc/self/stat (Linux; in clock ticks of USER_HZ = 1/100 s), `NAN` elsewhere. On a
/// shared machine the wall time carries the other processes' load; the CPU time is the
/// work this process did.
fn cpu_seconds() -> f64 {
    let read = || -> Option<f64> {
        let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
        // After the command name in parentheses: state is the first field (field 3),
        // utime field 14 and stime field 15.
        let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
        let utime: f64 = fields.get(11)?.parse().ok()?;
        let stime: f64 = fields.get(12)?.parse().ok()?;
        Some((utime + stime) / 100.0)
    };
    read().unwrap_or(f64::NAN)
}

/// The best wall time of `repeats` runs, the mean CPU time per run, and the last result.
fn best<T>(repeats: usize, mut run: impl FnMut() -> T) -> (f64, f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    let cpu = cpu_seconds();
    for _ in 0..repeats {
        let start = Instant::now();
        let out = run();
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(out);
    }
    let cpu = (cpu_seconds() - cpu) / repeats as f64;
    (best, cpu, last.expect("at least one repeat"))
}

fn main() -> Result<(), dampid::Error> {
    faer::set_global_parallelism(faer::Par::Seq);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number =
        |k: usize, default: usize| args.get(k).and_then(|a| a.parse().ok()).unwrap_or(default);
    match args.first().map(String::as_str) {
        Some("large") => {
            let (n, samples, repeats) = (number(1, 100), number(2, 100_000), number(3, 3));
            let (h, omega) = (0.05, 0.618);
            let x = Mat::from_fn(samples, n, |i, j| {
                (1.0 + j as f64 / n as f64) * (omega * (i as f64 * h) + 0.01 * j as f64).sin()
            });
            let f = Mat::from_fn(samples, 1, |i, _| (omega * (i as f64 * h)).cos());
            let parts = RecordParts {
                label: "large".into(),
                step: h,
                start_time: 0.0,
                displacements: x,
                velocities: None,
                forcing: Forcing::on_dofs(f, vec![0]),
                period: 2.0 * std::f64::consts::PI / omega,
            };
            let model = DampingModel::new()
                .with(Term::per_dof(Linear, n, Coefficients::Shared("c".into())))
                .with(Term::per_dof(
                    Quadratic,
                    n,
                    Coefficients::Shared("d".into()),
                ));
            let settings = dampid::model_file::identification(&Default::default())?;
            // What Python's `dampid.identify` runs: the steady-state check of the
            // windows (as `dampid identify`), then the library's `identify`.
            let run = |records: &[Record]| -> Result<FitReport, dampid::Error> {
                identify(
                    &ParametricRegressor::linear(&model, records),
                    &settings,
                    &silent,
                )
                .map(|i| i.report)
            };
            let records = [Record::new(parts.clone())?];
            let (seconds, cpu, report) = best(repeats, || run(&records));
            let report = report?;
            // With the record built in the timing, as Python's `Record(...)` is: the
            // parts' matrices cloned (one copy, as from NumPy) and validated.
            let (with_record, with_record_cpu, _) =
                best(repeats, || run(&[Record::new(parts.clone())?]));
            println!(
                "rust large {n} {samples}: {seconds:.6} s (cpu {cpu:.4} s), with the record built {with_record:.6} s (cpu {with_record_cpu:.4} s), c = {:?}, d = {:?}",
                report.coefficient("c").unwrap_or(f64::NAN),
                report.coefficient("d").unwrap_or(f64::NAN)
            );
        }
        Some(mode @ ("small" | "map")) => {
            let (count, samples, repeats) = (number(1, 200), number(2, 1000), number(3, 3));
            let per_period = number(4, 0);
            let n = 4;
            let records = (0..count)
                .map(|k| {
                    let omega = 0.55 + 0.15 * k as f64 / count.max(1) as f64;
                    // h = 0.05 (a period of 180–228 samples, not whole), or exactly
                    // PER_PERIOD samples per period (the campaign example's records).
                    let h = match per_period {
                        0 => 0.05,
                        whole => 2.0 * std::f64::consts::PI / (omega * whole as f64),
                    };
                    let x = Mat::from_fn(samples, n, |i, j| {
                        (1.0 + j as f64 / n as f64)
                            * (omega * (i as f64 * h) + 0.01 * j as f64).sin()
                    });
                    let f = Mat::from_fn(samples, 1, |i, _| (omega * (i as f64 * h)).cos());
                    Record::new(RecordParts {
                        label: format!("small {k}"),
                        step: h,
                        start_time: 0.0,
                        displacements: x,
                        velocities: None,
                        forcing: Forcing::on_dofs(f, vec![0]),
                        period: 2.0 * std::f64::consts::PI / omega,
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let model = DampingModel::new()
                .with(Term::per_dof(Linear, n, Coefficients::Shared("c".into())))
                .with(Term::per_dof(
                    Quadratic,
                    n,
                    Coefficients::Shared("d".into()),
                ));
            let settings = dampid::model_file::identification(&Default::default())?;
            if mode == "small" {
                let (seconds, cpu, report) = best(repeats, || {
                    identify(
                        &ParametricRegressor::linear(&model, &records),
                        &settings,
                        &silent,
                    )
                    .map(|i| i.report)
                });
                let report = report?;
                println!(
                    "rust small {count} x {n} DOFs x {samples}: {seconds:.6} s (cpu {cpu:.4} s), {:.0} records/s, c = {:?}, d = {:?}",
                    count as f64 / seconds,
                    report.coefficient("c").unwrap_or(f64::NAN),
                    report.coefficient("d").unwrap_or(f64::NAN)
                );
            }
            // A campaign's map on one core: each record's rows alone (what Python's
            // `regressor_rows` runs per record), steady-state check included.
            let (seconds, cpu, rows) = best(repeats, || {
                records
                    .iter()
                    .enumerate()
                    .map(|(k, r)| {
                        dampid::campaign::rows(&model, std::slice::from_ref(r), k, &settings)
                            .map(|rows| rows.equations())
                    })
                    .sum::<Result<usize, _>>()
            });
            println!(
                "rust small rows {count} x {n} DOFs x {samples}: {seconds:.6} s (cpu {cpu:.4} s), {:.0} records/s, {} rows",
                count as f64 / seconds,
                rows?
            );
        }
        _ => {
            let repeats = number(1, 5);
            let (seconds, cpu, report) = best(repeats, || -> Result<FitReport, dampid::Error> {
                let job = dampid::model_file::load(
                    Path::new("models/four_mass.toml"),
                    Default::default(),
                )?;
                let options = dampid::command::identify::IdentifyOptions::default();
                let found = dampid::command::identify::run(&job, &options, &silent)?;
                // The text report, as `dampid identify` prints it and Python's
                // `identify_file` keeps it.
                let text = dampid::command::identify::Identified {
                    job: &job,
                    options: &options,
                    identification: &found,
                }
                .to_string();
                std::hint::black_box(text);
                Ok(found.report)
            });
            let report = report?;
            println!(
                "rust four_mass: {seconds:.6} s (cpu {cpu:.6} s), c = {:?}, d = {:?}",
                report.coefficient("c").unwrap_or(f64::NAN),
                report.coefficient("d").unwrap_or(f64::NAN)
            );
        }
    }
    Ok(())
}
