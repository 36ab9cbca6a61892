//! A window projected on the harmonics that stand above its noise floor:
//! x̂ = B c, v̂ = D c with c = (BᵀB)⁻¹ Bᵀ x fitted over the window's m samples of whole
//! periods (B = QR; by one real FFT per channel when the window holds a whole number of
//! samples per period, `prep/fourier/dft.rs`, the same c to round-off), evaluated at every sample the window reads and at its end
//! t_E = t_0 + kT. For unit white noise on a channel, Var x̂_i = ‖R⁻ᵀ b_i‖² and
//! Var v̂_i = ‖R⁻ᵀ d_i‖² (b_i, d_i the design and derivative rows at sample i).
//!
//! A channel measured by a velocity or acceleration sensor ([`Record::measured_motion`])
//! is projected as measured, c_m = (BᵀB)⁻¹ Bᵀ s, and mapped per kept harmonic k to the
//! displacement coefficients c_x = S c_m: for an acceleration (a_k, b_k) → −(a_k, b_k)/(kω)²,
//! for a velocity (a_k, b_k) → (−b_k, a_k)/(kω) (x = −a/(kω)², x = v/(ikω)); the mean
//! coefficient maps to 0 (the mean of x̂ and v̂ over the window is zero: the k = 0
//! component, whose integral is unknown, is removed). Then Cov c_x = σ² S(RᵀR)⁻¹Sᵀ, so
//! Var x̂_i = σ² ‖R⁻ᵀ Sᵀ b_i‖², Var v̂_i = σ² ‖R⁻ᵀ Sᵀ d_i‖², and a gradient u in c_x is
//! whitened as σ R⁻ᵀ Sᵀ u. Everything downstream reads c_x, x̂ and v̂ as for a
//! displacement channel (S = I).
//!
//! The total variation of a combination x̂_e = Σ_j s_j x̂_j (an element's relative
//! displacement) over [t_0, t_0 + kT] is computed exactly from the series: its turning
//! points τ (zeros of v̂_e, bracketed by sign changes between samples and refined by
//! bisection to round-off) split the window into monotone pieces, and
//! TV = Σ |x̂_e(τ_{k+1}) − x̂_e(τ_k)|. It equals ∫ |v̂_e| dt with no quadrature error at
//! the kinks of |v̂_e|. Its gradient in the coefficients is Σ ±(b(τ_{k+1}) − b(τ_k)):
//! the turning points move with the coefficients, but v̂_e = 0 there, so only to second
//! order.

use std::cell::OnceCell;

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::fourier::{HarmonicBasis, RecordNoise, WholePeriods, fit_on_design};
use crate::record::{Record, Sensor, col};
use crate::terms::Element;

/// The projection of one window's displacements.
pub(crate) struct ProjectedWindow {
    /// Harmonic orders kept, ascending.
    pub(crate) kept: Vec<usize>,
    /// Per channel, the noise standard deviation per sample of its signal.
    pub(crate) noise_std: Vec<f64>,
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
    /// Displacement coefficients c_x (p × n).
    pub(crate) coefficients: Mat<f64>,
    /// x̂ per channel (rows), formed on first use ([`ProjectedWindow::x`]).
    x: Vec<OnceCell<Vec<f64>>>,
    /// v̂ per channel (rows), formed on first use ([`ProjectedWindow::v`]).
    v: Vec<OnceCell<Vec<f64>>>,
    /// What each channel's sensor measures.
    pub(crate) sensors: Vec<Sensor>,
    /// S of each channel whose sensor is not a displacement (c_x = S c_m).
    maps: Vec<Option<Mat<f64>>>,
    /// (Var x̂_i, Var v̂_i) per unit noise variance per sensor kind (displacement,
    /// velocity, acceleration), formed the first time a channel of that kind asks: only
    /// the terms that read samples need them (not a viscous term, `quadratic.rs`).
    variances: [OnceCell<(Vec<f64>, Vec<f64>)>; 3],
    /// S (RᵀR)⁻¹ Sᵀ per sensor kind, likewise formed on first use.
    covariances: [OnceCell<Mat<f64>>; 3],
}

/// The slot of a sensor kind in the per-kind caches of [`ProjectedWindow`].
fn kind_slot(kind: Sensor) -> usize {
    match kind {
        Sensor::Displacement => 0,
        Sensor::Velocity => 1,
        Sensor::Acceleration => 2,
    }
}

