//! Coefficients that a bound, not the data, sets.
//!
//! A constrained fit holds each active coefficient j exactly on its bound β_j, and the
//! standard errors of the free coefficients F are those of a fit in which θ_j = β_j is
//! known. When the data cannot tell β_j from values well inside the feasible side, and
//! the free coefficients are correlated with θ_j, those errors hide how far the free
//! coefficients move with θ_j: noise that puts a coefficient on its bound pulls the
//! others by many of their standard errors.
//!
//! Freeing j alone (the other active coefficients held), on the rows the fit weighted
//! (W = diag(1/s_r²), or the identity), with the columns scaled to unit norm,
//!
//! ```text
//!   h     = argmin_h ‖a_j − A_F h‖_W            a_j regressed on the free columns
//!   s_j   = ‖a_j − A_F h‖²_W                    what only θ_j explains
//!   θ̃_j   = β_j + a_jᵀ W e / s_j               the estimate of θ_j when it is free
//!                                              (e = b − Aθ̂, and A_Fᵀ W e = 0 at θ̂)
//!   se(θ̃_j) = √(v / s_j)                       v the variance factor of the reported
//!                                              errors (s² unweighted, 1 plug-in, χ²/ν scaled)
//!   θ_F(θ_j) = θ̂_F − h (θ_j − β_j)              the free coefficients' best fit at each θ_j
//! ```
//!
//! At an active lower bound θ̃_j ≤ β_j (an upper one is mirrored). Either the data allow
//! θ_j from its bound to θ̃_j + z·se(θ̃_j), z = 1.96, a span Δ_j = θ̃_j + z·se − β_j > 0
//! that the data cannot tell apart from the bound; or they exclude the bound's side
//! (θ̃_j + z·se ≤ β_j: the bound holds θ_j where the data do not put it), and the span is
//! Δ_j = β_j − θ̃_j, how far the bound moved it. Over that span each free coefficient
//! moves by |h_k| Δ_j. When that exceeds [`MOVES`] of its own reported
//! standard error (for coefficients the identifiability analysis calls determined: the
//! others carry no interval), its value and interval rest on the bound being exact, and
//! [`crate::report::Warning::BoundSetsCoefficients`] names both. Coefficients held at a
//! fixed value are the user's statement and are not questioned.

use faer::Mat;

use crate::analysis::diagnostics::{Diagnostics, StandardErrorBasis};
use crate::fit::scaling::Scaling;
use crate::fit::{BoundSide, Fit, FitMethod};
use crate::regressor::Regressor;

/// How many of its standard errors a free coefficient must move, over the values of an
/// active coefficient the data allow, for the bound to be named as what sets it.
pub const MOVES: f64 = 3.0;

/// The two-sided 95 % normal quantile: the data allow θ_j up to θ̃_j + Z·se(θ̃_j).
const Z: f64 = 1.959_963_984_540_054;

/// An active coefficient whose bound sets free coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundSet {
    /// The coefficient held at its bound.
    pub coefficient: String,
    /// Which bound.
    pub side: BoundSide,
    /// The bound's value β_j.
    pub bound: f64,
    /// θ̃_j, its estimate when it is free.
    pub free_estimate: f64,
    /// se(θ̃_j).
    pub free_std_error: f64,
    /// The far end of what the data allow, θ̃_j ± z·se(θ̃_j), when it lies on the feasible
    /// side; `None` when the data exclude that side (the bound holds θ_j where the data
    /// do not put it).
    pub allowed: Option<f64>,
    /// The free coefficients that move by more than [`MOVES`] standard errors over the
    /// span Δ_j: (name, |h_k| Δ_j, that in their standard errors).
    pub moved: Vec<(String, f64, f64)>,
}

