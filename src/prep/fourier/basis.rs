//! A least-squares Fourier basis on the sample times t_i = i h of a window, in the
//! harmonics S of ω: x(t) ≈ a_0 + Σ_{k ∈ S} (a_k cos kωt + b_k sin kωt), fitted by QR
//! of the m × (2|S| + 1) design B = QR. Its derivative Dc gives spectral velocities,
//! and the mean coefficient times the span gives the spectral quadrature weights
//! w = span · B R⁻¹R⁻ᵀ e_0 (see the module doc of [`crate::prep::fourier`]).

use faer::{Mat, MatRef};

use super::Phasor;
use crate::error::{Error, Result};

/// Samples whose phasor recurrences run side by side ([`HarmonicBasis::row_table`]).
const LANES: usize = 4;

/// How many R factors each thread keeps ([`HarmonicBasis::r_factor`]).
const CACHED_FACTORS: usize = 8;

/// (ω bits, h bits, m, S) of a basis.
type FactorKey = (u64, u64, usize, Vec<usize>);

/// How many design tables each thread keeps ([`HarmonicBasis::row_table`]), and the
/// largest it keeps, in values (1 MiB): a small record's periods repeat a table whose
/// recurrence costs more than the fit it serves, a long window's table is read once.
const CACHED_TABLES: usize = 4;
const CACHED_TABLE_VALUES: usize = 1 << 17;

