//! What the data say about a fit.
//!
//! - Residuals e = b − A θ (input work minus identified dissipated work, per window),
//!   the relative residual ‖e‖/‖b‖, and the residual bias: mean(e)/mean(|b|) with the
//!   counts of positive and negative residuals. A model that misses a mechanism leaves
//!   residuals of one sign (the paper's one-mode string fit is "negatively biased").
//! - Conditioning of the column-scaled regressor A_s (unit-norm columns): its singular
//!   values, κ = σ_1/σ_p, and the numerical rank (σ_i > tol·σ_1). κ near 1 means the
//!   columns are nearly orthogonal; κ ≫ 1 means some combination of coefficients is
//!   barely determined by the data.
//! - Standard errors from the residual variance when there is redundancy: with F the
//!   coefficients not held at a bound, s² = ‖e‖²/(m − |F|) and
//!   Cov(θ_F) = s² (A_Fᵀ A_F)⁻¹ = s² S⁻¹ V Σ⁻² Vᵀ S⁻¹ from the SVD of the scaled A_F;
//!   the correlation matrix follows. Coefficients held at a bound get none.
//! - With propagated weights (the noise-robust pipeline), every quantity above except
//!   the residuals is computed on the weighted rows e_r/s_r, and the plug-in covariance
//!   (A_Fᵀ W A_F)⁻¹, W = diag(1/s_r²), gives standard errors that need no residual
//!   variance. The weighted residual sum of squares χ² = Σ (e_r/s_r)² against its
//!   ν = m − |F| degrees of freedom checks the model: a χ² far above ν (upper-tail
//!   probability P(χ²_ν > χ²) below [`REJECTION_P_VALUE`] = 1%) says the residuals are
//!   larger than the noise explains (a missing mechanism, a transient, coloured noise,
//!   or, on clean simulated data, discretisation error that no noise model describes).
//! - The standard errors the report shows ([`Diagnostics::std_errors`], their basis in
//!   [`StandardErrorBasis`]), one rule:
//!
//!   ```text
//!     unweighted fit:                     se_k = √(s² [(A_FᵀA_F)⁻¹]_kk),  s² = ‖e‖²/ν
//!     unweighted, lack of fit rejects:    se_k = scale · √(s² [(A_FᵀA_F)⁻¹]_kk) (between records)
//!     weighted, P(χ²_ν > χ²) ≥ 1%:        se_k = √([(A_FᵀWA_F)⁻¹]_kk)          (plug-in)
//!     weighted, P(χ²_ν > χ²) < 1%:        se_k = √(χ²/ν) · √([(A_FᵀWA_F)⁻¹]_kk) (scaled)
//!   ```
//!
//!   When the model check rejects the fit the noise model does not describe the
//!   residuals, so the plug-in errors (which on clean data rest on a round-off noise
//!   estimate) say nothing; the residual scatter does, and χ²/ν is its ratio to the
//!   noise model. The scale is then > 1 (a rejected χ² exceeds ν), so the rule never
//!   narrows an interval, and it leaves the intervals of every fit that passes the check
//!   exactly as they were. It is the weighted form of the unweighted rule, the same
//!   s² (A_FᵀWA_F)⁻¹ with s² = χ²/ν. An unweighted fit has no noise model to check
//!   against, but when its records have replicate windows the lack-of-fit test
//!   ([`crate::analysis::lack_of_fit`]) compares the records' mean residuals with the
//!   scatter within records, and a rejected fit takes its errors from the records'
//!   means, scale = √((SS_lof/ν_lof)/s²) > 1. The sandwich (heteroscedasticity-consistent) form
//!   was measured against it on the reference cases (docs/noise.md) and is not used.
//! - Identifiability (see [`crate::analysis::identifiability`]): practically zero singular values
//!   against the noise level of the equations, near-null directions and determined
//!   combinations by name, variance inflation factors.

use std::fmt;

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::analysis::identifiability::{
    Identifiability, IdentifiabilitySettings, analyse, analyse_factored,
};
use crate::analysis::lack_of_fit::{LackOfFit, lack_of_fit};
use crate::fit::scaling::{Scaling, norm};
use crate::fit::svd::numerical_rank;
use crate::fit::{Fit, ScaledSvd};
use crate::regressor::Regressor;

/// Upper-tail probability P(χ²_ν > χ²) below which the model check rejects a weighted
/// fit: its standard errors are then scaled by √(χ²/ν) (see the module doc), and the
/// report warns ([`crate::report::INADEQUATE_P_VALUE`] is this level). At 1% a fit
/// whose residuals are noise as modelled is rejected once in a hundred, and then its
/// errors grow by √(χ²/ν), which is close to 1 for many degrees of freedom (1.3 at
/// ν = 30 on the rejection boundary, 2.1 at ν = 2).
pub const REJECTION_P_VALUE: f64 = 0.01;

