//! How an expression law's cost grows with its length, and where dampid caps it.
//! For sums of n terms `0.5*v+0.5*v+…`: exmex's parse time and time per evaluation
//! (one sample), and what `Expression::parse` does with the text (accepted below
//! `MAX_EXPRESSION_BYTES`, refused at once above).
//! `cargo run --release --example expression_length`

use std::time::Instant;

use dampid::terms::laws::{Expression, MAX_EXPRESSION_BYTES};
use exmex::prelude::*;

fn main() {
    println!("cap: {MAX_EXPRESSION_BYTES} bytes");
    for terms in [1_000, 2_000, 10_000, 20_000, 40_000] {
        let text = vec!["0.5*v"; terms].join("+");
        let started = Instant::now();
        let parsed = exmex::FlatEx::<f64>::parse(&text).unwrap();
        let parse = started.elapsed().as_secs_f64();
        let evaluations = 20;
        let started = Instant::now();
        let mut sum = 0.0;
        for k in 0..evaluations {
            sum += parsed.eval(&[k as f64 * 1e-3]).unwrap();
        }
        let eval = started.elapsed().as_secs_f64() / evaluations as f64;
        let started = Instant::now();
        let dampid = match Expression::parse(&text) {
            Ok(_) => "accepted".to_string(),
            Err(_) => "refused".to_string(),
        };
        let refused_in = started.elapsed().as_secs_f64();
        println!(
            "{terms:>6} terms ({:>6} bytes): exmex parse {parse:.4} s, one evaluation {:.3} ms (check {sum:.1}); dampid {dampid} in {refused_in:.4} s",
            text.len(),
            eval * 1e3
        );
    }
}
