//! Identifiability: which coefficients, and which combinations of them, the data
//! determine.
//!
//! Everything is read off the thin SVD of the column-scaled regressor
//! A_s = A S⁻¹ = U Σ Vᵀ (S = diag‖A_j‖, b_s = b/‖b‖, so θ_s = Sθ/‖b‖ is of order one;
//! [`crate::fit::ScaledSvd`], shared with the fit and the diagnostics):
//!
//! - **Noise level of the equations.** With the numerical rank r (σ_i > tol·σ_1), the
//!   least-squares residual of the scaled equations is e_s = b_s − Σ_{i≤r} u_i u_iᵀ b_s
//!   and its standard deviation s = ‖e_s‖/√(m − r) (unknown when m = r).
//! - **Practically zero singular values.** The component of θ_s along v_i is
//!   α_i = u_iᵀ b_s/σ_i with standard error s/σ_i. σ_i is *practically zero* when
//!
//!   ```text
//!     σ_i < τ = max(tol·σ_1, κ·max(s, s_w, ε·σ_1), κ·ε)   or σ_i = 0,   κ = 3, ε = 1e-6,
//!   ```
//!
//!   i.e. when the equation noise leaves that component uncertain by more than a third of
//!   an order-one scaled coefficient. The floor ε is the relative precision assumed for
//!   the scaled equations even when the residual is smaller: noise-free simulations
//!   still carry quadrature and velocity errors, which enter A and b consistently and so
//!   hide from the residual (a first-resonance record of a linear chain gives σ_2/σ_1
//!   between 1e-12 and 1e-7 depending on the rule, with s smaller still). The absolute
//!   floor κ·ε is the relative one at σ_1 = 1: a nonzero column has unit norm after
//!   scaling, so σ_1 ≥ 1 whenever any column is nonzero and the absolute floor changes
//!   nothing then; when every column is zero (σ_1 = 0) it keeps τ above zero, so that
//!   no coefficient is called determined by a zero regressor. Such a regressor is
//!   refused before any fit by [`require_information`] ([`Error::NoInformation`]).
//!   s_w is the scatter of a scaled row between the windows of one record, which are
//!   replicates of one experiment ([`crate::analysis::replicates`]): quadrature and
//!   velocity errors that differ from window to window make singular values that no
//!   experiment supports, and hide from s when they enter A and b consistently. For the
//!   same reason at most R singular values count, R the number of experiments (records
//!   of whole-period windows, and each window of the non-periodic mode).
//! - **Near-null directions.** For each practically zero σ_i, the coefficient change
//!   Δθ_j ∝ v_ji/S_j leaves the fit (nearly) unchanged. It is normalised so that its
//!   largest component is 1, components below 5% of it are dropped, and it is written
//!   with the coefficient names: the coefficients in it trade off against each other.
//!   A coefficient that appears in any near-null direction is practically
//!   unidentifiable.
//! - **Determined combinations.** When some direction is null, only the linear
//!   functionals v_iᵀθ_s = Σ_j v_ji S_j θ_j/‖b‖ with σ_i ≥ τ are determined: the weights
//!   g_j ∝ v_ji S_j, normalised to a largest weight of 1 (for C = c0 I + c1 K driven at
//!   the first resonance, c0 + λ_1 c1). Value g·θ̂ and standard error (‖b‖/c)·s/σ_i,
//!   with c the normalising factor. Weights below 0.1% are dropped from the written
//!   form (not 5%: the value belongs to the whole combination, and a dropped weight
//!   times a large, undetermined coefficient would make the written one misleading).
//! - **Variance inflation factor** (uncentred, as the energy balance has no intercept):
//!   VIF_j = 1/(1 − R_j²) = [(A_sᵀA_s)⁻¹]_jj = Σ_i v_ji²/σ_i², with R_j² the uncentred
//!   R² of column j on the others; infinite (`None`) when the regressor is rank
//!   deficient. VIF 1 means an orthogonal column; VIF 100 inflates the variance a
//!   hundredfold.
//! - **Many coefficients.** Each combination keeps its whole weight vector in model
//!   order (`weights`, nothing dropped) beside the kept terms. Its written form lists
//!   every kept term up to [`FULL_TEXT`] of them, else the [`digest::CONTRIBUTORS`]
//!   largest, "+ N more" and the count per term; above [`digest::FULL_LISTING`]
//!   coefficients the text report lists the [`digest::LISTED`] smallest null directions
//!   and best-determined combinations, the largest VIFs and a histogram of them by
//!   decade ([`crate::analysis::digest`]).

