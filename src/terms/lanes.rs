//! Weighted sums with independent accumulators, for the inner loops of the power
//! integrals over a run of samples:
//!
//! ```text
//!   Σ_i w_i g(v_i)            (sum)
//!   Σ_i w_i g(a_i − b_i)      (sum_of_difference: a law on an element's relative velocity)
//!   Σ_i w_i a_i b_i           (dot: a Gram entry, or the work of a force channel)
//! ```
//!
//! with the weights either one per sample or one value for the whole run (then
//! w Σ_i g(…), which saves a load and a multiplication per sample).
//!
//! A plain `.sum()` is one chain of dependent adds (each waits for the previous one,
//! about 4 cycles), and the compiler may not reorder floating-point adds. Here sample i
//! goes to accumulator i mod 16 and the partial sums are added at the end, so
//! the adds are independent and the loop compiles to packed SIMD (sixteen lanes fill
//! two AVX-512 or four AVX2 registers). Each sum runs under the run-time dispatch of
//! [`crate::terms::simd`]: AVX-512 where the CPU has it, else AVX2, else SSE2. Every
//! lane does the same operations in the same order at every level, so the result is
//! bitwise the same on every x86-64 CPU and every run; it differs from the sequential
//! sum only by round-off.
//!
//! Public so that a custom [`crate::terms::Law`] can use them in its power sums.

use crate::terms::law::{ElementMotion, Weights};
use crate::terms::simd::{self, Kernel};

/// Number of independent accumulators.
pub const LANES: usize = 16;

/// Σ_i w_i g(v_i).
#[inline]
pub fn sum(weights: Weights<'_>, v: &[f64], g: impl Fn(f64) -> f64) -> f64 {
    match weights {
        Weights::Uniform(w) => w * dispatch(Sum { v, g }),
        Weights::PerSample(w) => dispatch(WeightedSum { w, v, g }),
    }
}

/// Σ_i w_i g(a_i − b_i), without storing the difference.
#[inline]
pub fn sum_of_difference(
    weights: Weights<'_>,
    a: &[f64],
    b: &[f64],
    g: impl Fn(f64) -> f64,
) -> f64 {
    match weights {
        Weights::Uniform(w) => w * dispatch(SumOfDifference { a, b, g }),
        Weights::PerSample(w) => dispatch(WeightedSumOfDifference { w, a, b, g }),
    }
}

/// Σ_i w_i g(v_i) of an element's velocity relative to ground or between its DOFs: the
/// power sum of a law f(v) with v f(v) = g(v) (see [`crate::terms::Law::power_sum`]).
#[inline]
pub fn velocity_power(
    motion: ElementMotion<'_>,
    weights: Weights<'_>,
    g: impl Fn(f64) -> f64,
) -> f64 {
    match motion {
        ElementMotion::Ground { v, .. } => sum(weights, v, g),
        ElementMotion::Between { v_a, v_b, .. } => sum_of_difference(weights, v_a, v_b, g),
    }
}

/// Σ_i w_i a_i b_i.
#[inline]
pub fn dot(weights: Weights<'_>, a: &[f64], b: &[f64]) -> f64 {
    match weights {
        Weights::Uniform(w) => w * dispatch(Dot { a, b }),
        Weights::PerSample(w) => dispatch(WeightedDot { w, a, b }),
    }
}

/// One of the loops below with its operands.
trait Loop {
    fn run(self) -> f64;
}

/// Runs `op` compiled for the best instruction set the CPU has. (The loop must be
/// inlined into the level's target-feature function: a closure is not, a trait method
/// marked `inline(always)` is.)
#[inline(always)]
fn dispatch(op: impl Loop) -> f64 {
    struct Op<L>(L);
    impl<L: Loop> Kernel for Op<L> {
        type Output = f64;
        #[inline(always)]
        fn run(self) -> f64 {
            self.0.run()
        }
    }
    simd::dispatch(Op(op))
}

