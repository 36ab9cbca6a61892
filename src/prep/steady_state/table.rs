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
//! matrix of fitted values.

use faer::Mat;

use crate::prep::fourier::HarmonicBasis;

/// The design columns and R of a harmonic basis over `samples` samples.
pub(super) struct HarmonicTable {
    /// B, m × p (column-major: each column contiguous).
    design: Mat<f64>,
    /// R (upper triangular, p × p), RᵀR = BᵀB.
    pub(super) r: Mat<f64>,
}

/// Σ_i a_i (b_i − shift), in four interleaved partial sums (vectorisable).
fn dot_shifted(a: &[f64], b: &[f64], shift: f64) -> f64 {
    let mut acc = [0.0f64; 4];
    let (a4, a_rest) = a.split_at(a.len() - a.len() % 4);
    let (b4, b_rest) = b.split_at(a4.len());
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for l in 0..4 {
            acc[l] += x[l] * (y[l] - shift);
        }
    }
    let tail: f64 = a_rest
        .iter()
        .zip(b_rest)
        .map(|(x, y)| x * (y - shift))
        .sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// [`dot_shifted`] of four columns `a` against one `b`, each sum bitwise the one
/// `dot_shifted(a[c], b, shift)` gives (the same four partial sums, tail and order),
/// with `b` read once.
fn dots_shifted(a: [&[f64]; 4], b: &[f64], shift: f64) -> [f64; 4] {
    // The columns' length decides the split, as in `dot_shifted`.
    let n = a[0].len();
    let whole = n - n % 4;
    let [a0, a1, a2, a3] = a.map(|column| &column[..whole]);
    let mut acc = [[0.0f64; 4]; 4];
    for ((((y, x0), x1), x2), x3) in b[..whole]
        .chunks_exact(4)
        .zip(a0.chunks_exact(4))
        .zip(a1.chunks_exact(4))
        .zip(a2.chunks_exact(4))
        .zip(a3.chunks_exact(4))
    {
        for l in 0..4 {
            let d = y[l] - shift;
            acc[0][l] += x0[l] * d;
            acc[1][l] += x1[l] * d;
            acc[2][l] += x2[l] * d;
            acc[3][l] += x3[l] * d;
        }
    }
    let mut out = [0.0; 4];
    for ((o, column), sums) in out.iter_mut().zip(a).zip(acc) {
        let tail: f64 = column[whole..]
            .iter()
            .zip(&b[whole..])
            .map(|(x, y)| x * (y - shift))
            .sum();
        *o = (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail;
    }
    out
}

impl HarmonicTable {
    /// The table of `basis` over its `samples` samples.
    pub(super) fn new(basis: &HarmonicBasis, samples: usize) -> Self {
        HarmonicTable {
            design: basis.design(samples),
            r: basis.r_factor(),
        }
    }

    /// p.
    pub(super) fn columns(&self) -> usize {
        self.design.ncols()
    }

    /// The least-squares coefficients of the samples `x` (m of them): module doc.
    pub(super) fn fit(&self, x: &[f64]) -> Vec<f64> {
        let p = self.columns();
        let shift = x.first().copied().unwrap_or(0.0);
        let mut c = vec![0.0; p];
        // Four columns per pass over x: each sum is bitwise the one `dot_shifted`
        // gives alone (the same operations in the same order), with x read once per
        // four columns instead of once per column.
        let mut k = 0;
        while k + 4 <= p {
            let columns = [0, 1, 2, 3].map(|l| self.design.col_as_slice(k + l));
            c[k..k + 4].copy_from_slice(&dots_shifted(columns, x, shift));
            k += 4;
        }
        for (k, ck) in c.iter_mut().enumerate().skip(k) {
            *ck = dot_shifted(self.design.col_as_slice(k), x, shift);
        }
        // Rᵀ y = Bᵀx', then R c = y.
        let r = &self.r;
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
        if let Some(a0) = c.first_mut() {
            *a0 += shift;
        }
        c
    }

    /// ŷ = B c at the first `out.len()` samples, into `out`.
    pub(super) fn evaluate(&self, coefficients: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        // The nonzero terms added in order, up to four per pass over `out`: each ŷ_i
        // takes the same additions in the same order as one pass per column, so it is
        // bitwise the same, with `out` read and written once per four columns.
        let n = out.len();
        let terms: Vec<(f64, &[f64])> = coefficients
            .iter()
            .enumerate()
            .filter(|(_, ck)| **ck != 0.0)
            .map(|(k, &ck)| (ck, &self.design.col_as_slice(k)[..n]))
            .collect();
        for group in terms.chunks(4) {
            match group {
                [(c0, b0), (c1, b1), (c2, b2), (c3, b3)] => {
                    // Slices of exactly n let the loop run without bounds checks.
                    let (b0, b1, b2, b3) = (&b0[..n], &b1[..n], &b2[..n], &b3[..n]);
                    for i in 0..n {
                        let mut sum = out[i];
                        sum += c0 * b0[i];
                        sum += c1 * b1[i];
                        sum += c2 * b2[i];
                        sum += c3 * b3[i];
                        out[i] = sum;
                    }
                }
                _ => {
                    for (ck, column) in group {
                        for (y, b) in out.iter_mut().zip(column.iter()) {
                            *y += ck * b;
                        }
                    }
                }
            }
        }
    }

    /// ½ (max − min) of B c over the first `buffer.len()` samples.
    pub(super) fn half_range(&self, coefficients: &[f64], buffer: &mut [f64]) -> f64 {
        self.evaluate(coefficients, buffer);
        let (lo, hi) = buffer
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &y| {
                (lo.min(y), hi.max(y))
            });
        0.5 * (hi - lo)
    }

    /// Σ_i (x_i − (B c)_i)² over the samples of `x`, with `buffer` (as long as `x`).
    pub(super) fn residual_sum_of_squares(
        &self,
        coefficients: &[f64],
        x: &[f64],
        buffer: &mut [f64],
    ) -> f64 {
        self.evaluate(coefficients, buffer);
        x.iter()
            .zip(buffer.iter())
            .map(|(a, b)| (a - b).powi(2))
            .sum()
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

    /// The fused passes are bitwise the per-column ones: four dot products against one
    /// sample column, and an evaluation with zero coefficients skipped, at lengths with
    /// every remainder mod 4.
    #[test]
    fn fused_passes_are_bitwise_the_per_column_ones() {
        for m in [8usize, 9, 10, 11, 13, 64, 101] {
            let column = |c: usize| -> Vec<f64> {
                (0..m)
                    .map(|i| {
                        ((i * (c + 3)) as f64 * 0.731 + c as f64).sin() * 10f64.powi(c as i32 - 2)
                    })
                    .collect()
            };
            let columns: Vec<Vec<f64>> = (0..4).map(column).collect();
            let b: Vec<f64> = (0..m).map(|i| 1e3 + (i as f64 * 0.37).cos()).collect();
            let shift = b[0];
            let fused = dots_shifted([0, 1, 2, 3].map(|c| columns[c].as_slice()), &b, shift);
            for c in 0..4 {
                let alone = dot_shifted(&columns[c], &b, shift);
                assert_eq!(fused[c].to_bits(), alone.to_bits(), "m = {m}, column {c}");
            }
            let omega = 2.0 * std::f64::consts::PI / 7.3;
            let basis = HarmonicBasis::with_orders(omega, vec![1, 2, 3], 0.5, m).unwrap();
            let table = HarmonicTable::new(&basis, m);
            let coefficients = [0.3, -1.7, 0.0, 2.5e-3, 4.0, 0.0, -0.9];
            let mut fused = vec![0.0; m];
            table.evaluate(&coefficients, &mut fused);
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
            let c = table.fit(&b);
            let by_column: Vec<f64> = (0..table.columns())
                .map(|k| dot_shifted(table.design.col_as_slice(k), &b, shift))
                .collect();
            let mut reference = by_column;
            let r = &table.r;
            let p = table.columns();
            for i in 0..p {
                let mut s = reference[i];
                for k in 0..i {
                    s -= r[(k, i)] * reference[k];
                }
                reference[i] = s / r[(i, i)];
            }
            for i in (0..p).rev() {
                let mut s = reference[i];
                for k in i + 1..p {
                    s -= r[(i, k)] * reference[k];
                }
                reference[i] = s / r[(i, i)];
            }
            reference[0] += shift;
            assert_eq!(bits(&c), bits(&reference), "fit, m = {m}");
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
        let mut buffer = vec![0.0; m];
        let ours = table.residual_sum_of_squares(&c, xs, &mut buffer);
        assert!((ours - rss).abs() < 1e-6 * rss, "{ours} vs {rss}");
        let (lo, hi) = (0..m).fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), i| {
            (l.min(fitted[(i, 0)]), u.max(fitted[(i, 0)]))
        });
        let half = table.half_range(&c, &mut buffer);
        assert!((half - 0.5 * (hi - lo)).abs() < 1e-12, "{half}");
    }
}
