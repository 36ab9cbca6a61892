//! A model of `dampid compare` on a job's equations: its regressor, built at the
//! nonlinear parameters that minimise its residual sum of squares when it has any
//! (estimated law parameters, a stepped-sine table's residual receptances).
//!
//! The comparison's criteria are those of ordinary least squares
//! ([`crate::analysis::compare`]: RSS, AIC = m ln(RSS/m) + 2k, BIC, PRESS), so η̂ here is
//!
//! ```text
//!   η̂ = argmin_η min_θ ‖A(η) θ − b‖²
//! ```
//!
//! by [`crate::identify::identify`] with an unweighted, unconstrained inner fit and no
//! profile intervals, whatever the job's own fit settings are: the estimate `dampid
//! identify` reports (weighted by the propagated noise, under constraints) can differ
//! from it, and the comparison says which values it used.

use super::Job;
use crate::analysis::compare::Candidate;
use crate::error::{Error, Result};
use crate::fit::{Constraints, FitSettings, Weighting};
use crate::identify::{IdentifySettings, identify};
use crate::regressor::{ParametricModel, Regressor};
use crate::varpro::VarProSettings;

/// A model ready for [`crate::analysis::compare::compare_candidates`].
#[derive(Debug, Clone)]
pub struct ComparedModel {
    /// Its label.
    pub label: String,
    /// Its regressor on the job's equations, at `estimated`.
    pub regressor: Regressor,
    /// The estimated nonlinear law parameters: (name, least-squares value).
    pub estimated: Vec<(String, f64)>,
    /// The estimated nuisance parameters (the table's residual receptances).
    pub nuisance: Vec<(String, f64)>,
}

impl ComparedModel {
    /// The candidate this model is in a comparison.
    pub fn candidate(&self) -> Candidate<'_> {
        Candidate {
            label: &self.label,
            regressor: &self.regressor,
            estimated: &self.estimated,
            nuisance: &self.nuisance,
        }
    }
}

impl Job {
    /// `law` (with its estimated parameters, if any, and the job's residual
    /// receptances, if it estimates them) on this job's equations, labelled `label`
    /// (module doc). An outer loop that does not converge is an error naming the model.
    pub fn compared(&self, label: &str, law: &ParametricModel) -> Result<ComparedModel> {
        let problem = self.problem_of(law);
        if problem.is_linear() {
            return Ok(ComparedModel {
                label: label.to_string(),
                regressor: problem.regressor(&[], &self.settings.regressor)?,
                estimated: Vec::new(),
                nuisance: Vec::new(),
            });
        }
        let settings = IdentifySettings {
            regressor: self.settings.regressor.clone(),
            fit: FitSettings {
                constraints: Constraints::default(),
                weighting: Weighting::Ordinary,
                ..self.settings.fit.clone()
            },
            estimation: VarProSettings {
                profile: false,
                ..VarProSettings::default()
            },
            steady_state: None,
            bootstrap: None,
        };
        let found = identify(&problem, &settings, &crate::progress::silent)?;
        let estimation = found
            .report
            .estimation
            .as_ref()
            .filter(|_| found.report.is_estimate());
        let Some(estimation) = estimation else {
            return Err(Error::Numerical {
                stage: format!("the least-squares fit of {label}'s estimated parameters"),
                detail: format!(
                    "variable projection did not converge ({}); fix them or widen their bounds",
                    found
                        .report
                        .estimation
                        .as_ref()
                        .map_or("no estimate", |e| e.status.reason.as_str())
                ),
            });
        };
        let (nuisance, estimated): (Vec<_>, Vec<_>) = problem
            .parameters()
            .into_iter()
            .zip(estimation.values())
            .partition(|(spec, _)| spec.nuisance);
        let named = |list: Vec<(crate::regressor::NonlinearParameter, f64)>| {
            list.into_iter().map(|(spec, v)| (spec.name, v)).collect()
        };
        Ok(ComparedModel {
            label: label.to_string(),
            regressor: found.regressor,
            estimated: named(estimated),
            nuisance: named(nuisance),
        })
    }
}