/// The active coefficients of a constrained `fit` on `regressor` whose bounds set free
/// coefficients (the module doc), by the standard errors of `diagnostics`.
pub fn bound_set(regressor: &Regressor, fit: &Fit, diagnostics: &Diagnostics) -> Vec<BoundSet> {
    let p = regressor.columns().len();
    if fit.method != FitMethod::Constrained
        || !fit.status.is_usable()
        || fit.active.is_empty()
        || diagnostics.rank < p
        || diagnostics.std_errors.iter().all(Option::is_none)
    {
        return Vec::new();
    }
    let index = |name: &str| regressor.columns().iter().position(|c| c == name);
    let free: Vec<usize> = (0..p)
        .filter(|j| !fit.active.iter().any(|c| c.name == regressor.columns()[*j]))
        .collect();
    if free.is_empty() {
        return Vec::new();
    }
    let Some(rows) = Rows::of(regressor, fit, diagnostics) else {
        return Vec::new();
    };
    let Some(projection) = Projection::onto(&rows, &free) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    for active in &fit.active {
        let sign = match active.side {
            BoundSide::Lower => 1.0,
            BoundSide::Upper => -1.0,
            BoundSide::Fixed => continue,
        };
        let Some(j) = index(&active.name) else {
            continue;
        };
        let Some(freed) = projection.free(&rows, j) else {
            continue;
        };
        // θ̃_j − β_j and se(θ̃_j) in physical units (÷ S_j).
        let scale_j = rows.scales[j];
        let free_estimate = active.value + rows.residual_scale * freed.gradient / freed.s / scale_j;
        let free_std_error = rows.residual_scale * (rows.variance / freed.s).sqrt() / scale_j;
        let reach = free_estimate + sign * Z * free_std_error;
        let inside = sign * (reach - active.value);
        let (allowed, span) = if inside > 0.0 {
            (Some(reach), inside)
        } else {
            (None, sign * (active.value - free_estimate))
        };
        if !(span > 0.0 && span.is_finite()) {
            continue;
        }
        let moved: Vec<(String, f64, f64)> = free
            .iter()
            .zip(&freed.h)
            .filter(|(k, _)| {
                // One the report already calls not determined has no interval to doubt.
                diagnostics
                    .identifiability
                    .is_identifiable(&regressor.columns()[**k])
            })
            .filter_map(|(&k, h)| {
                let se = diagnostics.std_errors[k]?;
                let shift = h.abs() * span * (scale_j / rows.scales[k]);
                let sigmas = shift / se;
                (se > 0.0 && shift.is_finite() && sigmas > MOVES)
                    .then(|| (regressor.columns()[k].clone(), shift, sigmas))
            })
            .collect();
        if !moved.is_empty() {
            found.push(BoundSet {
                coefficient: active.name.clone(),
                side: active.side,
                bound: active.value,
                free_estimate,
                free_std_error,
                allowed,
                moved,
            });
        }
    }
    found
}

/// The fit's rows as its diagnostics saw them: weighted when the fit was, columns
/// scaled to unit norm, the residual scaled by its largest entry.
struct Rows {
    /// The weighted rows, columns of unit norm.
    matrix: Mat<f64>,
    /// S_k, the weighted columns' norms.
    scales: Vec<f64>,
    /// The weighted residual e_w / ρ.
    residual: Vec<f64>,
    /// ρ = max |e_w| (the squares of residuals of 1e±160 would leave range).
    residual_scale: f64,
    /// v / ρ², the variance factor of the reported standard errors.
    variance: f64,
}