impl ProjectedWindow {
    /// Projects samples `start..start + rows` of `record`, a window of `span` = kT read
    /// by a rule over `count` samples (rows ≥ count), on harmonics 1..K when `harmonics`
    /// is `Some(K)`, else on those of the record that stand above its noise, with the
    /// record's noise σ̂ (`noise`, `prep/fourier/record_noise.rs`).
    pub(crate) fn new(
        record: &Record,
        start: usize,
        count: usize,
        rows: usize,
        span: f64,
        harmonics: Option<usize>,
        noise: &RecordNoise,
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
        let (signals, sensors) = match record.measured_motion() {
            Some(m) => (m.signals.as_ref(), m.sensors.clone()),
            None => (
                record.displacements(),
                vec![Sensor::Displacement; record.dofs()],
            ),
        };
        let fitted = signals.subrows(start, whole.samples);
        let kept = noise.orders_for(whole.samples, step, period, harmonics)?;
        let noise_std = noise.motion_std.clone();
        let omega = 2.0 * std::f64::consts::PI / period;
        let basis = HarmonicBasis::with_orders(omega, kept.clone(), step, whole.samples)?;
        let r = basis.r_factor();
        let design = basis.design(rows);
        // c_m of each channel on the first m rows of the design (or of its own design
        // over the m samples, when the window reads fewer)
        let longer;
        let fit_design = if design.nrows() >= whole.samples {
            &design
        } else {
            longer = basis.design(whole.samples);
            &longer
        };
        let mut measured = Mat::<f64>::zeros(basis.columns(), fitted.ncols());
        for j in 0..fitted.ncols() {
            let c = fit_on_design(fit_design, &r, &col(fitted, j)[..whole.samples]);
            measured.col_as_slice_mut(j).copy_from_slice(&c);
        }
        let maps: Vec<Option<Mat<f64>>> = sensors
            .iter()
            .map(|s| sensor_map(*s, &kept, omega))
            .collect();
        let coefficients = if maps.iter().all(Option::is_none) {
            measured
        } else {
            let mut c = measured.clone();
            for (j, map) in maps.iter().enumerate() {
                if let Some(map) = map {
                    let mapped = map * measured.col(j);
                    for k in 0..c.nrows() {
                        c[(k, j)] = mapped[k];
                    }
                }
            }
            c
        };
        let derivative = derivative_of(&design, basis.orders(), omega);
        let channels = coefficients.ncols();
        let x = (0..channels).map(|_| OnceCell::new()).collect();
        let v = (0..channels).map(|_| OnceCell::new()).collect();
        let variances = Default::default();
        let covariances = Default::default();
        let end_row = basis.row_at(span);
        Ok(ProjectedWindow {
            kept,
            noise_std,
            r,
            basis,
            step,
            design,
            derivative,
            end_row,
            coefficients,
            x,
            v,
            sensors,
            maps,
            variances,
            covariances,
        })
    }

    /// x̂ of channel `j` at the samples read: B c_j, formed the first time it is asked
    /// for (a term whose column is a quadratic form in the coefficients never reads the
    /// samples, `quadratic.rs`).
    pub(crate) fn x(&self, j: usize) -> &[f64] {
        self.x[j].get_or_init(|| series(&self.design, self.coefficients.col_as_slice(j)))
    }

    /// v̂ of channel `j` at the samples read: D c_j, formed on first use.
    pub(crate) fn v(&self, j: usize) -> &[f64] {
        self.v[j].get_or_init(|| series(&self.derivative, self.coefficients.col_as_slice(j)))
    }

    /// The number of samples read (rows of the design).
    pub(crate) fn rows(&self) -> usize {
        self.design.nrows()
    }

    fn variances(&self, channel: usize) -> &(Vec<f64>, Vec<f64>) {
        self.variances[kind_slot(self.sensors[channel])].get_or_init(|| match &self.maps[channel] {
            None => (
                unit_variances(&self.r, &self.design),
                unit_variances(&self.r, &self.derivative),
            ),
            Some(map) => (
                unit_variances(&self.r, &(&self.design * map)),
                unit_variances(&self.r, &(&self.derivative * map)),
            ),
        })
    }

    /// Var x̂_i of channel `j` per unit noise variance of that channel.
    pub(crate) fn var_x(&self, j: usize) -> &[f64] {
        &self.variances(j).0
    }

    /// Var v̂_i of channel `j` per unit noise variance of that channel.
    pub(crate) fn var_v(&self, j: usize) -> &[f64] {
        &self.variances(j).1
    }

