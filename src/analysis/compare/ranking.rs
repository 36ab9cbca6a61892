//! Candidate laws ranked: every candidate regressor (built from the same records and
//! windows, so the same b) fitted by least squares and ranked by AIC, with BIC and
//! leave-one-out cross-validation beside it (`dampid compare --laws`); a candidate with
//! a negative coefficient is flagged.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::conclusion::{estimated_note, estimated_values};
use super::fit::{differing_input_work, solve};
use super::{Candidate, CompareSettings, ModelFit};
use crate::error::{Error, Result};
use crate::regressor::Regressor;

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
