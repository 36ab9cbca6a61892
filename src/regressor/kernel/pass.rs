//! One pass over a window: every sum of the plan, block by block.
//!
//! The window's m samples are cut into blocks of [`BLOCK_SIZE`] samples (the last may be
//! shorter); the plan's groups (the sums of one velocity column) into segments. A task
//! evaluates one segment over one block,
//!
//! ```text
//!   P[b][s] = Σ_{i ∈ block b} w_i g_s(i)     for every sum s of the segment,
//! ```
//!
//! group by group, reading each velocity column of the block once from memory: a
//! group's sums with a closed form run in one loop (`fused.rs`), the others one by one
//! through their law's `power_sum` while the column is in cache. The tasks of all blocks form one flat list that
//! runs in parallel on rayon's pool (on the calling thread when the window is small, see
//! [`worth_parallel`]), and the totals are added in block order,
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
//! Inside the interior of a rectangular or trapezoid rule, where every weight is h, a
//! block's sum is h Σ_i g(i), without reading or multiplying weights; the few samples at
//! the ends keep their own weights.

use std::ops::Range;

use rayon::prelude::*;

use crate::record::col;
use crate::regressor::kernel::WindowSamples;
use crate::regressor::kernel::fused;
use crate::regressor::kernel::plan::{Plan, Sum};
use crate::terms::lanes;
use crate::terms::{ElementMotion, Weights};

/// Samples per block: 64 KiB per velocity column, so the two columns a group reads and
/// the next one being prefetched stay in the core's L2 cache (512 KiB on the 2-core
/// EPYC of BENCHMARKS.md §1, where 8192 took 8–20 % less time than 4096 on 1000 × 1e5
/// at 1 thread, interleaved runs; `DAMPID_BLOCK` overrides it).
pub(crate) static BLOCK_SIZE: std::sync::LazyLock<usize> = std::sync::LazyLock::new(|| {
    std::env::var("DAMPID_BLOCK")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(8192)
});

/// Partial sums held at once (8 MiB): a wave takes as many blocks as fit, at least
/// [`MIN_WAVE`], so that a long window with few sums is one parallel call rather than
/// many small ones (each a hand-off to the pool).
const PARTIALS_BUDGET: usize = 1 << 20;

/// Blocks per wave at least.
const MIN_WAVE: usize = 16;

/// Work of fewer sample-sums than this runs on the calling thread (same blocks and
/// order, so the same result): handing it to the pool costs more than it saves. On this
/// machine's 2 threads, 3.2e5 sample-sums took 72 µs on one thread and 112 µs on two;
/// 3e6 took 1.02 ms on one and 0.91 ms on two.
const PARALLEL_WORK: usize = 1 << 20;

/// Whether `sample_sums` (samples × sums) is worth spreading over rayon's pool: enough
/// work, and more than one thread to take it. A one-thread pool only adds the hand-off
/// (a futex wake and a context switch each way), which a profile of a 0.3 ms build
/// showed as 45 % of its time.
pub(crate) fn worth_parallel(sample_sums: usize) -> bool {
    sample_sums >= PARALLEL_WORK && rayon::current_num_threads() > 1
}

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
    let parallel = worth_parallel(m.saturating_mul(slots));
    let wave_len = (PARTIALS_BUDGET / slots).max(MIN_WAVE);
    let mut partials = vec![0.0; wave_len.min(blocks) * slots];
    for wave_start in (0..blocks).step_by(wave_len) {
        let wave = wave_len.min(blocks - wave_start);
        let partials = &mut partials[..wave * slots];
        // One task per (block, segment), each writing its own slots of `partials`.
        let tasks: Vec<Task<'_>> = partials
            .chunks_mut(slots)
            .enumerate()
            .flat_map(|(offset, block_sums)| {
                let block = wave_start + offset;
                let rows = block * block_len..((block + 1) * block_len).min(m);
                plan.segments
                    .iter()
                    .zip(split_segments(block_sums, plan))
                    .map(move |(segment, out)| Task {
                        rows: rows.clone(),
                        groups: segment.clone(),
                        out,
                    })
            })
            .collect();
        let run = |task: Task<'_>| run_task(plan, samples, task);
        if parallel {
            tasks.into_par_iter().for_each(run);
        } else {
            tasks.into_iter().for_each(run);
        }
        for block_sums in partials.chunks(slots) {
            for (total, part) in totals.iter_mut().zip(block_sums) {
                *total += part;
            }
        }
    }
    totals
}

/// The groups of one segment over the samples of one block, and where their partial
/// sums go (the segment's slots).
struct Task<'o> {
    rows: Range<usize>,
    groups: Range<usize>,
    out: &'o mut [f64],
}

/// The sums of the task's groups over its block: each group's fusable sums in one loop
/// (with a prefetch of the next group's column), the others one by one.
fn run_task(plan: &Plan<'_>, samples: &WindowSamples<'_>, task: Task<'_>) {
    let first_slot = plan.groups[task.groups.start].slots.start;
    for g in task.groups {
        let group = &plan.groups[g];
        let out = &mut task.out[group.slots.start - first_slot..][..group.slots.len()];
        let (fused_out, single_out) = out.split_at_mut(group.fused);
        let (fused, single) = plan.sums[group.slots.clone()].split_at(group.fused);
        let ahead = plan.groups.get(g + 1).map(|next| next.column);
        fused::group_sums(fused, samples, task.rows.clone(), ahead, fused_out);
        for (sum, out) in single.iter().zip(single_out) {
            *out = block_sum(sum, samples, task.rows.clone());
        }
    }
}

/// The block's output slice cut into one piece per segment.
fn split_segments<'a>(mut out: &'a mut [f64], plan: &Plan<'_>) -> Vec<&'a mut [f64]> {
    let mut pieces = Vec::with_capacity(plan.segments.len());
    for segment in &plan.segments {
        let (piece, rest) = out.split_at_mut(plan.segment_slots(segment).len());
        pieces.push(piece);
        out = rest;
    }
    pieces
}

/// One sum that is not fusable over the samples `rows` of the window, piece by piece of its weights (the
/// interior of a rectangular or trapezoid rule with its one weight, the ends and the
/// spectral rule sample by sample).
pub(crate) fn block_sum(sum: &Sum<'_>, samples: &WindowSamples<'_>, rows: Range<usize>) -> f64 {
    samples
        .weights
        .pieces(rows)
        .map(|piece| run_sum(sum, samples, piece.rows, piece.weights))
        .sum()
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