    /// Dᵀ W Y = Σ_i w_i d_i y_iᵀ over the window's first `weights.len()` samples (p × p),
    /// with y_i the derivative rows (`of_derivative`) or the design rows: the sums over
    /// samples of the terms that are quadratic forms in the coefficients (`quadratic.rs`,
    /// `structural.rs`).
    pub(crate) fn weighted_gram(&self, weights: &[f64], of_derivative: bool) -> Mat<f64> {
        let count = weights.len();
        let p = self.columns();
        let rows = if of_derivative {
            &self.derivative
        } else {
            &self.design
        };
        let weighted = Mat::from_fn(count, p, |i, l| weights[i] * rows[(i, l)]);
        let mut gram = Mat::<f64>::zeros(p, p);
        // sequential: windows already run in parallel, and a split product's sums would
        // depend on the thread count
        faer::linalg::matmul::matmul(
            gram.as_mut(),
            faer::Accum::Replace,
            self.derivative.as_ref().subrows(0, count).transpose(),
            weighted.as_ref(),
            1.0,
            faer::Par::Seq,
        );
        gram
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

    /// Cov(c_x) of channel `j` per unit noise variance of its measured signal,
    /// S (RᵀR)⁻¹ Sᵀ = YᵀY with Rᵀ Y = Sᵀ (S = I for a displacement), p × p: one per
    /// sensor kind, formed the first time a channel of that kind asks.
    pub(crate) fn unit_covariance(&self, j: usize) -> &Mat<f64> {
        self.covariances[kind_slot(self.sensors[j])].get_or_init(|| {
            let p = self.columns();
            let mut y = match &self.maps[j] {
                None => Mat::<f64>::identity(p, p),
                Some(map) => map.transpose().to_owned(),
            };
            self.r
                .transpose()
                .solve_lower_triangular_in_place(y.as_mut());
            y.transpose() * &y
        })
    }

    /// [`Self::covariance_trace`] of `a` for channel `j`, kept in `traces` per sensor
    /// kind (C_j is one per kind): a term's elements ask for it once per end, a window's
    /// channels have at most three kinds.
    pub(crate) fn covariance_trace_in(
        &self,
        traces: &mut [Option<f64>; 3],
        a: &Mat<f64>,
        j: usize,
    ) -> f64 {
        *traces[kind_slot(self.sensors[j])].get_or_insert_with(|| self.covariance_trace(a, j))
    }

    /// tr(A C_j) for a p × p matrix `a` and C_j the [`Self::unit_covariance`] of
    /// channel `j`: the expected noise contribution per unit variance of a quadratic form
    /// cᵀ A c in channel j's coefficients.
    pub(crate) fn covariance_trace(&self, a: &Mat<f64>, j: usize) -> f64 {
        let unit = self.unit_covariance(j);
        let p = self.columns();
        let mut trace = 0.0;
        for r in 0..p {
            for c in 0..p {
                trace += a[(r, c)] * unit[(c, r)];
            }
        }
        trace
    }

    /// σ R⁻ᵀ Sᵀ u: the whitened sensitivity of a quantity with gradient `u` in the
    /// displacement coefficients of `channel`, whose measured signal has noise σ.
    pub(crate) fn whiten(&self, u: &[f64], sigma: f64, channel: usize) -> Vec<f64> {
        let mut y = match &self.maps[channel] {
            None => Mat::from_fn(u.len(), 1, |k, _| u[k]),
            Some(map) => {
                let u = Mat::from_fn(u.len(), 1, |k, _| u[k]);
                map.transpose() * &u
            }
        };
        self.r
            .transpose()
            .solve_lower_triangular_in_place(y.as_mut());
        (0..u.len()).map(|k| sigma * y[(k, 0)]).collect()
    }
}

/// An element's ends with the sign of each in its relative motion: (a, 1), then (b, −1)
/// for a two-ended element.
pub(crate) fn signed_ends(element: &Element) -> Vec<(usize, f64)> {
    std::iter::once((element.a, 1.0))
        .chain(element.b.map(|b| (b, -1.0)))
        .collect()
}

impl ProjectedWindow {
    /// The coefficients Σ_j s_j c_j of the combination `terms` = [(channel j, s_j)].
    pub(crate) fn combination(&self, terms: &[(usize, f64)]) -> Vec<f64> {
        let mut c = vec![0.0; self.columns()];
        self.combination_into(terms, &mut c);
        c
    }

