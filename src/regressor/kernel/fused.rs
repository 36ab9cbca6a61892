//! The sums of one group (every sum whose newest velocity column is the same) in one
//! loop over a block's samples,
//!
//! ```text
//!   for each sub-block of 128 samples:
//!       prefetch the same rows of the next group's column
//!       for each member m, for each sample i:    L_m[i mod 16] += w_i g_m(i)
//!   S_m = Σ_k L_m[k] + Σ_{i ∈ tail} w_i g_m(i)       (w (Σ_k L_m[k] + Σ_tail g_m) when the
//!                                                      weights are one value h)
//! ```
//!
//! where the member's term g_m(i) is one of
//!
//! ```text
//!   g(v_a)  or  g(v_a − v_b)   a law with a closed power form (Law::power_form) on DOF a
//!                              or on the dashpot (a, b),
//!   v_j v_k                    a Gram entry,
//!   s_c v_j                    the work of force channel c on DOF j.
//! ```
//!
//! The lanes, their order and the tail are exactly those of `terms::lanes` (`sum`,
//! `sum_of_difference`, `dot`), so each member's sum is bitwise the one it makes alone;
//! only the memory traffic differs. One sum at a time, the group's first sum waits for
//! the new column to arrive from memory while the arithmetic idles, and the others then
//! compute on it while the memory idles. In one loop, the members compute while the
//! column streams in, and the prefetch puts the next group's loads in flight during
//! this group's arithmetic.

use std::ops::Range;

use crate::record::col;
use crate::regressor::kernel::WindowSamples;
use crate::regressor::kernel::plan::Sum;
use crate::terms::lanes::{self, LANES};
use crate::terms::simd::{self, Kernel};
use crate::terms::{PowerForm, Weights};

/// Members in one loop at most: their accumulators (8 × 16 values) stay on the stack.
const MAX_MEMBERS: usize = 8;

/// Samples per sub-block: 128 samples of the next column are 16 cache lines, prefetched
/// once per sub-block.
const SUB_BLOCK: usize = 128;

/// What a member adds per sample, from its one or two operand columns p and q.
#[derive(Debug, Clone, Copy)]
enum Term {
    /// g(p).
    Power(PowerForm),
    /// g(p − q).
    PowerOfDifference(PowerForm),
    /// p q.
    Product,
}

/// One member's term and operands over the rows of a piece.
#[derive(Debug, Clone, Copy)]
struct Member<'a> {
    term: Term,
    p: &'a [f64],
    q: &'a [f64],
}

/// Evaluates `$body` with `$g` bound to g of `$form` as a closure of its own, so that
/// each form's loop is compiled separately (no match inside the loop).
macro_rules! with_form {
    ($form:expr, |$g:ident| $body:expr) => {
        match $form {
            PowerForm::Square => {
                let $g = |v: f64| PowerForm::Square.power(v);
                $body
            }
            PowerForm::AbsCube => {
                let $g = |v: f64| PowerForm::AbsCube.power(v);
                $body
            }
            PowerForm::Abs => {
                let $g = |v: f64| PowerForm::Abs.power(v);
                $body
            }
            PowerForm::AbsPow(exponent) => {
                let $g = move |v: f64| PowerForm::AbsPow(exponent).power(v);
                $body
            }
        }
    };
}
/// S for each sum of `sums` (all [`Sum::fusable`]) over the window's `rows`, written to
/// `out`; `ahead` is the column to prefetch (the next group's), if any.
pub(crate) fn group_sums(
    sums: &[Sum<'_>],
    samples: &WindowSamples<'_>,
    rows: Range<usize>,
    ahead: Option<usize>,
    out: &mut [f64],
) {
    for (sums, out) in sums.chunks(MAX_MEMBERS).zip(out.chunks_mut(MAX_MEMBERS)) {
        // Pieces added as `Iterator::sum` adds them, from −0.0, as the unfused pass did.
        out.fill(-0.0);
        for piece in samples.weights.pieces(rows.clone()) {
            let rows = piece.rows;
            let v = |j: usize| &col(samples.v, j)[rows.clone()];
            let mut members = [Member {
                term: Term::Product,
                p: &[],
                q: &[],
            }; MAX_MEMBERS];
            for (member, sum) in members.iter_mut().zip(sums) {
                *member = match *sum {
                    Sum::Power { law, a, b } => {
                        // cannot fail: the plan fuses only sums whose law has a power
                        // form (plan.rs, `fusable`), and a law's form is fixed.
                        let form = law.power_form().expect("fusable sums have a power form");
                        match b {
                            None => Member {
                                term: Term::Power(form),
                                p: v(a),
                                q: &[],
                            },
                            Some(b) => Member {
                                term: Term::PowerOfDifference(form),
                                p: v(a),
                                q: v(b),
                            },
                        }
                    }
                    Sum::Product { j, k } => Member {
                        term: Term::Product,
                        p: v(j),
                        q: v(k),
                    },
                    Sum::Work { channel, dof } => Member {
                        term: Term::Product,
                        p: &col(samples.signals, channel)[rows.clone()],
                        q: v(dof),
                    },
                };
            }
            let fused = Fused {
                members: &members[..sums.len()],
                weights: piece.weights,
                ahead: ahead.map_or(&[][..], v),
            };
            let totals = simd::dispatch(fused);
            for (out, total) in out.iter_mut().zip(totals) {
                *out += total;
            }
        }
    }
}

/// The loop over one piece (rows with uniform or per-sample weights), compiled for the
/// best instruction set the CPU has.
struct Fused<'a, 'm> {
    members: &'m [Member<'a>],
    weights: Weights<'a>,
    ahead: &'a [f64],
}

