//! A job with estimated nonlinear parameters (law parameters `{ estimate = true, … }`,
//! a stepped-sine table's residual receptances) identified by variable projection as
//! `dampid identify` runs it, with what its reports need besides the
//! [`VarProReport`]: the regressor and the damping model at η̂, and the equivalent
//! damping of a one-mode stepped-sine table at η̂ with the joint intervals
//! ([`crate::analysis::equivalent_estimated`]).

use crate::analysis::equivalent::EquivalentDamping;
use crate::analysis::equivalent_estimated::{EstimatedLaw, equivalent_damping_estimated};
use crate::error::Result;
use crate::model::DampingModel;
use crate::regressor::Regressor;
use crate::varpro::{
    VarProReport, identify_varpro_regressor_with_regressor, identify_varpro_with_regressor,
};

/// A variable-projection fit of a job, with the regressor and the damping model at η̂
/// (the last trial when the outer loop did not converge).
#[derive(Debug, Clone)]
pub struct VarProFit {
    /// The regressor at η̂.
    pub regressor: Regressor,
    /// The damping model at η̂: the parametric model at the law parameters' estimates,
    /// or the job's model when only residual receptances are estimated (they change
    /// the table, not the law).
    pub model: DampingModel,
    /// The report.
    pub report: VarProReport,
}

impl super::Job {
    /// True when the job estimates nonlinear parameters (identified by
    /// [`Self::identify_varpro`], not by the linear fit alone).
    pub fn estimates_nonlinear(&self) -> bool {
        self.parametric.is_some() || self.estimates_residual()
    }

    /// The variable-projection fit of a job that [`Self::estimates_nonlinear`], with
    /// [`Self::varpro_settings`]: a stepped-sine table through
    /// [`Self::parametric_regressor`], records through [`Self::parametric`]. `None`
    /// for other jobs.
    pub fn identify_varpro(&self) -> Option<Result<VarProFit>> {
        let varpro = self.varpro_settings();
        if let Some(regressor) = self.parametric_regressor() {
            return Some(regressor.and_then(|builder| {
                let (regressor, report) =
                    identify_varpro_regressor_with_regressor(&builder, &self.settings, &varpro)?;
                let model = match &self.parametric {
                    Some(law) => {
                        let q = law.parameters().len();
                        let values: Vec<f64> =
                            report.parameters[..q].iter().map(|p| p.value).collect();
                        law.model(&values)?
                    }
                    None => self.model.clone(),
                };
                Ok(VarProFit {
                    regressor,
                    model,
                    report,
                })
            }));
        }
        let law = self.parametric.as_ref()?;
        Some(
            identify_varpro_with_regressor(law, &self.records, &self.settings, &varpro).map(
                |(regressor, model, report)| VarProFit {
                    regressor,
                    model,
                    report,
                },
            ),
        )
    }

    /// For a one-DOF `[stepped_sine]` job: the equivalent viscous damping ratio and loss
    /// factor versus amplitude of a variable-projection fit at η̂ (its `report` and
    /// its damping `model` at η̂, [`VarProFit`]), with intervals from the joint
    /// covariance, which include the uncertainty of the estimated law parameters and
    /// residual receptances; the modal mass and stiffness as
    /// [`Self::equivalent_damping`] takes them. No intervals when the fit is not an
    /// estimate. `None` for other jobs.
    pub fn equivalent_damping_varpro(
        &self,
        model: &DampingModel,
        report: &VarProReport,
    ) -> Option<Result<EquivalentDamping>> {
        let table = self.stepped_sine.as_ref()?;
        let modal = self.modal()?;
        let covariance = report
            .covariance
            .as_deref()
            .filter(|_| report.is_estimate());
        let coefficients: Vec<f64> = report.coefficients.iter().map(|c| c.value).collect();
        let law_values: Vec<f64>;
        let bounds: (Vec<f64>, Vec<f64>);
        let builder;
        let law = match &self.parametric {
            Some(parametric) => {
                let q = parametric.parameters().len();
                law_values = report.parameters[..q].iter().map(|p| p.value).collect();
                bounds = parametric
                    .parameters()
                    .iter()
                    .map(|p| (p.lower, p.upper))
                    .unzip();
                builder = move |eta: &[f64]| parametric.model(eta);
                Some(EstimatedLaw {
                    model: &builder,
                    values: &law_values,
                    lower: &bounds.0,
                    upper: &bounds.1,
                })
            }
            None => None,
        };
        Some(modal.and_then(|modal| {
            equivalent_damping_estimated(
                model,
                law.as_ref(),
                &table.structural,
                &table.approximation,
                &table.table,
                &coefficients,
                covariance,
                modal,
            )
        }))
    }
}
