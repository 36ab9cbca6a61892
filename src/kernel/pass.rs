//! One pass over a window: every sum of the plan, block by block.
//!
//! The window's m samples are cut into blocks of [`BLOCK`] samples (the last may be
//! shorter); the plan's sums into segments. A task evaluates one segment over one block,
//!
//! ```text
//!   P[b][s] = Σ_{i ∈ block b} w_i g_s(i)     for every sum s of the segment,
//! ```
//!
//! reading each velocity column of the block once from memory (the plan orders the sums
//! so that the others find it in cache). Tasks run in parallel on rayon's pool, and the
//! totals are added in block order,
//!
//! ```text
//!   S[s] = ((P[0][s] + P[1][s]) + P[2][s]) + …,
//! ```
//!
//! so the result depends only on the window and never on the number of threads or on
//! how the tasks were scheduled: it is bitwise reproducible. Partial sums are held for
//! a wave of blocks at a time (at most [`PARTIALS_BUDGET`] values, or [`MIN_WAVE`] blocks),
//! so memory stays bounded for any record length.
//!
//! Inside the longest run of equal weights (all of a rectangular rule, the interior of a
//! trapezoid) a block's sum is w Σ_i g(i), without reading or multiplying the weights;
//! the few samples outside it keep their own weights.

use std::ops::Range;

use rayon::prelude::*;

use crate::kernel::WindowSamples;
use crate::kernel::plan::{Plan, Sum};
use crate::record::col;
use crate::terms::lanes;
use crate::terms::{ElementMotion, Weights};

/// Samples per block: 32 KiB per velocity column, so the columns a segment reads
/// together stay in the core's L2 cache.
pub(crate) static BLOCK_SIZE: std::sync::LazyLock<usize> = std::sync::LazyLock::new(|| {
    std::env::var("DAMPID_BLOCK")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4096)
});

/// Partial sums held at once (8 MiB): a wave takes as many blocks as fit, at least
/// [`MIN_WAVE`], so that a long window with few sums is one parallel call rather than
/// many small ones (each a hand-off to the pool).
const PARTIALS_BUDGET: usize = 1 << 20;

/// Blocks per wave at least.
const MIN_WAVE: usize = 16;

/// Runs of equal weights shorter than this are summed with per-sample weights.
const MIN_UNIFORM_RUN: usize = 64;

/// Windows with fewer sample-sums than this run on the calling thread (same blocks and
/// order, so the same result).
const PARALLEL_WORK: usize = 1 << 16;

/// S[s] for every sum of `plan` over the window `samples`.
pub(crate) fn window_sums(plan: &Plan<'_>, samples: &WindowSamples<'_>) -> Vec<f64> {
    let m = samples.weights.len();
    let slots = plan.sums.len();
    let mut totals = vec![0.0; slots];
    if slots == 0 || m == 0 {
        return totals;
    }
    let block_len = *BLOCK_SIZE;
    let blocks = m.div_ceil(block_len);
    let parallel = m.saturating_mul(slots) >= PARALLEL_WORK;
    let uniform = uniform_run(samples.weights);
    let wave_len = (PARTIALS_BUDGET / slots).max(MIN_WAVE);
    let mut partials = vec![0.0; wave_len.min(blocks) * slots];
    for wave_start in (0..blocks).step_by(wave_len) {
        let wave = wave_len.min(blocks - wave_start);
        let partials = &mut partials[..wave * slots];
        let block_task = |(offset, block_sums): (usize, &mut [f64])| {
            let block = wave_start + offset;
            let rows = block * block_len..((block + 1) * block_len).min(m);
            let tasks = split_segments(block_sums, &plan.segments);
            let segment_task = |(range, out): (&Range<usize>, &mut [f64])| {
                for (sum, out) in plan.sums[range.clone()].iter().zip(out) {
                    *out = block_sum(sum, samples, rows.clone(), &uniform);
                }
            };
            if parallel {
                plan.segments.par_iter().zip(tasks).for_each(segment_task);
            } else {
                plan.segments.iter().zip(tasks).for_each(segment_task);
            }
        };
        if parallel {
            partials
                .par_chunks_mut(slots)
                .enumerate()
                .for_each(block_task);
        } else {
            partials.chunks_mut(slots).enumerate().for_each(block_task);
        }
        for block_sums in partials.chunks(slots) {
            for (total, part) in totals.iter_mut().zip(block_sums) {
                *total += part;
            }
        }
    }
    totals
}

