//! The least-squares coefficients of one channel on a harmonic design held column by
//! column (m × p, t_i = i h), in packed sums:
//!
//! ```text
//!   c = (RᵀR)⁻¹ Bᵀ(x − s 1) + s e₀,   s = x₀   (RᵀR = BᵀB: two triangular solves),
//! ```
//!
//! the shift by the first sample keeping a large offset out of the sums (a constant
//! signal gives exactly zero harmonics). Each entry of Bᵀ(x − s 1) is one pass over a
//! design column and the samples, both in L1 for a period or a window of a few
//! thousand samples, with sample i in partial sum i mod 16 and the partial sums added
//! in lane order: the loop compiles to packed multiplies and adds at every level of
//! [`simd::dispatch`] (AVX-512, AVX2, SSE2), each lane doing the same operations, so
//! the same bits at every level. Shared by the steady-state check's periods
//! (`steady_state/table.rs`) and the noise-robust rows' windows
//! (`regressor/robust/projected.rs`).

use faer::Mat;

use crate::terms::lanes::{LANES as SUM_LANES, combine};
use crate::terms::simd::{self, Kernel};

/// Σ_i a_i (b_i − shift) with sample i in partial sum i mod [`SUM_LANES`] and the partial
/// sums added in lane order (the loop the compiler turns into packed multiplies and
/// adds at every level of [`simd::dispatch`], each lane doing the same operations: the
/// same bits at every level), then the tail in order.
#[inline(always)]
fn dot_shifted(a: &[f64], b: &[f64], shift: f64) -> f64 {
    let mut lanes = [0.0f64; SUM_LANES];
    let mut a_chunks = a.chunks_exact(SUM_LANES);
    let mut b_chunks = b[..a.len()].chunks_exact(SUM_LANES);
    for (x, y) in (&mut a_chunks).zip(&mut b_chunks) {
        for k in 0..SUM_LANES {
            lanes[k] += x[k] * (y[k] - shift);
        }
    }
    let tail: f64 = a_chunks
        .remainder()
        .iter()
        .zip(b_chunks.remainder())
        .map(|(x, y)| x * (y - shift))
        .sum();
    combine(lanes) + tail
}

/// c ← (RᵀR)⁻¹ c in place: Rᵀ y = c, then R c = y (R upper triangular, p × p).
fn solve_factored(r: &Mat<f64>, c: &mut [f64]) {
    let p = c.len();
    for i in 0..p {
        let mut s = c[i];
        for k in 0..i {
            s -= r[(k, i)] * c[k];
        }
        c[i] = s / r[(i, i)];
    }
    for i in (0..p).rev() {
        let mut s = c[i];
        for k in i + 1..p {
            s -= r[(i, k)] * c[k];
        }
        c[i] = s / r[(i, i)];
    }
}

/// Bᵀ(x − shift) into `out`, a column at a time ([`dot_shifted`]), compiled for the
/// widest instruction set the CPU has.
struct Projections<'a> {
    design: &'a Mat<f64>,
    x: &'a [f64],
    shift: f64,
    out: &'a mut [f64],
}

impl Kernel for Projections<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (k, out) in self.out.iter_mut().enumerate() {
            let column = &self.design.col_as_slice(k)[..self.x.len()];
            *out = dot_shifted(column, self.x, self.shift);
        }
    }
}

/// Σ_i (x_i − shift)² in the lanes of [`dot_shifted`], compiled for the widest
/// instruction set the CPU has.
struct ShiftedSquares<'a> {
    x: &'a [f64],
    shift: f64,
}

impl Kernel for ShiftedSquares<'_> {
    type Output = f64;
    #[inline(always)]
    fn run(self) -> f64 {
        let shift = self.shift;
        let mut lanes = [0.0f64; SUM_LANES];
        let mut chunks = self.x.chunks_exact(SUM_LANES);
        for x in &mut chunks {
            for k in 0..SUM_LANES {
                let d = x[k] - shift;
                lanes[k] += d * d;
            }
        }
        let tail: f64 = chunks
            .remainder()
            .iter()
            .map(|x| (x - shift) * (x - shift))
            .sum();
        combine(lanes) + tail
    }
}

