//! Lack of fit of an unweighted fit, with the windows of one record as replicates. A
//! weighted fit checks its residuals against the propagated noise (the χ² check of
//! [`crate::analysis::diagnostics`]); an unweighted fit has no noise model, but the
//! windows of whole periods of one steady record repeat one experiment
//! ([`crate::analysis::replicates`]), so the scatter of the residuals within a record
//! is what noise does, and what the records' mean residuals add beyond it is misfit.
//! With e_i = b_i − a_iᵀθ, experiment g (a record's windows; a stepped-sine point or a
//! span alone) of m_g rows with mean residual ē_g, R experiments and q free
//! coefficients and parameters:
//!
//! ```text
//!   SS_pe  = Σ_g Σ_{i∈g} (e_i − ē_g)²,   ν_pe  = Σ_g (m_g − 1)      (pure error)
//!   SS_lof = Σ_g m_g ē_g²,               ν_lof = R − q              (lack of fit)
//!   F = (SS_lof/ν_lof) / (SS_pe/ν_pe),   P = P(F_{ν_lof, ν_pe} > F)
//! ```
//!
//! (SS_lof + SS_pe = ‖e‖², the classical decomposition). The fit is rejected when
//! P < [`REJECTION_P_VALUE`] = 1 % (the χ² check's level) and the misfit could move the
//! coefficients materially:
//!
//! ```text
//!   κ · √SS_lof / ‖b‖  ≥  MATERIAL = 10⁻³,
//! ```
//!
//! with κ the condition number of the column-scaled regressor: a change δb of the input
//! work moves the scaled coefficients by at most κ ‖δb‖/‖b‖ of their size (the
//! least-squares perturbation bound for a small residual), so a misfit that cannot move
//! them by 0.1 % is not reported. The floor is needed because clean simulated records
//! have no pure error but round-off and discretisation error (10⁻¹⁶ to 10⁻⁶ of the
//! input work), whose differences between records are "significant" against a pure
//! error of round-off. Measured on the shipped models: a clean chain with one dashpot
//! per element, κ · misfit = 1.5·10⁻⁵ (F = 78); a Rayleigh chain 1.7·10⁻⁶ (F = 141); an
//! Iwan joint with a fitted power law 2.2·10⁻⁴ (F = 10¹⁴); noisy records of a correct
//! model are not significant (F ≈ 1); the measured chain fitted without its friction
//! term 1.8 (misfit 2.3 %), rejected.
//!
//! **Why it matters.** An error common to a record's windows (velocities given as
//! displacements, a force on the wrong DOF, a model that misses a mechanism) shifts
//! the record's equations together. The residual variance s² = ‖e‖²/(m − q) divides
//! that shift among all m windows as if each were independent, but a record's windows
//! are one experiment: with a record error δ_g of variance σ_δ² and window noise of
//! variance σ², E[SS_lof/ν_lof] = σ² + m̄ σ_δ² (one-way analysis of variance), which
//! is the variance of the estimate's error along the records' mean rows. So a rejected
//! fit's standard errors are taken from the records' means,
//!
//! ```text
//!   se_k = √(SS_lof/ν_lof) · √([(A_FᵀA_F)⁻¹]_kk) = scale · se_k(s²),
//!   scale = √((SS_lof/ν_lof) / s²) > 1,
//! ```
//!
//! (s² is a weighted mean of SS_lof/ν_lof and SS_pe/ν_pe, so a significant F makes the
//! scale exceed 1, and the rule never narrows an interval). The physics fuzz target
//! found the case: a 2-DOF chain, four noise-free records with velocities given as
//! displacements, spectral velocities, gave c[0-1] = 0.021 ± 0.0099 for a truth of
//! 0.19 with "every coefficient is determined" (within-record scatter 10⁻²⁸, record
//! means 53 in units of work², relative misfit 6.8 %).

use crate::analysis::replicates::grouped;
use crate::analysis::stats::f_upper_tail;
use crate::fit::scaling::norm;
use crate::regressor::Regressor;

use serde::{Deserialize, Serialize};

/// The smallest κ · √SS_lof / ‖b‖, a bound on the coefficients' relative change by the
/// misfit, that the check reports (module doc).
pub const MATERIAL: f64 = 1e-3;

/// P below which the test rejects a fit: 1 %, the level of the χ² check of weighted fits.
pub const REJECTION_P_VALUE: f64 = 0.01;

/// How many experiments the result names, largest share of SS_lof first.
const NAMED: usize = 3;