/// The block's output slice cut into one piece per segment.
fn split_segments<'a>(mut out: &'a mut [f64], segments: &[Range<usize>]) -> Vec<&'a mut [f64]> {
    let mut pieces = Vec::with_capacity(segments.len());
    for range in segments {
        let (piece, rest) = out.split_at_mut(range.len());
        pieces.push(piece);
        out = rest;
    }
    pieces
}

/// The longest run of equal weights that contains the window's middle sample (all of
/// a rectangular rule, the interior of a trapezoid); `None` when it is short (a spectral
/// rule).
fn uniform_run(weights: &[f64]) -> Option<(f64, Range<usize>)> {
    let middle = weights.len() / 2;
    let value = *weights.get(middle)?;
    let start = weights[..middle]
        .iter()
        .rposition(|w| *w != value)
        .map_or(0, |i| i + 1);
    let end = weights[middle..]
        .iter()
        .position(|w| *w != value)
        .map_or(weights.len(), |i| middle + i);
    (end - start >= MIN_UNIFORM_RUN).then_some((value, start..end))
}

/// One sum over the samples `rows` of the window: the part inside the uniform run with
/// its one weight, the parts before and after it with their own weights.
fn block_sum(
    sum: &Sum<'_>,
    samples: &WindowSamples<'_>,
    rows: Range<usize>,
    uniform: &Option<(f64, Range<usize>)>,
) -> f64 {
    let Some((weight, run)) = uniform else {
        return run_sum(
            sum,
            samples,
            rows.clone(),
            Weights::PerSample(&samples.weights[rows]),
        );
    };
    let inner = run.start.clamp(rows.start, rows.end)..run.end.clamp(rows.start, rows.end);
    let mut total = 0.0;
    if rows.start < inner.start {
        let before = rows.start..inner.start;
        total += run_sum(
            sum,
            samples,
            before.clone(),
            Weights::PerSample(&samples.weights[before]),
        );
    }
    if !inner.is_empty() {
        total += run_sum(sum, samples, inner.clone(), Weights::Uniform(*weight));
    }
    if inner.end < rows.end {
        let after = inner.end..rows.end;
        total += run_sum(
            sum,
            samples,
            after.clone(),
            Weights::PerSample(&samples.weights[after]),
        );
    }
    total
}

/// One sum over the samples `rows`, with their weights.
fn run_sum(
    sum: &Sum<'_>,
    samples: &WindowSamples<'_>,
    rows: Range<usize>,
    weights: Weights<'_>,
) -> f64 {
    let v = |j: usize| &col(samples.v, j)[rows.clone()];
    match *sum {
        Sum::Power { law, a, b } => {
            let x = |j: usize| -> &[f64] {
                if law.uses_displacement() {
                    &col(samples.x, j)[rows.clone()]
                } else {
                    &[]
                }
            };
            let motion = match b {
                None => ElementMotion::Ground { x: x(a), v: v(a) },
                Some(b) => ElementMotion::Between {
                    x_a: x(a),
                    x_b: x(b),
                    v_a: v(a),
                    v_b: v(b),
                },
            };
            law.power_sum(motion, weights)
        }
        Sum::Product { j, k } => lanes::dot(weights, v(j), v(k)),
        Sum::Work { channel, dof } => lanes::dot(
            weights,
            &col(samples.signals, channel)[rows.clone()],
            v(dof),
        ),
    }
}
