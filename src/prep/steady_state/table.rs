//! The harmonic design of a span of samples held once as columns, and what the
//! steady-state check computes from it per channel in passes over the samples:
//!
//! ```text
//!   c = (BᵀB)⁻¹ Bᵀ(x − x₀1) + x₀ e₀      (RᵀR = BᵀB: two triangular solves, p² per channel),
//!   ŷ_i = Σ_k B_ik c_k,   RSS = Σ_i (x_i − ŷ_i)²,   ½ range ŷ = ½ (max_i ŷ_i − min_i ŷ_i),
//! ```
//!
//! B the m × p design [1, cos q₁ωt, sin q₁ωt, …] at t_i = i h (one table per span,
//! shared by every channel), x₀ the channel's first sample (a large offset costs no
//! accuracy, as in [`crate::prep::fourier::HarmonicBasis::fit_with`]). Each product is a
//! pass over a column of samples: O(m p) per channel, no copy of the samples, no
//! matrix of fitted values. Of the ranges only the largest over a period's channels is
//! wanted, so a channel is evaluated only when a bound on its range,
//!
//! ```text
//!   ½ range ŷ ≤ Σ_q √(a_q² + b_q²) ρ_q + round-off,   ρ_q = max_i |(B_{i,cos q}, B_{i,sin q})|,
//! ```
//!
//! can reach the largest range found so far (the channels of the largest bounds first),
//! and then only when a second bound, from its values on a grid of every eighth sample
//! (`range_grid.rs`: within about (Δ²/8) max |ŷ''| of the range itself), can too: the
//! series are evaluated in decreasing order of that second bound, so that the largest
//! range is usually found first and the rest skipped.
//!
//! Bᵀx and ‖x − x₀1‖² read x from L1 in sixteen partial sums per sum, several columns
//! and the squares per pass (`prep/fourier/fused_sums.rs`); for the range, ŷ is
//! formed eight samples at a time in registers and reduced at once; for the residual,
//! 128 samples at a time on the stack. The passes of the fit and the range are compiled
//! for the widest instruction set the CPU has ([`simd::dispatch`]) with every lane doing
//! the operations of the plain loop in its order, so the results are the same bits at
//! every level.

use faer::Mat;

use crate::prep::fourier::{HarmonicBasis, fit_and_shifted_squares, fit_on_design};
use crate::terms::simd::{self, Kernel};

use super::few;
use super::range_grid::{RangeGrid, modulus};

/// Samples of B c held at a time ([`HarmonicTable::chunks`]): on the stack, in L1.
const CHUNK: usize = 128;

/// The design columns and R of a harmonic basis over `samples` samples.
pub(super) struct HarmonicTable {
    /// B, m × p (column-major: each column contiguous).
    design: Mat<f64>,
    /// R (upper triangular, p × p), RᵀR = BᵀB.
    pub(super) r: Mat<f64>,
    /// The upper triangle of R row by row (row i from its diagonal: p − i values), for
    /// ‖R v‖².
    upper: Vec<f64>,
    /// ρ_q = max_i √(B_{i,cos q}² + B_{i,sin q}²) per harmonic of the design (1 but
    /// for the round-off of the table's recurrence): |a B_cos + b B_sin| ≤ √(a² + b²) ρ_q.
    moduli: Vec<f64>,
}

/// Samples of B c evaluated side by side in registers by [`Extremes`].
const LANES: usize = 8;

/// The least and the largest of ŷ_i = Σ_k c_k B_ik over the first `n` samples, for
/// each of `S` series c (c_x, c_v or both), [`LANES`] samples at a time (the columns of
/// all read while in L1). Each ŷ_i is its own nonzero terms added to 0.0 in the order of
/// k (the operations of [`HarmonicTable::chunks`]), in registers with their extremes
/// kept per lane: no buffer, no branch in the inner loop, and no comparison waits on
/// the one before; a series' extremes do not depend on the others evaluated with it.
/// `if y < lo` is the hardware's minimum (the same as `f64::min` for finite values but
/// for the sign of a zero). Compiled for the widest instruction set the CPU has.
struct Extremes<'a, const S: usize> {
    design: &'a Mat<f64>,
    series: [&'a [f64]; S],
    n: usize,
}