/// The partial sums added in lane order. (Of the orders tried, this is the one with
/// which the compiler keeps the accumulators in four 4-wide registers for every loop
/// below; pairwise trees made it shuffle partial sums inside some loops.)
#[inline(always)]
pub(crate) fn combine(lanes: [f64; LANES]) -> f64 {
    let mut total = 0.0;
    for lane in lanes {
        total += lane;
    }
    total
}

// The six loops below differ only in the term they add; each is written out so that
// the compiler sees the plain pattern it vectorises into 4-wide registers.

struct Sum<'a, G> {
    v: &'a [f64],
    g: G,
}

impl<G: Fn(f64) -> f64> Loop for Sum<'_, G> {
    #[inline(always)]
    fn run(self) -> f64 {
        let Sum { v, g } = self;
        let mut lanes = [0.0; LANES];
        let mut v_chunks = v.chunks_exact(LANES);
        for vc in &mut v_chunks {
            for k in 0..LANES {
                lanes[k] += g(vc[k]);
            }
        }
        let tail: f64 = v_chunks.remainder().iter().map(|v| g(*v)).sum();
        combine(lanes) + tail
    }
}

struct WeightedSum<'a, G> {
    w: &'a [f64],
    v: &'a [f64],
    g: G,
}

impl<G: Fn(f64) -> f64> Loop for WeightedSum<'_, G> {
    #[inline(always)]
    fn run(self) -> f64 {
        let WeightedSum { w, v, g } = self;
        let len = w.len().min(v.len());
        let (w, v) = (&w[..len], &v[..len]);
        let mut lanes = [0.0; LANES];
        let mut w_chunks = w.chunks_exact(LANES);
        let mut v_chunks = v.chunks_exact(LANES);
        for (wc, vc) in (&mut w_chunks).zip(&mut v_chunks) {
            for k in 0..LANES {
                lanes[k] += wc[k] * g(vc[k]);
            }
        }
        let tail: f64 = w_chunks
            .remainder()
            .iter()
            .zip(v_chunks.remainder())
            .map(|(w, v)| w * g(*v))
            .sum();
        combine(lanes) + tail
    }
}

struct SumOfDifference<'a, G> {
    a: &'a [f64],
    b: &'a [f64],
    g: G,
}

impl<G: Fn(f64) -> f64> Loop for SumOfDifference<'_, G> {
    #[inline(always)]
    fn run(self) -> f64 {
        let SumOfDifference { a, b, g } = self;
        let len = a.len().min(b.len());
        let (a, b) = (&a[..len], &b[..len]);
        let mut lanes = [0.0; LANES];
        let mut a_chunks = a.chunks_exact(LANES);
        let mut b_chunks = b.chunks_exact(LANES);
        for (ac, bc) in (&mut a_chunks).zip(&mut b_chunks) {
            for k in 0..LANES {
                lanes[k] += g(ac[k] - bc[k]);
            }
        }
        let tail: f64 = a_chunks
            .remainder()
            .iter()
            .zip(b_chunks.remainder())
            .map(|(a, b)| g(a - b))
            .sum();
        combine(lanes) + tail
    }
}

struct WeightedSumOfDifference<'a, G> {
    w: &'a [f64],
    a: &'a [f64],
    b: &'a [f64],
    g: G,
}

impl<G: Fn(f64) -> f64> Loop for WeightedSumOfDifference<'_, G> {
    #[inline(always)]
    fn run(self) -> f64 {
        let WeightedSumOfDifference { w, a, b, g } = self;
        let len = w.len().min(a.len()).min(b.len());
        let (w, a, b) = (&w[..len], &a[..len], &b[..len]);
        let mut lanes = [0.0; LANES];
        let mut w_chunks = w.chunks_exact(LANES);
        let mut a_chunks = a.chunks_exact(LANES);
        let mut b_chunks = b.chunks_exact(LANES);
        for ((wc, ac), bc) in (&mut w_chunks).zip(&mut a_chunks).zip(&mut b_chunks) {
            for k in 0..LANES {
                lanes[k] += wc[k] * g(ac[k] - bc[k]);
            }
        }
        let tail: f64 = w_chunks
            .remainder()
            .iter()
            .zip(a_chunks.remainder().iter().zip(b_chunks.remainder()))
            .map(|(w, (a, b))| w * g(a - b))
            .sum();
        combine(lanes) + tail
    }
}