mod text;

use serde::{Deserialize, Serialize};

use crate::analysis::digest::{self, CONTRIBUTORS};
use crate::error::{Error, Result};
use crate::fit::ScaledSvd;
use crate::regressor::Regressor;
pub(crate) use text::list;
use text::{trade_off_text, written};

/// Weights below this fraction of the largest are dropped from a determined combination.
const DETERMINED_DROP: f64 = 1e-3;

/// A combination of more kept terms than this is written by its largest contributors.
pub const FULL_TEXT: usize = 8;

/// Settings of the identifiability analysis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IdentifiabilitySettings {
    /// κ: a singular value below κ·s is practically zero (default 3).
    pub noise_factor: f64,
    /// ε: relative precision assumed for the scaled equations when the residual is
    /// smaller (default 1e-6).
    pub precision: f64,
    /// Components below this fraction of a direction's largest are dropped from its
    /// written form (default 0.05).
    pub drop: f64,
    /// Parameters estimated from the same equations outside the linear fit (variable
    /// projection's η, [`crate::fit::FitSettings::nonlinear_parameters`]): the noise
    /// level s counts m − rank − this many degrees of freedom (default 0).
    #[serde(default)]
    pub nonlinear_parameters: usize,
    /// s_w: the scatter of a column-scaled row between windows of one record
    /// ([`crate::analysis::replicates`]); the threshold uses max(s, s_w) (default 0,
    /// set by [`analyse_with`] and the fit's diagnostics from the regressor).
    #[serde(default)]
    pub window_scatter: f64,
    /// The experiments behind the rows (records of replicate windows,
    /// [`crate::analysis::replicates::experiments`]): at most this many singular values
    /// are practically nonzero (0: no cap; set like `window_scatter`).
    #[serde(default)]
    pub experiments: usize,
    /// A factor on the noise level s: the lack-of-fit test's scale when it takes the
    /// standard errors from the records' means ([`crate::analysis::lack_of_fit`]), so
    /// that "practically zero" and the standard errors read the same noise (default 1).
    #[serde(default = "unit")]
    pub noise_scale: f64,
}

fn unit() -> f64 {
    1.0
}

impl Default for IdentifiabilitySettings {
    fn default() -> Self {
        IdentifiabilitySettings {
            noise_factor: 3.0,
            precision: 1e-6,
            drop: 0.05,
            nonlinear_parameters: 0,
            window_scatter: 0.0,
            noise_scale: 1.0,
            experiments: 0,
        }
    }
}

impl IdentifiabilitySettings {
    /// Rejects non-positive factors and a drop fraction outside [0, 1).
    pub fn validate(&self) -> Result<()> {
        if !(self.noise_factor.is_finite() && self.noise_factor > 0.0) {
            return Err(Error::invalid(
                "noise_factor",
                self.noise_factor,
                "must be finite and positive",
            ));
        }
        if !(self.precision >= 0.0 && self.precision < 1.0) {
            return Err(Error::invalid(
                "precision",
                self.precision,
                "must be in [0, 1)",
            ));
        }
        if !(self.drop >= 0.0 && self.drop < 1.0) {
            return Err(Error::invalid("drop", self.drop, "must be in [0, 1)"));
        }
        Ok(())
    }
}

/// One named coefficient in a combination, with its weight.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CombinationTerm {
    /// Coefficient name.
    pub name: String,
    /// Its weight (the largest in a combination is 1).
    pub weight: f64,
}

