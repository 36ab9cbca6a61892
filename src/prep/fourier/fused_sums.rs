//! The sums of a fit on a harmonic design, several columns per pass over the samples:
//!
//! ```text
//!   s_k = Σ_i B_ik (x_i − s)   for the columns k of a group,   Σ_i (x_i − s)²   (the first pass),
//! ```
//!
//! each with sample i in partial sum i mod 16 and the partial sums added in lane order,
//! then the samples after the last whole sixteen in order: per lane the operations of
//! the one-column loop of `packed.rs` (x_i − s, a product, an add to the lane), so the
//! same bits as one pass per sum, at every level. A pass forms x_i − s once for all its
//! sums, where one pass per column forms it again for each: at AVX2 a group of three
//! columns costs two instructions per four samples and column, against four.
//!
//! The loops are written with the CPU's vector registers (`std::arch`), not left to the
//! compiler: it packed one sum per loop, but not several (it kept them in scalar or
//! two-lane registers). The group fills twelve of the sixteen registers of AVX2 (three
//! columns, or two with the squares) and eight to ten of AVX-512's thirty-two (four
//! columns with or without the squares). At the baseline level (SSE2) the sums are left
//! to `packed.rs`, one column per pass.

#[cfg(target_arch = "x86_64")]
use faer::Mat;

#[cfg(target_arch = "x86_64")]
use crate::terms::lanes::{LANES, combine};
#[cfg(target_arch = "x86_64")]
use crate::terms::simd::{self, Level};

/// Bᵀ(x − shift) into `out` (one sum per column of `design`, over its first x.len()
/// rows), and Σ_i (x_i − shift)² when `squares` (else 0), in passes of several columns
/// at the level of [`simd::level`]; `None`, with `out` untouched, at the baseline level
/// or off x86-64.
#[cfg(target_arch = "x86_64")]
pub(super) fn shifted_sums(
    design: &Mat<f64>,
    x: &[f64],
    shift: f64,
    out: &mut [f64],
    squares: bool,
) -> Option<f64> {
    let level = simd::level();
    match level {
        Level::Avx512 => Some(Passes::<4, 4>::run(design, x, shift, out, squares, level)),
        Level::Avx2 => Some(Passes::<3, 2>::run(design, x, shift, out, squares, level)),
        Level::Baseline => None,
    }
}

/// Off x86-64 the sums are `packed.rs`'s.
#[cfg(not(target_arch = "x86_64"))]
pub(super) fn shifted_sums(
    _: &faer::Mat<f64>,
    _: &[f64],
    _: f64,
    _: &mut [f64],
    _: bool,
) -> Option<f64> {
    None
}

/// Passes of `G` columns, the first of `F` columns and the squares.
#[cfg(target_arch = "x86_64")]
struct Passes<const G: usize, const F: usize>;

#[cfg(target_arch = "x86_64")]
impl<const G: usize, const F: usize> Passes<G, F> {
    fn run(
        design: &Mat<f64>,
        x: &[f64],
        shift: f64,
        out: &mut [f64],
        squares: bool,
        level: Level,
    ) -> f64 {
        let n = x.len();
        let (blocks, tail) = x.as_chunks::<LANES>();
        let whole = n - tail.len();
        let p = out.len();
        let pass = Pass {
            design,
            blocks,
            tail,
            whole,
            shift,
            level,
        };
        let mut k = 0;
        let mut total = 0.0;
        if squares {
            // the squares with the first columns (up to F of them)
            let first = p.min(F);
            total = match first {
                0 => pass.run::<0, true>(0, out),
                1 => pass.run::<1, true>(0, out),
                2 => pass.run::<2, true>(0, out),
                3 => pass.run::<3, true>(0, out),
                _ => pass.run::<4, true>(0, out),
            };
            k = first;
        }
        while p - k >= G {
            pass.run::<G, false>(k, out);
            k += G;
        }
        match p - k {
            0 => {}
            1 => {
                pass.run::<1, false>(k, out);
            }
            2 => {
                pass.run::<2, false>(k, out);
            }
            _ => {
                pass.run::<3, false>(k, out);
            }
        }
        total
    }
}

/// What every pass over one series reads.
#[cfg(target_arch = "x86_64")]
struct Pass<'a> {
    design: &'a Mat<f64>,
    /// The samples in whole blocks of [`LANES`].
    blocks: &'a [[f64; LANES]],
    /// The samples after the last whole block.
    tail: &'a [f64],
    /// The samples in whole blocks.
    whole: usize,
    shift: f64,
    level: Level,
}

