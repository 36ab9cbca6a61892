//! A window projected on the harmonics that stand above its noise floor:
//! x̂ = B c, v̂ = D c with c = (BᵀB)⁻¹ Bᵀ x fitted over the window's m samples of whole
//! periods (B = QR), evaluated at every sample the window reads and at its end
//! t_E = t_0 + kT. For unit white noise on a channel, Var x̂_i = ‖R⁻ᵀ b_i‖² and
//! Var v̂_i = ‖R⁻ᵀ d_i‖² (b_i, d_i the design and derivative rows at sample i).
//!
//! The total variation of a combination x̂_e = Σ_j s_j x̂_j (an element's relative
//! displacement) over [t_0, t_0 + kT] is computed exactly from the series: its turning
//! points τ (zeros of v̂_e, bracketed by sign changes between samples and refined by
//! bisection to round-off) split the window into monotone pieces, and
//! TV = Σ |x̂_e(τ_{k+1}) − x̂_e(τ_k)|. It equals ∫ |v̂_e| dt with no quadrature error at
//! the kinks of |v̂_e|. Its gradient in the coefficients is Σ ±(b(τ_{k+1}) − b(τ_k)):
//! the turning points move with the coefficients, but v̂_e = 0 there, so only to second
//! order.

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::fourier::{
    HarmonicBasis, HarmonicSelection, WholePeriods, first_orders, select_harmonics,
};
use crate::record::Record;

/// The projection of one window's displacements.
pub(crate) struct ProjectedWindow {
    /// The harmonics kept and the noise estimates of the displacement channels.
    pub(crate) selection: HarmonicSelection,
    /// R of the QR factorization of the m × p design (upper triangular).
    r: Mat<f64>,
    /// The basis, for evaluating the series between samples.
    basis: HarmonicBasis,
    /// Sampling step h.
    step: f64,
    /// Design rows b_i at the samples read (rows × p).
    pub(crate) design: Mat<f64>,
    /// Derivative rows d_i (rows × p).
    pub(crate) derivative: Mat<f64>,
    /// The design row at the window's end t_E = t_0 + kT.
    pub(crate) end_row: Vec<f64>,
    /// Projection coefficients (p × n).
    pub(crate) coefficients: Mat<f64>,
    /// x̂ (rows × n).
    pub(crate) x: Mat<f64>,
    /// v̂ (rows × n).
    pub(crate) v: Mat<f64>,
    /// Var x̂_i per unit noise variance.
    pub(crate) var_x: Vec<f64>,
    /// Var v̂_i per unit noise variance.
    pub(crate) var_v: Vec<f64>,
}

impl ProjectedWindow {
    /// Projects samples `start..start + rows` of `record`, a window of `span` = kT read
    /// by a rule over `count` samples (rows ≥ count), on harmonics 1..K when `harmonics`
    /// is `Some(K)`, else on those above the noise floor.
    pub(crate) fn new(
        record: &Record,
        start: usize,
        count: usize,
        rows: usize,
        span: f64,
        harmonics: Option<usize>,
    ) -> Result<Self> {
        let available = record.samples().saturating_sub(start);
        if rows > available {
            return Err(Error::RecordTooShort {
                record: record.label().to_string(),
                needed: start.saturating_add(rows),
                available: record.samples(),
            });
        }
        let (step, period) = (record.step(), record.period());
        let whole = WholePeriods::of_window(count, available, step, period)?;
        let fitted = record.displacements().subrows(start, whole.samples);
        let mut selection = select_harmonics(fitted, step, period, whole.periods)?;
        if let Some(k) = harmonics {
            selection.kept = first_orders(k, whole.samples)?;
        }
        let omega = 2.0 * std::f64::consts::PI / period;
        let basis = HarmonicBasis::with_orders(omega, selection.kept.clone(), step, whole.samples)?;
        let r = basis.r_factor();
        let coefficients = basis.fit_with(&r, fitted);
        let design = basis.design(rows);
        let derivative = basis.derivative_design(rows);
        let x = &design * &coefficients;
        let v = &derivative * &coefficients;
        let var_x = unit_variances(&r, &design);
        let var_v = unit_variances(&r, &derivative);
        let end_row = basis.row_at(span);
        Ok(ProjectedWindow {
            selection,
            r,
            basis,
            step,
            design,
            derivative,
            end_row,
            coefficients,
            x,
            v,
            var_x,
            var_v,
        })
    }