/// A linear combination of coefficients, largest weight 1, small weights dropped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Combination {
    /// The weights kept, in model order.
    pub terms: Vec<CombinationTerm>,
    /// Every weight, in model order (the names are [`Identifiability::names`]), the
    /// largest 1, none dropped.
    #[serde(default)]
    pub weights: Vec<f64>,
    /// Written out, e.g. `c0 + 0.198 c1`; with more than [`FULL_TEXT`] terms, the
    /// [`digest::CONTRIBUTORS`] largest and "+ N more".
    pub text: String,
}

/// A direction in coefficient space along which the fit barely changes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NullDirection {
    /// Its singular value (of the column-scaled regressor).
    pub singular_value: f64,
    /// The change Δθ, largest component 1.
    pub direction: Combination,
    /// In words.
    pub text: String,
}

/// A combination of coefficients the data do determine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeterminedCombination {
    /// Its singular value.
    pub singular_value: f64,
    /// The functional g·θ, largest weight 1.
    pub combination: Combination,
    /// Its least-squares value g·θ̂ (all weights, including dropped ones).
    pub value: f64,
    /// Its standard error, when the data have redundancy.
    pub std_error: Option<f64>,
}

/// What the data can and cannot determine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Identifiability {
    /// Coefficient names, in model order.
    pub names: Vec<String>,
    /// s: standard deviation of the scaled equations' residuals (`None` without
    /// redundancy).
    pub noise_level: Option<f64>,
    /// s_w: the scatter of a scaled row between windows of one record, when it sets the
    /// threshold (it exceeds s; [`crate::analysis::replicates`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window_scatter: Option<f64>,
    /// The number of experiments, when it and not the threshold caps the practical rank
    /// (records whose windows are replicates).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub experiments: Option<usize>,
    /// τ: singular values below it are practically zero.
    pub threshold: f64,
    /// Singular values at or above τ.
    pub practical_rank: usize,
    /// Variance inflation factor per coefficient (`None`: infinite).
    pub variance_inflation: Vec<Option<f64>>,
    /// Directions the data do not determine, smallest singular value first.
    pub null_directions: Vec<NullDirection>,
    /// When some direction is null: the combinations that are determined.
    pub determined: Vec<DeterminedCombination>,
    /// Coefficients that appear in a near-null direction.
    pub unidentifiable: Vec<String>,
}

impl Identifiability {
    /// True when every coefficient is practically identifiable: no near-null
    /// direction, and every singular value above the threshold.
    pub fn separable(&self) -> bool {
        self.null_directions.is_empty() && self.practical_rank == self.names.len()
    }

    /// True when coefficient `name` is practically identifiable.
    pub fn is_identifiable(&self, name: &str) -> bool {
        !self.unidentifiable.iter().any(|n| n == name)
    }
}

/// Analyses `regressor` with numerical rank tolerance `rank_tolerance` (relative to
/// σ_1) and the default [`IdentifiabilitySettings`].
pub fn analyse(regressor: &Regressor, rank_tolerance: f64) -> Identifiability {
    analyse_with(
        regressor,
        rank_tolerance,
        &IdentifiabilitySettings::default(),
    )
}

/// Analyses `regressor` with explicit settings (validated by the caller; see
/// [`IdentifiabilitySettings::validate`]).
pub fn analyse_with(
    regressor: &Regressor,
    rank_tolerance: f64,
    settings: &IdentifiabilitySettings,
) -> Identifiability {
    let names = regressor.columns().to_vec();
    let settings = IdentifiabilitySettings {
        window_scatter: settings
            .window_scatter
            .max(crate::analysis::replicates::window_scatter(regressor).unwrap_or(0.0)),
        experiments: match settings.experiments {
            0 => crate::analysis::replicates::experiments(regressor),
            given => given,
        },
        ..*settings
    };
    match ScaledSvd::new(regressor.matrix(), regressor.rhs(), rank_tolerance) {
        Ok(svd) => analyse_factored(names, &svd, rank_tolerance, &settings),
        Err(_) => unidentifiable(names, &settings),
    }
}