impl Rows {
    fn of(regressor: &Regressor, fit: &Fit, diagnostics: &Diagnostics) -> Option<Self> {
        let a = regressor.matrix();
        let (m, p) = a.shape();
        let weights = match &fit.residual_std {
            Some(std) => crate::fit::inverse_std(std),
            None => vec![1.0; m],
        };
        if weights.len() != m || diagnostics.residuals.len() != m {
            return None;
        }
        let weighted: Vec<f64> = diagnostics
            .residuals
            .iter()
            .zip(&weights)
            .map(|(e, w)| e * w)
            .collect();
        let residual_scale = weighted.iter().fold(0.0f64, |s, e| s.max(e.abs()));
        if !(residual_scale > 0.0 && residual_scale.is_finite()) {
            return None;
        }
        let residual: Vec<f64> = weighted.iter().map(|e| e / residual_scale).collect();
        let variance = match diagnostics.std_error_basis {
            StandardErrorBasis::ResidualVariance | StandardErrorBasis::BetweenRecords { .. } => {
                let dof = diagnostics.degrees_of_freedom;
                if dof == 0 {
                    return None;
                }
                let scale = match diagnostics.std_error_basis {
                    StandardErrorBasis::BetweenRecords { scale, .. } => scale,
                    _ => 1.0,
                };
                scale * scale * residual.iter().map(|e| e * e).sum::<f64>() / dof as f64
            }
            StandardErrorBasis::PlugIn => (1.0 / residual_scale).powi(2),
            StandardErrorBasis::ScaledPlugIn {
                chi_square_per_dof, ..
            } => chi_square_per_dof / residual_scale.powi(2),
        };
        let weighted_rows = Mat::from_fn(m, p, |i, k| weights[i] * a[(i, k)]);
        let scaling = Scaling::of(&weighted_rows, &weighted);
        if !variance.is_finite() {
            return None;
        }
        let matrix = scaling.matrix(&weighted_rows);
        let scales = scaling.columns;
        Some(Rows {
            matrix,
            scales,
            residual,
            residual_scale,
            variance,
        })
    }
}

/// The thin SVD of the free columns, U Σ Vᵀ, truncated at the numerical rank.
struct Projection {
    u: Mat<f64>,
    sigma: Vec<f64>,
    v: Mat<f64>,
}

/// One active column regressed on the free ones.
struct Freed {
    /// ĥ, in scaled units.
    h: Vec<f64>,
    /// ŝ_j = ‖â_j − Â_F ĥ‖².
    s: f64,
    /// â_jᵀ ê, the scaled gradient of the residual along column j.
    gradient: f64,
}

impl Projection {
    fn onto(rows: &Rows, free: &[usize]) -> Option<Self> {
        let m = rows.matrix.nrows();
        let a_free = Mat::from_fn(m, free.len(), |i, k| rows.matrix[(i, free[k])]);
        let svd = a_free.thin_svd().ok()?;
        let s = svd.S().column_vector();
        let sigma: Vec<f64> = (0..free.len()).map(|i| s[i]).collect();
        let rank = crate::fit::svd::numerical_rank(&sigma, 1e-12);
        Some(Projection {
            u: svd.U().subcols(0, rank).to_owned(),
            sigma: sigma[..rank].to_vec(),
            v: svd.V().subcols(0, rank).to_owned(),
        })
    }

    fn free(&self, rows: &Rows, j: usize) -> Option<Freed> {
        let m = rows.matrix.nrows();
        let column = |i: usize| rows.matrix[(i, j)];
        let rank = self.sigma.len();
        let coordinates: Vec<f64> = (0..rank)
            .map(|c| (0..m).map(|i| self.u[(i, c)] * column(i)).sum())
            .collect();
        let s: f64 = (0..m)
            .map(|i| {
                let fitted: f64 = (0..rank).map(|c| self.u[(i, c)] * coordinates[c]).sum();
                (column(i) - fitted).powi(2)
            })
            .sum();
        if s.is_nan() || s <= f64::EPSILON {
            return None;
        }
        let h = (0..self.v.nrows())
            .map(|k| {
                (0..rank)
                    .map(|c| self.v[(k, c)] * coordinates[c] / self.sigma[c])
                    .sum()
            })
            .collect();
        let gradient = (0..m).map(|i| column(i) * rows.residual[i]).sum();
        Some(Freed { h, s, gradient })
    }
}
