//! The one-call entry point: records → regressor → fit → diagnostics → report.

use serde::{Deserialize, Serialize};

use crate::analysis::diagnostics::diagnose;
use crate::error::Result;
use crate::fit::{FitSettings, solve};
use crate::model::DampingModel;
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings};
use crate::report::FitReport;

/// Settings for [`identify`].
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct IdentifySettings {
    /// Windows, quadrature and velocity source.
    pub regressor: RegressorSettings,
    /// Constraints and solver settings.
    pub fit: FitSettings,
}

/// Identifies the coefficients of `model` from `records`.
pub fn identify(
    model: &DampingModel,
    records: &[Record],
    settings: &IdentifySettings,
) -> Result<FitReport> {
    identify_with_regressor(model, records, settings).map(|(_, report)| report)
}

/// [`identify`], also returning the regressor the fit used (for plots and research).
pub fn identify_with_regressor(
    model: &DampingModel,
    records: &[Record],
    settings: &IdentifySettings,
) -> Result<(Regressor, FitReport)> {
    settings.fit.validate()?;
    let regressor = Regressor::build(model, records, &settings.regressor)?;
    let fit = solve(&regressor, &settings.fit)?;
    let diagnostics = diagnose(&regressor, &fit, settings.fit.rank_tolerance);
    let report = FitReport::new(&regressor, fit, diagnostics);
    Ok((regressor, report))
}
