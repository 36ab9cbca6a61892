//! Times `dampid::io::read_table` on the files given, for benches/io_read.sh: each
//! file is read `--repeat` times (default 5) and one line is printed per file,
//!
//! `dampid <file> <best seconds> <median seconds> <MB> <rows> <columns> <CPU seconds> <sum>`
//!
//! (MB = 10^6 bytes of the file; CPU seconds: the median over the reads of the time all
//! the process's threads ran, user and system, from Linux's /proc/self/task/*/schedstat,
//! 0 elsewhere; sum: of every value read, which the other readers' must match).
//! `cargo run --release --example io_read -- FILE...`

use std::path::Path;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut repeat = 5;
    if let Some(k) = args.iter().position(|a| a == "--repeat") {
        repeat = args.get(k + 1).ok_or("--repeat needs a count")?.parse()?;
        args.drain(k..k + 2);
    }
    for file in &args {
        let path = Path::new(file);
        let megabytes = std::fs::metadata(path)?.len() as f64 / 1e6;
        let mut seconds = Vec::with_capacity(repeat);
        let mut cpu = Vec::with_capacity(repeat);
        let mut shape = (0, 0);
        let mut sum = 0.0;
        for _ in 0..repeat {
            let (start, start_cpu) = (Instant::now(), cpu_seconds());
            let table = dampid::io::read_table(path)?;
            seconds.push(start.elapsed().as_secs_f64());
            cpu.push(cpu_seconds() - start_cpu);
            shape = (table.rows(), table.columns.len());
            sum = table.columns.iter().flatten().sum::<f64>();
            drop(table);
        }
        seconds.sort_by(f64::total_cmp);
        cpu.sort_by(f64::total_cmp);
        println!(
            "dampid {file} {:.4} {:.4} {megabytes:.1} {} {} {:.4} {sum:.12e}",
            seconds[0],
            seconds[seconds.len() / 2],
            shape.0,
            shape.1,
            cpu[cpu.len() / 2]
        );
    }
    Ok(())
}

/// The time every thread of this process has run so far (user and system), in
/// seconds: the first field of each thread's schedstat, in nanoseconds.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    tasks
        .flatten()
        .filter_map(|task| std::fs::read_to_string(task.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}
