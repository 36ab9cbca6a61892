//! How far the outer loop's stopping rule fixes the estimates of a variable projection
//! (BENCHMARKS.md §14, branch `vp3`): [`dampid::identify`] of a model file without the
//! profile intervals at each outer-loop tolerance given (`estimation.tolerance`, default
//! 10⁻⁸: an accepted Levenberg–Marquardt step that lowers the cost by at most this
//! fraction of it ends the search), printing per tolerance one line per parameter —
//! value and Wald standard error — and the cost φ̂, the outer loop's iterations and
//! trials, and the wall time. Parameters along a flat valley of φ (weakly determined
//! residual receptances) move with the tolerance by amounts that are small against
//! their standard errors; well-determined ones do not.
//!
//! `cargo run --release --example varpro_valley -- MODEL.toml [TOL ...]`
//! (default tolerances 1e-8 1e-10 1e-12 1e-14)

use std::path::Path;
use std::time::Instant;

use dampid::model_file::{Options, load};

#[cfg(feature = "cli")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: varpro_valley MODEL.toml [TOL ...]")?;
    let mut tolerances: Vec<f64> = args.map(|t| t.parse()).collect::<Result<_, _>>()?;
    if tolerances.is_empty() {
        tolerances = vec![1e-8, 1e-10, 1e-12, 1e-14];
    }
    faer::set_global_parallelism(faer::Par::Seq);
    let job = load(Path::new(&path), Options::default())?;
    let silent = &|_: u64, _: u64| {};
    for tolerance in tolerances {
        let mut settings = job.settings.clone();
        settings.estimation.profile = false;
        settings.estimation.tolerance = tolerance;
        let start = Instant::now();
        let out = dampid::identify(&job.problem(), &settings, silent)?;
        let seconds = start.elapsed().as_secs_f64();
        let Some(estimation) = &out.report.estimation else {
            return Err("no estimation in the report".into());
        };
        println!(
            "tolerance {tolerance:e}: cost {:.17e}, iterations {}, trials {}, {} ({seconds:.4} s)",
            estimation.cost,
            estimation.status.iterations,
            estimation.status.evaluations,
            estimation.status.reason
        );
        for p in &estimation.parameters {
            let se = p.std_error.unwrap_or(f64::NAN);
            println!("  {} {:.17e} se {se:.6e}", p.name, p.value);
        }
        for c in &estimation.coefficients {
            println!("  {} {:.17e}", c.name, c.value);
        }
    }
    Ok(())
}
