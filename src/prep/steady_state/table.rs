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
        let mut c: Vec<f64> = (0..p)
            .map(|k| dot_shifted(self.design.col_as_slice(k), x, shift))
            .collect();
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
        for (k, &ck) in coefficients.iter().enumerate() {
            if ck != 0.0 {
                let column = &self.design.col_as_slice(k)[..out.len()];
                for (y, b) in out.iter_mut().zip(column) {
                    *y += ck * b;
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