impl Kernel for Fused<'_, '_> {
    type Output = [f64; MAX_MEMBERS];

    #[inline(always)]
    fn run(self) -> Self::Output {
        let Fused {
            members,
            weights,
            ahead,
        } = self;
        let len = members.first().map_or(0, |m| m.p.len());
        let per_sample = match weights {
            Weights::Uniform(_) => None,
            Weights::PerSample(w) => Some(&w[..len]),
        };
        let full = len - len % LANES;
        let mut lanes = [[0.0; LANES]; MAX_MEMBERS];
        for start in (0..full).step_by(SUB_BLOCK) {
            let rows = start..(start + SUB_BLOCK).min(full);
            if !ahead.is_empty() {
                prefetch(&ahead[rows.clone()]);
            }
            let w = per_sample.map(|w| &w[rows.clone()]);
            for (member, lanes) in members.iter().zip(lanes.iter_mut()) {
                add_lanes(member, rows.clone(), w, lanes);
            }
        }
        let mut totals = [0.0; MAX_MEMBERS];
        for ((member, lanes), total) in members.iter().zip(lanes).zip(totals.iter_mut()) {
            let tail = tail_sum(member, full..len, per_sample.map(|w| &w[full..]));
            *total = match weights {
                Weights::Uniform(w) => w * (lanes::combine(lanes) + tail),
                Weights::PerSample(_) => lanes::combine(lanes) + tail,
            };
        }
        totals
    }
}