/// Where the standard errors of a fit come from (one rule, in the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "basis")]
pub enum StandardErrorBasis {
    /// An unweighted fit: s² (A_FᵀA_F)⁻¹ with s² = ‖e‖²/ν, the residual variance.
    #[default]
    ResidualVariance,
    /// A weighted fit whose χ² check passes (or has no degrees of freedom): the plug-in
    /// (A_FᵀWA_F)⁻¹ of the propagated noise.
    PlugIn,
    /// A weighted fit whose χ² check rejects it: (χ²/ν) (A_FᵀWA_F)⁻¹, the plug-in
    /// errors times `scale` = √(χ²/ν), from the residual scatter.
    ScaledPlugIn {
        /// χ²/ν.
        chi_square_per_dof: f64,
        /// √(χ²/ν), the factor on every plug-in standard error.
        scale: f64,
    },
    /// An unweighted fit whose lack-of-fit test rejects it
    /// ([`crate::analysis::lack_of_fit`]): the residual-variance errors times `scale`,
    /// √((SS_lof/ν_lof) (A_FᵀA_F)⁻¹), from the scatter of the records' mean residuals.
    BetweenRecords {
        /// F of the test (`None`: infinite, the windows of each record agree exactly).
        f_statistic: Option<f64>,
        /// √((SS_lof/ν_lof)/s²), the factor on every residual-variance standard error.
        scale: f64,
    },
}

/// Mean signed residual relative to the mean |b|, and the sign counts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ResidualBias {
    /// mean(e) / mean(|b|).
    pub relative_mean: f64,
    /// Residuals > 0 (input work exceeds identified dissipation).
    pub positive: usize,
    /// Residuals < 0.
    pub negative: usize,
}

/// Correlation between the free coefficients.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Correlation {
    /// Coefficient names, in matrix order.
    pub names: Vec<String>,
    /// Row-major correlation matrix.
    pub matrix: Vec<Vec<f64>>,
}

impl fmt::Display for Correlation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.names.len() > crate::analysis::digest::FULL_LISTING {
            return self.digest(f);
        }
        let width = self.names.iter().map(|n| n.len()).max().unwrap_or(0).max(7);
        writeln!(f, "correlation of the estimates:")?;
        write!(f, "  {:width$}", "")?;
        for n in &self.names {
            write!(f, " {n:>width$}")?;
        }
        writeln!(f)?;
        for (n, row) in self.names.iter().zip(&self.matrix) {
            write!(f, "  {n:<width$}")?;
            for r in row {
                write!(f, " {r:>width$.3}")?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}

impl Correlation {
    /// The text form for many coefficients: the [`crate::analysis::digest::LISTED`] pairs
    /// of largest |correlation| (the whole matrix is in the JSON).
    fn digest(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.names.len();
        let pairs: Vec<(usize, usize)> = (0..p)
            .flat_map(|i| (i + 1..p).map(move |j| (i, j)))
            .collect();
        let values: Vec<f64> = pairs.iter().map(|&(i, j)| self.matrix[i][j]).collect();
        let top: Vec<String> =
            crate::analysis::digest::largest(&values, crate::analysis::digest::LISTED)
                .into_iter()
                .map(|k| {
                    let (i, j) = pairs[k];
                    format!("{} ~ {} {:.3}", self.names[i], self.names[j], values[k])
                })
                .collect();
        writeln!(
            f,
            "correlation of the estimates ({p} coefficients, the matrix in the JSON); largest |r|: {}",
            top.join(", ")
        )
    }
}

/// Diagnostics of one fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostics {
    /// e = b − A θ.
    pub residuals: Vec<f64>,
    /// ‖e‖ / ‖b‖.
    pub relative_residual: f64,
    /// Bias of the residuals.
    pub residual_bias: ResidualBias,
    /// Singular values of the column-scaled regressor, descending.
    pub singular_values: Vec<f64>,
    /// σ_1/σ_p; infinite when the regressor is rank deficient.
    pub condition_number: f64,
    /// Numerical rank.
    pub rank: usize,
    /// The standard error per coefficient the report shows (None when not estimable),
    /// by the rule of the module doc.
    pub std_errors: Vec<Option<f64>>,
    /// Which covariance `std_errors` come from.
    pub std_error_basis: StandardErrorBasis,
    /// Correlation of the free coefficients, when standard errors exist.
    pub correlation: Option<Correlation>,
    /// What the data can and cannot determine.
    pub identifiability: Identifiability,
    /// With propagated weights: the model-adequacy check and plug-in standard errors.
    pub weighted: Option<WeightedDiagnostics>,
    /// Without them: the lack-of-fit test with a record's windows as replicates
    /// ([`crate::analysis::lack_of_fit`]), when it has degrees of freedom.
    pub lack_of_fit: Option<LackOfFit>,
    /// m − (free coefficients) − (nonlinear parameters), saturating at 0.
    pub degrees_of_freedom: usize,
    /// The nonlinear parameters estimated outside the linear fit (they use degrees of
    /// freedom and experiments too).
    pub nonlinear_parameters: usize,
}

