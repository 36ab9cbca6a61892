//! Damping-law expressions: `Expression::parse` on arbitrary text, then the force and
//! the weighted power at arbitrary (x, v), finite or not. The input is the expression
//! text up to the first NUL byte, then little-endian f64 triples (x, v, weight). Any
//! `Err` is fine, and so is a non-finite force; a panic is a bug.

#![no_main]

use dampid::terms::Law;
use dampid::terms::laws::Expression;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let split = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    let Ok(text) = std::str::from_utf8(&bytes[..split]) else {
        return;
    };
    let Ok(law) = Expression::parse(text) else {
        return;
    };
    let _ = law.name();
    let numbers: Vec<f64> = bytes[(split + 1).min(bytes.len())..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    let (mut x, mut v, mut w) = (Vec::new(), Vec::new(), Vec::new());
    for triple in numbers.chunks_exact(3) {
        let _ = law.force(triple[0], triple[1]);
        x.push(triple[0]);
        v.push(triple[1]);
        w.push(triple[2]);
    }
    // The tame points every law is evaluated at in practice.
    for (xi, vi) in [(0.0, 0.0), (1.0, -1.0), (-0.5, 2.0), (1e-300, -1e-300)] {
        let _ = law.force(xi, vi);
    }
    let x: &[f64] = if law.uses_displacement() { &x } else { &[] };
    let _ = law.weighted_power(x, &v, &w);
});