/// Requests the cache lines of `column` (one prefetch per 64-byte line).
#[inline(always)]
fn prefetch(column: &[f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        for line in column.chunks(8) {
            // SAFETY: a prefetch is a hint that never faults, and the pointer is in
            // bounds.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line.as_ptr().cast()) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = column;
}

/// L[i mod 16] += w_i g(i) over `rows` (a whole number of lane groups).
#[inline(always)]
fn add_lanes(member: &Member<'_>, rows: Range<usize>, w: Option<&[f64]>, lanes: &mut [f64; LANES]) {
    let p = &member.p[rows.clone()];
    let q = if member.q.is_empty() {
        &[][..]
    } else {
        &member.q[rows]
    };
    match member.term {
        Term::Power(form) => with_form!(form, |g| add_power(g, p, None, w, lanes)),
        Term::PowerOfDifference(form) => with_form!(form, |g| add_power(g, p, Some(q), w, lanes)),
        Term::Product => match w {
            None => {
                for (pc, qc) in p.chunks_exact(LANES).zip(q.chunks_exact(LANES)) {
                    for k in 0..LANES {
                        lanes[k] += pc[k] * qc[k];
                    }
                }
            }
            Some(w) => {
                for ((wc, pc), qc) in w
                    .chunks_exact(LANES)
                    .zip(p.chunks_exact(LANES))
                    .zip(q.chunks_exact(LANES))
                {
                    for k in 0..LANES {
                        lanes[k] += wc[k] * pc[k] * qc[k];
                    }
                }
            }
        },
    }
}

/// L[i mod 16] += w_i g(p_i) or w_i g(p_i − q_i).
#[inline(always)]
fn add_power(
    g: impl Fn(f64) -> f64,
    p: &[f64],
    q: Option<&[f64]>,
    w: Option<&[f64]>,
    lanes: &mut [f64; LANES],
) {
    match (q, w) {
        (None, None) => {
            for pc in p.chunks_exact(LANES) {
                for k in 0..LANES {
                    lanes[k] += g(pc[k]);
                }
            }
        }
        (Some(q), None) => {
            for (pc, qc) in p.chunks_exact(LANES).zip(q.chunks_exact(LANES)) {
                for k in 0..LANES {
                    lanes[k] += g(pc[k] - qc[k]);
                }
            }
        }
        (None, Some(w)) => {
            for (wc, pc) in w.chunks_exact(LANES).zip(p.chunks_exact(LANES)) {
                for k in 0..LANES {
                    lanes[k] += wc[k] * g(pc[k]);
                }
            }
        }
        (Some(q), Some(w)) => {
            for ((wc, pc), qc) in w
                .chunks_exact(LANES)
                .zip(p.chunks_exact(LANES))
                .zip(q.chunks_exact(LANES))
            {
                for k in 0..LANES {
                    lanes[k] += wc[k] * g(pc[k] - qc[k]);
                }
            }
        }
    }
}

/// Σ w_i g(i) over the last `rows` (fewer than 16), in sample order as `terms::lanes`
/// adds its tail. Without weights w_i = 1, and 1 · x is exactly x.
fn tail_sum(member: &Member<'_>, rows: Range<usize>, w: Option<&[f64]>) -> f64 {
    let p = &member.p[rows.clone()];
    let q = if member.q.is_empty() {
        &[][..]
    } else {
        &member.q[rows.clone()]
    };
    (0..rows.len())
        .map(|i| {
            let w = w.map_or(1.0, |w| w[i]);
            match member.term {
                Term::Power(form) => w * form.power(p[i]),
                Term::PowerOfDifference(form) => w * form.power(p[i] - q[i]),
                // (w p) q, as `lanes::dot` multiplies.
                Term::Product => w * p[i] * q[i],
            }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use faer::Mat;

    use super::*;
    use crate::prep::quadrature::WindowWeights;
    use crate::terms::laws::{Coulomb, Custom, Linear, PowerLaw, Quadratic};
    use crate::terms::{ElementMotion, Law};

    fn column(m: &Mat<f64>, j: usize, rows: Range<usize>) -> &[f64] {
        &col(m.as_ref(), j)[rows]
    }

    /// Each member of a fused group gives bitwise the sum that `terms::lanes` (through
    /// the law's own `power_sum`) gives alone: every kind of member, more members than
    /// one loop holds, uniform (banded) and per-sample weights, and row ranges that end
    /// inside a lane group, on a sub-block edge and in the banded rule's head and tail.
    #[test]
    fn fused_sums_are_bitwise_the_lone_sums() {
        let samples = 700;
        let v = Mat::from_fn(samples, 3, |i, j| ((i * (j + 2)) as f64 * 0.37).sin() + 0.1);
        let signals = Mat::from_fn(samples, 2, |i, c| ((i + 5 * c) as f64 * 0.11).cos());
        let x = Mat::<f64>::zeros(samples, 3);
        let power = PowerLaw::new(0.7).unwrap();
        let laws: [&dyn Law; 4] = [&Linear, &Quadratic, &Coulomb, &power];
        let mut sums = Vec::new();
        for law in laws {
            sums.push(Sum::Power { law, a: 2, b: None });
            sums.push(Sum::Power {
                law,
                a: 2,
                b: Some(0),
            });
        }
        sums.push(Sum::Product { j: 1, k: 2 });
        sums.push(Sum::Work { channel: 1, dof: 2 });
        assert!(sums.len() > MAX_MEMBERS);
        assert!(sums.iter().all(Sum::fusable));

        let banded = WindowWeights::banded(vec![0.3, 0.6], 0.01, vec![0.6, 0.3, 0.1], samples);
        let per_sample =
            WindowWeights::PerSample((0..samples).map(|i| 0.5 + (i % 7) as f64 * 0.1).collect());
        for weights in [&banded, &per_sample] {
            let window = WindowSamples {
                x: x.as_ref(),
                v: v.as_ref(),
                signals: signals.as_ref(),
                weights,
            };
            for rows in [
                0..0,
                0..1,
                0..15,
                3..131,
                0..128,
                5..400,
                1..samples,
                650..samples,
            ] {
                let mut fused = vec![f64::NAN; sums.len()];
                group_sums(&sums, &window, rows.clone(), Some(1), &mut fused);
                for (sum, &fused) in sums.iter().zip(&fused) {
                    let alone: f64 = weights
                        .pieces(rows.clone())
                        .map(|piece| {
                            let column = |m, j| column(m, j, piece.rows.clone());
                            match *sum {
                                Sum::Power { law, a, b } => {
                                    let motion = match b {
                                        None => ElementMotion::Ground {
                                            x: &[],
                                            v: column(&v, a),
                                        },
                                        Some(b) => ElementMotion::Between {
                                            x_a: &[],
                                            x_b: &[],
                                            v_a: column(&v, a),
                                            v_b: column(&v, b),
                                        },
                                    };
                                    law.power_sum(motion, piece.weights)
                                }
                                Sum::Product { j, k } => {
                                    lanes::dot(piece.weights, column(&v, j), column(&v, k))
                                }
                                Sum::Work { channel, dof } => lanes::dot(
                                    piece.weights,
                                    column(&signals, channel),
                                    column(&v, dof),
                                ),
                            }
                        })
                        .sum();
                    assert_eq!(
                        fused.to_bits(),
                        alone.to_bits(),
                        "{sum:?} over {rows:?}: fused {fused}, alone {alone}"
                    );
                }
            }
        }

        // A law without a closed form is not fusable: the pass calls its power_sum.
        let custom = Custom::new("v|v|", |_x, v| v * v.abs());
        assert!(
            !Sum::Power {
                law: &custom,
                a: 0,
                b: None
            }
            .fusable()
        );
    }
}