#[cfg(target_arch = "x86_64")]
impl Pass<'_> {
    /// The sums of the `C` columns from column `k` into `out[k..k + C]`, and the
    /// squares' when `SQUARES` (else 0): one pass over the samples.
    fn run<const C: usize, const SQUARES: bool>(&self, k: usize, out: &mut [f64]) -> f64 {
        let n = self.whole + self.tail.len();
        let columns: [&[f64]; C] = std::array::from_fn(|g| &self.design.col_as_slice(k + g)[..n]);
        // (as long as the samples' blocks: no bounds check in the loop)
        let blocks = columns.map(|c| &c.as_chunks::<LANES>().0[..self.blocks.len()]);
        let (lanes, squares) = match self.level {
            // SAFETY: `shifted_sums` passes Avx512 only when `simd::level` found the CPU
            // has every feature the function enables.
            Level::Avx512 => unsafe {
                lanes_in_avx512::<C, SQUARES>(blocks, self.blocks, self.shift)
            },
            // SAFETY: as above, for AVX2.
            _ => unsafe { lanes_in_avx2::<C, SQUARES>(blocks, self.blocks, self.shift) },
        };
        let shift = self.shift;
        for ((out, lanes), column) in out[k..k + C].iter_mut().zip(lanes).zip(columns) {
            let rest: f64 = column[self.whole..]
                .iter()
                .zip(self.tail)
                .map(|(c, y)| c * (y - shift))
                .sum();
            *out = combine(lanes) + rest;
        }
        if SQUARES {
            let rest: f64 = self.tail.iter().map(|x| (x - shift) * (x - shift)).sum();
            combine(squares) + rest
        } else {
            0.0
        }
    }
}

/// A vector register of `WIDTH` doubles and the operations of a pass.
#[cfg(target_arch = "x86_64")]
trait Register: Copy {
    const WIDTH: usize;
    /// Every lane `value`.
    fn splat(value: f64) -> Self;
    /// The `WIDTH` values from `values`.
    fn load(values: &[f64]) -> Self;
    fn sub(self, other: Self) -> Self;
    fn mul(self, other: Self) -> Self;
    fn add(self, other: Self) -> Self;
    /// Its lanes into `values`.
    fn store(self, values: &mut [f64]);
}

#[cfg(target_arch = "x86_64")]
mod registers {
    use std::arch::x86_64::*;

    use super::Register;

    // Each method is compiled inside a function that enables the register's features
    // (`lanes_in_avx2`, `lanes_in_avx512`), into which it is inlined; `load` and `store`
    // check the length (a slice of exactly WIDTH values is what every caller passes).

    impl Register for __m256d {
        const WIDTH: usize = 4;
        #[inline(always)]
        fn splat(value: f64) -> Self {
            // SAFETY: called only inside `lanes_in_avx2`, which enables AVX2.
            unsafe { _mm256_set1_pd(value) }
        }
        #[inline(always)]
        fn load(values: &[f64]) -> Self {
            let values = &values[..4];
            // SAFETY: four readable doubles; AVX2 as for `splat`.
            unsafe { _mm256_loadu_pd(values.as_ptr()) }
        }
        #[inline(always)]
        fn sub(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm256_sub_pd(self, other) }
        }
        #[inline(always)]
        fn mul(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm256_mul_pd(self, other) }
        }
        #[inline(always)]
        fn add(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm256_add_pd(self, other) }
        }
        #[inline(always)]
        fn store(self, values: &mut [f64]) {
            let values = &mut values[..4];
            // SAFETY: four writable doubles; AVX2 as for `splat`.
            unsafe { _mm256_storeu_pd(values.as_mut_ptr(), self) }
        }
    }

    impl Register for __m512d {
        const WIDTH: usize = 8;
        #[inline(always)]
        fn splat(value: f64) -> Self {
            // SAFETY: called only inside `lanes_in_avx512`, which enables AVX-512 F.
            unsafe { _mm512_set1_pd(value) }
        }
        #[inline(always)]
        fn load(values: &[f64]) -> Self {
            let values = &values[..8];
            // SAFETY: eight readable doubles; AVX-512 as for `splat`.
            unsafe { _mm512_loadu_pd(values.as_ptr()) }
        }
        #[inline(always)]
        fn sub(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm512_sub_pd(self, other) }
        }
        #[inline(always)]
        fn mul(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm512_mul_pd(self, other) }
        }
        #[inline(always)]
        fn add(self, other: Self) -> Self {
            // SAFETY: as for `splat`.
            unsafe { _mm512_add_pd(self, other) }
        }
        #[inline(always)]
        fn store(self, values: &mut [f64]) {
            let values = &mut values[..8];
            // SAFETY: eight writable doubles; AVX-512 as for `splat`.
            unsafe { _mm512_storeu_pd(values.as_mut_ptr(), self) }
        }
    }
}

