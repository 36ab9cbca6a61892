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

use super::fused_sums::shifted_sums;
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

/// c ← (RᵀR)⁻¹ c in place: Rᵀ y = c, then R c = y (R upper triangular, p × p):
///
/// ```text
///   y_i = (c_i − Σ_{k<i} R_ki y_k) / R_ii   (i ascending),
///   c_i = (y_i − Σ_{k>i} R_ik c_k) / R_ii   (i descending),
/// ```
///
/// each sum subtracted term by term in the order of k. Unrolled for p = 3, 5, 7, 9 and
/// 11 (one to five harmonics) on a copy of R's columns, where a loop of a few turns
/// costs more in its setup and bounds checks than in its products: the same operations
/// in the same order, so the same bits.
fn solve_factored(r: &Mat<f64>, c: &mut [f64]) {
    match c.len() {
        3 => solve_of::<3>(r, c),
        5 => solve_of::<5>(r, c),
        7 => solve_of::<7>(r, c),
        9 => solve_of::<9>(r, c),
        11 => solve_of::<11>(r, c),
        _ => solve_any(r, c),
    }
}

/// [`solve_factored`] for p = `P`.
#[inline(always)]
fn solve_of<const P: usize>(r: &Mat<f64>, c: &mut [f64]) {
    // columns[k][i] = R_ik
    let mut columns = [[0.0f64; P]; P];
    for (k, column) in columns.iter_mut().enumerate() {
        column.copy_from_slice(&r.col_as_slice(k)[..P]);
    }
    let c = &mut c[..P];
    for i in 0..P {
        let mut s = c[i];
        for k in 0..i {
            s -= columns[i][k] * c[k];
        }
        c[i] = s / columns[i][i];
    }
    for i in (0..P).rev() {
        let mut s = c[i];
        for k in i + 1..P {
            s -= columns[k][i] * c[k];
        }
        c[i] = s / columns[i][i];
    }
}

/// [`solve_factored`] for any p.
fn solve_any(r: &Mat<f64>, c: &mut [f64]) {
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
    fit_with_squares(design, r, x, &mut c, false);
    c
}

/// [`fit_on_design`] into `c` (one value per column of `design`), and Σ_i (x_i − x₀)²
/// (x₀ the first sample, the fit's shift) in the same passes over the samples.
pub(crate) fn fit_and_shifted_squares(
    design: &Mat<f64>,
    r: &Mat<f64>,
    x: &[f64],
    c: &mut [f64],
) -> f64 {
    fit_with_squares(design, r, x, c, true)
}

/// The fit into `c`, and Σ_i (x_i − x₀)² when `squares` (else 0): the sums several
/// columns per pass where the CPU has AVX2 or AVX-512 (`fused_sums.rs`), else one
/// column per pass here, the same bits either way.
fn fit_with_squares(
    design: &Mat<f64>,
    r: &Mat<f64>,
    x: &[f64],
    c: &mut [f64],
    squares: bool,
) -> f64 {
    let shift = x.first().copied().unwrap_or(0.0);
    let total = match shifted_sums(design, x, shift, c, squares) {
        Some(total) => total,
        None => {
            simd::dispatch(Projections {
                design,
                x,
                shift,
                out: c,
            });
            if squares {
                simd::dispatch(ShiftedSquares { x, shift })
            } else {
                0.0
            }
        }
    };
    solve_factored(r, c);
    if let Some(a0) = c.first_mut() {
        *a0 += shift;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed sums are bitwise the plain ones: Bᵀ(x − s 1) and Σ (x − s)² at the
    /// CPU's level, one column per pass and several (`fused_sums.rs`, at each level the
    /// CPU has), against sixteen partial sums in plain Rust (sample i in sum i mod 16,
    /// the sums in lane order, then the tail), at lengths with every remainder mod 16,
    /// on designs of 0 to 10 columns (whole groups per pass and every remainder) with
    /// more rows than the samples fitted, with and without the squares.
    #[test]
    fn packed_sums_are_bitwise_the_plain_ones() {
        for m in [1usize, 8, 15, 16, 17, 31, 64, 101, 263] {
            let b: Vec<f64> = (0..m).map(|i| 1e3 + (i as f64 * 0.37).cos()).collect();
            let shift = b[0];
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
            let squares = plain(&|i| (b[i] - shift) * (b[i] - shift));
            let one_per_pass = simd::dispatch(ShiftedSquares { x: &b, shift });
            assert_eq!(one_per_pass.to_bits(), squares.to_bits(), "m = {m}");
            let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
            for p in 0..=10 {
                let design = Mat::from_fn(m + 3, p, |i, c| {
                    ((i * (c + 3)) as f64 * 0.731 + c as f64).sin() * 10f64.powi(c as i32 - 2)
                });
                let expected: Vec<u64> = (0..p)
                    .map(|c| plain(&|i| design[(i, c)] * (b[i] - shift)).to_bits())
                    .collect();
                let mut packed = vec![0.0; p];
                simd::dispatch(Projections {
                    design: &design,
                    x: &b,
                    shift,
                    out: &mut packed,
                });
                assert_eq!(bits(&packed), expected, "m = {m}, {p} columns");
                for with_squares in [false, true] {
                    let levels =
                        super::super::fused_sums::every_level(&design, &b, shift, with_squares);
                    for (level, sums, total) in levels {
                        let what = format!("{level:?}, m = {m}, {p} columns, {with_squares}");
                        assert_eq!(bits(&sums), expected, "{what}");
                        let squares = if with_squares { squares } else { 0.0 };
                        assert_eq!(total.to_bits(), squares.to_bits(), "{what}");
                    }
                }
            }
        }
    }

    /// The unrolled solves are bit for bit the loop, for p = 1 to 13 on a random upper
    /// triangle with values over twenty decades.
    #[test]
    fn the_unrolled_solves_are_the_loop() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        let mut next = || {
            let value = 10f64.powf(rng.random_range(-10.0..10.0));
            if rng.random_bool(1.0 / 3.0) {
                -value
            } else {
                value
            }
        };
        for p in 1..=13 {
            for _ in 0..20 {
                let r = Mat::from_fn(p + 2, p, |i, k| if i <= k { next() } else { 0.0 });
                let c: Vec<f64> = (0..p).map(|_| next()).collect();
                let (mut ours, mut theirs) = (c.clone(), c.clone());
                solve_factored(&r, &mut ours);
                solve_any(&r, &mut theirs);
                let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&ours), bits(&theirs), "p = {p}");
            }
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