/// [`Error::NoInformation`] when every column of `regressor` is zero. Column scaling
/// keeps a zero column zero and gives any other unit norm, so this is exactly a zero
/// column-scaled regressor (σ_1 = 0): no coefficient changes the fit, and the least-
/// squares "solution" θ = 0 would be no estimate at all. Entries that underflowed to
/// zero while the regressor was built count as zero.
pub fn require_information(regressor: &Regressor) -> Result<()> {
    let a = regressor.matrix();
    let zero = (0..a.ncols()).all(|j| (0..a.nrows()).all(|i| a[(i, j)] == 0.0));
    if !zero || a.ncols() == 0 {
        return Ok(());
    }
    let names: Vec<&str> = regressor.columns().iter().map(String::as_str).collect();
    Err(Error::NoInformation {
        coefficients: list(&names),
        reason: format!(
            "every column of the regressor ({} equations) is zero: the terms do no work on \
             this motion (the DOFs they act on do not move, their weights or matrices are \
             zero, or the work underflows in floating point); record motion where the terms \
             act, or check their weights and matrices",
            regressor.equations()
        ),
    })
}

/// Nothing determined: the analysis of a regressor that cannot be factored or has no
/// nonzero singular value. Each coefficient is a null direction of its own, and the
/// threshold is the absolute floor κ·ε.
fn unidentifiable(names: Vec<String>, settings: &IdentifiabilitySettings) -> Identifiability {
    let null_directions = names
        .iter()
        .map(|name| {
            let (mut direction, _) = combination(std::slice::from_ref(name), &[1.0], 0.0);
            direction.weights = names.iter().map(|n| f64::from(n == name)).collect();
            let text = trade_off_text(&direction);
            NullDirection {
                singular_value: 0.0,
                direction,
                text,
            }
        })
        .collect();
    Identifiability {
        variance_inflation: vec![None; names.len()],
        unidentifiable: names.clone(),
        names,
        noise_level: None,
        window_scatter: None,
        experiments: None,
        threshold: settings.noise_factor * settings.precision,
        practical_rank: 0,
        null_directions,
        determined: Vec::new(),
    }
}