/// The coefficients of `x` on the first x.len() rows of `design`, whose R is `r`
/// (module doc).
pub(crate) fn fit_on_design(design: &Mat<f64>, r: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; design.ncols()];
    fit_on_design_into(design, r, x, &mut c);
    c
}

/// [`fit_on_design`] into `c` (one value per column of `design`).
pub(crate) fn fit_on_design_into(design: &Mat<f64>, r: &Mat<f64>, x: &[f64], c: &mut [f64]) {
    let shift = x.first().copied().unwrap_or(0.0);
    simd::dispatch(Projections {
        design,
        x,
        shift,
        out: c,
    });
    solve_factored(r, c);
    if let Some(a0) = c.first_mut() {
        *a0 += shift;
    }
}

/// Σ_i (x_i − shift)² in the lanes of the fit's sums (a second pass over samples in L1:
/// fused into the fit's first pass it kept the compiler from packing either).
pub(crate) fn shifted_squares(x: &[f64], shift: f64) -> f64 {
    simd::dispatch(ShiftedSquares { x, shift })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed sums are bitwise the plain ones: Bᵀ(x − s 1) and Σ (x − s)² at the
    /// CPU's level against sixteen partial sums in plain Rust (sample i in sum i mod 16,
    /// the sums in lane order, then the tail), at lengths with every remainder mod 16,
    /// on a design with more rows than the samples fitted.
    #[test]
    fn packed_sums_are_bitwise_the_plain_ones() {
        for m in [1usize, 8, 15, 16, 17, 31, 64, 101, 263] {
            let design = Mat::from_fn(m + 3, 4, |i, c| {
                ((i * (c + 3)) as f64 * 0.731 + c as f64).sin() * 10f64.powi(c as i32 - 2)
            });
            let b: Vec<f64> = (0..m).map(|i| 1e3 + (i as f64 * 0.37).cos()).collect();
            let shift = b[0];
            let mut packed = [0.0; 4];
            simd::dispatch(Projections {
                design: &design,
                x: &b,
                shift,
                out: &mut packed,
            });
            let plain = |term: &dyn Fn(usize) -> f64| {
                let mut lanes = [0.0f64; SUM_LANES];
                let whole = m - m % SUM_LANES;
                for i in 0..whole {
                    lanes[i % SUM_LANES] += term(i);
                }
                let mut total = 0.0;
                for lane in lanes {
                    total += lane;
                }
                total + (whole..m).map(term).sum::<f64>()
            };
            for c in 0..4 {
                let alone = plain(&|i| design[(i, c)] * (b[i] - shift));
                assert_eq!(packed[c].to_bits(), alone.to_bits(), "m = {m}, column {c}");
            }
            let alone = plain(&|i| (b[i] - shift) * (b[i] - shift));
            assert_eq!(
                shifted_squares(&b, shift).to_bits(),
                alone.to_bits(),
                "m = {m}"
            );
        }
    }

    /// The fit reproduces a series on its basis: the coefficients of
    /// 4 + 0.5 cos ωt − 2 sin 3ωt on [1, cos, sin, cos 3, sin 3] to round-off, a large
    /// offset included.
    #[test]
    fn fits_a_series_on_its_basis() {
        let (omega, step, m) = (2.0 * std::f64::consts::PI / 40.0, 1.0, 40);
        let basis =
            crate::prep::fourier::HarmonicBasis::with_orders(omega, vec![1, 3], step, m).unwrap();
        let design = basis.design(m);
        let r = basis.r_factor();
        for offset in [0.0, 1e6] {
            let x: Vec<f64> = (0..m)
                .map(|i| {
                    let t = i as f64 * step;
                    offset + 4.0 + 0.5 * (omega * t).cos() - 2.0 * (3.0 * omega * t).sin()
                })
                .collect();
            let c = fit_on_design(&design, &r, &x);
            let expected = [offset + 4.0, 0.5, 0.0, 0.0, -2.0];
            for (a, b) in c.iter().zip(expected) {
                assert!((a - b).abs() <= 1e-9 * (1.0 + offset), "{c:?}");
            }
        }
    }
}