impl<const S: usize> Kernel for Extremes<'_, S> {
    type Output = [(f64, f64); S];
    #[inline(always)]
    fn run(self) -> [(f64, f64); S] {
        let n = self.n;
        // per series, the columns with a nonzero term and the term, in the order of k
        let terms = |c: &[f64]| -> Vec<(&[f64], f64)> {
            c.iter()
                .enumerate()
                .filter(|&(_, &ck)| ck != 0.0)
                .map(|(k, &ck)| (&self.design.col_as_slice(k)[..n], ck))
                .collect()
        };
        let series = self.series.map(terms);
        let mut lo = [[f64::INFINITY; LANES]; S];
        let mut hi = [[f64::NEG_INFINITY; LANES]; S];
        let whole = n - n % LANES;
        for start in (0..whole).step_by(LANES) {
            for ((terms, lo), hi) in series.iter().zip(&mut lo).zip(&mut hi) {
                let mut y = [0.0f64; LANES];
                for &(column, c) in terms {
                    let column = &column[start..start + LANES];
                    for l in 0..LANES {
                        y[l] += c * column[l];
                    }
                }
                for l in 0..LANES {
                    lo[l] = if y[l] < lo[l] { y[l] } else { lo[l] };
                    hi[l] = if y[l] > hi[l] { y[l] } else { hi[l] };
                }
            }
        }
        for i in whole..n {
            let l = i - whole;
            for ((terms, lo), hi) in series.iter().zip(&mut lo).zip(&mut hi) {
                let mut y = 0.0f64;
                for &(column, c) in terms {
                    y += c * column[i];
                }
                lo[l] = if y < lo[l] { y } else { lo[l] };
                hi[l] = if y > hi[l] { y } else { hi[l] };
            }
        }
        std::array::from_fn(|s| {
            (
                lo[s].iter().fold(f64::INFINITY, |a, &b| a.min(b)),
                hi[s].iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b)),
            )
        })
    }
}

/// Whether a range bounded by `bound` can reach `largest`: not below it (a NaN bound
/// can).
fn can_reach(bound: f64, largest: f64) -> bool {
    bound.partial_cmp(&largest) != Some(std::cmp::Ordering::Less)
}

/// The ½ ranges of B c over the first `n` rows of `design` for each of the series c
/// ([`Extremes`]).
fn extremes_on<const S: usize>(design: &Mat<f64>, series: [&[f64]; S], n: usize) -> [f64; S] {
    let extremes = simd::dispatch(Extremes { design, series, n });
    extremes.map(|(lo, hi)| 0.5 * (hi - lo))
}

/// The ½ ranges over the first `n` rows of `design` of the series `which` of one
/// channel's (c_x, c_v): both in one pass when both are asked.
fn ranges_on(
    design: &Mat<f64>,
    (cx, cv): (&[f64], &[f64]),
    n: usize,
    which: [bool; 2],
) -> [Option<f64>; 2] {
    match which {
        [true, true] => extremes_on(design, [cx, cv], n).map(Some),
        [true, false] => [Some(extremes_on(design, [cx], n)[0]), None],
        [false, true] => [None, Some(extremes_on(design, [cv], n)[0])],
        [false, false] => [None, None],
    }
}

impl HarmonicTable {
    /// The table of `basis` over its `samples` samples.
    pub(super) fn new(basis: &HarmonicBasis, samples: usize) -> Self {
        let design = basis.design(samples);
        let moduli = (1..design.ncols())
            .step_by(2)
            .map(|k| {
                let (c, s) = (design.col_as_slice(k), design.col_as_slice(k + 1));
                c.iter()
                    .zip(s)
                    .fold(0.0f64, |m, (c, s)| m.max((c * c + s * s).sqrt()))
            })
            .collect();
        let r = basis.r_factor();
        let p = r.ncols();
        let upper = (0..p)
            .flat_map(|i| (i..p).map(move |k| (i, k)))
            .map(|(i, k)| r[(i, k)])
            .collect();
        HarmonicTable {
            design,
            r,
            upper,
            moduli,
        }
    }