    /// [`Self::combination`] written into `out` (p values), for a caller that forms one
    /// per element.
    pub(crate) fn combination_into(&self, terms: &[(usize, f64)], out: &mut [f64]) {
        for (k, value) in out.iter_mut().enumerate() {
            *value = terms
                .iter()
                .map(|&(j, s)| s * self.coefficients[(k, j)])
                .sum();
        }
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

/// S, the map c_x = S c_m from the projection coefficients of a `sensor`'s signal to
/// those of the displacement, for the basis [1, cos k₁ωt, sin k₁ωt, …] of `orders`;
/// `None` for a displacement (S = I).
fn sensor_map(sensor: Sensor, orders: &[usize], omega: f64) -> Option<Mat<f64>> {
    let velocity = match sensor {
        Sensor::Displacement => return None,
        Sensor::Velocity => true,
        Sensor::Acceleration => false,
    };
    let p = 2 * orders.len() + 1;
    let mut map = Mat::zeros(p, p);
    for (q, k) in orders.iter().enumerate() {
        let w = *k as f64 * omega;
        let (cos, sin) = (2 * q + 1, 2 * q + 2);
        if velocity {
            map[(cos, sin)] = -1.0 / w;
            map[(sin, cos)] = 1.0 / w;
        } else {
            map[(cos, cos)] = -1.0 / (w * w);
            map[(sin, sin)] = -1.0 / (w * w);
        }
    }
    Some(map)
}

/// The derivative rows d_i of the design rows b_i = [1, cos k₁ωt_i, sin k₁ωt_i, …] of
/// `orders`: (0, −k₁ω sin k₁ωt_i, k₁ω cos k₁ωt_i, …), read from the design's own
/// cosines and sines. [`HarmonicBasis::design`] and
/// [`HarmonicBasis::derivative_design`] take them from the same recurrence on the
/// phasor e^{iωt_i} (the design from a per-thread table), so this is bitwise
/// `derivative_design` without its sine and cosine per row (a unit test compares them).
fn derivative_of(design: &Mat<f64>, orders: &[usize], omega: f64) -> Mat<f64> {
    let rows = design.nrows();
    let mut derivative = Mat::zeros(rows, design.ncols());
    for (q, order) in orders.iter().enumerate() {
        let kw = *order as f64 * omega;
        let (cos, sin) = (2 * q + 1, 2 * q + 2);
        for (d, s) in derivative
            .col_as_slice_mut(cos)
            .iter_mut()
            .zip(design.col_as_slice(sin))
        {
            *d = -kw * s;
        }
        for (d, c) in derivative
            .col_as_slice_mut(sin)
            .iter_mut()
            .zip(design.col_as_slice(cos))
        {
            *d = kw * c;
        }
    }
    derivative
}

/// Σ_k c_k rows_k: the series with coefficients `c` at every row of `rows` (rows × p),
/// one column of the basis at a time.
fn series(rows: &Mat<f64>, c: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; rows.nrows()];
    for (k, ck) in c.iter().enumerate() {
        for (o, b) in out.iter_mut().zip(rows.col_as_slice(k)) {
            *o += ck * b;
        }
    }
    out
}

/// ‖R⁻ᵀ row_i‖² for every row of `rows` (rows × p).
fn unit_variances(r: &Mat<f64>, rows: &Mat<f64>) -> Vec<f64> {
    let mut y = rows.transpose().to_owned();
    r.transpose().solve_lower_triangular_in_place(y.as_mut());
    (0..y.ncols())
        .map(|i| y.col_as_slice(i).iter().map(|a| a * a).sum())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivative read from the design is bitwise `derivative_design`: whole and
    /// non-whole samples per period, consecutive and gapped orders, row counts on and
    /// off the table's lanes, tables cached and not.
    #[test]
    fn derivative_of_the_design_is_derivative_design() {
        for (omega, step, samples) in [(0.618, 0.05, 203), (2.0, 0.0157, 400), (15.7, 0.001, 1001)]
        {
            for orders in [vec![1], vec![1, 2, 3], vec![1, 4, 7], vec![2, 5]] {
                let basis = HarmonicBasis::with_orders(omega, orders.clone(), step, samples)
                    .expect("a valid basis");
                for rows in [samples, samples + 1, samples + 3] {
                    let design = basis.design(rows);
                    let ours = derivative_of(&design, basis.orders(), omega);
                    let theirs = basis.derivative_design(rows);
                    assert_eq!(
                        (ours.nrows(), ours.ncols()),
                        (theirs.nrows(), theirs.ncols())
                    );
                    for i in 0..rows {
                        for k in 0..ours.ncols() {
                            assert_eq!(
                                ours[(i, k)].to_bits(),
                                theirs[(i, k)].to_bits(),
                                "ω {omega}, orders {orders:?}, row {i}, column {k}"
                            );
                        }
                    }
                }
            }
        }
    }
}
