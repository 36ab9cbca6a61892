//! The exact Jacobian columns of the projected residual in a table's residual unknowns
//! (Golub–Pereyra), for the Levenberg–Marquardt of `levenberg_marquardt.rs`.
//!
//! With the rows weighted by fixed weights w (w = 1 for ordinary weighting),
//! Ã = W^{1/2} A(η), b̃ = W^{1/2} b, and the inner fit plain least squares,
//!
//! ```text
//!   θ̂ = Ã⁺ b̃,   ρ(η) = Ã θ̂ − b̃,
//!   ∂ρ/∂η_j = P⊥ (∂Ã θ̂) − (Ã⁺)ᵀ (∂Ãᵀ ρ),   P⊥ = I − U_r U_rᵀ,
//!   (Ã⁺)ᵀ g = U_r Σ_r⁻¹ V_rᵀ S⁻¹ g,          Ã S⁻¹ = U Σ Vᵀ,
//! ```
//!
//! U, Σ, V, S and the numerical rank r those of the inner fit's own SVD
//! ([`crate::fit::svd::ScaledSvd`]), ∂Ã/∂η_j = W^{1/2} ∂A/∂η_j (b does not depend on the
//! residual unknowns) in closed form and nonzero only on the rows of η_j's sweep
//! ([`super::sweep_blocks::SweepBlocks::derivative`]): ∂Ã θ̂, ∂Ãᵀρ and U_rᵀ(∂Ã θ̂) read
//! those rows alone, one column costs O(m p). No Kaufman term is dropped.
//!
//! A constrained inner fit (the user's constraints, solved by clarabel) is not
//! differentiated so (its active set moves the projection): its columns stay the fit
//! of A(η) + h ∂A/∂η_j, a forward difference ([`super::problem::Problem::shifted_by`]).

use std::cell::RefCell;

use crate::error::Result;
use crate::fit::FitSettings;
use crate::fit::factored_least_squares;
use crate::fit::svd::ScaledSvd;
use crate::regressor::Regressor;

use super::minimum::Column;
use super::problem::{Problem, weighted_residuals};
use super::sweep_blocks::RowDerivatives;

/// The inner fit at one η, factored: what every column at that η reads.
pub(super) struct Projection {
    theta: Vec<f64>,
    residual: Vec<f64>,
    svd: ScaledSvd,
}

impl Projection {
    /// The plain least-squares fit of the rows `rows` (Ã, b̃) with `settings`' rank
    /// tolerance, as [`crate::fit::solve`] makes it for unconstrained ordinary fits.
    pub fn new(rows: &Regressor, settings: &FitSettings) -> Result<Self> {
        let (fit, svd) = factored_least_squares(rows, settings.rank_tolerance)?;
        let residual = weighted_residuals(rows, &fit.coefficients, None);
        Ok(Projection {
            theta: fit.coefficients,
            residual,
            svd,
        })
    }

    /// ∂ρ/∂η_j from ∂A/∂η_j on its rows `derivative` (rows of Ã's numbering), the rows
    /// weighted by `weights` (module doc).
    pub fn column(&self, derivative: &RowDerivatives, weights: Option<&[f64]>) -> Vec<f64> {
        let u = self.svd.u();
        let v = self.svd.v();
        let sigma = self.svd.singular_values();
        let rank = self.svd.rank();
        let scale = &self.svd.scaling().columns;
        let p = self.theta.len();
        let m = self.residual.len();
        // ∂Ã θ̂ on the sweep's rows, ∂Ãᵀ ρ and U_rᵀ (∂Ã θ̂)
        let mut column = vec![0.0; m];
        let mut g = vec![0.0; p];
        let mut c = vec![0.0; rank];
        for (row, d) in derivative {
            let w = weights.map_or(1.0, |w| w[*row]);
            let moved: f64 = d.iter().zip(&self.theta).map(|(x, t)| x * t).sum::<f64>() * w;
            column[*row] = moved;
            for (k, x) in d.iter().enumerate().take(p) {
                g[k] += w * x * self.residual[*row];
            }
            for (i, ci) in c.iter_mut().enumerate() {
                *ci += u[(*row, i)] * moved;
            }
        }
        // + Σ_r⁻¹ V_rᵀ S⁻¹ g
        for (i, ci) in c.iter_mut().enumerate() {
            let e: f64 = (0..p).map(|k| v[(k, i)] * g[k] / scale[k]).sum();
            *ci += e / sigma[i];
        }
        for (r, x) in column.iter_mut().enumerate() {
            *x -= (0..rank).map(|i| u[(r, i)] * c[i]).sum::<f64>();
        }
        column
    }
}

/// The projections kept by one Levenberg–Marquardt hook: the last η's (its bits).
pub(super) type Projections = RefCell<Option<(Vec<u64>, Projection)>>;