struct Dot<'a> {
    a: &'a [f64],
    b: &'a [f64],
}

impl Loop for Dot<'_> {
    #[inline(always)]
    fn run(self) -> f64 {
        let Dot { a, b } = self;
        let len = a.len().min(b.len());
        let (a, b) = (&a[..len], &b[..len]);
        let mut lanes = [0.0; LANES];
        let mut a_chunks = a.chunks_exact(LANES);
        let mut b_chunks = b.chunks_exact(LANES);
        for (ac, bc) in (&mut a_chunks).zip(&mut b_chunks) {
            for k in 0..LANES {
                lanes[k] += ac[k] * bc[k];
            }
        }
        let tail: f64 = a_chunks
            .remainder()
            .iter()
            .zip(b_chunks.remainder())
            .map(|(a, b)| a * b)
            .sum();
        combine(lanes) + tail
    }
}

struct WeightedDot<'a> {
    w: &'a [f64],
    a: &'a [f64],
    b: &'a [f64],
}

impl Loop for WeightedDot<'_> {
    #[inline(always)]
    fn run(self) -> f64 {
        let WeightedDot { w, a, b } = self;
        let len = w.len().min(a.len()).min(b.len());
        let (w, a, b) = (&w[..len], &a[..len], &b[..len]);
        let mut lanes = [0.0; LANES];
        let mut w_chunks = w.chunks_exact(LANES);
        let mut a_chunks = a.chunks_exact(LANES);
        let mut b_chunks = b.chunks_exact(LANES);
        for ((wc, ac), bc) in (&mut w_chunks).zip(&mut a_chunks).zip(&mut b_chunks) {
            for k in 0..LANES {
                lanes[k] += wc[k] * ac[k] * bc[k];
            }
        }
        let tail: f64 = w_chunks
            .remainder()
            .iter()
            .zip(a_chunks.remainder().iter().zip(b_chunks.remainder()))
            .map(|(w, (a, b))| w * a * b)
            .sum();
        combine(lanes) + tail
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every length from 0 to 69 (whole lane groups and remainders), with weights per
    /// sample and uniform, against plain sums.
    #[test]
    fn lane_sums_match_plain_sums() {
        let cube = |v: f64| v * v * v.abs();
        for len in 0..70 {
            let w: Vec<f64> = (0..len).map(|i| 0.5 + (i % 3) as f64).collect();
            let a: Vec<f64> = (0..len).map(|i| (i as f64 * 0.7).sin()).collect();
            let b: Vec<f64> = (0..len).map(|i| (i as f64 * 0.3).cos()).collect();
            let uniform = vec![0.25; len];
            for (weights, w) in [
                (Weights::PerSample(&w), &w),
                (Weights::Uniform(0.25), &uniform),
            ] {
                let plain = |f: &dyn Fn(usize) -> f64| (0..len).map(|i| w[i] * f(i)).sum::<f64>();
                let close = |x: f64, y: f64| (x - y).abs() <= 1e-13 * (1.0 + y.abs());
                assert!(close(sum(weights, &a, cube), plain(&|i| cube(a[i]))));
                assert!(close(
                    sum_of_difference(weights, &a, &b, cube),
                    plain(&|i| cube(a[i] - b[i]))
                ));
                assert!(close(dot(weights, &a, &b), plain(&|i| a[i] * b[i])));
            }
        }
    }
}
