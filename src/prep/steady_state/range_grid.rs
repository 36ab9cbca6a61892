//! A bound on the computed ½ range of a harmonic series over a period's samples from a
//! coarse grid of them, to skip the channels whose range cannot be the largest
//! (`table.rs`, `HarmonicTable::largest_half_ranges`).
//!
//! For y(t) = a₀ + Σ_q (a_q cos qωt + b_q sin qωt) on [0, (N − 1)h], with a grid of
//! every g-th sample and the last (spacing at most Δ = g h): at an interior maximum t*,
//! y'(t*) = 0, and a grid point t_s lies within Δ/2 of it, so by Taylor
//!
//! ```text
//!   max_t y ≤ max_s y(t_s) + (Δ²/8) M₂,   M₂ = Σ_q (qω)² √(a_q² + b_q²)  ≥ max |y''|,
//! ```
//!
//! (at a maximum on the interval's ends t* is itself a grid point), and the same for the
//! minimum. A value computed on the table, ŷ_i = Σ_k c_k B_ik, is within
//!
//! ```text
//!   E = γ_p Σ_k |c_k B_ik| + δ Σ_k |c_k| ≤ 2(p + 1) u e + δ Σ_k |c_k|
//! ```
//!
//! of y(t_i) (u the unit round-off, e = |a₀| + Σ_q (|a_q| + |b_q|) ρ_q as in
//! `HarmonicTable::range_bound`, δ the table's largest deviation from the exact basis
//! functions, measured here against `sin_cos` and widened for its error and that of
//! its argument), so
//!
//! ```text
//!   computed ½ range ≤ (½ (max_s ŷ_s − min_s ŷ_s) + (Δ²/8) M₂ + 2E)(1 + 10⁻¹²) + ε_min,
//! ```
//!
//! the factor covering the roundings of the halved difference and of the bound itself,
//! ε_min (the smallest normal number) the absolute round-off below the normal range. The
//! bound costs 1/g of an evaluation and exceeds the range by about (Δ²/8) M₂ (0.2 % of
//! the fundamental's amplitude for N = 400, g = 8), where the bound by amplitudes alone
//! exceeds it by the higher harmonics' amplitudes.

use faer::Mat;

use crate::prep::fourier::HarmonicBasis;

/// √(a² + b²) within about 2u of its value (u the unit round-off): the plain formula
/// where the sum of the squares is finite and far above the bottom of the normal range
/// (a square that underflows is then below the sum's round-off), `hypot` elsewhere
/// (which neither overflows nor underflows, and costs several times more). The bounds
/// of this module and `HarmonicTable::range_bound` carry a factor 1 + 10⁻¹² for such
/// round-off.
pub(super) fn modulus(a: f64, b: f64) -> f64 {
    let squares = a * a + b * b;
    if squares.is_finite() && squares >= 1e-290 {
        squares.sqrt()
    } else {
        a.hypot(b)
    }
}

/// Samples between grid points.
const GRID: usize = 8;

/// The design of a table at every [`GRID`]-th sample and the last, and what the bound
/// adds to the grid's ½ range (module doc).
pub(super) struct RangeGrid {
    /// B at the grid's samples (grid rows × p).
    pub(super) design: Mat<f64>,
    /// (Δ²/8)(qω)² per harmonic of the design.
    curvature: Vec<f64>,
    /// δ, the table's largest deviation from the exact basis functions.
    deviation: f64,
}

impl RangeGrid {
    /// The grid of `design` (the table of `basis` over its rows).
    pub(super) fn new(basis: &HarmonicBasis, design: &Mat<f64>) -> Self {
        let (rows, p) = (design.nrows(), design.ncols());
        let mut at: Vec<usize> = (0..rows).step_by(GRID).collect();
        if rows > 0 && at.last() != Some(&(rows - 1)) {
            at.push(rows - 1);
        }
        let grid = Mat::from_fn(at.len(), p, |s, k| design[(at[s], k)]);
        let (omega, step) = (basis.omega(), basis.step());
        let spacing = GRID as f64 * step;
        let curvature = basis
            .orders()
            .iter()
            .map(|&q| spacing * spacing / 8.0 * (q as f64 * omega).powi(2))
            .collect();
        // δ: each entry against sin_cos of its angle, which is within an ulp of the exact
        // value at the rounded angle; the angle's own rounding (three operations, each
        // within u of its result) moves a sine or cosine by at most 4u |angle|
        let unit = f64::EPSILON / 2.0;
        let mut deviation = (0..rows).fold(0.0f64, |d, i| d.max((design[(i, 0)] - 1.0).abs()));
        for (h, &q) in basis.orders().iter().enumerate() {
            for i in 0..rows {
                let angle = q as f64 * omega * (i as f64 * step);
                let (s, c) = angle.sin_cos();
                let off = (design[(i, 2 * h + 1)] - c)
                    .abs()
                    .max((design[(i, 2 * h + 2)] - s).abs());
                deviation = deviation.max(off + 4.0 * unit * (1.0 + angle.abs()));
            }
        }
        RangeGrid {
            design: grid,
            curvature,
            deviation,
        }
    }

    /// The bound on the computed ½ range over the table's samples of the series with
    /// coefficients `c`, whose computed ½ range over the grid is `grid_half_range` and
    /// whose round-off term is `rounding` (2(p + 1) u e, `HarmonicTable::range_bound`).
    /// Infinite or NaN when a term overflows or a coefficient is not finite: never below
    /// a range.
    pub(super) fn bound(&self, c: &[f64], grid_half_range: f64, rounding: f64) -> f64 {
        let mut curvature = 0.0;
        let mut absolute = c.first().map_or(0.0, |a| a.abs());
        for (pair, k) in c[1..].chunks_exact(2).zip(&self.curvature) {
            let (a, b) = (pair[0], pair[1]);
            curvature += modulus(a, b) * k;
            absolute += a.abs() + b.abs();
        }
        let error = rounding + self.deviation * absolute;
        (grid_half_range + curvature + 2.0 * error + f64::MIN_POSITIVE) * (1.0 + 1e-12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The modulus is within 2.5u of hypot's (itself within an ulp of the exact value)
    /// from below the normal range to near overflow, across the switch between the
    /// two formulas, with signed zeros, infinities and NaN as hypot gives them.
    #[test]
    fn the_modulus_is_hypot_to_round_off() {
        let unit = f64::EPSILON / 2.0;
        for ea in (-320..=305).step_by(5) {
            for eb in [-320, -160, -146, -145, -100, 0, 100, 150, 154, 155, 305] {
                for (sa, sb) in [(1.0, 1.0), (-1.3, 0.7), (0.9, -1.7)] {
                    let (a, b) = (sa * 10f64.powi(ea), sb * 10f64.powi(eb));
                    let (ours, theirs) = (modulus(a, b), a.hypot(b));
                    assert!(
                        (ours - theirs).abs() <= 2.5 * unit * theirs,
                        "{a:e}, {b:e}: {ours:e} vs {theirs:e}"
                    );
                }
            }
        }
        for (a, b) in [
            (0.0, -0.0),
            (f64::INFINITY, 1.0),
            (f64::NAN, f64::INFINITY),
            (f64::NAN, 1.0),
        ] {
            assert_eq!(modulus(a, b).to_bits(), a.hypot(b).to_bits(), "{a}, {b}");
        }
    }
}
