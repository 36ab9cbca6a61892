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

use std::fmt;

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::analysis::stats::f_upper_tail;
use crate::error::{Error, Result};
use crate::fit::ScaledSvd;
use crate::model::DampingModel;
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings};

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

/// The least-squares fit of one regressor at its numerical rank, with the orthonormal
/// basis of its column space (for the nesting test).
struct Solved {
    fit: ModelFit,
    basis: Mat<f64>,
}

fn solve(candidate: Candidate<'_>, tolerance: f64) -> Result<Solved> {
    let (label, r) = (candidate.label, candidate.regressor);
    let a = r.matrix();
    let (m, p) = a.shape();
    if p == 0 {
        return Err(Error::Empty {
            what: format!("the coefficients of model {label}"),
        });
    }
    if m == 0 {
        return Err(Error::TooFewEquations {
            equations: 0,
            coefficients: p,
        });
    }
    let svd = ScaledSvd::new(a, r.rhs(), tolerance)?;
    let (u, b_s) = (svd.u(), svd.rhs());
    let rank = svd.rank();
    let theta_s = svd.scaled_solution();
    let mut fitted = vec![0.0; m];
    for (i, ub) in svd.projections().iter().enumerate().take(rank) {
        for (row, value) in fitted.iter_mut().enumerate() {
            *value += u[(row, i)] * ub;
        }
    }
    let rss_s: f64 = (0..m).map(|i| (b_s[(i, 0)] - fitted[i]).powi(2)).sum();
    // Leverages h_ii = ‖U_i‖² over the rank's left singular vectors (the hat matrix of
    // the column-scaled rows, which scaling columns does not change).
    let press_s = (0..m).try_fold(0.0, |sum, i| {
        let h: f64 = (0..rank).map(|k| u[(i, k)] * u[(i, k)]).sum();
        (h < 1.0 - 1e-10).then(|| sum + ((b_s[(i, 0)] - fitted[i]) / (1.0 - h)).powi(2))
    });
    let scaling = svd.scaling();
    let rss = rss_s * scaling.rhs * scaling.rhs;
    let mf = m as f64;
    let log_likelihood_term = mf * (rss.max(f64::MIN_POSITIVE) / mf).ln();
    let basis = Mat::from_fn(m, rank, |i, k| u[(i, k)]);
    let k = rank + candidate.estimated.len() + candidate.nuisance.len();
    Ok(Solved {
        fit: ModelFit {
            label: label.to_string(),
            coefficients: r.columns().to_vec(),
            values: scaling.unscale(&theta_s),
            parameters: k,
            estimated: candidate.estimated.to_vec(),
            nuisance: candidate.nuisance.to_vec(),
            residual_sum_of_squares: rss,
            relative_residual: rss_s.sqrt(),
            aic: log_likelihood_term + 2.0 * k as f64,
            bic: log_likelihood_term + k as f64 * mf.ln(),
            cross_validation: press_s.map(|p| p * scaling.rhs * scaling.rhs),
        },
        basis,
    })
}

/// The first equation whose input work differs between two regressors of as many
/// equations by more than round-off, 10⁻¹² of the largest |b| (a stepped-sine table's
/// residual receptance leaves b = −π a Im Z unchanged analytically, R a being real,
/// but the synthesized periods integrate it again).
fn differing_input_work(a: &Regressor, b: &Regressor) -> Option<usize> {
    let scale = a.rhs().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // NaN differs too.
    let same = |i: usize| (a.rhs()[i] - b.rhs()[i]).abs() <= 1e-12 * scale;
    (0..a.equations()).find(|&i| !same(i))
}