/// Diagnostics of a fit weighted by propagated residual variances.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WeightedDiagnostics {
    /// χ² = Σ_r (e_r/s_r)².
    pub chi_square: f64,
    /// m − |F|.
    pub degrees_of_freedom: usize,
    /// P(χ²_dof > χ²): values below [`REJECTION_P_VALUE`] say the residuals exceed the
    /// noise. None without degrees of freedom.
    pub p_value: Option<f64>,
    /// Plug-in standard errors √diag((A_Fᵀ W A_F)⁻¹) (None for coefficients at a bound).
    pub plug_in_std_errors: Vec<Option<f64>>,
    /// The plug-in standard errors times √(χ²/dof), from the residual scatter
    /// (None without degrees of freedom).
    pub scaled_std_errors: Vec<Option<f64>>,
    /// s_r, the propagated standard deviation of each equation's residual.
    pub residual_std: Vec<f64>,
}

/// Computes the diagnostics of `fit` on `regressor` (on its weighted rows when the fit
/// was weighted).
pub fn diagnose(regressor: &Regressor, fit: &Fit, rank_tolerance: f64) -> Diagnostics {
    diagnose_factored(regressor, fit, rank_tolerance, None, 0)
}

/// [`diagnose`], with the factorization of `regressor`'s rows when the fit made one
/// ([`crate::fit::solve_factored`]), so that they are factored once; `nonlinear`
/// parameters estimated outside the fit use degrees of freedom too
/// ([`crate::fit::FitSettings::nonlinear_parameters`]).
pub(crate) fn diagnose_factored(
    regressor: &Regressor,
    fit: &Fit,
    rank_tolerance: f64,
    svd: Option<ScaledSvd>,
    nonlinear: usize,
) -> Diagnostics {
    let Some(std) = &fit.residual_std else {
        return diagnose_rows(regressor, fit, rank_tolerance, None, svd, nonlinear);
    };
    let weights = crate::fit::inverse_std(std);
    let Ok(weighted) = regressor.weighted(&weights) else {
        return diagnose_rows(regressor, fit, rank_tolerance, None, svd, nonlinear);
    };
    // Residuals and their bias in physical units; everything else on the weighted rows.
    let physical = Residuals::of(regressor, fit);
    let mut diagnostics = diagnose_rows(&weighted, fit, rank_tolerance, Some(std), None, nonlinear);
    diagnostics.residuals = physical.residuals;
    diagnostics.relative_residual = physical.relative_residual;
    diagnostics.residual_bias = physical.residual_bias;
    diagnostics
}

/// e = b − Aθ, ‖e‖/‖b‖ and the bias of e.
struct Residuals {
    residuals: Vec<f64>,
    relative_residual: f64,
    residual_bias: ResidualBias,
}

impl Residuals {
    fn of(regressor: &Regressor, fit: &Fit) -> Self {
        let a = regressor.matrix();
        let b = regressor.rhs();
        let (m, p) = a.shape();
        let theta = Mat::from_fn(p, 1, |j, _| fit.coefficients[j]);
        let fitted = a * &theta;
        let residuals: Vec<f64> = (0..m).map(|i| b[i] - fitted[(i, 0)]).collect();
        let b_norm = norm(b);
        let relative_residual = if b_norm > 0.0 {
            norm(&residuals) / b_norm
        } else {
            norm(&residuals)
        };
        let mean_abs_b = b.iter().map(|v| v.abs()).sum::<f64>() / m.max(1) as f64;
        let mean_e = residuals.iter().sum::<f64>() / m.max(1) as f64;
        let residual_bias = ResidualBias {
            relative_mean: if mean_abs_b > 0.0 {
                mean_e / mean_abs_b
            } else {
                mean_e
            },
            positive: residuals.iter().filter(|e| **e > 0.0).count(),
            negative: residuals.iter().filter(|e| **e < 0.0).count(),
        };
        Residuals {
            residuals,
            relative_residual,
            residual_bias,
        }
    }
}