thread_local! {
    /// The last R factors this thread computed, oldest first.
    static FACTORS: std::cell::RefCell<Vec<(FactorKey, Mat<f64>)>> =
        const { std::cell::RefCell::new(Vec::new()) };
    /// The last small design tables this thread computed, oldest first, keyed by
    /// (ω bits, h bits, rows, S).
    static TABLES: std::cell::RefCell<Vec<(FactorKey, std::sync::Arc<[f64]>)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// A harmonic basis on the times t_i = i h, i = 0..m, with harmonic orders S.
pub(crate) struct HarmonicBasis {
    omega: f64,
    orders: Vec<usize>,
    step: f64,
    samples: usize,
}

/// Harmonic orders 1..=K, checked against a window of `samples` samples before they are
/// allocated (K comes from the user: K = 10⁹ must be refused, not allocated).
pub(crate) fn first_orders(harmonics: usize, samples: usize) -> Result<Vec<usize>> {
    if harmonics == 0 {
        return Err(Error::invalid("harmonics", 0.0, "must be at least 1"));
    }
    if harmonics > samples.saturating_sub(1) / 2 {
        return Err(Error::invalid(
            "harmonics",
            harmonics as f64,
            &format!(
                "a window of {samples} samples can fit at most {} harmonics",
                samples.saturating_sub(1) / 2
            ),
        ));
    }
    Ok((1..=harmonics).collect())
}

impl HarmonicBasis {
    /// Harmonics 1..=K. Checks that the fit is overdetermined and below the Nyquist
    /// frequency.
    pub(crate) fn new(omega: f64, harmonics: usize, step: f64, samples: usize) -> Result<Self> {
        let columns = 2 * harmonics + 1;
        if harmonics == 0 {
            return Err(Error::invalid("harmonics", 0.0, "must be at least 1"));
        }
        if samples < columns {
            return Err(Error::invalid(
                "harmonics",
                harmonics as f64,
                &format!(
                    "a window of {samples} samples can fit at most {} harmonics",
                    (samples.saturating_sub(1)) / 2
                ),
            ));
        }
        Self::with_orders(omega, first_orders(harmonics, samples)?, step, samples)
    }

    /// The harmonic orders `orders` (ascending, distinct, ≥ 1).
    pub(crate) fn with_orders(
        omega: f64,
        orders: Vec<usize>,
        step: f64,
        samples: usize,
    ) -> Result<Self> {
        let Some(&highest) = orders.last() else {
            return Err(Error::invalid("harmonics", 0.0, "must be at least 1"));
        };
        if orders[0] == 0 || orders.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::invalid(
                "harmonics",
                orders[0] as f64,
                "harmonic orders must be ascending, distinct and at least 1",
            ));
        }
        let columns = 2 * orders.len() + 1;
        if samples < columns {
            return Err(Error::invalid(
                "harmonics",
                orders.len() as f64,
                &format!(
                    "a window of {samples} samples can fit at most {} harmonics",
                    (samples.saturating_sub(1)) / 2
                ),
            ));
        }
        // The dense work on the basis (its design matrix, the derivative's, a QR copy)
        // is checked before any of it is allocated: samples × columns grows as the
        // square of the samples per period when the harmonics follow them.
        crate::budget::require(
            &format!(
                "a harmonic basis of {} samples × {} columns ({} harmonics)",
                crate::format::integer(samples as u128),
                crate::format::integer(columns as u128),
                crate::format::integer(orders.len() as u128)
            ),
            crate::budget::f64s((samples as u128).saturating_mul(3 * columns as u128)),
            "use fewer samples per period or fewer harmonics (`harmonics`), or raise --max-memory",
        )?;
        let nyquist = std::f64::consts::PI / step;
        if highest as f64 * omega >= nyquist {
            return Err(Error::invalid(
                "harmonics",
                highest as f64,
                &format!(
                    "harmonic {highest} of ω = {omega} is above the Nyquist frequency {nyquist}"
                ),
            ));
        }
        Ok(HarmonicBasis {
            omega,
            orders,
            step,
            samples,
        })
    }

    /// The harmonic orders S, ascending.
    pub(crate) fn orders(&self) -> &[usize] {
        &self.orders
    }

    /// ω.
    pub(crate) fn omega(&self) -> f64 {
        self.omega
    }

    /// h, the step between samples.
    pub(crate) fn step(&self) -> f64 {
        self.step
    }

    pub(crate) fn columns(&self) -> usize {
        2 * self.orders.len() + 1
    }

    /// Angular frequency of column j ≥ 1 and whether it is a cosine.
    fn column(&self, j: usize) -> (f64, bool) {
        let order = self.orders[(j - 1) / 2] as f64;
        (order * self.omega, j % 2 == 1)
    }

    /// rows × (2|S|+1) design matrix [1, cos k₁ωt, sin k₁ωt, cos k₂ωt, …] at t_i = i h.
    pub(crate) fn design(&self, rows: usize) -> Mat<f64> {
        let p = self.columns();
        let table = self.row_table(rows);
        Mat::from_fn(rows, p, |i, k| table[i * p + k])
    }

    /// The design rows at t_i = i h, i = 0..rows, row after row (rows × p, row-major):
    /// the values of [`HarmonicBasis::for_each_phasor`], computed for [`LANES`] samples
    /// at a time (independent recurrences side by side, each with the same arithmetic
    /// as alone, so the same values bit for bit, without waiting on one chain).
    ///
    /// The table depends on (ω, h, rows, S) alone, and the periods of one record (or of
    /// records at one frequency) repeat them, so each thread keeps the last
    /// [`CACHED_TABLES`] tables of at most [`CACHED_TABLE_VALUES`] values and shares one
    /// it has: the same values, without the recurrence.
    fn row_table(&self, rows: usize) -> std::sync::Arc<[f64]> {
        let small = rows.saturating_mul(self.columns()) <= CACHED_TABLE_VALUES;
        if !small {
            return self.compute_row_table(rows).into();
        }
        let key = (
            self.omega.to_bits(),
            self.step.to_bits(),
            rows,
            self.orders.clone(),
        );
        let cached = TABLES.with(|t| {
            t.borrow()
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, table)| table.clone())
        });
        if let Some(table) = cached {
            return table;
        }
        let table: std::sync::Arc<[f64]> = self.compute_row_table(rows).into();
        TABLES.with(|t| {
            let mut t = t.borrow_mut();
            if t.len() >= CACHED_TABLES {
                t.remove(0);
            }
            t.push((key, table.clone()));
        });
        table
    }

    /// [`HarmonicBasis::row_table`] computed.
    fn compute_row_table(&self, rows: usize) -> Vec<f64> {
        let p = self.columns();
        let highest = *self.orders.last().unwrap_or(&0);
        let mut table = vec![0.0; rows * p];
        for block in (0..rows).step_by(LANES) {
            let lanes = (rows - block).min(LANES);
            let (mut s1, mut c1) = ([0.0; LANES], [1.0; LANES]);
            for l in 0..lanes {
                let angle = self.omega * (block + l) as f64 * self.step;
                (s1[l], c1[l]) = angle.sin_cos();
            }
            let (mut c, mut s) = ([1.0; LANES], [0.0; LANES]);
            let mut q = 0;
            for k in 1..=highest {
                for l in 0..LANES {
                    (c[l], s[l]) = (c[l] * c1[l] - s[l] * s1[l], s[l] * c1[l] + c[l] * s1[l]);
                }
                if self.orders[q] == k {
                    for l in 0..lanes {
                        let row = (block + l) * p;
                        table[row + 2 * q + 1] = c[l];
                        table[row + 2 * q + 2] = s[l];
                    }
                    q += 1;
                }
            }
            for l in 0..lanes {
                table[(block + l) * p] = 1.0;
            }
        }
        table
    }

    /// Calls `f(q, cos k_q ωt_i, sin k_q ωt_i)` for every order of S at t_i = i h, from
    /// the powers of the phasor e^{iωt_i} (one sine and cosine per sample; the
    /// recurrence loses about k·ε, far below any noise).
    fn for_each_phasor(&self, i: usize, mut f: impl FnMut(usize, f64, f64)) {
        let angle = self.omega * i as f64 * self.step;
        let (s1, c1) = angle.sin_cos();
        let (mut c, mut s) = (1.0, 0.0);
        let mut q = 0;
        for k in 1..=*self.orders.last().unwrap_or(&0) {
            (c, s) = (c * c1 - s * s1, s * c1 + c * s1);
            if self.orders[q] == k {
                f(q, c, s);
                q += 1;
            }
        }
    }

    /// BᵀB of the design over the fitted samples, in closed form: with θ = ωh and the
    /// sums C(α) = Σ_{i<m} cos αi = cos((m−1)α/2) sin(mα/2)/sin(α/2) and
    /// S(α) = Σ_{i<m} sin αi = sin((m−1)α/2) sin(mα/2)/sin(α/2) (C(0) = m, S(0) = 0),
    /// ⟨cos k, cos l⟩ = ½[C((k−l)θ) + C((k+l)θ)], ⟨sin k, sin l⟩ = ½[C((k−l)θ) − C((k+l)θ)],
    /// ⟨cos k, sin l⟩ = ½[S((k+l)θ) − S((k−l)θ)], ⟨1, cos k⟩ = C(kθ), ⟨1, sin k⟩ = S(kθ).
    fn gram(&self) -> Mat<f64> {
        let m = self.samples as f64;
        let theta = self.omega * self.step;
        let sums = |order: i64| -> (f64, f64) {
            if order == 0 {
                return (m, 0.0);
            }
            let alpha = order as f64 * theta;
            let ratio = (m * alpha / 2.0).sin() / (alpha / 2.0).sin();
            let (s, c) = ((m - 1.0) * alpha / 2.0).sin_cos();
            (c * ratio, s * ratio)
        };
        // C and S at every order the entries read (k − l ≤ 0 and k + l ≤ 2K): 3K + 1
        // evaluations instead of two per entry, the same values.
        let highest = *self.orders.last().unwrap_or(&0) as i64;
        let table: Vec<(f64, f64)> = (-highest..=2 * highest).map(sums).collect();
        let sums = |order: i64| table[(order + highest) as usize];
        let p = self.columns();
        let mut g = Mat::zeros(p, p);
        g[(0, 0)] = m;
        for (q, &k) in self.orders.iter().enumerate() {
            let (ck, sk) = sums(k as i64);
            g[(0, 2 * q + 1)] = ck;
            g[(0, 2 * q + 2)] = sk;
            for (r, &l) in self.orders.iter().enumerate().skip(q) {
                let (cd, sd) = sums(k as i64 - l as i64);
                let (cs, ss) = sums((k + l) as i64);
                g[(2 * q + 1, 2 * r + 1)] = 0.5 * (cd + cs);
                g[(2 * q + 2, 2 * r + 2)] = 0.5 * (cd - cs);
                g[(2 * q + 1, 2 * r + 2)] = 0.5 * (ss - sd);
                g[(2 * q + 2, 2 * r + 1)] = 0.5 * (ss + sd);
            }
        }
        for j in 0..p {
            for i in 0..j {
                g[(j, i)] = g[(i, j)];
            }
        }
        g
    }

    /// R (upper triangular) with RᵀR = BᵀB: the R of a QR factorization of the design.
    /// From the Cholesky factor of the closed-form Gram matrix (the harmonic basis over
    /// whole periods is nearly orthogonal, so BᵀB is well conditioned), or from a QR
    /// of the design if Cholesky fails.
    ///
    /// R depends on (ω, h, m, S) alone, and the windows and spans of one record repeat
    /// them (the same m, or m ± 1), so each thread keeps the last [`CACHED_FACTORS`]
    /// factors and returns a copy of one it has: the same values, without the O(p³)
    /// factorisation (p = 2|S| + 1 reaches 201 with the noise floor's K_max = 100).
    pub(crate) fn r_factor(&self) -> Mat<f64> {
        let key = (
            self.omega.to_bits(),
            self.step.to_bits(),
            self.samples,
            self.orders.clone(),
        );
        let cached = FACTORS.with(|f| {
            f.borrow()
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, r)| r.clone())
        });
        if let Some(r) = cached {
            return r;
        }
        let r = match self.gram().llt(faer::Side::Lower) {
            Ok(llt) => llt.L().transpose().to_owned(),
            Err(_) => self.design(self.samples).qr().thin_R().to_owned(),
        };
        FACTORS.with(|f| {
            let mut f = f.borrow_mut();
            if f.len() >= CACHED_FACTORS {
                f.remove(0);
            }
            f.push((key, r.clone()));
        });
        r
    }

    /// Bᵀ values for `values` (m × n), by the phasor recurrence.
    fn transpose_times(&self, values: MatRef<'_, f64>, table: &[f64]) -> Mat<f64> {
        let (n, p) = (values.ncols(), self.columns());
        let rows = self.samples.min(values.nrows()).min(table.len() / p.max(1));
        let mut out = Mat::zeros(p, n);
        // Per column, the sum over the samples in their order (as one row at a time
        // would add them), the p accumulators side by side.
        for c in 0..n {
            let x = crate::record::col(values, c);
            let sums = out.col_as_slice_mut(c);
            for (i, &xi) in x[..rows].iter().enumerate() {
                if xi != 0.0 {
                    for (sum, b) in sums.iter_mut().zip(&table[i * p..(i + 1) * p]) {
                        *sum += b * xi;
                    }
                }
            }
        }
        out
    }

    /// The design row [1, cos k₁ωt, sin k₁ωt, …] at time t (from the first sample).
    pub(crate) fn row_at(&self, t: f64) -> Vec<f64> {
        (0..self.columns())
            .map(|j| {
                if j == 0 {
                    return 1.0;
                }
                let (kw, cosine) = self.column(j);
                if cosine {
                    (kw * t).cos()
                } else {
                    (kw * t).sin()
                }
            })
            .collect()
    }

    /// The derivative of the design row at time t.
    pub(crate) fn derivative_row_at(&self, t: f64) -> Vec<f64> {
        (0..self.columns())
            .map(|j| {
                if j == 0 {
                    return 0.0;
                }
                let (kw, cosine) = self.column(j);
                if cosine {
                    -kw * (kw * t).sin()
                } else {
                    kw * (kw * t).cos()
                }
            })
            .collect()
    }

    /// The time derivative of the design matrix at t_i = i h, i = 0..rows.
    pub(crate) fn derivative_design(&self, rows: usize) -> Mat<f64> {
        let mut design = Mat::zeros(rows, self.columns());
        for i in 0..rows {
            self.for_each_phasor(i, |q, cos, sin| {
                let kw = self.orders[q] as f64 * self.omega;
                design[(i, 2 * q + 1)] = -kw * sin;
                design[(i, 2 * q + 2)] = kw * cos;
            });
        }
        design
    }

    /// Least-squares coefficients ((2|S|+1) × n: a_0, then a_k, b_k per order) of every
    /// column of `values` (m × n).
    /// By the normal equations RᵀR c = Bᵀx with R from [`HarmonicBasis::r_factor`]:
    /// O(m p n + p³) instead of the O(m p²) of a QR of the design.
    pub(crate) fn fit(&self, values: MatRef<'_, f64>) -> Mat<f64> {
        self.fit_with(&self.r_factor(), values)
    }

    /// [`HarmonicBasis::fit`] with R already computed. Each column is fitted relative
    /// to its first sample (added back to a_0), so that a constant signal gives exactly
    /// zero harmonics and a large offset costs no accuracy.
    pub(crate) fn fit_with(&self, r: &Mat<f64>, values: MatRef<'_, f64>) -> Mat<f64> {
        let table = self.row_table(self.samples.min(values.nrows()));
        self.fit_with_table(r, values, &table)
    }

    /// [`HarmonicBasis::fit`] and the design over the fitted samples, from one table of
    /// the design rows (the same values as `fit` and `design` apart).
    pub(crate) fn fit_and_design(&self, values: MatRef<'_, f64>) -> (Mat<f64>, Mat<f64>) {
        let rows = self.samples.min(values.nrows());
        let table = self.row_table(rows);
        let p = self.columns();
        let coefficients = self.fit_with_table(&self.r_factor(), values, &table);
        (coefficients, Mat::from_fn(rows, p, |i, k| table[i * p + k]))
    }

    fn fit_with_table(&self, r: &Mat<f64>, values: MatRef<'_, f64>, table: &[f64]) -> Mat<f64> {
        let first: Vec<f64> = (0..values.ncols())
            .map(|j| {
                if values.nrows() > 0 {
                    values[(0, j)]
                } else {
                    0.0
                }
            })
            .collect();
        let shifted = Mat::from_fn(values.nrows(), values.ncols(), |i, j| {
            values[(i, j)] - first[j]
        });
        let mut c = self.transpose_times(shifted.as_ref(), table);
        r.transpose().solve_lower_triangular_in_place(c.as_mut());
        r.solve_upper_triangular_in_place(c.as_mut());
        for (j, offset) in first.iter().enumerate() {
            c[(0, j)] += offset;
        }
        c
    }

    /// The phasor of the `index`-th order of S in every column of `coefficients`.
    pub(crate) fn phasors(&self, coefficients: &Mat<f64>, index: usize) -> Vec<Phasor> {
        (0..coefficients.ncols())
            .map(|c| {
                Phasor::from_cos_sin(
                    coefficients[(2 * index + 1, c)],
                    coefficients[(2 * index + 2, c)],
                )
            })
            .collect()
    }

    /// The derivative of the fitted series at t_i = i h, i = 0..rows (rows may exceed
    /// the fitted samples: the series is periodic).
    pub(crate) fn derivative(&self, coefficients: &Mat<f64>, rows: usize) -> Mat<f64> {
        self.derivative_design(rows) * coefficients
    }

    /// Fits every column of `values` (m × n) and returns the derivative of the fitted
    /// series at the same samples (m × n).
    pub(crate) fn differentiate(&self, values: MatRef<'_, f64>) -> Mat<f64> {
        let coefficients = self.fit(values);
        self.derivative(&coefficients, self.samples)
    }

    /// Weights w (length m) such that Σ w_i p(t_i) = span · a_0(p): the integral over
    /// the window of the fitted periodic series. w = span · Q R^{-T} e_0 for B = QR.
    ///
    /// Since Q = B R⁻¹, w = span · B z with z = R⁻¹ R⁻ᵀ e_0: two triangular solves and
    /// one product, without forming Q.
    pub(crate) fn integration_weights(&self, span: f64) -> Vec<f64> {
        let design = self.design(self.samples);
        let r = self.r_factor();
        let mut z = Mat::<f64>::zeros(self.columns(), 1);
        z[(0, 0)] = 1.0;
        r.transpose().solve_lower_triangular_in_place(z.as_mut());
        r.solve_upper_triangular_in_place(z.as_mut());
        let w = design * z;
        (0..self.samples).map(|i| span * w[(i, 0)]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x = 1 + 0.5 cos ωt − 0.2 sin 3ωt sampled with T/h = 37.3 (not an integer):
    /// the derivative must be exact to round-off, v = −0.5ω sin ωt − 0.6ω cos 3ωt.
    #[test]
    fn differentiates_band_limited_signal_exactly_on_incommensurate_grid() {
        let omega = 2.0 * std::f64::consts::PI / 3.73;
        let h = 0.1;
        let m = 75; // two periods (74.6 samples) and a bit
        let x = Mat::from_fn(m, 1, |i, _| {
            let t = i as f64 * h;
            1.0 + 0.5 * (omega * t).cos() - 0.2 * (3.0 * omega * t).sin()
        });
        let basis = HarmonicBasis::new(omega, 8, h, m).unwrap();
        let v = basis.differentiate(x.as_ref());
        for i in 0..m {
            let t = i as f64 * h;
            let exact = -0.5 * omega * (omega * t).sin() - 0.6 * omega * (3.0 * omega * t).cos();
            assert!((v[(i, 0)] - exact).abs() < 1e-10, "sample {i}");
        }
    }

    /// ∫_0^T cos²(ωt) dt = T/2 exactly from samples that do not close the period.
    #[test]
    fn integration_weights_are_exact_for_trigonometric_polynomials() {
        let period = 3.73;
        let omega = 2.0 * std::f64::consts::PI / period;
        let h = 0.1;
        let m = 38; // t = 0 .. 3.7 < T
        let basis = HarmonicBasis::new(omega, 5, h, m).unwrap();
        let w = basis.integration_weights(period);
        let integral: f64 = (0..m)
            .map(|i| w[i] * (omega * i as f64 * h).cos().powi(2))
            .sum();
        assert!((integral - period / 2.0).abs() < 1e-12);
    }

    /// A chosen set of orders {1, 4} fits x = cos ωt + 0.1 sin 4ωt exactly and gives its
    /// phasors: 0.1 sin θ = 0.1 cos(θ − π/2).
    /// phasors: 0.1 sin θ = 0.1 cos(θ − π/2).
    #[test]
    fn fits_a_set_of_orders_and_reads_phasors() {
        let omega = 2.0 * std::f64::consts::PI / 2.91;
        let (h, m) = (0.1, 30);
        let x = Mat::from_fn(m, 1, |i, _| {
            let t = i as f64 * h;
            (omega * t).cos() + 0.1 * (4.0 * omega * t).sin()
        });
        let basis = HarmonicBasis::with_orders(omega, vec![1, 4], h, m).unwrap();
        let c = basis.fit(x.as_ref());
        let first = basis.phasors(&c, 0)[0];
        let fourth = basis.phasors(&c, 1)[0];
        assert!((first.amplitude - 1.0).abs() < 1e-12 && first.phase.abs() < 1e-12);
        assert!((fourth.amplitude - 0.1).abs() < 1e-12);
        assert!((fourth.phase - std::f64::consts::FRAC_PI_2).abs() < 1e-10);
        assert!(HarmonicBasis::with_orders(omega, vec![2, 2], h, m).is_err());
        assert!(HarmonicBasis::with_orders(omega, vec![], h, m).is_err());
    }

    #[test]
    fn rejects_more_harmonics_than_samples_allow() {
        assert!(matches!(
            HarmonicBasis::new(1.0, 10, 0.01, 15),
            Err(Error::InvalidParameter { .. })
        ));
        // harmonic 40 of ω = 1 is above Nyquist π/0.1 ≈ 31.4
        assert!(matches!(
            HarmonicBasis::new(1.0, 40, 0.1, 1000),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
