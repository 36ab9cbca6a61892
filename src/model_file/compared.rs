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
//! by variable projection ([`crate::varpro`]) with an unweighted, unconstrained inner
//! fit and no profile intervals, whatever the job's own fit settings are: the estimate
//! `dampid identify` reports (weighted by the propagated noise, under constraints) can
//! differ from it, and the comparison says which values it used.

use super::Job;
use crate::analysis::compare::Candidate;
use crate::error::{Error, Result};
use crate::fit::{Constraints, FitSettings, Weighting};
use crate::identify::IdentifySettings;
use crate::model::DampingModel;
use crate::regressor::Regressor;
use crate::varpro::{ParametricModel, VarProReport, VarProSettings};

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
    /// `model` (with its estimated law parameters `law`, if any, and the job's residual
    /// receptances, if it estimates them) on this job's equations, labelled `label`
    /// (module doc). An outer loop that does not converge is an error naming the model.
    pub fn compared(
        &self,
        label: &str,
        model: &DampingModel,
        law: Option<&ParametricModel>,
    ) -> Result<ComparedModel> {
        let settings = IdentifySettings {
            regressor: self.settings.regressor.clone(),
            fit: FitSettings {
                constraints: Constraints::default(),
                weighting: Weighting::Ordinary,
                ..self.settings.fit.clone()
            },
        };
        let varpro = VarProSettings {
            profile: false,
            ..VarProSettings::default()
        };
        let converged = |report: VarProReport| -> Result<Vec<f64>> {
            if report.is_estimate() {
                Ok(report.parameters.iter().map(|p| p.value).collect())
            } else {
                Err(Error::Numerical {
                    stage: format!("the least-squares fit of {label}'s estimated parameters"),
                    detail: format!(
                        "variable projection did not converge ({}); fix them or widen their bounds",
                        report.status.reason
                    ),
                })
            }
        };
        let (regressor, specs, values) = match (self.parametric_regressor_of(model, law), law) {
            (Some(parametric), _) => {
                let parametric = parametric?;
                let values = converged(crate::varpro::identify_varpro_regressor(
                    &parametric,
                    &settings,
                    &varpro,
                )?)?;
                let specs = parametric.parameters().to_vec();
                (parametric.regressor(&values)?, specs, values)
            }
            (None, Some(law)) => {
                let values = converged(crate::varpro::identify_varpro(
                    law,
                    &self.records,
                    &settings,
                    &varpro,
                )?)?;
                (
                    self.regressor_of(&law.model(&values)?)?,
                    law.parameters().to_vec(),
                    values,
                )
            }
            (None, None) => (self.regressor_of(model)?, Vec::new(), Vec::new()),
        };
        let (nuisance, estimated): (Vec<_>, Vec<_>) = specs
            .into_iter()
            .zip(values)
            .partition(|(spec, _)| spec.nuisance);
        let named = |list: Vec<(crate::varpro::NonlinearParameter, f64)>| {
            list.into_iter().map(|(spec, v)| (spec.name, v)).collect()
        };
        Ok(ComparedModel {
            label: label.to_string(),
            regressor,
            estimated: named(estimated),
            nuisance: named(nuisance),
        })
    }
}