/// The partial sums (lane l of register r is partial sum r·WIDTH + l) of the `C`
/// columns' products and of the squares over the whole blocks: per lane
/// d = x_i − shift, then lane + c_i d (and lane + d d), in the order of the blocks.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn lanes_of<V: Register, const C: usize, const SQUARES: bool>(
    columns: [&[[f64; LANES]]; C],
    samples: &[[f64; LANES]],
    shift: f64,
) -> ([[f64; LANES]; C], [f64; LANES]) {
    // (as long as the samples, which lets the compiler drop the bounds checks)
    let columns = columns.map(|c| &c[..samples.len()]);
    // registers per block of LANES (4 for AVX2, 2 for AVX-512), at most 4
    let per = LANES / V::WIDTH;
    let zero = V::splat(0.0);
    let s = V::splat(shift);
    let mut sums = [[zero; 4]; C];
    let mut squares = [zero; 4];
    for (i, x) in samples.iter().enumerate() {
        for r in 0..per {
            let at = r * V::WIDTH..(r + 1) * V::WIDTH;
            let d = V::load(&x[at.clone()]).sub(s);
            if SQUARES {
                squares[r] = squares[r].add(d.mul(d));
            }
            for (sums, column) in sums.iter_mut().zip(&columns) {
                sums[r] = sums[r].add(V::load(&column[i][at.clone()]).mul(d));
            }
        }
    }
    let mut lanes = [[0.0; LANES]; C];
    for (lanes, sums) in lanes.iter_mut().zip(&sums) {
        for r in 0..per {
            sums[r].store(&mut lanes[r * V::WIDTH..(r + 1) * V::WIDTH]);
        }
    }
    let mut square_lanes = [0.0; LANES];
    for r in 0..per {
        squares[r].store(&mut square_lanes[r * V::WIDTH..(r + 1) * V::WIDTH]);
    }
    (lanes, square_lanes)
}

/// [`lanes_of`] in AVX2 registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn lanes_in_avx2<const C: usize, const SQUARES: bool>(
    columns: [&[[f64; LANES]]; C],
    samples: &[[f64; LANES]],
    shift: f64,
) -> ([[f64; LANES]; C], [f64; LANES]) {
    lanes_of::<std::arch::x86_64::__m256d, C, SQUARES>(columns, samples, shift)
}

/// [`lanes_of`] in AVX-512 registers (the features of [`simd::Level::Avx512`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(
    enable = "avx512f,avx512bw,avx512cd,avx512dq,avx512vl,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
)]
fn lanes_in_avx512<const C: usize, const SQUARES: bool>(
    columns: [&[[f64; LANES]]; C],
    samples: &[[f64; LANES]],
    shift: f64,
) -> ([[f64; LANES]; C], [f64; LANES]) {
    lanes_of::<std::arch::x86_64::__m512d, C, SQUARES>(columns, samples, shift)
}

/// The sums and the squares of [`shifted_sums`] at every level with passes the CPU has
/// (for the tests: `packed.rs` compares them with plain sums).
#[cfg(test)]
pub(super) fn every_level(
    design: &faer::Mat<f64>,
    x: &[f64],
    shift: f64,
    squares: bool,
) -> Vec<(crate::terms::simd::Level, Vec<f64>, f64)> {
    #[cfg(target_arch = "x86_64")]
    {
        let p = design.ncols();
        let mut found = Vec::new();
        if Level::Avx512.available() {
            let mut sums = vec![0.0; p];
            let total = Passes::<4, 4>::run(design, x, shift, &mut sums, squares, Level::Avx512);
            found.push((Level::Avx512, sums, total));
        }
        if Level::Avx2.available() {
            let mut sums = vec![0.0; p];
            let total = Passes::<3, 2>::run(design, x, shift, &mut sums, squares, Level::Avx2);
            found.push((Level::Avx2, sums, total));
        }
        found
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (design, x, shift, squares);
        Vec::new()
    }
}
