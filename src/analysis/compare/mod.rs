//! Comparing two damping models on the same equations: is the Coulomb term needed? Is
//! one shared quadratic coefficient enough, or one per dashpot?
//!
//! Both models are fitted by least squares on the same windows (same b). With m
//! equations, k_i the numerical rank of model i's column-scaled regressor and RSS_i its
//! residual sum of squares (in the units of b):
//!
//! ```text
//!   AIC = m ln(RSS/m) + 2k,        BIC = m ln(RSS/m) + k ln m        (lower is better)
//! ```
//!
//! (Gaussian equation errors of one variance), and leave-one-out cross-validation over
//! the equations (points or windows), PRESS = Σ_i (e_i/(1 − h_ii))² with h_ii the
//! leverage of equation i (the exact refit-without-i residual of least squares), which
//! compares models that are not nested without a likelihood. The models are *nested* when every
//! column of the smaller one lies in the column space of the larger one (relative
//! residual of its projection below `nesting_tolerance`): a subset of terms, or one
//! shared coefficient whose column is the sum of per-element columns. For nested models
//! with d₁ = k_L − k_S > 0 and d₂ = m − k_L > 0 the F-test on the change in residual,
//!
//! ```text
//!   F = ((RSS_S − RSS_L)/d₁) / (RSS_L/d₂),   p = P(F_{d₁,d₂} > F)
//! ```
//!
//! (its upper tail from statrs, `src/analysis/stats.rs`) decides: the
//! larger model is needed when p < level (default 0.05), else the smaller suffices.
//! AIC and BIC are reported beside it, and the conclusion says when they disagree. The
//! F-test assumes errors of one variance; equations of very different amplitude violate
//! that, so read p as a guide, not an exact probability. A preferred model with a
//! negative coefficient (a damper that feeds energy in) is flagged in the conclusion:
//! least squares lets a negative Coulomb or viscous term absorb a missing mechanism, so
//! its winning says nothing about physics until the nonnegative fits agree.
//!
//! **Estimated nonlinear parameters** ([`Candidate::estimated`]: an exponent, a
//! stepped-sine table's residual receptances): the candidate's regressor is built at η̂,
//! the η minimising its RSS by variable projection ([`crate::varpro`], unweighted, so
//! that the criteria above are those of its own maximum likelihood), and each estimated
//! parameter counts in k: k = rank + q. Its leave-one-out refits hold η at η̂ (a refit of
//! η per equation would cost a variable projection each), which favours it slightly:
//! the text says so.

mod conclusion;
mod fit;
mod ranking;

pub use ranking::{RankedModel, Ranking, rank, rank_candidates};

use serde::{Deserialize, Serialize};

use crate::analysis::stats::f_upper_tail;
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings};
use conclusion::{conclusion, other};
use fit::{differing_input_work, nesting_residual, solve};

/// Settings of a comparison.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CompareSettings {
    /// Significance level of the F-test (default 0.05).
    pub level: f64,
    /// Numerical rank tolerance relative to σ_1 (default 1e-10).
    pub rank_tolerance: f64,
    /// Largest relative residual of a smaller model's column projected on the larger
    /// model's column space for the models to count as nested (default 1e-6).
    pub nesting_tolerance: f64,
}

impl Default for CompareSettings {
    fn default() -> Self {
        CompareSettings {
            level: 0.05,
            rank_tolerance: 1e-10,
            nesting_tolerance: 1e-6,
        }
    }
}

impl CompareSettings {
    /// Checks the settings themselves.
    pub fn validate(&self) -> Result<()> {
        if !(self.level > 0.0 && self.level < 1.0) {
            return Err(Error::invalid(
                "significance level",
                self.level,
                "must be in (0, 1)",
            ));
        }
        if !(self.rank_tolerance > 0.0 && self.rank_tolerance < 1.0) {
            return Err(Error::invalid(
                "rank_tolerance",
                self.rank_tolerance,
                "must be in (0, 1)",
            ));
        }
        if !(self.nesting_tolerance > 0.0 && self.nesting_tolerance < 1.0) {
            return Err(Error::invalid(
                "nesting_tolerance",
                self.nesting_tolerance,
                "must be in (0, 1)",
            ));
        }
        Ok(())
    }
}