/// Largest relative residual of `small`'s columns projected on the span of `basis`.
fn nesting_residual(small: &Regressor, basis: &Mat<f64>) -> f64 {
    let a = small.matrix();
    let (m, p) = a.shape();
    (0..p)
        .map(|j| {
            let column: Vec<f64> = (0..m).map(|i| a[(i, j)]).collect();
            let norm = crate::fit::scaling::norm(&column);
            if norm == 0.0 {
                return 0.0;
            }
            let mut residual: Vec<f64> = column.iter().map(|c| c / norm).collect();
            for k in 0..basis.ncols() {
                let dot: f64 = (0..m).map(|i| basis[(i, k)] * residual[i]).sum();
                for (i, r) in residual.iter_mut().enumerate() {
                    *r -= dot * basis[(i, k)];
                }
            }
            crate::fit::scaling::norm(&residual)
        })
        .fold(0.0, f64::max)
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

/// What k and the leave-one-out refits mean for models with estimated parameters.
fn estimated_note<'a>(models: impl IntoIterator<Item = &'a ModelFit>) -> Option<String> {
    let with: Vec<&str> = models
        .into_iter()
        .filter(|m| !m.estimated.is_empty() || !m.nuisance.is_empty())
        .map(|m| m.label.as_str())
        .collect();
    (!with.is_empty()).then(|| {
        format!(
            "; k counts the estimated parameters of {}, and their leave-one-out refits hold them at their estimates (which favours them slightly)",
            with.join(", ")
        )
    })
}

/// `name = value` of each estimated parameter, then the count of nuisance ones.
fn estimated_values(m: &ModelFit) -> Vec<String> {
    m.estimated
        .iter()
        .map(|(n, v)| format!("{n} = {v:.4e} (estimated)"))
        .chain((!m.nuisance.is_empty()).then(|| {
            format!(
                "+ {} residual receptances (estimated; --json lists them)",
                m.nuisance.len()
            )
        }))
        .collect()
}

fn other(which: Which) -> Which {
    match which {
        Which::First => Which::Second,
        Which::Second => Which::First,
    }
}

fn conclusion(c: &Comparison, small: Which, large: Which) -> String {
    let (s, l) = (c.model(small), c.model(large));
    let extra: Vec<&str> = l
        .coefficients
        .iter()
        .filter(|n| !s.coefficients.contains(n))
        .map(String::as_str)
        .collect();
    let extra = if !extra.is_empty() && s.coefficients.iter().all(|n| l.coefficients.contains(n)) {
        format!(
            "its extra terms ({})",
            crate::analysis::identifiability::list(&extra)
        )
    } else {
        "its extra freedom".to_string()
    };
    let mut text = match (c.verdict, &c.f_test) {
        (Verdict::LargerNeeded, Some(t)) => format!(
            "{} is needed: {extra} reduce the residual sum of squares from {:.4e} to {:.4e} (F = {:.4e} with ({}, {}) degrees of freedom, p = {:.3e} < {})",
            l.label,
            s.residual_sum_of_squares,
            l.residual_sum_of_squares,
            t.statistic,
            t.numerator_degrees,
            t.denominator_degrees,
            t.p_value,
            c.level
        ),
        (Verdict::SmallerSuffices, Some(t)) => format!(
            "{} suffices: the extra terms of {} do not reduce the residual beyond the noise (F = {:.4e} with ({}, {}) degrees of freedom, p = {:.3} ≥ {})",
            s.label,
            l.label,
            t.statistic,
            t.numerator_degrees,
            t.denominator_degrees,
            t.p_value,
            c.level
        ),
        (Verdict::Equivalent, _) => format!(
            "{} adds nothing these data can see: both models span the same equations",
            l.label
        ),
        (Verdict::NoRedundancy, _) => format!(
            "the models are nested, but {} fits the {} equations exactly: no equations are left to test it; add windows or records",
            l.label, c.equations
        ),
        _ => "the models are not nested, so no F-test; compare them by AIC and BIC".to_string(),
    };
    let name = |w: Which| c.model(w).label.clone();
    match (c.aic_prefers == c.bic_prefers, c.verdict) {
        (true, Verdict::LargerNeeded) if c.aic_prefers != large => text.push_str(&format!(
            "; but AIC and BIC prefer {}: the improvement is small for its cost",
            name(c.aic_prefers)
        )),
        (true, Verdict::SmallerSuffices) if c.aic_prefers != small => {
            text.push_str(&format!("; but AIC and BIC prefer {}", name(c.aic_prefers)))
        }
        (true, _) => text.push_str(&format!("; AIC and BIC prefer {}", name(c.aic_prefers))),
        (false, _) => text.push_str(&format!(
            "; AIC prefers {}, BIC prefers {}",
            name(c.aic_prefers),
            name(c.bic_prefers)
        )),
    }
    if let Some(w) = c.cross_validation_prefers {
        text.push_str(&format!(
            "; leave-one-out cross-validation prefers {}",
            name(w)
        ));
    }
    if let Some(note) = estimated_note([&c.first, &c.second]) {
        text.push_str(&note);
    }
    // A model that wins with a negative coefficient wins unphysically: say so.
    let winner = match c.verdict {
        Verdict::LargerNeeded => large,
        Verdict::SmallerSuffices => small,
        _ => c.aic_prefers,
    };
    let negative = |w: Which| -> Vec<String> {
        let m = c.model(w);
        m.coefficients
            .iter()
            .zip(&m.values)
            .filter(|(_, v)| **v < 0.0)
            .map(|(n, v)| format!("{n} = {v:.4e}"))
            .collect()
    };
    let (win, lose) = (negative(winner), negative(other(winner)));
    if !win.is_empty() {
        text.push_str(&format!(
            "; caution: {} is preferred with negative damping ({}){}, which feeds energy in: it is not a physical preference; compare fits with nonnegative = true",
            name(winner),
            win.join(", "),
            if lose.is_empty() {
                format!(", while {} is physical", name(other(winner)))
            } else {
                String::new()
            }
        ));
    }
    text
}

impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} equations", self.equations)?;
        let width = self
            .first
            .label
            .chars()
            .count()
            .max(self.second.label.chars().count())
            .max(5);
        writeln!(
            f,
            "{:<width$} {:>6} {:>13} {:>11} {:>13} {:>13} {:>13}",
            "model", "k", "RSS", "rel. resid.", "AIC", "BIC", "LOO PRESS"
        )?;
        for m in [&self.first, &self.second] {
            let press = m
                .cross_validation
                .map_or("-".to_string(), |p| format!("{p:.4e}"));
            writeln!(
                f,
                "{:<width$} {:>6} {:>13.4e} {:>11.3e} {:>13.4e} {:>13.4e} {:>13}",
                m.label,
                m.parameters,
                m.residual_sum_of_squares,
                m.relative_residual,
                m.aic,
                m.bic,
                press
            )?;
        }
        for m in [&self.first, &self.second] {
            if !m.estimated.is_empty() || !m.nuisance.is_empty() {
                writeln!(
                    f,
                    "{}: at its least-squares {}",
                    m.label,
                    estimated_values(m).join(", ")
                )?;
            }
        }
        match self.nested_in {
            Some(w) => writeln!(
                f,
                "{} is nested in {}",
                self.model(w).label,
                self.model(other(w)).label
            )?,
            None => writeln!(f, "the models are not nested")?,
        }
        writeln!(f, "{}", self.text)
    }
}

/// One candidate of a [`Ranking`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RankedModel {
    /// Its least-squares fit and criteria.
    pub fit: ModelFit,
    /// Its negative coefficients (`name = value`): a damper that feeds energy in.
    pub negative: Vec<String>,
}

/// Candidate models fitted on the same equations, ranked by AIC (lower first).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ranking {
    /// Equations m.
    pub equations: usize,
    /// The candidates, best AIC first.
    pub models: Vec<RankedModel>,
    /// The best-ranked candidate without a negative coefficient, when the first has one.
    pub best_physical: Option<String>,
    /// The conclusion in words.
    pub text: String,
}

/// Fits every candidate regressor (built from the same records and windows: same b) by
/// least squares and ranks them by AIC, with BIC and leave-one-out cross-validation
/// beside it. A candidate with a negative coefficient is flagged; when the first is
/// one, the text names the best physical candidate.
pub fn rank(candidates: &[(&str, &Regressor)], settings: &CompareSettings) -> Result<Ranking> {
    let candidates: Vec<Candidate<'_>> = candidates
        .iter()
        .map(|(label, r)| Candidate::linear(label, r))
        .collect();
    rank_candidates(&candidates, settings)
}