    /// B.
    pub(super) fn design(&self) -> &Mat<f64> {
        &self.design
    }

    /// m, the samples of the design.
    pub(super) fn rows(&self) -> usize {
        self.design.nrows()
    }

    /// p.
    pub(super) fn columns(&self) -> usize {
        self.design.ncols()
    }

    /// The least-squares coefficients of the samples `x` (m of them): module doc.
    pub(super) fn fit(&self, x: &[f64]) -> Vec<f64> {
        fit_on_design(&self.design, &self.r, x)
    }

    /// ŷ = B c over the first `n` samples, [`CHUNK`] samples at a time into a buffer on
    /// the stack: `visit(start, ŷ[start..start + len])` in order. Each ŷ_i is the
    /// nonzero terms c_k B_ik added to 0.0 in the order of k (a column at a time over the
    /// chunk, so the loop runs over contiguous samples), the same operations as one
    /// pass over all samples per column.
    fn chunks(&self, coefficients: &[f64], n: usize, mut visit: impl FnMut(usize, &[f64])) {
        let mut values = [0.0f64; CHUNK];
        let mut start = 0;
        while start < n {
            let len = CHUNK.min(n - start);
            let fitted = &mut values[..len];
            fitted.fill(0.0);
            for (k, &ck) in coefficients.iter().enumerate() {
                if ck != 0.0 {
                    let column = &self.design.col_as_slice(k)[start..start + len];
                    for (y, b) in fitted.iter_mut().zip(column) {
                        *y += ck * b;
                    }
                }
            }
            visit(start, fitted);
            start += len;
        }
    }

    /// The ½ ranges (max − min)/2 of B c_x and of B c_v over the first `n` samples, in
    /// one pass ([`Extremes`]): the least and the largest of finite values do not
    /// depend on the order they are met in, so each range is the same as in sample order
    /// (a zero range might differ in the sign of its zero only, which every use of it
    /// treats alike).
    #[cfg(test)]
    pub(super) fn half_ranges(
        &self,
        displacement: &[f64],
        velocity: &[f64],
        n: usize,
    ) -> (f64, f64) {
        let [x, v] = extremes_on(&self.design, [displacement, velocity], n);
        (x, v)
    }