/// A model to compare: its label and regressor, and the nonlinear parameters the
/// regressor was built at when they were estimated (empty for a linear model).
#[derive(Debug, Clone, Copy)]
pub struct Candidate<'a> {
    /// The model's label (e.g. its file).
    pub label: &'a str,
    /// Its regressor (at the estimated parameters).
    pub regressor: &'a Regressor,
    /// The estimated nonlinear law parameters: (name, value minimising the RSS).
    pub estimated: &'a [(String, f64)],
    /// Estimated nuisance parameters (a stepped-sine table's residual receptances,
    /// [`crate::varpro::NonlinearParameter::nuisance`]): counted in k like the others,
    /// listed in the JSON, summarised as a count in the text.
    pub nuisance: &'a [(String, f64)],
}

impl<'a> Candidate<'a> {
    /// A model linear in its coefficients, nothing estimated.
    pub fn linear(label: &'a str, regressor: &'a Regressor) -> Self {
        Candidate {
            label,
            regressor,
            estimated: &[],
            nuisance: &[],
        }
    }
}

/// One model's least-squares fit in the comparison.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFit {
    /// The model's label (e.g. its file).
    pub label: String,
    /// Its coefficient names.
    pub coefficients: Vec<String>,
    /// Least-squares values (minimum norm when rank deficient).
    pub values: Vec<f64>,
    /// k: numerical rank of its column-scaled regressor, plus its estimated nonlinear
    /// parameters.
    pub parameters: usize,
    /// The nonlinear parameters estimated for it (name, value at the least-squares
    /// optimum), counted in `parameters`; empty for a linear model.
    #[serde(default)]
    pub estimated: Vec<(String, f64)>,
    /// The nuisance parameters estimated for it ([`Candidate::nuisance`]), counted in
    /// `parameters`.
    #[serde(default)]
    pub nuisance: Vec<(String, f64)>,
    /// RSS = ‖b − Aθ‖².
    pub residual_sum_of_squares: f64,
    /// ‖b − Aθ‖/‖b‖.
    pub relative_residual: f64,
    /// Akaike information criterion.
    pub aic: f64,
    /// Bayesian (Schwarz) information criterion.
    pub bic: f64,
    /// Leave-one-out cross-validation: the sum of squared prediction errors of each
    /// equation from a fit without it, PRESS = Σ_i (e_i/(1 − h_ii))² (in the units of
    /// b²); `None` when an equation has leverage 1 (it cannot be predicted without itself).
    pub cross_validation: Option<f64>,
}

/// Which of the two models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Which {
    /// The first model given.
    First,
    /// The second model given.
    Second,
}

/// The F-test of nested models.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FTest {
    /// F.
    pub statistic: f64,
    /// d₁ = k_L − k_S.
    pub numerator_degrees: usize,
    /// d₂ = m − k_L.
    pub denominator_degrees: usize,
    /// P(F_{d₁,d₂} > F).
    pub p_value: f64,
}

/// What the comparison concludes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Nested, and the larger model's extra terms reduce the residual significantly.
    LargerNeeded,
    /// Nested, and the smaller model explains the data as well, within the noise.
    SmallerSuffices,
    /// Nested, but the larger model adds nothing these data can see (same rank).
    Equivalent,
    /// Nested, but no equations to spare for the test (m = k_L).
    NoRedundancy,
    /// Not nested: only the information criteria compare them.
    NotNested,
}

/// The comparison of two models on the same equations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Equations m.
    pub equations: usize,
    /// The first model's fit.
    pub first: ModelFit,
    /// The second model's fit.
    pub second: ModelFit,
    /// The smaller of two nested models, if they are nested.
    pub nested_in: Option<Which>,
    /// The F-test, for nested models with d₁, d₂ > 0.
    pub f_test: Option<FTest>,
    /// Significance level.
    pub level: f64,
    /// The model AIC prefers.
    pub aic_prefers: Which,
    /// The model BIC prefers.
    pub bic_prefers: Which,
    /// The model leave-one-out cross-validation prefers (smaller PRESS), when both
    /// have one.
    pub cross_validation_prefers: Option<Which>,
    /// The conclusion.
    pub verdict: Verdict,
    /// The conclusion in words.
    pub text: String,
}

impl Comparison {
    /// The fit of `which`.
    pub fn model(&self, which: Which) -> &ModelFit {
        match which {
            Which::First => &self.first,
            Which::Second => &self.second,
        }
    }
}

