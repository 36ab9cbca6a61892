//! The library's side of the issue 30 item 6 benchmark (`benches/stepped_sine_residual/`,
//! run by its `run.sh`): the stages of one identification of a model file in-process,
//! best wall time of `repeats` runs each, without the process start, the report files
//! and the text output that `dampid identify` adds:
//!
//! - `load`: the model file read and its table built ([`dampid::model_file::load`]);
//! - `fit`: [`dampid::identify`] without the profile intervals (`estimation.profile =
//!   false`): the outer loop, the fit at its minimum and the joint covariance, the work
//!   SciPy's `least_squares` baseline does (it computes no interval);
//! - `identify`: [`dampid::identify`] as the model file asks (the exponent's profile
//!   interval included), the work of the baseline's `with interval` time.
//!
//! With the `cli` feature (the default) it allocates with mimalloc, as the `dampid` binary
//! does: the trials allocate much (per-row vectors), and the system allocator makes the
//! same identification about three times slower.
//!
//! faer runs its decompositions sequentially (`faer::Par::Seq`), as the `dampid` binary
//! sets it (`src/bin/dampid/main.rs`): the inner fits are SVDs of 492 × 2 matrices, which
//! faer's default (rayon's pool) splits into tasks costing more in thread wake-ups and
//! futex waits than the arithmetic (about a fifth of the run's cycles).
//!
//! Prints one line per stage and the estimate (exponent and its profile interval) of the
//! last `identify`, so a run shows that the timed work gave the same answer.
//!
//! `cargo run --release --example varpro_residual_speed -- MODEL.toml [REPEATS]`

use std::path::Path;
use std::time::Instant;

use dampid::model_file::{Options, load};

#[cfg(feature = "cli")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The best wall time of `repeats` runs of `run`, and the last result.
fn best<T>(repeats: usize, mut run: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let out = run();
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(out);
    }
    (best, last.expect("at least one repeat"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: varpro_residual_speed MODEL.toml [REPEATS]")?;
    let repeats: usize = args.next().map_or(Ok(5), |r| r.parse())?;
    faer::set_global_parallelism(faer::Par::Seq);
    let (load_s, job) = best(repeats, || load(Path::new(&path), Options::default()));
    let job = job?;
    let mut without = job.settings.clone();
    without.estimation.profile = false;
    let silent = &|_: u64, _: u64| {};
    let (fit_s, fit) = best(repeats, || {
        dampid::identify(&job.problem(), &without, silent)
    });
    fit?;
    let (all_s, all) = best(repeats, || {
        dampid::identify(&job.problem(), &job.settings, silent)
    });
    let all = all?;
    println!("load (read, table): {load_s:.4} s");
    println!("fit (outer loop, joint covariance; no profile): {fit_s:.4} s");
    println!("identify (with the profile intervals): {all_s:.4} s");
    if let Some(estimation) = &all.report.estimation {
        for p in &estimation.parameters {
            if let Some(interval) = &p.interval {
                println!(
                    "{} = {:.9e}, profile interval [{:?}, {:?}]",
                    p.name, p.value, interval.lower, interval.upper
                );
            }
        }
        println!(
            "outer loop: {} regressors built",
            estimation.status.evaluations
        );
    }
    Ok(())
}
