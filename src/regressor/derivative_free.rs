//! Derivative-free window integrals, exact where they apply, so that a noisy velocity
//! estimate does not enter them.
//!
//! The window is the path t_0 .. t_F sampled every h, closed by the end point
//! t_E = t_0 + kT = t_0 + (F + φ)h when φ > 0 (values there by linear interpolation for
//! raw samples, or read from the fitted periodic series). A window that closes
//! periodically ([`Window::closed`]: L = kT/h whole samples ending with the record)
//! has F = L − 1 and φ = 1: its last interval [t_{L−1}, t_0 + kT] ends at the closing
//! sample, which is the window's first, r_E = r_0 and x_E = x_0, so
//! ∫ rᵀ dx = Σ_{j<L} ½(r_j + r_{j+1 mod L}) · (x_{j+1 mod L} − x_j).
//!
//! - **Input work** ∫ rᵀ dx as the trapezoidal Stieltjes sum
//!   Σ_j ½(r_j + r_{j+1}) · (x_{j+1} − x_j) (plus the partial last interval to t_E),
//!   summed over DOFs. Symmetric in j and j + 1, so second-order accurate; the left-point
//!   sum Σ r_j (x_{j+1} − x_j) is off by ½h ∫ rᵀ ẍ dt, a large elastic product when the
//!   input work is a small part of it (tens of percent near resonance).
//! - **Coulomb work** ∫ |v| dt = total variation of x over the window,
//!   Σ_j |x_{j+1} − x_j| (plus the last partial interval): exact for a displacement
//!   that is monotone between samples, with no velocity at all.

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::quadrature::Quadrature;
use crate::prep::window::Window;
use crate::record::{LoadDistribution, Record, col};
use crate::terms::OnElements;
use crate::terms::{Coefficients, Term};

/// The samples t_0..t_F of a window of span kT and the fractional end φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Path {
    /// F: the last whole sample inside the window that the path reads.
    pub(crate) whole: usize,
    /// φ: how far past t_F the window ends, in steps; in [0, 1), or 1 when closed.
    pub(crate) frac: f64,
    /// Whether the end point t_E = t_F + h is the window's first sample (periodic
    /// closure).
    pub(crate) closed: bool,
}

impl Path {
    /// The path of a window of `span` at sampling step `step`.
    pub(crate) fn of(span: f64, step: f64) -> Self {
        let (whole, frac) = Quadrature::length(span, step);
        Path {
            whole,
            frac,
            closed: false,
        }
    }

    /// The path of window `w` at sampling step `step`: as [`Path::of`], or F = L − 1,
    /// φ = 1 ending on the window's first sample when `w` closes periodically.
    pub(crate) fn of_window(w: &Window, step: f64) -> Self {
        match w.closed_length(step) {
            Some(length) => Path {
                whole: length - 1,
                frac: 1.0,
                closed: true,
            },
            None => Self::of(w.span, step),
        }
    }

    /// Samples read from the window's first: F + 1, and one more for interpolating the
    /// end point when φ > 0 (none when closed: the end point is the first sample).
    pub(crate) fn samples(&self) -> usize {
        self.whole
            .saturating_add(1 + usize::from(self.frac > 0.0 && !self.closed))
    }

    /// The value at t_E of a sampled signal (slice from the window's first sample, at
    /// least [`Path::samples`] long): by linear interpolation, or the first sample
    /// when closed.
    pub(crate) fn end(&self, s: &[f64]) -> f64 {
        if self.closed {
            s[0]
        } else if self.frac > 0.0 {
            s[self.whole] + self.frac * (s[self.whole + 1] - s[self.whole])
        } else {
            s[self.whole]
        }
    }
}

/// ∫ r dx over the path: `r` and `x` hold the values at t_0..t_F (at least F + 1), the
/// end values at t_E are `r_end` and `x_end` (ignored when φ = 0).
pub(crate) fn stieltjes(path: Path, r: &[f64], r_end: f64, x: &[f64], x_end: f64) -> f64 {
    let f = path.whole;
    let mut total = 0.0;
    for j in 0..f {
        total += 0.5 * (r[j] + r[j + 1]) * (x[j + 1] - x[j]);
    }
    if path.frac > 0.0 {
        total += 0.5 * (r[f] + r_end) * (x_end - x[f]);
    }
    total
}

/// The total variation of x over the path (values at t_0..t_F, end value `x_end`).
pub(crate) fn total_variation(path: Path, x: &[f64], x_end: f64) -> f64 {
    let f = path.whole;
    let mut total = 0.0;
    for j in 0..f {
        total += (x[j + 1] - x[j]).abs();
    }
    if path.frac > 0.0 {
        total += (x_end - x[f]).abs();
    }
    total
}