/// Builds both regressors from `records` and compares the models.
pub fn compare(
    first: (&str, &DampingModel),
    second: (&str, &DampingModel),
    records: &[Record],
    regressor: &RegressorSettings,
    settings: &CompareSettings,
) -> Result<Comparison> {
    let a = Regressor::build(first.1, records, regressor)?;
    let b = Regressor::build(second.1, records, regressor)?;
    compare_regressors((first.0, &a), (second.0, &b), settings)
}

/// Compares two models already turned into regressors on the same windows.
pub fn compare_regressors(
    first: (&str, &Regressor),
    second: (&str, &Regressor),
    settings: &CompareSettings,
) -> Result<Comparison> {
    compare_candidates(
        Candidate::linear(first.0, first.1),
        Candidate::linear(second.0, second.1),
        settings,
    )
}

/// [`compare_regressors`] for candidates that may carry estimated nonlinear
/// parameters (counted in k; module doc).
pub fn compare_candidates(
    first: Candidate<'_>,
    second: Candidate<'_>,
    settings: &CompareSettings,
) -> Result<Comparison> {
    settings.validate()?;
    let (ra, rb) = (first.regressor, second.regressor);
    if ra.equations() != rb.equations() {
        return Err(Error::mismatch(
            "equations of the two models (they must be built from the same windows)",
            ra.equations(),
            rb.equations(),
        ));
    }
    if let Some(row) = differing_input_work(ra, rb) {
        return Err(Error::invalid(
            &format!("input work of equation {row}"),
            rb.rhs()[row],
            &format!(
                "differs between the two models' regressors ({}): they must be built from the same records and windows",
                ra.rhs()[row]
            ),
        ));
    }
    let m = ra.equations();
    let a = solve(first, settings.rank_tolerance)?;
    let b = solve(second, settings.rank_tolerance)?;
    // The candidate smaller model: fewer parameters (ties: fewer columns, then first).
    let (small_which, small_r, large) =
        if (b.fit.parameters, rb.columns().len()) < (a.fit.parameters, ra.columns().len()) {
            (Which::Second, rb, &a)
        } else {
            (Which::First, ra, &b)
        };
    let nested = nesting_residual(small_r, &large.basis) <= settings.nesting_tolerance;
    let (small_fit, large_fit) = match small_which {
        Which::First => (&a.fit, &b.fit),
        Which::Second => (&b.fit, &a.fit),
    };
    let large_which = other(small_which);
    let d1 = large_fit.parameters.saturating_sub(small_fit.parameters);
    let d2 = m.saturating_sub(large_fit.parameters);
    let f_test = (nested && d1 > 0 && d2 > 0).then(|| {
        let reduction =
            (small_fit.residual_sum_of_squares - large_fit.residual_sum_of_squares).max(0.0);
        let statistic = if large_fit.residual_sum_of_squares > 0.0 {
            (reduction / d1 as f64) / (large_fit.residual_sum_of_squares / d2 as f64)
        } else if reduction > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        FTest {
            statistic,
            numerator_degrees: d1,
            denominator_degrees: d2,
            p_value: f_upper_tail(statistic, d1 as f64, d2 as f64),
        }
    });
    let prefers = |x: f64, y: f64| if y < x { Which::Second } else { Which::First };
    let aic_prefers = prefers(a.fit.aic, b.fit.aic);
    let bic_prefers = prefers(a.fit.bic, b.fit.bic);
    let cross_validation_prefers = match (a.fit.cross_validation, b.fit.cross_validation) {
        (Some(x), Some(y)) => Some(prefers(x, y)),
        _ => None,
    };
    let verdict = match (nested, &f_test) {
        (false, _) => Verdict::NotNested,
        (true, Some(t)) if t.p_value < settings.level => Verdict::LargerNeeded,
        (true, Some(_)) => Verdict::SmallerSuffices,
        (true, None) if d1 == 0 => Verdict::Equivalent,
        (true, None) => Verdict::NoRedundancy,
    };
    let mut comparison = Comparison {
        equations: m,
        first: a.fit,
        second: b.fit,
        nested_in: nested.then_some(small_which),
        f_test,
        level: settings.level,
        aic_prefers,
        bic_prefers,
        cross_validation_prefers,
        verdict,
        text: String::new(),
    };
    comparison.text = conclusion(&comparison, small_which, large_which);
    Ok(comparison)
}