/// The analysis of the columns `names` from the factorization of their scaled
/// regressor.
pub(crate) fn analyse_factored(
    names: Vec<String>,
    svd: &ScaledSvd,
    rank_tolerance: f64,
    settings: &IdentifiabilitySettings,
) -> Identifiability {
    let (u, v, b_s) = (svd.u(), svd.v(), svd.rhs());
    let sigma = svd.singular_values();
    let ub = svd.projections();
    let scaling = svd.scaling();
    let (m, p) = (svd.equations(), sigma.len());
    let rows = u.nrows();
    let sigma1 = sigma.first().copied().unwrap_or(0.0);
    if p == 0 || sigma1 <= 0.0 {
        return unidentifiable(names, settings);
    }
    let rank = sigma
        .iter()
        .filter(|s| **s > rank_tolerance * sigma1)
        .count();
    let spent = rank + settings.nonlinear_parameters;
    let noise_level = (m > spent).then(|| {
        let residual2: f64 = (0..rows)
            .map(|r| {
                let fitted: f64 = (0..rank).map(|i| u[(r, i)] * ub[i]).sum();
                (b_s[(r, 0)] - fitted).powi(2)
            })
            .sum();
        settings.noise_scale * (residual2 / (m - spent) as f64).sqrt()
    });
    let floor = settings.precision * sigma1;
    let absolute = settings.noise_factor * settings.precision;
    let scatter = settings.window_scatter;
    let window_scatter =
        (scatter > noise_level.unwrap_or(0.0) && scatter > floor).then_some(scatter);
    let threshold = (rank_tolerance * sigma1)
        .max(settings.noise_factor * noise_level.unwrap_or(0.0).max(floor).max(scatter))
        .max(absolute);
    let cap = match settings.experiments {
        0 => p,
        n => n,
    };
    let practical: Vec<bool> = sigma
        .iter()
        .enumerate()
        .map(|(i, s)| *s >= threshold && *s > 0.0 && i < cap)
        .collect();
    let practical_rank = practical.iter().filter(|k| **k).count();
    let experiments = (sigma.iter().skip(cap).any(|s| *s >= threshold)).then_some(cap);

    let variance_inflation = (0..p)
        .map(|j| (rank == p).then(|| (0..p).map(|i| (v[(j, i)] / sigma[i]).powi(2)).sum::<f64>()))
        .collect();

    let mut null_directions = Vec::new();
    let mut unidentifiable = vec![false; p];
    for i in (0..p).filter(|&i| !practical[i]).rev() {
        let weights: Vec<f64> = (0..p).map(|j| v[(j, i)] / scaling.columns[j]).collect();
        let (direction, _) = combination(&names, &weights, settings.drop);
        for (j, w) in direction.weights.iter().enumerate() {
            if w.abs() >= settings.drop && *w != 0.0 {
                unidentifiable[j] = true;
            }
        }
        let text = trade_off_text(&direction);
        null_directions.push(NullDirection {
            singular_value: sigma[i],
            direction,
            text,
        });
    }
    let determined = if null_directions.is_empty() {
        Vec::new()
    } else {
        (0..p)
            .filter(|&i| practical[i])
            .map(|i| {
                let weights: Vec<f64> = (0..p).map(|j| v[(j, i)] * scaling.columns[j]).collect();
                let drop = settings.drop.min(DETERMINED_DROP);
                let (combination, factor) = combination(&names, &weights, drop);
                // g·θ = (‖b‖/factor)·v_iᵀθ_s, v_iᵀθ_s estimated by u_iᵀb_s/σ_i.
                let to_g = scaling.rhs / factor;
                DeterminedCombination {
                    singular_value: sigma[i],
                    combination,
                    value: to_g * ub[i] / sigma[i],
                    std_error: noise_level.map(|s| to_g.abs() * s / sigma[i]),
                }
            })
            .collect()
    };
    Identifiability {
        unidentifiable: names
            .iter()
            .zip(&unidentifiable)
            .filter(|(_, u)| **u)
            .map(|(n, _)| n.clone())
            .collect(),
        names,
        noise_level,
        window_scatter,
        experiments,
        threshold,
        practical_rank,
        variance_inflation,
        null_directions,
        determined,
    }
}

/// Normalises `weights` so that the largest in magnitude is +1, drops those below
/// `drop`, and writes the rest with `names`. Returns the combination and the factor
/// the weights were divided by (signed).
fn combination(names: &[String], weights: &[f64], drop: f64) -> (Combination, f64) {
    let largest = weights
        .iter()
        .copied()
        .max_by(|x, y| x.abs().total_cmp(&y.abs()))
        .filter(|w| *w != 0.0)
        .unwrap_or(1.0);
    let normalised: Vec<f64> = weights.iter().map(|w| w / largest).collect();
    let terms: Vec<CombinationTerm> = names
        .iter()
        .zip(&normalised)
        .map(|(name, w)| CombinationTerm {
            name: name.clone(),
            weight: *w,
        })
        .filter(|t| t.weight.abs() >= drop && t.weight != 0.0)
        .collect();
    let text = if terms.len() <= FULL_TEXT {
        written(&terms)
    } else {
        let weights: Vec<f64> = terms.iter().map(|t| t.weight).collect();
        let shown: Vec<CombinationTerm> = digest::largest(&weights, CONTRIBUTORS)
            .into_iter()
            .map(|k| terms[k].clone())
            .collect();
        format!(
            "{} + {} more ({} terms: {})",
            written(&shown),
            terms.len() - shown.len(),
            terms.len(),
            digest::by_term_text(terms.iter().map(|t| t.name.as_str()))
        )
    };
    (
        Combination {
            terms,
            weights: normalised,
            text,
        },
        largest,
    )
}
