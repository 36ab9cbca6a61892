//! Times `dampid::io::read_table` on the files given, for benches/io_read.sh: each
//! file is read `--repeat` times (default 5) and one line is printed per file,
//!
//! `dampid <file> <best seconds> <median seconds> <MB> <rows> <columns>`
//!
//! (MB = 10^6 bytes of the file). `cargo run --release --example io_read -- FILE...`

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
        let mut shape = (0, 0);
        for _ in 0..repeat {
            let start = Instant::now();
            let table = dampid::io::read_table(path)?;
            seconds.push(start.elapsed().as_secs_f64());
            shape = (table.rows(), table.columns.len());
            drop(table);
        }
        seconds.sort_by(f64::total_cmp);
        println!(
            "dampid {file} {:.4} {:.4} {megabytes:.1} {} {}",
            seconds[0],
            seconds[seconds.len() / 2],
            shape.0,
            shape.1
        );
    }
    Ok(())
}