fn diagnose_rows(
    regressor: &Regressor,
    fit: &Fit,
    rank_tolerance: f64,
    residual_std: Option<&Vec<f64>>,
    svd: Option<ScaledSvd>,
    nonlinear: usize,
) -> Diagnostics {
    let a = regressor.matrix();
    let (m, p) = a.shape();
    let Residuals {
        residuals,
        relative_residual,
        residual_bias,
    } = Residuals::of(regressor, fit);
    let svd = match svd {
        Some(svd) => Ok(svd),
        None => ScaledSvd::new(a, regressor.rhs(), rank_tolerance),
    };
    let (singular_values, rank, condition_number) = match &svd {
        Ok(svd) => (
            svd.singular_values().to_vec(),
            svd.rank(),
            svd.condition_number(),
        ),
        Err(_) => (Vec::new(), 0, f64::INFINITY),
    };
    let free: Vec<usize> = (0..p)
        .filter(|j| !fit.active.iter().any(|c| c.name == regressor.columns()[*j]))
        .collect();
    let unit = match &svd {
        // Every column free: (A_sᵀA_s)⁻¹ from the factorization already made.
        Ok(svd) if free.len() == p => full_covariance(svd, m),
        _ => unit_covariance(a, &Scaling::of(a, regressor.rhs()), &free, rank_tolerance),
    };
    let dof = m.saturating_sub(free.len() + nonlinear);
    let (std_errors, correlation) = unit
        .as_ref()
        .filter(|_| dof > 0)
        .map(|cov| {
            let (variance, beta) = scaled_variance(&residuals, dof);
            let (se, corr) = standard_errors(cov, variance, beta, &free, p, regressor.columns());
            (se, Some(corr))
        })
        .unwrap_or((vec![None; p], None));
    let weighted = residual_std.map(|std| {
        let chi_square: f64 = residuals.iter().map(|e| e * e).sum();
        let plug_in_std_errors = match &unit {
            Some(cov) => standard_errors(cov, 1.0, 1.0, &free, p, regressor.columns()).0,
            None => vec![None; p],
        };
        WeightedDiagnostics {
            chi_square,
            degrees_of_freedom: dof,
            p_value: (dof > 0)
                .then(|| crate::analysis::stats::chi_square_upper_tail(chi_square, dof as f64)),
            plug_in_std_errors,
            // s² (A_FᵀWA_F)⁻¹ on the weighted rows, s² = χ²/dof
            scaled_std_errors: std_errors.clone(),
            residual_std: std.clone(),
        }
    });
    let lack_of_fit = residual_std
        .is_none()
        .then(|| {
            lack_of_fit(
                regressor,
                &residuals,
                free.len() + nonlinear,
                condition_number,
            )
        })
        .flatten();
    let (std_errors, std_error_basis) = match (&weighted, &lack_of_fit) {
        (None, Some(l)) if l.rejects() => (
            std_errors
                .iter()
                .map(|se| se.map(|se| se * l.scale))
                .collect(),
            StandardErrorBasis::BetweenRecords {
                f_statistic: l.f_statistic,
                scale: l.scale,
            },
        ),
        (None, _) => (std_errors, StandardErrorBasis::ResidualVariance),
        (Some(w), _) => match w.p_value {
            Some(p) if p < REJECTION_P_VALUE => {
                let per_dof = w.chi_square / w.degrees_of_freedom as f64;
                let basis = StandardErrorBasis::ScaledPlugIn {
                    chi_square_per_dof: per_dof,
                    scale: per_dof.sqrt(),
                };
                (w.scaled_std_errors.clone(), basis)
            }
            _ => (w.plug_in_std_errors.clone(), StandardErrorBasis::PlugIn),
        },
    };
    let identifiability = match &svd {
        Ok(svd) => analyse_factored(
            regressor.columns().to_vec(),
            svd,
            rank_tolerance,
            &IdentifiabilitySettings {
                nonlinear_parameters: nonlinear,
                window_scatter: crate::analysis::replicates::window_scatter(regressor)
                    .unwrap_or(0.0),
                experiments: crate::analysis::replicates::experiments(regressor),
                noise_scale: match std_error_basis {
                    StandardErrorBasis::BetweenRecords { scale, .. } => scale,
                    _ => 1.0,
                },
                ..IdentifiabilitySettings::default()
            },
        ),
        Err(_) => analyse(regressor, rank_tolerance),
    };
    Diagnostics {
        residuals,
        relative_residual,
        residual_bias,
        singular_values,
        condition_number,
        rank,
        std_errors,
        std_error_basis,
        correlation,
        identifiability,
        weighted,
        lack_of_fit,
        degrees_of_freedom: dof,
        nonlinear_parameters: nonlinear,
    }
}