/// [`rank`] for candidates that may carry estimated nonlinear parameters (counted in
/// k; module doc).
pub fn rank_candidates(
    candidates: &[Candidate<'_>],
    settings: &CompareSettings,
) -> Result<Ranking> {
    settings.validate()?;
    let Some(first) = candidates.first().map(|c| c.regressor) else {
        return Err(Error::Empty {
            what: "candidate models".into(),
        });
    };
    for &Candidate {
        label,
        regressor: r,
        ..
    } in candidates
    {
        if r.equations() != first.equations() || differing_input_work(r, first).is_some() {
            return Err(Error::choice(
                "candidate models",
                format!("'{label}'"),
                "every candidate must be built from the same records and windows (the same input work)",
            ));
        }
    }
    let mut models = candidates
        .iter()
        .map(|&candidate| {
            let fit = solve(candidate, settings.rank_tolerance)?.fit;
            let negative = fit
                .coefficients
                .iter()
                .zip(&fit.values)
                .filter(|(_, v)| **v < 0.0)
                .map(|(n, v)| format!("{n} = {v:.4e}"))
                .collect();
            Ok(RankedModel { fit, negative })
        })
        .collect::<Result<Vec<_>>>()?;
    models.sort_by(|a, b| a.fit.aic.total_cmp(&b.fit.aic));
    let best_physical = match models.first() {
        Some(top) if !top.negative.is_empty() => models
            .iter()
            .find(|m| m.negative.is_empty())
            .map(|m| m.fit.label.clone()),
        _ => None,
    };
    let top = &models[0];
    let mut text = format!("AIC ranks {} first", top.fit.label);
    let by = |key: fn(&ModelFit) -> Option<f64>| {
        models
            .iter()
            .filter_map(|m| key(&m.fit).map(|v| (v, &m.fit.label)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, l)| l.clone())
    };
    if let Some(bic) = by(|f| Some(f.bic)) {
        text.push_str(&format!("; BIC prefers {bic}"));
    }
    if let Some(cv) = by(|f| f.cross_validation) {
        text.push_str(&format!("; leave-one-out cross-validation prefers {cv}"));
    }
    if let Some(note) = estimated_note(models.iter().map(|m| &m.fit)) {
        text.push_str(&note);
    }
    if !top.negative.is_empty() {
        text.push_str(&format!(
            "; caution: {} has negative damping ({}), which feeds energy in, so its rank is not a physical preference{}; compare fits with nonnegative = true",
            top.fit.label,
            top.negative.join(", "),
            best_physical
                .as_ref()
                .map_or(String::new(), |b| format!(" (the best physical candidate is {b})"))
        ));
    }
    Ok(Ranking {
        equations: first.equations(),
        models,
        best_physical,
        text,
    })
}

impl fmt::Display for Ranking {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} equations, candidates ranked by AIC", self.equations)?;
        let width = self
            .models
            .iter()
            .map(|m| m.fit.label.chars().count())
            .max()
            .unwrap_or(5)
            .max(5);
        writeln!(
            f,
            "{:>4} {:<width$} {:>4} {:>11} {:>13} {:>13} {:>13}  coefficients",
            "rank", "model", "k", "rel. resid.", "AIC", "BIC", "LOO PRESS"
        )?;
        for (i, m) in self.models.iter().enumerate() {
            let press = m
                .fit
                .cross_validation
                .map_or("-".to_string(), |p| format!("{p:.4e}"));
            let values: Vec<String> = m
                .fit
                .coefficients
                .iter()
                .zip(&m.fit.values)
                .map(|(n, v)| format!("{n} = {v:.4e}"))
                .chain(estimated_values(&m.fit))
                .collect();
            let flag = if m.negative.is_empty() {
                ""
            } else {
                "  (negative)"
            };
            writeln!(
                f,
                "{:>4} {:<width$} {:>4} {:>11.3e} {:>13.4e} {:>13.4e} {:>13}  {}{flag}",
                i + 1,
                m.fit.label,
                m.fit.parameters,
                m.fit.relative_residual,
                m.fit.aic,
                m.fit.bic,
                press,
                values.join(", ")
            )?;
        }
        writeln!(f, "{}", self.text)
    }
}