    /// The largest ½ ranges of B c_x and of B c_v over the first `n` samples among
    /// `channels` (each (c_x, c_v)), each 0 when none is larger: the largest of the
    /// ½ ranges of every channel, bit for bit, with only the series evaluated that can
    /// hold it. A series' computed ½ range is at most [`HarmonicTable::range_bound`] of
    /// its coefficients; the series of the largest bound (of x̂, of v̂) is evaluated
    /// first (x̂ and v̂ in one pass when one channel leads both), and a series whose
    /// bound is below the largest range found is skipped (its range cannot be the
    /// largest). With the table's `grid` (over all its samples), a series that passes
    /// that bound is bounded again from its values on the grid ([`RangeGrid::bound`],
    /// about the range itself). The series left are then evaluated one at a time, the
    /// largest of their bounds first, each as long as its bound can reach the largest
    /// range found (a NaN bound always can).
    pub(super) fn largest_half_ranges(
        &self,
        channels: &[(&[f64], &[f64])],
        n: usize,
        grid: Option<&RangeGrid>,
    ) -> (f64, f64) {
        let bounds: Vec<[(f64, f64); 2]> = channels
            .iter()
            .map(|(cx, cv)| [self.range_bound(cx), self.range_bound(cv)])
            .collect();
        // the channel of the largest bound on each, first (a channel with a NaN bound is
        // never skipped, wherever it orders)
        let leader = |s: usize| {
            (0..channels.len()).max_by(|&a, &b| bounds[a][s].0.total_cmp(&bounds[b][s].0))
        };
        let leaders = [leader(0), leader(1)];
        let grid = grid.filter(|_| n == self.rows());
        let mut largest = [0.0f64; 2];
        let merge = |largest: &mut [f64; 2], ranges: [Option<f64>; 2]| {
            for (l, h) in largest.iter_mut().zip(ranges) {
                if let Some(h) = h {
                    *l = l.max(h);
                }
            }
        };
        // each leader on the series it leads (both in one pass when it leads both)
        let mut led: Vec<usize> = leaders.iter().flatten().copied().collect();
        led.dedup();
        for j in led {
            let which = leaders.map(|leader| leader == Some(j));
            merge(&mut largest, ranges_on(&self.design, channels[j], n, which));
        }
        // per series, the others that can reach the largest, with their sharpest bound
        let mut left: [Vec<(f64, usize)>; 2] = [Vec::new(), Vec::new()];
        for (j, bound) in bounds.iter().enumerate() {
            let which: [bool; 2] =
                std::array::from_fn(|s| can_reach(bound[s].0, largest[s]) && leaders[s] != Some(j));
            let sharper: [Option<f64>; 2] = match grid.filter(|_| which.contains(&true)) {
                Some(grid) => {
                    let rows = grid.design.nrows();
                    let coarse = ranges_on(&grid.design, channels[j], rows, which);
                    let series = [channels[j].0, channels[j].1];
                    std::array::from_fn(|s| {
                        coarse[s].map(|range| grid.bound(series[s], range, bound[s].1))
                    })
                }
                None => std::array::from_fn(|s| which[s].then_some(bound[s].0)),
            };
            for (left, sharper) in left.iter_mut().zip(sharper) {
                if let Some(b) = sharper {
                    left.push((b, j));
                }
            }
        }
        // the largest bound first (a NaN one before every other), while it can reach
        let key = |b: f64| if b.is_nan() { f64::INFINITY } else { b };
        for (s, left) in left.iter_mut().enumerate() {
            loop {
                left.retain(|&(b, _)| can_reach(b, largest[s]));
                let next =
                    (0..left.len()).max_by(|&a, &b| key(left[a].0).total_cmp(&key(left[b].0)));
                let Some(at) = next else { break };
                let (_, j) = left.swap_remove(at);
                let which = std::array::from_fn(|t| t == s);
                merge(&mut largest, ranges_on(&self.design, channels[j], n, which));
            }
        }
        (largest[0], largest[1])
    }

    /// An upper bound on the computed ½ range of B c over any samples of the table, c =
    /// [a₀, a_q, b_q, …]: in exact arithmetic the range of a₀ + Σ_q (a_q B_cos + b_q B_sin)
    /// is at most 2 Σ_q √(a_q² + b_q²) ρ_q (Cauchy–Schwarz on each harmonic, the constant
    /// column exactly 1); each ŷ_i computed as a sum of p products is within
    /// γ_p Σ_k |c_k B_ik| ≤ 2(p + 1) u e of its exact value, e = |a₀| + Σ_q (|a_q| + |b_q|) ρ_q
    /// (u the unit round-off), and the halved difference of the extremes rounds once more:
    /// computed ½ range ≤ (Σ_q √(a_q² + b_q²) ρ_q + 2(p + 1) u e)(1 + u). The factor
    /// 1 + 10⁻¹² covers that last rounding and the round-off of the bound itself (a few
    /// p u, p ≤ 201; [`modulus`] neither overflows nor underflows), and the smallest normal
    /// number the absolute round-off of values below the normal range. NaN when a
    /// coefficient is not finite, or infinite: never below a range. With the bound, its
    /// round-off term 2(p + 1) u e.
    fn range_bound(&self, c: &[f64]) -> (f64, f64) {
        let unit_round_off = f64::EPSILON / 2.0;
        let (mut amplitude, mut absolute) = (0.0, c.first().map_or(0.0, |a| a.abs()));
        for (pair, rho) in c[1..].chunks_exact(2).zip(&self.moduli) {
            let (a, b) = (pair[0], pair[1]);
            amplitude += modulus(a, b) * rho;
            absolute += (a.abs() + b.abs()) * rho;
        }
        let rounding = 2.0 * (c.len() + 1) as f64 * unit_round_off * absolute;
        let bound = (amplitude + rounding + f64::MIN_POSITIVE) * (1.0 + 1e-12);
        (bound, rounding)
    }

