//! The pipeline, one for every job: a problem ([`ParametricRegressor`]: a damping law,
//! perhaps with estimated parameters, on records or a stepped-sine table) and one
//! settings value in, one [`Identification`] out.
//!
//! ```text
//!   steady state (optional) → regressor (or variable projection over η) → fit →
//!   diagnostics → velocity-noise assessment → equivalent damping (one-mode tables) →
//!   bootstrap (optional)
//! ```
//!
//! A problem without nonlinear parameters builds its one regressor and fits it
//! ([`crate::analysis::solved`]); with them, variable projection ([`crate::varpro`])
//! minimises the projected cost over η and reports the linear fit at η̂ with the
//! [`crate::report::Estimation`]. Either way the report is one [`FitReport`], its text,
//! JSON, HTML page, `--strict` failures and exit status the same code. The stages stay
//! public for research use: [`crate::regressor::Regressor::build`],
//! [`crate::analysis::solved::solved`], [`crate::analysis::bootstrap::bootstrap`] and
//! [`FitReport::new`].

use std::sync::Arc;

use crate::analysis::backbone::Backbone;
use crate::analysis::bootstrap::{Bootstrap, BootstrapSettings};
use crate::analysis::equivalent::{EquivalentDamping, equivalent_damping};
use crate::analysis::velocity_noise;
use crate::error::Result;
use crate::fit::FitSettings;
use crate::model::DampingModel;
use crate::prep::steady_state::{SteadyStateReport, SteadyStateSettings};
use crate::progress::Progress;
use crate::regressor::{ParametricRegressor, Regressor, RegressorSettings, Source, Windows};
use crate::report::outliers::reported;
use crate::report::{FitReport, Warning};
use crate::varpro::VarProSettings;

/// Settings for [`identify`], validated there.
///
/// | setting | default | what |
/// |---|---|---|
/// | `regressor.windows` | one window of one period per record | [`crate::regressor::Windows`]: whole periods, or fixed spans of non-periodic records (a table's equations are its points) |
/// | `regressor.quadrature` | trapezoid | rule for the window integrals |
/// | `regressor.velocity` | harmonic projection | measured, central differences, spectral, harmonic projection |
/// | `regressor.noise` | auto | the noise-robust rows with harmonic projection |
/// | `regressor.work_form` | velocity | ∫ vᵀr dt, or the derivative-free ∫ rᵀdx |
/// | `fit.constraints` | none | bounds, fixed values, linear relations (clarabel) |
/// | `fit.weighting` | auto | propagated weights when the rows carry a noise model |
/// | `fit.rank_tolerance` | 1e-10 | singular values below it, relative to σ₁, count as zero |
/// | `fit.solver` | tolerance 1e-10, 200 iterations, polish | the constrained solver |
/// | `estimation` | tolerance 1e-8, 200 iterations, 95 %, profiles | the outer loop over estimated parameters ([`VarProSettings`]) |
/// | `steady_state` | `None`: not checked | check the windows for steady state first, refusing transients unless accepted (rows built apart carry their own check: [`crate::campaign`]) |
/// | `bootstrap` | `None` | percentile intervals from refits of resampled windows (a table's whole sweeps) |
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IdentifySettings {
    /// Windows, quadrature and velocity source.
    pub regressor: RegressorSettings,
    /// Constraints and solver settings.
    pub fit: FitSettings,
    /// The outer loop and the intervals of estimated nonlinear parameters.
    pub estimation: VarProSettings,
    /// The steady-state check of the windows of whole periods, when asked for.
    pub steady_state: Option<SteadyStateSettings>,
    /// A bootstrap, when asked for.
    pub bootstrap: Option<BootstrapSettings>,
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
            ..Default::default()
        }
    }

    /// Checks every part: the fit, the outer loop, the steady-state thresholds and the
    /// bootstrap.
    pub fn validate(&self) -> Result<()> {
        self.fit.validate()?;
        self.estimation.validate()?;
        if let Some(steady) = &self.steady_state {
            steady.validate()?;
        }
        if let Some(bootstrap) = &self.bootstrap {
            bootstrap.validate()?;
        }
        Ok(())
    }
}

/// The equivalent damping of a one-mode stepped-sine identification, or why it was not
/// computed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Equivalent {
    /// ζ_eq(X) and η(X) over the measured amplitudes.
    Computed(EquivalentDamping),
    /// Why not.
    NotComputed {
        /// The reason.
        error: String,
    },
}

impl Equivalent {
    /// The equivalent damping, or why it was not computed.
    pub fn as_result(&self) -> std::result::Result<&EquivalentDamping, &str> {
        match self {
            Equivalent::Computed(e) => Ok(e),
            Equivalent::NotComputed { error } => Err(error),
        }
    }
}

/// What [`identify`] found: the report, the regressor and damping model it ends at
/// (those at η̂ when parameters were estimated), the steady-state check, the equivalent
/// damping of a one-mode table and the bootstrap.
#[derive(Debug, Clone)]
pub struct Identification {
    /// The report (its `Display` is the text report, serde gives the JSON).
    pub report: FitReport,
    /// The regressor the final fit used.
    pub regressor: Regressor,
    /// The damping model of that fit.
    pub model: DampingModel,
    /// The steady-state check of the windows, when it ran: shared, not copied, with the
    /// rows that carry it ([`crate::campaign`]; a campaign's holds a check per window).
    pub steady_state: Option<Arc<SteadyStateReport>>,
    /// The equivalent damping of a one-mode stepped-sine table (`None` for other
    /// problems).
    pub equivalent: Option<Equivalent>,
    /// The bootstrap, when one was run (its replicates, for research use; the report
    /// carries its intervals).
    pub bootstrap: Option<Bootstrap>,
    /// The backbone of a free decay: amplitude, frequency, measured and fitted ζ per
    /// window (`None` for other problems).
    pub backbone: Option<Backbone>,
}

