//! Table and plot of the regressor grid benchmark (benches/grid.rs): time against the
//! work n·N (DOFs × samples), from criterion's results.
//!
//! ```sh
//! RAYON_NUM_THREADS=1 cargo bench --bench grid      # and/or with 2 threads
//! cargo run --release --example grid_plot [-- CRITERION_DIR [SVG_PATH [RUN,RUN,…]]]
//! ```
//!
//! Reads `<CRITERION_DIR>/grid/t{T}/n{n}_N{N}/<RUN>/{estimates,sample}.json` (default
//! CRITERION_DIR: `$CARGO_TARGET_DIR/criterion` or `target/criterion`; default RUN:
//! `new`, criterion's latest; several runs are the baselines of
//! `cargo bench --bench grid -- --save-baseline RUN`, and a cell's time is then the
//! median over the runs of criterion's medians), prints a Markdown table per thread
//! count (median and fastest sample, ns per element, and the ratio of each cell's cost
//! per element to the median cost per element over all its cells: 1 is exactly
//! linear), the exponent p of the least-squares fit ln t = ln c + p ln(n·N) over the
//! cells (1 is linear growth), and draws time against n·N on log-log axes with the
//! line t = c·n·N through each thread count's median cost per element
//! (`docs/benchmarks/regressor_grid.svg` by default).

use std::path::{Path, PathBuf};

use plotters::prelude::*;

const DOFS: [usize; 4] = [10, 100, 1000, 3000];
const SAMPLES: [usize; 3] = [10_000, 100_000, 1_000_000];

/// One measured cell.
struct Cell {
    dofs: usize,
    samples: usize,
    median: f64,
    fastest: f64,
}

impl Cell {
    fn work(&self) -> f64 {
        (self.dofs * self.samples) as f64
    }
}

/// The cell as measured in each of `runs`, with its time the median over the runs (and
/// the fastest sample of all of them); `None` if a run lacks it.
fn read_runs(dir: &Path, dofs: usize, samples: usize, runs: &[String]) -> Option<Cell> {
    let cells: Vec<Cell> = runs
        .iter()
        .map(|run| read_cell(dir, dofs, samples, run))
        .collect::<Option<_>>()?;
    Some(Cell {
        dofs,
        samples,
        median: median(cells.iter().map(|c| c.median).collect()),
        fastest: cells
            .iter()
            .map(|c| c.fastest)
            .fold(f64::INFINITY, f64::min),
    })
}

/// The exponent p of the least-squares line ln t = ln c + p ln(n·N) through the cells.
fn growth_exponent(cells: &[Cell]) -> f64 {
    let points: Vec<(f64, f64)> = cells
        .iter()
        .map(|c| (c.work().ln(), c.median.ln()))
        .collect();
    let count = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / count;
    let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    sxy / sxx
}

fn read_cell(dir: &Path, dofs: usize, samples: usize, run: &str) -> Option<Cell> {
    let base = dir.join(format!("n{dofs}_N{samples}")).join(run);
    let estimates: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(base.join("estimates.json")).ok()?).ok()?;
    let sample: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(base.join("sample.json")).ok()?).ok()?;
    let median = estimates["median"]["point_estimate"].as_f64()? * 1e-9;
    let times = sample["times"].as_array()?;
    let iters = sample["iters"].as_array()?;
    let fastest = times
        .iter()
        .zip(iters)
        .filter_map(|(t, i)| Some(t.as_f64()? / i.as_f64()?))
        .fold(f64::INFINITY, f64::min)
        * 1e-9;
    Some(Cell {
        dofs,
        samples,
        median,
        fastest,
    })
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let mid = values.len() / 2;
    if values.len() % 2 == 1 {
        values[mid]
    } else {
        0.5 * (values[mid - 1] + values[mid])
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let criterion = args.first().map(PathBuf::from).unwrap_or_else(|| {
        let target = std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into());
        PathBuf::from(target).join("criterion")
    });
    let svg = args
        .get(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("docs/benchmarks/regressor_grid.svg"));
    let runs: Vec<String> = args.get(2).map_or_else(
        || vec!["new".to_string()],
        |list| list.split(',').map(str::to_string).collect(),
    );

    let mut series: Vec<(usize, Vec<Cell>, f64)> = Vec::new();
    for threads in 1..=8 {
        let dir = criterion.join("grid").join(format!("t{threads}"));
        let cells: Vec<Cell> = DOFS
            .iter()
            .flat_map(|&n| SAMPLES.iter().map(move |&s| (n, s)))
            .filter_map(|(n, s)| read_runs(&dir, n, s, &runs))
            .collect();
        if cells.is_empty() {
            continue;
        }
        let per_element = median(cells.iter().map(|c| c.median / c.work()).collect());
        let within = cells
            .iter()
            .filter(|c| (c.median / c.work() / per_element - 1.0).abs() <= 0.2)
            .count();
        println!(
            "\n{threads} thread(s), runs {}: median cost {:.3} ns per element; {within} of {} \
             cells within 20 % of it; time grows as (n·N)^{:.3}\n",
            runs.join(", "),
            per_element * 1e9,
            cells.len(),
            growth_exponent(&cells)
        );
        println!(
            "| n | N | n·N | median s | fastest s | ns per element (median) | relative to the median cost |"
        );
        println!("|---|---|---|---|---|---|---|");
        for c in &cells {
            println!(
                "| {} | {} | {:.0e} | {:.4} | {:.4} | {:.3} | {:.2} |",
                c.dofs,
                c.samples,
                c.work(),
                c.median,
                c.fastest,
                c.median / c.work() * 1e9,
                c.median / c.work() / per_element
            );
        }
        series.push((threads, cells, per_element));
    }
    if series.is_empty() {
        return Err(format!("no grid results under {}", criterion.display()).into());
    }

    if let Some(parent) = svg.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let all = series.iter().flat_map(|(_, cells, _)| cells);
    let (work_lo, work_hi, time_lo, time_hi) = all.fold(
        (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64),
        |(wl, wh, tl, th), c| {
            (
                wl.min(c.work()),
                wh.max(c.work()),
                tl.min(c.median),
                th.max(c.median),
            )
        },
    );
    let root = SVGBackend::new(&svg, (720, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Regressor row: time against DOFs × samples",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (work_lo / 2.0..work_hi * 2.0).log_scale(),
            (time_lo / 2.0..time_hi * 2.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("n · N (DOFs × samples)")
        .y_desc("time per row (s, criterion median)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    let colors = [BLUE, RED, GREEN, MAGENTA];
    for (k, (threads, cells, per_element)) in series.iter().enumerate() {
        let color = colors[k % colors.len()];
        chart
            .draw_series(
                cells
                    .iter()
                    .map(|c| Circle::new((c.work(), c.median), 4, color.filled())),
            )?
            .label(format!("{threads} thread(s), measured"))
            .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
        chart
            .draw_series(LineSeries::new(
                [work_lo / 2.0, work_hi * 2.0].map(|w| (w, w * per_element)),
                color.mix(0.6).stroke_width(1),
            ))?
            .label(format!(
                "{threads} thread(s), t = {:.2} ns · n·N",
                per_element * 1e9
            ))
            .legend(move |(x, y)| PathElement::new([(x - 8, y), (x + 8, y)], color));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK.mix(0.3))
        .draw()?;
    root.present()?;
    println!("\nwrote {}", svg.display());
    Ok(())
}