    /// Number of projection coefficients per channel, p.
    pub(crate) fn columns(&self) -> usize {
        self.r.ncols()
    }

    /// x̂ of channel `j` at t_E.
    pub(crate) fn end_value(&self, j: usize) -> f64 {
        self.end_row
            .iter()
            .enumerate()
            .map(|(k, b)| b * self.coefficients[(k, j)])
            .sum()
    }

    /// σ R⁻ᵀ u: the whitened sensitivity of a quantity with gradient `u` in the
    /// coefficients of a channel with noise σ.
    pub(crate) fn whiten(&self, u: &[f64], sigma: f64) -> Vec<f64> {
        let mut y = Mat::from_fn(u.len(), 1, |k, _| u[k]);
        self.r
            .transpose()
            .solve_lower_triangular_in_place(y.as_mut());
        (0..u.len()).map(|k| sigma * y[(k, 0)]).collect()
    }
}

impl ProjectedWindow {
    /// The coefficients Σ_j s_j c_j of the combination `terms` = [(channel j, s_j)].
    pub(crate) fn combination(&self, terms: &[(usize, f64)]) -> Vec<f64> {
        (0..self.columns())
            .map(|k| {
                terms
                    .iter()
                    .map(|(j, s)| s * self.coefficients[(k, *j)])
                    .sum()
            })
            .collect()
    }

    /// The exact total variation over [0, `span`] of the series with coefficients `c`,
    /// and its gradient in `c` (see the module doc). `v` holds the series' derivative at
    /// the samples 0..=⌊span/h⌋ (at least).
    pub(crate) fn total_variation(&self, c: &[f64], v: &[f64], span: f64) -> (f64, Vec<f64>) {
        let dot = |row: &[f64]| row.iter().zip(c).map(|(a, b)| a * b).sum::<f64>();
        let slope = |t: f64| dot(&self.basis.derivative_row_at(t));
        let last = ((span / self.step).floor() as usize).min(v.len().saturating_sub(1));
        // the breakpoints: window start, turning points, window end
        let mut points = vec![0.0];
        for i in 0..last {
            let (a, b) = (v[i], v[i + 1]);
            if a == 0.0 && i > 0 {
                points.push(i as f64 * self.step);
            } else if a * b < 0.0 {
                points.push(bisect(
                    &slope,
                    i as f64 * self.step,
                    (i + 1) as f64 * self.step,
                    a,
                ));
            }
        }
        let t_last = last as f64 * self.step;
        if t_last < span && v[last] != 0.0 {
            let end = slope(span);
            if v[last] * end < 0.0 {
                points.push(bisect(&slope, t_last, span, v[last]));
            }
        }
        points.push(span);
        let rows: Vec<Vec<f64>> = points.iter().map(|t| self.basis.row_at(*t)).collect();
        let values: Vec<f64> = rows.iter().map(|r| dot(r)).collect();
        let mut total = 0.0;
        let mut gradient = vec![0.0; c.len()];
        for k in 0..points.len() - 1 {
            let change = values[k + 1] - values[k];
            total += change.abs();
            let sign = crate::terms::law::sign(change);
            if sign != 0.0 {
                for (g, (a, b)) in gradient.iter_mut().zip(rows[k + 1].iter().zip(&rows[k])) {
                    *g += sign * (a - b);
                }
            }
        }
        (total, gradient)
    }
}

/// The zero of `f` in [a, b] where f changes sign (f(a) = `fa`), by bisection to
/// round-off (at most 60 halvings).
fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, fa: f64) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        let fm = f(mid);
        if fm == 0.0 {
            return mid;
        }
        if (fm < 0.0) == (fa < 0.0) {
            a = mid;
        } else {
            b = mid;
        }
    }
    0.5 * (a + b)
}

/// ‖R⁻ᵀ row_i‖² for every row of `rows` (rows × p).
fn unit_variances(r: &Mat<f64>, rows: &Mat<f64>) -> Vec<f64> {
    let mut y = rows.transpose().to_owned();
    r.transpose().solve_lower_triangular_in_place(y.as_mut());
    (0..y.ncols())
        .map(|i| (0..y.nrows()).map(|k| y[(k, i)] * y[(k, i)]).sum())
        .collect()
}