/// The derivative-free forms on the raw samples of window `w` of `record`: returns the
/// input work ∫ rᵀ dx, and replaces in `row` the columns of laws whose work is a total
/// variation (Coulomb) by weight · TV(relative x).
pub(crate) fn replace_with_raw(
    model: &DampingModel,
    record: &Record,
    w: &Window,
    row: &mut [f64],
) -> Result<f64> {
    let path = Path::of_window(w, record.step());
    let needed = w.start.saturating_add(path.samples());
    if needed > record.samples() {
        return Err(Error::RecordTooShort {
            record: record.label().to_string(),
            needed,
            available: record.samples(),
        });
    }
    let samples = path.samples();
    let x = record.displacements().subrows(w.start, samples);
    let forcing = record.forcing();
    let mut input = 0.0;
    for k in 0..forcing.signals.ncols() {
        let s = &forcing.signals.col_as_slice(k)[w.start..w.start + samples];
        let s_end = path.end(s);
        let mut on = |dof: usize, scale: f64| {
            let xj = col(x, dof);
            input += scale * stieltjes(path, s, s_end, xj, path.end(xj));
        };
        match &forcing.distribution {
            LoadDistribution::Dofs(dofs) => on(dofs[k], 1.0),
            LoadDistribution::Matrix(d) => {
                for dof in 0..d.nrows() {
                    if d[(dof, k)] != 0.0 {
                        on(dof, d[(dof, k)]);
                    }
                }
            }
        }
    }
    for (term, range) in model.term_columns() {
        let Term::Elements(t) = term else { continue };
        if !t.law().is_total_variation() {
            continue;
        }
        row[range.clone()].fill(0.0);
        let mut relative = vec![0.0; samples];
        for (e, element) in t.elements().iter().enumerate() {
            let xa = col(x, element.a);
            match element.b {
                None => relative.copy_from_slice(xa),
                Some(b) => {
                    for (r, (a, b)) in relative.iter_mut().zip(xa.iter().zip(col(x, b))) {
                        *r = a - b;
                    }
                }
            }
            let weight = t.weights().map_or(1.0, |w| w[e]);
            let column = match t.coefficients() {
                Coefficients::Shared(_) => range.start,
                Coefficients::PerElement(_) => range.start + e,
            };
            row[column] += weight * total_variation(path, &relative, path.end(&relative));
        }
    }
    Ok(input)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// x = X cos ωt, r = F sin ωt over one period with T/h = 101.67: ∫ r dx = −π F X
    /// (the input work of a force in quadrature), TV = 4X; both to second order in h.
    #[test]
    fn stieltjes_and_total_variation_of_a_harmonic_cycle() {
        let (h, period) = (0.1, 10.167);
        let omega = 2.0 * PI / period;
        let path = Path::of(period, h);
        assert_eq!(path.whole, 101);
        let n = path.samples();
        let x: Vec<f64> = (0..n).map(|i| 2.0 * (omega * i as f64 * h).cos()).collect();
        let r: Vec<f64> = (0..n).map(|i| 0.5 * (omega * i as f64 * h).sin()).collect();
        let work = stieltjes(path, &r, path.end(&r), &x, path.end(&x));
        let exact = -PI * 0.5 * 2.0;
        assert!((work / exact - 1.0).abs() < 1e-3, "{work} vs {exact}");
        let tv = total_variation(path, &x, path.end(&x));
        assert!((tv / 8.0 - 1.0).abs() < 1e-3, "{tv}");
    }

    /// The trapezoidal Stieltjes sum is exact when r is linear in x (r = a + b x, the
    /// work of a spring plus a constant force): ½(r_j + r_{j+1})Δx = aΔx + b Δ(x²)/2.
    #[test]
    fn stieltjes_is_exact_for_a_force_linear_in_displacement() {
        let path = Path {
            whole: 7,
            frac: 0.4,
            closed: false,
        };
        let x = [0.0, 0.3, -0.2, 1.1, 0.9, 0.4, -0.5, -0.1, 0.7];
        let r: Vec<f64> = x.iter().map(|x| 2.0 - 3.0 * x).collect();
        let x_end = path.end(&x);
        let exact = 2.0 * (x_end - x[0]) - 1.5 * (x_end * x_end - x[0] * x[0]);
        let got = stieltjes(path, &r, path.end(&r), &x, x_end);
        assert!((got - exact).abs() < 1e-13, "{got} vs {exact}");
    }
}