/// The Levenberg–Marquardt column of η_j at `eta` (step `h` for a difference) for the
/// fit with `settings` of `base` = A(η) (without its noise model) weighted by `weights`:
/// ∂ρ/∂η_j exact (module doc) for an unconstrained fit, else the residual of the fit of
/// A(η) + h ∂A/∂η_j; `None` when ∂A/∂η_j has no closed form (a law parameter: the caller
/// differences whole trials). `kept` holds the factored fit at the last η.
#[allow(clippy::too_many_arguments)]
pub(super) fn column(
    problem: &Problem<'_>,
    kept: &Projections,
    base: &Regressor,
    weights: Option<&[f64]>,
    settings: &FitSettings,
    eta: &[f64],
    j: usize,
    h: f64,
) -> Result<Option<Column>> {
    let Some(derivative) = problem.derivative_rows(eta, j)? else {
        return Ok(None);
    };
    let weighted = |rows: Regressor| -> Result<Regressor> {
        match weights {
            Some(w) => rows.weighted(w),
            None => Ok(rows),
        }
    };
    if !settings.constraints.is_empty() {
        let moved = weighted(Problem::shifted_by(base, &derivative, h)?)?;
        let fit = crate::fit::solve(&moved, settings)?;
        return Ok(Some(Column::Shifted(weighted_residuals(
            &moved,
            &fit.coefficients,
            fit.residual_std.as_deref(),
        ))));
    }
    let key: Vec<u64> = eta.iter().map(|x| x.to_bits()).collect();
    let mut kept = kept.borrow_mut();
    if kept.as_ref().is_none_or(|(at, _)| *at != key) {
        let projection = match weights {
            Some(w) => Projection::new(&base.weighted(w)?, settings)?,
            None => Projection::new(base, settings)?,
        };
        *kept = Some((key, projection));
    }
    // cannot fail: set just above when it was not the projection at `eta`.
    let (_, projection) = kept.as_ref().expect("projection at eta");
    Ok(Some(Column::Derivative(
        projection.column(&derivative, weights),
    )))
}

#[cfg(test)]
mod tests {
    use faer::Mat;

    use super::*;
    use crate::regressor::RowLabel;

    fn regressor(a: &Mat<f64>, b: &[f64]) -> Regressor {
        let rows = (0..a.nrows())
            .map(|i| RowLabel {
                record: "r".into(),
                record_index: 0,
                window: i,
                start_time: 0.0,
                cycles: 1,
                frequency: None,
            })
            .collect();
        Regressor::from_parts(
            a.clone(),
            b.to_vec(),
            (0..a.ncols()).map(|k| format!("c{k}")).collect(),
            rows,
        )
        .expect("a valid regressor")
    }

    /// ρ of the weighted least-squares fit of A + t D.
    fn residual_at(a: &Mat<f64>, d: &Mat<f64>, b: &[f64], w: &[f64], t: f64) -> Vec<f64> {
        let moved = Mat::from_fn(a.nrows(), a.ncols(), |i, k| a[(i, k)] + t * d[(i, k)]);
        let rows = regressor(&moved, b).weighted(w).expect("weights");
        let fit = crate::fit::least_squares(&rows, 1e-12).expect("a fit");
        weighted_residuals(&rows, &fit.coefficients, None)
    }

    /// The exact column against central differences of whole fits (Richardson
    /// extrapolated), on a weighted three-column problem whose ∂A touches a block of
    /// rows, with a residual far from zero.
    #[test]
    fn column_matches_central_differences() {
        let m = 40;
        let a = Mat::from_fn(m, 3, |i, k| {
            let x = i as f64 / m as f64;
            [1.0 + x, x * x * 3.0 - 0.5, (4.0 * x).sin()][k] * 10f64.powi(k as i32 - 1)
        });
        let b: Vec<f64> = (0..m)
            .map(|i| (i as f64 * 0.37).cos() + 0.1 * i as f64)
            .collect();
        let w: Vec<f64> = (0..m).map(|i| 1.0 + 0.5 * (i as f64).sin()).collect();
        let block: Vec<usize> = (10..22).collect();
        let d = Mat::from_fn(m, 3, |i, k| {
            if block.contains(&i) {
                ((i * 3 + k) as f64).cos() * 10f64.powi(k as i32 - 1)
            } else {
                0.0
            }
        });
        let derivative: RowDerivatives = block
            .iter()
            .map(|&i| (i, (0..3).map(|k| d[(i, k)]).collect()))
            .collect();
        let settings = FitSettings::default();
        let rows = regressor(&a, &b).weighted(&w).expect("weights");
        let exact = Projection::new(&rows, &settings)
            .expect("a fit")
            .column(&derivative, Some(&w));
        let central = |h: f64| -> Vec<f64> {
            let (hi, lo) = (
                residual_at(&a, &d, &b, &w, h),
                residual_at(&a, &d, &b, &w, -h),
            );
            hi.iter()
                .zip(&lo)
                .map(|(x, y)| (x - y) / (2.0 * h))
                .collect()
        };
        let (c1, c2) = (central(1e-3), central(5e-4));
        let richardson: Vec<f64> = c1
            .iter()
            .zip(&c2)
            .map(|(x, y)| (4.0 * y - x) / 3.0)
            .collect();
        let norm = richardson.iter().map(|x| x * x).sum::<f64>().sqrt();
        let error = exact
            .iter()
            .zip(&richardson)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(norm > 1e-3, "a column that is not trivially zero: {norm}");
        assert!(error <= 1e-6 * norm, "relative error {}", error / norm);
    }
}
