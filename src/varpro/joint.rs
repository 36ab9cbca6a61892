//! The joint covariance of the linear coefficients θ and the nonlinear parameters η at
//! the optimum, from the full Jacobian of the weighted residuals r = W^{1/2}(A(η)θ − b):
//!
//! ```text
//!   J = [W^{1/2} A(η̂),  ∂r/∂η],   Cov(θ, η) = σ² (JᵀJ)⁻¹,
//! ```
//!
//! σ² as [`super::problem::Variance`] says. ∂r/∂η_j at fixed θ̂ and W: W^{1/2} ∂A/∂η_j θ̂
//! in closed form for a table's residual unknowns (`sweep_blocks.rs`, its sweep's rows
//! alone), else by central differences with a step of 10⁻⁵ of the parameter's bound
//! interval (one-sided at a bound).
//! JᵀJ is never formed: J's columns are scaled to unit norm and (JᵀJ)⁻¹ = S⁻¹VΣ⁻²VᵀS⁻¹
//! from the thin SVD J_s = UΣVᵀ; a rank below p + q (singular values under 10⁻¹⁰σ₁)
//! leaves every standard error out. The covariance itself (θ then η, the report's
//! `covariance`) is σ² S⁻¹VΣ⁻²VᵀS⁻¹ entry by entry. The half-width of an interval is the standard error
//! times the Student t_ν quantile (σ² estimated) or the normal one (plug-in).

use faer::Mat;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

use super::problem::{Problem, Trial, Variance, weighted_residuals};
use crate::error::{Error, Result};

/// Standard errors of θ then η, their covariance, and the quantile their intervals use.
pub(super) struct Joint {
    pub std_errors: Vec<Option<f64>>,
    /// σ² S⁻¹VΣ⁻²VᵀS⁻¹, (p + q) × (p + q), θ then η; `None` when an entry is not finite.
    pub covariance: Option<Vec<Vec<f64>>>,
    pub quantile: f64,
}

/// The joint covariance at the optimum `eta` (its trial `best`), or `None` when J is
/// rank deficient.
pub(super) fn covariance(
    problem: &Problem<'_>,
    best: &Trial,
    eta: &[f64],
    variance: Variance,
    dof: usize,
    level: f64,
) -> Result<Option<Joint>> {
    let a = best.regressor.matrix();
    let (m, p) = (a.nrows(), a.ncols());
    let q = eta.len();
    let std = best.fit.residual_std.as_deref();
    let theta = &best.fit.coefficients;
    let mut columns: Vec<Vec<f64>> = (0..p)
        .map(|k| {
            (0..m)
                .map(|r| a[(r, k)] / std.map_or(1.0, |s| s[r]))
                .collect()
        })
        .collect();
    let parameters = problem.parameters();
    for j in 0..q {
        // a table's residual unknown: ∂A/∂η_j θ̂ / s in closed form, on its sweep's rows
        if let Some(derivative) = problem.derivative_rows(eta, j)? {
            let mut column = vec![0.0; m];
            for (row, d) in &derivative {
                let moved: f64 = d.iter().zip(theta).map(|(x, t)| x * t).sum();
                column[*row] = moved / std.map_or(1.0, |s| s[*row]);
            }
            columns.push(column);
            continue;
        }
        let spec = &parameters[j];
        let h = 1e-5 * (spec.upper - spec.lower);
        let shifted = |t: f64| -> Result<Vec<f64>> {
            let mut at = eta.to_vec();
            at[j] = t;
            // A and b alone: the noise model is not read at fixed θ̂ and W
            let regressor = problem.equations(&at)?;
            Ok(weighted_residuals(&regressor, theta, std))
        };
        let (lo, hi) = ((eta[j] - h).max(spec.lower), (eta[j] + h).min(spec.upper));
        let (r_lo, r_hi) = (shifted(lo)?, shifted(hi)?);
        columns.push(
            r_lo.iter()
                .zip(&r_hi)
                .map(|(l, h)| (h - l) / (hi - lo))
                .collect(),
        );
    }
    let norms: Vec<f64> = columns
        .iter()
        .map(|c| c.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    if norms.iter().any(|&n| !(n > 0.0 && n.is_finite())) {
        return Ok(None);
    }
    let j_s = Mat::from_fn(m, p + q, |r, k| columns[k][r] / norms[k]);
    let svd = j_s.thin_svd().map_err(|e| Error::Numerical {
        stage: "SVD of the variable-projection Jacobian".into(),
        detail: format!("{e:?}"),
    })?;
    let s = svd.S().column_vector();
    let sigma: Vec<f64> = (0..p + q).map(|i| s[i]).collect();
    if sigma.iter().any(|&x| x.is_nan() || x <= 1e-10 * sigma[0]) {
        return Ok(None);
    }
    let v = svd.V();
    let std_errors = (0..p + q)
        .map(|k| {
            let c: f64 = (0..p + q).map(|i| (v[(k, i)] / sigma[i]).powi(2)).sum();
            let se = (variance.scale * c).sqrt() / norms[k];
            se.is_finite().then_some(se)
        })
        .collect();
    let covariance: Vec<Vec<f64>> = (0..p + q)
        .map(|k| {
            (0..p + q)
                .map(|l| {
                    let c: f64 = (0..p + q)
                        .map(|i| v[(k, i)] * v[(l, i)] / (sigma[i] * sigma[i]))
                        .sum();
                    variance.scale * c / (norms[k] * norms[l])
                })
                .collect()
        })
        .collect();
    let covariance = covariance
        .iter()
        .flatten()
        .all(|x| x.is_finite())
        .then_some(covariance);
    let tail = (1.0 + level) / 2.0;
    let quantile = if variance.estimated {
        StudentsT::new(0.0, 1.0, dof as f64)
            .map(|d| d.inverse_cdf(tail))
            .map_err(|e| e.to_string())
    } else {
        Normal::new(0.0, 1.0)
            .map(|d| d.inverse_cdf(tail))
            .map_err(|e| e.to_string())
    }
    .map_err(|e| Error::Numerical {
        stage: "joint intervals".into(),
        detail: e,
    })?;
    Ok(Some(Joint {
        std_errors,
        covariance,
        quantile,
    }))
}
