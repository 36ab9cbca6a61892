//! The Rust side of the Python overhead benchmark (`examples/python/overhead.py` runs
//! this and the same calls through the Python package, and prints both): the wall time
//! of the same identification in-process, best of `repeats` runs.
//!
//! - `four_mass`: `models/four_mass.toml` loaded, steady-state checked and identified
//!   (what `dampid identify` and Python's `dampid.identify_file` do).
//! - `large DOFS SAMPLES`: one synthetic record, x_j(t) = (1 + j/n) sin(ω t + 0.01 j)
//!   (j = 0..n−1), a force cos(ω t) on DOF 1, ω = 0.618, h = 0.05, with viscous and
//!   quadratic damping on every DOF (shared c, d) and the `[identification]` defaults
//!   (one-period windows as many as fit, harmonic projection, noise-robust rows): the
//!   data already in the library's layout, as a Rust caller holds it.
//!
//! `cargo run --release --example python_overhead -- large 100 100000 5`

use std::path::Path;
use std::time::Instant;

use dampid::prelude::*;
use faer::Mat;

fn best<T>(repeats: usize, mut run: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats {
        let start = Instant::now();
        let out = run();
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(out);
    }
    (best, last.expect("at least one repeat"))
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
            let record = Record::new(RecordParts {
                label: "large".into(),
                step: h,
                start_time: 0.0,
                displacements: x,
                velocities: None,
                forcing: Forcing::on_dofs(f, vec![0]),
                period: 2.0 * std::f64::consts::PI / omega,
            })?;
            let model = DampingModel::new()
                .with(Term::per_dof(Linear, n, Coefficients::Shared("c".into())))
                .with(Term::per_dof(
                    Quadratic,
                    n,
                    Coefficients::Shared("d".into()),
                ));
            let settings = dampid::model_file::identification(&Default::default())?.settings;
            let records = [record];
            let (seconds, report) = best(repeats, || identify(&model, &records, &settings));
            let report = report?;
            println!(
                "rust large {n} {samples}: {seconds:.6} s, c = {:?}, d = {:?}",
                report.coefficient("c").unwrap_or(f64::NAN),
                report.coefficient("d").unwrap_or(f64::NAN)
            );
        }
        _ => {
            let repeats = number(1, 5);
            let (seconds, report) = best(repeats, || -> Result<FitReport, dampid::Error> {
                let job = dampid::model_file::load(Path::new("models/four_mass.toml"))?;
                if let Some(steady) = job.steady_state()? {
                    steady.enforce()?;
                }
                job.settings.fit.validate()?;
                let regressor = job.regressor()?;
                let noise = dampid::analysis::velocity_noise::assess_or_none(
                    &job.model,
                    &job.records,
                    &job.settings.regressor,
                    &regressor,
                );
                Ok(identify_regressor(&regressor, &job.settings.fit)?.with_velocity_noise(noise))
            });
            let report = report?;
            println!(
                "rust four_mass: {seconds:.6} s, c = {:?}, d = {:?}",
                report.coefficient("c").unwrap_or(f64::NAN),
                report.coefficient("d").unwrap_or(f64::NAN)
            );
        }
    }
    Ok(())
}
