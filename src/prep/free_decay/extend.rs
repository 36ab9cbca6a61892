//! A ringdown continued past its ends by linear prediction, so that a filter sees no cut.
//!
//! A sum of q damped sinusoids obeys a linear recurrence of order 2q: each sample is a
//! fixed combination of the p = [`ORDER`] samples after it (backward) or before it
//! (forward). The coefficients are the least-squares fit over the first (last) M samples
//! of the record,
//!
//! ```text
//!   backward:  s_i ≈ Σ_{k=1..p} b_k s_{i+k},     i = 0 … M − p − 1,
//!   forward:   s_i ≈ Σ_{k=1..p} a_k s_{i−k},     i = N − M + p … N − 1,
//! ```
//!
//! and the recurrence then runs past the end, one new sample at a time. A cut record
//! (a shaker switched off, a trigger after the impact) filtered through a band-pass
//! rings for about the inverse of the band's taper; continued this way, the filter sees
//! the mode's own motion on both sides of the cut. The continuation is faded out with
//! a half cosine over its outer half, so that its far end is no cut either. Noise
//! biases the fit towards smaller coefficients, which damps the continuation; this
//! only changes samples outside the record.

use nalgebra::{DMatrix, DVector};

/// The order p of the recurrence (up to p/2 modes in the fit's span).
pub const ORDER: usize = 12;

/// The recurrence's coefficients over `samples` (oldest first), predicting each from the
/// p before it.
fn fit(samples: &[f64]) -> Option<Vec<f64>> {
    let p = ORDER;
    let rows = samples.len().checked_sub(p).filter(|&r| r >= 2 * p)?;
    let a = DMatrix::from_fn(rows, p, |i, k| samples[i + p - 1 - k]);
    let b = DVector::from_fn(rows, |i, _| samples[i + p]);
    let svd = a.svd(true, true);
    let largest = svd.singular_values.max();
    let solution = svd.solve(&b, 1e-10 * largest).ok()?;
    solution
        .iter()
        .all(|c| c.is_finite())
        .then(|| solution.iter().copied().collect())
}

/// `count` samples continuing `samples` (oldest first) past its last, by the recurrence
/// fitted over its last `span` samples, faded out over the outer half (module doc);
/// zeros when the fit fails.
pub fn forward(samples: &[f64], span: usize, count: usize) -> Vec<f64> {
    let n = samples.len();
    let tail = &samples[n.saturating_sub(span)..];
    let Some(coefficients) = fit(tail) else {
        return vec![0.0; count];
    };
    let mut history: Vec<f64> = tail[tail.len().saturating_sub(ORDER)..].to_vec();
    let mut out = Vec::with_capacity(count);
    for _ in 0..count {
        let next: f64 = coefficients
            .iter()
            .zip(history.iter().rev())
            .map(|(c, s)| c * s)
            .sum();
        history.remove(0);
        history.push(next);
        out.push(next);
    }
    fade(&mut out);
    out
}

/// `count` samples continuing `samples` before its first, nearest first (module doc).
pub fn backward(samples: &[f64], span: usize, count: usize) -> Vec<f64> {
    let reversed: Vec<f64> = samples[..span.min(samples.len())]
        .iter()
        .rev()
        .copied()
        .collect();
    forward(&reversed, span, count)
}

/// Multiplies the outer half of `continuation` (nearest first) by a half cosine from 1
/// to 0.
fn fade(continuation: &mut [f64]) {
    let n = continuation.len();
    let half = n / 2;
    for (j, s) in continuation.iter_mut().enumerate().skip(half) {
        let u = (j - half + 1) as f64 / (n - half + 1) as f64;
        *s *= 0.5 * (1.0 + (std::f64::consts::PI * u).cos());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two damped sinusoids continue exactly (before the fade).
    #[test]
    fn continues_two_damped_sinusoids() {
        let s = |i: f64| {
            (-0.001 * i).exp() * (0.05 * i).sin()
                + 0.3 * (-0.002 * i).exp() * (0.17 * i + 1.0).cos()
        };
        let samples: Vec<f64> = (0..2000).map(|i| s(i as f64)).collect();
        let ahead = forward(&samples, 600, 400);
        for (j, value) in ahead.iter().take(200).enumerate() {
            assert!((value - s((2000 + j) as f64)).abs() < 1e-8, "{j}");
        }
        let behind = backward(&samples, 600, 400);
        for (j, value) in behind.iter().take(200).enumerate() {
            assert!((value - s(-1.0 - j as f64)).abs() < 1e-8, "{j}");
        }
        assert!(ahead[399].abs() < 1e-2 && behind[399].abs() < 1e-2);
    }
}