    /// ‖R v‖² = vᵀ BᵀB v: the sum of squares over the table's samples of the series
    /// with coefficients `v`.
    pub(super) fn norm_squared(&self, v: &[f64]) -> f64 {
        few::triangle_norm(&self.upper, v)
    }

    /// The least-squares coefficients of `x` into `c` (p of them), and the residual sum
    /// of squares of that fit, from sums instead of a pass over the fitted values: with s = x_0 (the shift
    /// of [`HarmonicTable::fit`], which keeps an offset out of the difference),
    /// ‖x − s 1‖² − ‖R (c − s e₀)‖², at least 0.
    pub(super) fn fit_and_residual(&self, x: &[f64], c: &mut [f64]) -> f64 {
        let total = fit_and_shifted_squares(&self.design, &self.r, x, c);
        let shift = x.first().copied().unwrap_or(0.0);
        // ‖R (c − s e₀)‖²: the constant's coefficient shifted back for the sum
        let Some(&a0) = c.first() else {
            return total;
        };
        c[0] = a0 - shift;
        let fitted = self.norm_squared(c);
        c[0] = a0;
        (total - fitted).max(0.0)
    }

    /// Σ_i (x_i − (B c)_i)² over the samples of `x`, summed in sample order.
    pub(super) fn residual_sum_of_squares(&self, coefficients: &[f64], x: &[f64]) -> f64 {
        let mut sum = 0.0;
        self.chunks(coefficients, x.len(), |start, fitted| {
            for (a, b) in x[start..start + fitted.len()].iter().zip(fitted) {
                let r = a - b;
                sum += r * r;
            }
        });
        sum
    }
}

