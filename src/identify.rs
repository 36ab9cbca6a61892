//! The pipeline: records → regressor → fit → diagnostics → report, for every mode
//! (windows of whole periods, with or without the noise-robust rows, and fixed spans of
//! non-periodic records with stored-energy unknowns: [`crate::regressor::Windows`]).
//!
//! Three levels, as faer offers one-call methods over public building blocks:
//!
//! | call | from | to |
//! |---|---|---|
//! | [`identify`] | model, records, settings | report |
//! | [`identify_with_regressor`] | model, records, settings | regressor (for plots) and report |
//! | [`identify_regressor`] | a regressor built by hand or by [`Regressor::build`] | report |
//!
//! [`identify_with_bootstrap`] adds percentile intervals from refits on resampled
//! windows ([`crate::analysis::bootstrap`]). The stages themselves stay public:
//! [`Regressor::build`], [`crate::fit::solve`], [`crate::analysis::diagnostics::diagnose`]
//! and [`FitReport::new`].

use crate::analysis::bootstrap::{BootstrapSettings, bootstrap};
use crate::analysis::solved::{Solved, solved};
use crate::analysis::velocity_noise;
use crate::error::Result;
use crate::fit::FitSettings;
use crate::model::DampingModel;
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings};
use crate::report::FitReport;

/// Settings for [`identify`].
///
/// | setting | default | what |
/// |---|---|---|
/// | `regressor.windows` | one window of one period per record | [`crate::regressor::Windows`]: whole periods, or fixed spans of non-periodic records |
/// | `regressor.quadrature` | trapezoid | rule for the window integrals |
/// | `regressor.velocity` | harmonic projection | measured, central differences, spectral, harmonic projection |
/// | `regressor.noise` | auto | the noise-robust rows with harmonic projection |
/// | `regressor.work_form` | velocity | ∫ vᵀr dt, or the derivative-free ∫ rᵀdx |
/// | `fit.constraints` | none | bounds, fixed values, linear relations (clarabel) |
/// | `fit.weighting` | auto | propagated weights when the rows carry a noise model |
/// | `fit.rank_tolerance` | 1e-10 | singular values below it, relative to σ₁, count as zero |
/// | `fit.solver` | tolerance 1e-10, 200 iterations, polish | the constrained solver |
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IdentifySettings {
    /// Windows, quadrature and velocity source.
    pub regressor: RegressorSettings,
    /// Constraints and solver settings.
    pub fit: FitSettings,
}

impl IdentifySettings {
    /// The settings for the records a harmonic approximation synthesizes
    /// ([`crate::prep::harmonic::HarmonicApproximation::records`]): one window of one
    /// period, the spectral rule, the synthesized velocities
    /// ([`RegressorSettings::harmonic_approximation`]), with `fit`.
    pub fn harmonic_approximation(fit: FitSettings) -> Self {
        IdentifySettings {
            regressor: RegressorSettings::harmonic_approximation(),
            fit,
        }
    }
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
/// With a differencing velocity estimator the report also says how much of the damping
/// columns its noise makes up ([`crate::analysis::velocity_noise`]).
pub fn identify_with_regressor(
    model: &DampingModel,
    records: &[Record],
    settings: &IdentifySettings,
) -> Result<(Regressor, FitReport)> {
    settings.fit.validate()?;
    let regressor = Regressor::build(model, records, &settings.regressor)?;
    let noise = velocity_noise::assess_or_none(model, records, &settings.regressor, &regressor);
    let report = identify_regressor(&regressor, &settings.fit)?.with_velocity_noise(noise);
    Ok((regressor, report))
}

/// Fits `regressor` and diagnoses the fit: the middle level, for regressors built by
/// hand or kept from [`Regressor::build`]. A regressor whose every column is zero
/// carries no information and is an error
/// ([`crate::analysis::identifiability::require_information`]).
/// The solve and the diagnostics are [`crate::analysis::solved::solved`], which `dampid
/// check` shares; the rows are factored once there.
pub fn identify_regressor(regressor: &Regressor, settings: &FitSettings) -> Result<FitReport> {
    let Solved { fit, diagnostics } = solved(regressor, settings)?;
    let report = FitReport::new(regressor, fit, diagnostics);
    Ok(crate::analysis::outliers::with_left_out(
        report, regressor, settings,
    ))
}

/// [`identify`] followed by a bootstrap of the same regressor and fit settings: the
/// report carries the confidence intervals.
pub fn identify_with_bootstrap(
    model: &DampingModel,
    records: &[Record],
    settings: &IdentifySettings,
    bootstrap_settings: &BootstrapSettings,
) -> Result<FitReport> {
    let (regressor, report) = identify_with_regressor(model, records, settings)?;
    Ok(report.with_bootstrap(bootstrap(&regressor, &settings.fit, bootstrap_settings)?))
}