/// (A_Fᵀ A_F)⁻¹ with every column free, from the factorization of the scaled regressor:
/// S⁻¹ V Σ⁻² Vᵀ S⁻¹, when m > p and the columns have full rank.
/// (A_Fᵀ A_F)⁻¹ = S⁻¹ [(A_sᵀA_s)⁻¹] S⁻¹, kept as its scaled middle factor and the column
/// scales S of the free columns: with columns of norm 1e±160 the product overflows or
/// underflows, while the middle factor stays O(κ²) and a standard error is formed as
/// √(s² [(A_sᵀA_s)⁻¹]_jj) · β/S_j in that order (β the residuals' scale).
struct ScaledCovariance {
    /// (A_sᵀA_s)⁻¹ of the free columns.
    unit: Mat<f64>,
    /// S_j of the free columns.
    scales: Vec<f64>,
}

/// The covariance factors of every column, from the factorization already made.
fn full_covariance(svd: &ScaledSvd, m: usize) -> Option<ScaledCovariance> {
    let (s, v) = (svd.singular_values(), svd.v());
    let f = s.len();
    if f == 0 || m <= f || svd.rank() < f {
        return None;
    }
    Some(ScaledCovariance {
        unit: Mat::from_fn(f, f, |j, k| {
            (0..f).map(|i| v[(j, i)] * v[(k, i)] / (s[i] * s[i])).sum()
        }),
        scales: svd.scaling().columns.clone(),
    })
}

/// The covariance factors of the free columns (from the SVD of the scaled A_F), when
/// m > |F| and the free columns have full rank.
fn unit_covariance(
    a: &Mat<f64>,
    scaling: &Scaling,
    free: &[usize],
    rank_tolerance: f64,
) -> Option<ScaledCovariance> {
    let m = a.nrows();
    let f = free.len();
    if f == 0 || m <= f {
        return None;
    }
    let a_free = Mat::from_fn(m, f, |i, k| a[(i, free[k])] / scaling.columns[free[k]]);
    let svd = a_free.thin_svd().ok()?;
    let (s, v) = (svd.S().column_vector(), svd.V());
    let rank = numerical_rank(&(0..f).map(|i| s[i]).collect::<Vec<_>>(), rank_tolerance);
    if rank < f {
        return None;
    }
    Some(ScaledCovariance {
        unit: Mat::from_fn(f, f, |j, k| {
            (0..f).map(|i| v[(j, i)] * v[(k, i)] / (s[i] * s[i])).sum()
        }),
        scales: free.iter().map(|&j| scaling.columns[j]).collect(),
    })
}

/// The residual variance s² = Σ e_i²/ν as (s²/β², β), β = max |e_i|: the squares of
/// residuals of 1e±160 would overflow or underflow.
fn scaled_variance(residuals: &[f64], dof: usize) -> (f64, f64) {
    let beta = residuals.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    if beta == 0.0 || !beta.is_finite() {
        return (0.0, 1.0);
    }
    let sum: f64 = residuals.iter().map(|e| (e / beta).powi(2)).sum();
    (sum / dof as f64, beta)
}

/// Standard errors (one per coefficient, None when not free) and the correlation of
/// the free coefficients for Cov(θ_F) = β² · `variance` · S⁻¹ `cov.unit` S⁻¹.
fn standard_errors(
    cov: &ScaledCovariance,
    variance: f64,
    beta: f64,
    free: &[usize],
    coefficients: usize,
    names: &[String],
) -> (Vec<Option<f64>>, Correlation) {
    let unit = &cov.unit;
    let f = free.len();
    let mut std_errors = vec![None; coefficients];
    for (k, &j) in free.iter().enumerate() {
        let scaled = (variance * unit[(k, k)]).max(0.0).sqrt();
        std_errors[j] = Some(scaled * (beta / cov.scales[k]));
    }
    let matrix = (0..f)
        .map(|j| {
            (0..f)
                .map(|k| {
                    let denom = (unit[(j, j)] * unit[(k, k)]).sqrt();
                    if denom > 0.0 {
                        unit[(j, k)] / denom
                    } else if j == k {
                        1.0
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    let names = free.iter().map(|&j| names[j].clone()).collect();
    (std_errors, Correlation { names, matrix })
}