impl Identification {
    /// The estimate of coefficient `name` (damping or nuisance), if the model has it.
    pub fn coefficient(&self, name: &str) -> Option<f64> {
        self.report.coefficient(name)
    }

    /// Every estimated nonlinear parameter's value, in the problem's order (empty for a
    /// linear problem).
    pub fn parameter_values(&self) -> Vec<f64> {
        self.report
            .estimation
            .as_ref()
            .map_or_else(Vec::new, |e| e.values())
    }
}

/// Identifies `problem` with `settings` (table above), `progress(done, total)` counting
/// the bootstrap's replicates.
///
/// A problem whose every regressor column is zero carries no information and is an
/// error ([`crate::analysis::identifiability::require_information`]); windows that are
/// not in steady state are one ([`crate::Error::NotSteady`]) when the settings ask for
/// the check and do not accept transients, and a warning when they accept them.
pub fn identify(
    problem: &ParametricRegressor<'_>,
    settings: &IdentifySettings,
    progress: Progress<'_>,
) -> Result<Identification> {
    settings.validate()?;
    let steady = match (&settings.steady_state, problem.source()) {
        // Rows built apart carry the check made where they were built (crate::campaign).
        (_, Source::Rows(rows)) => rows.shared_steady_state(),
        (Some(steady), _) => problem
            .steady_state(&settings.regressor, steady)?
            .map(Arc::new),
        (None, _) => None,
    };
    if let Some(steady) = &steady {
        steady.enforce()?;
    }
    let (regressor, report) = if problem.is_linear() {
        let regressor = problem.regressor(&[], &settings.regressor)?;
        let report = reported(&regressor, &settings.fit)?;
        (regressor, report)
    } else {
        crate::varpro::estimate(
            problem,
            &settings.regressor,
            &settings.fit,
            &settings.estimation,
        )?
    };
    let values = report
        .estimation
        .as_ref()
        .map_or_else(Vec::new, |e| e.values());
    let model = problem.model(&values)?;
    let mut report = report
        .with_velocity_noise(velocity_noise::assess(&regressor))
        .with_steady_state(steady.as_deref());
    let equivalent = equivalent(problem, &values, &report);
    let backbone = match (&settings.regressor.windows, problem.source()) {
        (Windows::Decay(decay), Source::Records(records)) => {
            let theta: Vec<f64> = report.coefficients.iter().map(|c| c.value).collect();
            Some(crate::analysis::backbone::backbone(
                &model, &theta, records, decay,
            )?)
        }
        _ => None,
    };
    let bootstrap = match &settings.bootstrap {
        // Estimated parameters that are not an estimate have nothing to resample around.
        Some(_) if report.estimation.is_some() && !report.is_estimate() => {
            report.warnings.push(Warning::NoBootstrap {
                reason: "the variable projection did not reach an estimate, so there is none to resample around".into(),
            });
            None
        }
        Some(b) => Some(run_bootstrap(
            problem, settings, b, &regressor, &report, progress,
        )?),
        None => None,
    };
    if let Some(bootstrap) = &bootstrap {
        report = report.with_bootstrap(bootstrap);
    }
    Ok(Identification {
        report,
        regressor,
        model,
        steady_state: steady,
        equivalent,
        bootstrap,
        backbone,
    })
}

/// The equivalent damping at the estimate (none with intervals, and none at all, when
/// estimated parameters are not an estimate).
fn equivalent(
    problem: &ParametricRegressor<'_>,
    values: &[f64],
    report: &FitReport,
) -> Option<Equivalent> {
    let coefficients: Vec<f64> = report
        .coefficients
        .iter()
        .chain(&report.nuisance)
        .map(|c| c.value)
        .collect();
    let covariance = report.covariance();
    let result = equivalent_damping(problem, values, &coefficients, covariance.as_deref())?;
    Some(match result {
        Ok(_) if report.estimation.is_some() && !report.is_estimate() => Equivalent::NotComputed {
            error: "the fit is not an estimate".into(),
        },
        Ok(e) => Equivalent::Computed(e),
        Err(e) => Equivalent::NotComputed {
            error: e.to_string(),
        },
    })
}

/// The bootstrap of `problem` around the fit of `report` on `regressor`: the rows of
/// the one regressor of a linear problem (a table's whole sweeps), or the whole
/// variable projection per replicate.
fn run_bootstrap(
    problem: &ParametricRegressor<'_>,
    settings: &IdentifySettings,
    bootstrap: &BootstrapSettings,
    regressor: &Regressor,
    report: &FitReport,
    progress: Progress<'_>,
) -> Result<Bootstrap> {
    match &report.estimation {
        None => crate::analysis::bootstrap::bootstrap(
            regressor,
            &settings.fit,
            bootstrap,
            problem.groups(),
            progress,
        ),
        Some(estimation) => crate::varpro::bootstrap(
            problem,
            &settings.regressor,
            &settings.fit,
            &settings.estimation,
            &estimation.values(),
            bootstrap,
            progress,
        ),
    }
}