impl HarmonicTable {
    /// (RᵀR)⁻¹ = R⁻¹R⁻ᵀ (not finite when the design is singular).
    pub(super) fn gram_inverse(&self) -> Mat<f64> {
        let p = self.columns();
        let mut r_inverse = Mat::<f64>::identity(p, p);
        self.r.solve_upper_triangular_in_place(r_inverse.as_mut());
        &r_inverse * r_inverse.transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The evaluation by chunks with zero coefficients skipped (and the ½ range and
    /// residual sum of squares from it) is bitwise one pass per column over all
    /// samples, at lengths with every remainder mod 4 and over several chunks.
    #[test]
    fn chunked_evaluation_is_bitwise_the_per_column_one() {
        for m in [8usize, 9, 10, 11, 13, 64, 101, 2 * CHUNK + 7] {
            let b: Vec<f64> = (0..m).map(|i| 1e3 + (i as f64 * 0.37).cos()).collect();
            let omega = 2.0 * std::f64::consts::PI / 7.3;
            let basis = HarmonicBasis::with_orders(omega, vec![1, 2, 3], 0.5, m).unwrap();
            let table = HarmonicTable::new(&basis, m);
            let coefficients = [0.3, -1.7, 0.0, 2.5e-3, 4.0, 0.0, -0.9];
            let mut fused = vec![0.0; m];
            table.chunks(&coefficients, m, |start, fitted| {
                fused[start..start + fitted.len()].copy_from_slice(fitted)
            });
            let mut alone = vec![0.0; m];
            for (k, &ck) in coefficients.iter().enumerate() {
                if ck != 0.0 {
                    for (y, b) in alone.iter_mut().zip(table.design.col_as_slice(k)) {
                        *y += ck * b;
                    }
                }
            }
            let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fused), bits(&alone), "m = {m}");
            let (lo, hi) = alone
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &y| {
                    (lo.min(y), hi.max(y))
                });
            let rss: f64 = b.iter().zip(&alone).map(|(a, y)| (a - y).powi(2)).sum();
            let (half, _) = table.half_ranges(&coefficients, &coefficients, m);
            assert_eq!(half.to_bits(), (0.5 * (hi - lo)).to_bits(), "m = {m}");
            // the second of the pair on its own terms: a zero where the first has none,
            // and none where the first has a zero
            let mut other: Vec<f64> = coefficients.iter().map(|c| -0.7 * c).collect();
            (other[0], other[2]) = (0.0, 1.25);
            let mut second = vec![0.0; m];
            for (k, &ck) in other.iter().enumerate() {
                if ck != 0.0 {
                    for (y, b) in second.iter_mut().zip(table.design.col_as_slice(k)) {
                        *y += ck * b;
                    }
                }
            }
            let (lo, hi) = second
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &y| {
                    (lo.min(y), hi.max(y))
                });
            let pair = table.half_ranges(&coefficients, &other, m);
            assert_eq!(pair.0.to_bits(), half.to_bits(), "m = {m}");
            assert_eq!(pair.1.to_bits(), (0.5 * (hi - lo)).to_bits(), "m = {m}");
            // each series on its own: the same bits as in the pair
            let [own] = extremes_on(&table.design, [&other], m);
            assert_eq!(own.to_bits(), pair.1.to_bits(), "m = {m}");
            let [own] = extremes_on(&table.design, [&coefficients], m);
            assert_eq!(own.to_bits(), pair.0.to_bits(), "m = {m}");
            let ours = table.residual_sum_of_squares(&coefficients, &b);
            assert_eq!(ours.to_bits(), rss.to_bits(), "m = {m}");
        }
    }

    /// The table's fit, residual and range equal HarmonicBasis::fit and a direct
    /// evaluation, on T/h not whole, with an offset.
    #[test]
    fn agrees_with_the_basis_fit() {
        let (h, period) = (0.1, 3.73);
        let omega = 2.0 * std::f64::consts::PI / period;
        let m = 75;
        let x = Mat::from_fn(m, 1, |i, _| {
            let t = i as f64 * h;
            1e3 + 0.5 * (omega * t).cos() - 0.2 * (3.0 * omega * t).sin()
                + 1e-3 * ((i * 7919) % 13) as f64
        });
        let basis = HarmonicBasis::with_orders(omega, vec![1, 2, 3], h, m).unwrap();
        let table = HarmonicTable::new(&basis, m);
        let xs = x.col_as_slice(0);
        let c = table.fit(xs);
        let reference = basis.fit(x.as_ref());
        for k in 0..7 {
            assert!(
                (c[k] - reference[(k, 0)]).abs() < 1e-11 * reference[(k, 0)].abs().max(1.0),
                "coefficient {k}: {} vs {}",
                c[k],
                reference[(k, 0)]
            );
        }
        let fitted = basis.design(m) * &reference;
        let rss: f64 = (0..m).map(|i| (xs[i] - fitted[(i, 0)]).powi(2)).sum();
        let ours = table.residual_sum_of_squares(&c, xs);
        assert!((ours - rss).abs() < 1e-6 * rss, "{ours} vs {rss}");
        let (lo, hi) = (0..m).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), i| {
            (l.min(fitted[(i, 0)]), u.max(fitted[(i, 0)]))
        });
        let (half, _) = table.half_ranges(&c, &c, m);
        assert!((half - 0.5 * (hi - lo)).abs() < 1e-12, "{half}");
    }

    /// The largest ½ ranges among many channels, evaluated on the channels whose bound
    /// can reach them, are bit for bit the largest of every channel's own; and every
    /// channel's computed ½ range is within its bound. Amplitudes spread over thirty
    /// decades about 1, over eighteen below the normal range and fifteen near overflow;
    /// offsets 10⁹ times the amplitude (where the evaluation's round-off dominates the
    /// range); ties and near ties at the top (a channel copied, or scaled by 1 + 10⁻¹⁵);
    /// zero channels; a harmonic four times the fundamental; all-zero periods.
    #[test]
    fn the_largest_half_ranges_are_every_channels_largest() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let m = 400;
        let omega = 2.0 * std::f64::consts::PI / (m as f64 * 0.25);
        let mut all_zero = 0;
        for (case, orders) in [vec![1], vec![1, 3], vec![1, 2, 5, 40]]
            .into_iter()
            .enumerate()
        {
            let basis = HarmonicBasis::with_orders(omega, orders.clone(), 0.25, m).unwrap();
            let table = HarmonicTable::new(&basis, m);
            let grid = RangeGrid::new(&basis, &table.design);
            let p = table.columns();
            for trial in 0..40 {
                let channels = 1 + rng.random_range(0..60);
                let mut states: Vec<(Vec<f64>, Vec<f64>)> = (0..channels)
                    .map(|_| {
                        // decades: below the normal range, about 1, near overflow
                        let decades = match trial % 4 {
                            0 => -318.0..-300.0,
                            3 => 280.0..295.0,
                            _ => -15.0..15.0_f64,
                        };
                        let scale = 10f64.powf(rng.random_range(decades));
                        let mut x: Vec<f64> = (0..p)
                            .map(|_| scale * rng.random_range(-1.0..1.0))
                            .collect();
                        if trial % 3 == 0 {
                            x[0] = 1e9 * scale;
                        }
                        let mut v: Vec<f64> = x.iter().map(|c| 3.0 * c).collect();
                        v[0] = 0.0;
                        v.swap(1, 2);
                        (x, v)
                    })
                    .collect();
                match trial % 5 {
                    0 if channels >= 2 => states[1] = states[0].clone(),
                    1 if channels >= 2 => {
                        states[1] = states[0].clone();
                        states[1].0.iter_mut().for_each(|c| *c *= 1.0 + 1e-15);
                    }
                    2 => states[0] = (vec![0.0; p], vec![0.0; p]),
                    3 if case == 2 => states[0].0[7] = 4.0 * states[0].0[1],
                    _ => {}
                }
                if trial == 39 {
                    states.iter_mut().for_each(|(x, v)| {
                        x.fill(0.0);
                        v.fill(0.0);
                    });
                }
                let every = states.iter().fold((0.0f64, 0.0f64), |(ax, av), (x, v)| {
                    let (hx, hv) = table.half_ranges(x, v, m);
                    let ([gx], [gv]) = (
                        extremes_on(&grid.design, [x], grid.design.nrows()),
                        extremes_on(&grid.design, [v], grid.design.nrows()),
                    );
                    let ((bx, rx), (bv, rv)) = (table.range_bound(x), table.range_bound(v));
                    assert!(hx <= bx, "{orders:?} trial {trial}");
                    assert!(hv <= bv, "{orders:?} trial {trial}");
                    let (ux, uv) = (grid.bound(x, gx, rx), grid.bound(v, gv, rv));
                    assert!(hx <= ux, "{orders:?} trial {trial}");
                    assert!(hv <= uv, "{orders:?} trial {trial}");
                    // and close to it for a smooth series of amplitudes about 1 without
                    // an offset: (Δ²/8) M₂ is 0.2 % of an amplitude per unit of q²
                    if case == 1 && trial % 4 == 1 && trial % 3 != 0 && hx > 0.0 {
                        assert!(ux <= 1.05 * hx, "{ux} vs {hx}: trial {trial}");
                    }
                    (ax.max(hx), av.max(hv))
                });
                let refs: Vec<(&[f64], &[f64])> = states
                    .iter()
                    .map(|(x, v)| (x.as_slice(), v.as_slice()))
                    .collect();
                for grid in [None, Some(&grid)] {
                    let largest = table.largest_half_ranges(&refs, m, grid);
                    assert_eq!(largest.0.to_bits(), every.0.to_bits(), "{orders:?} {trial}");
                    assert_eq!(largest.1.to_bits(), every.1.to_bits(), "{orders:?} {trial}");
                }
                all_zero += usize::from(every == (0.0, 0.0));
            }
        }
        assert!(all_zero >= 3, "the all-zero periods");
    }
}