/// The lack-of-fit test of one unweighted fit (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LackOfFit {
    /// √SS_lof / ‖b‖: the share of the input work the records' means leave unexplained.
    pub relative_misfit: f64,
    /// κ · √SS_lof / ‖b‖: how far the misfit can move the column-scaled coefficients,
    /// relative to their size (infinite when the regressor is rank deficient).
    pub coefficient_bound: f64,
    /// F = (SS_lof/ν_lof) / (SS_pe/ν_pe); `None` when SS_pe = 0 (F is infinite).
    pub f_statistic: Option<f64>,
    /// ν_lof = experiments − free coefficients and parameters.
    pub degrees_of_freedom: usize,
    /// ν_pe = Σ (windows − 1) over the records.
    pub pure_error_degrees_of_freedom: usize,
    /// P(F_{ν_lof, ν_pe} > F).
    pub p_value: f64,
    /// √((SS_lof/ν_lof) / s²), the factor on the residual-variance standard errors.
    pub scale: f64,
    /// The experiments with the largest shares of SS_lof, with those shares.
    pub records: Vec<(String, f64)>,
}

impl LackOfFit {
    /// Whether the fit is rejected: significant and material (module doc).
    pub fn rejects(&self) -> bool {
        self.p_value < REJECTION_P_VALUE && self.coefficient_bound >= MATERIAL && self.scale > 1.0
    }
}

/// The test of the fit with `residuals` on `regressor`'s (unweighted) rows, with
/// `parameters` free coefficients and estimated parameters and the column-scaled
/// regressor's `condition_number`; `None` without degrees of freedom for both sums (no
/// more experiments than parameters, or no record with two windows).
pub fn lack_of_fit(
    regressor: &Regressor,
    residuals: &[f64],
    parameters: usize,
    condition_number: f64,
) -> Option<LackOfFit> {
    let groups = grouped(regressor);
    let dof_lof = groups.len().checked_sub(parameters).filter(|d| *d > 0)?;
    let dof_pe: usize = groups.iter().map(|g| g.rows.len() - 1).sum();
    if dof_pe == 0 {
        return None;
    }
    let m = residuals.len();
    let dof = m.checked_sub(parameters).filter(|d| *d > 0)?;
    // Sums of squares on residuals divided by their largest, so that data of any scale
    // neither overflow nor underflow (ratios are what the test reads).
    let largest = residuals.iter().fold(0.0f64, |a, e| a.max(e.abs()));
    if !(largest.is_finite() && largest > 0.0) {
        return None;
    }
    let (mut pure, mut misfit) = (0.0, 0.0);
    let mut shares: Vec<(String, f64)> = Vec::with_capacity(groups.len());
    for group in &groups {
        let scaled: Vec<f64> = group.rows.iter().map(|i| residuals[*i] / largest).collect();
        let mean = scaled.iter().sum::<f64>() / scaled.len() as f64;
        pure += scaled.iter().map(|e| (e - mean).powi(2)).sum::<f64>();
        let between = scaled.len() as f64 * mean * mean;
        misfit += between;
        let label = &regressor.rows()[group.rows[0]];
        let name = if group.replicated {
            label.record.clone()
        } else {
            label.to_string()
        };
        shares.push((name, between));
    }
    let ms_lof = misfit / dof_lof as f64;
    let ms_pe = pure / dof_pe as f64;
    let f_statistic = (pure > 0.0).then(|| ms_lof / ms_pe);
    let p_value = f_upper_tail(
        f_statistic.unwrap_or(f64::INFINITY),
        dof_lof as f64,
        dof_pe as f64,
    );
    let s2 = (misfit + pure) / dof as f64;
    let scale = if s2 > 0.0 { (ms_lof / s2).sqrt() } else { 1.0 };
    let b_norm = norm(regressor.rhs());
    let relative_misfit = if b_norm > 0.0 {
        // √(misfit) · largest / ‖b‖, without forming the product of two extremes first.
        misfit.sqrt() * (largest / b_norm)
    } else {
        f64::INFINITY
    };
    shares.iter_mut().for_each(|(_, s)| *s /= misfit);
    shares.sort_by(|a, b| b.1.total_cmp(&a.1));
    shares.truncate(NAMED);
    let coefficient_bound = if condition_number.is_finite() {
        condition_number * relative_misfit
    } else {
        f64::INFINITY
    };
    Some(LackOfFit {
        relative_misfit,
        coefficient_bound,
        f_statistic,
        degrees_of_freedom: dof_lof,
        pure_error_degrees_of_freedom: dof_pe,
        p_value,
        scale,
        records: shares,
    })
}
