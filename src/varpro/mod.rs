//! Estimated nonlinear law parameters by variable projection (Golub–Pereyra 1973).
//!
//! A parametric model is a damping model whose regressor depends on nonlinear parameters
//! η (a power law's exponent, a constant inside an expression law), each with an initial
//! value and bounds, while the coefficients θ stay linear:
//!
//! ```text
//!   r(θ, η) = W^{1/2} (A(η) θ − b),   min_{η ∈ [l, u]} min_θ ‖r(θ, η)‖².
//! ```
//!
//! For fixed η the inner problem is the ordinary fit ([`crate::fit::solve`]: least
//! squares, constrained, or weighted by the propagated noise model with W = diag(1/s²)
//! of the weighted fit), so θ̂(η) is a function of η and the projected cost
//! φ(η) = ‖r(θ̂(η), η)‖² is minimised over η alone (`outer.rs`): bounded Brent for one
//! parameter, a bounded Levenberg–Marquardt on the projected residual r(η) from a
//! multistart set for several (`levenberg_marquardt.rs`), with the weights of a weighted
//! inner fit held fixed during the search and refreshed once at its end
//! (`fixed_weights.rs`). Each trial rebuilds the
//! whole regressor of the model the builder makes for η (measured on the four-mass chain: a build costs about as much as the fit itself,
//! and rebuilding only the affected columns would need the kernel's plan per column).
//!
//! Uncertainty, with ν = m − p − q degrees of freedom (m equations, p linear and q
//! nonlinear parameters):
//!
//! - each η_j gets a profile-likelihood interval (`profile.rs`): the η_j where the
//!   profiled cost min_{θ, η_{k≠j}} ‖r‖² rises above φ̂ by F_{1,ν}(0.95)·s², s² = φ̂/ν,
//!   for an unweighted fit, and by χ²₁(0.95) (times χ²/ν when the weighted fit's χ² check
//!   rejects it, [`crate::analysis::diagnostics::REJECTION_P_VALUE`]) for a weighted one;
//!   an end beyond the parameter's bound is reported open;
//! - the linear coefficients (and η, as Wald errors) get the covariance of the full
//!   Jacobian J = [∂r/∂θ, ∂r/∂η] at the optimum (`joint.rs`), σ²(JᵀJ)⁻¹, so their intervals
//!   include the uncertainty of η; ∂r/∂η by central differences of rebuilt regressors.
//!
//! An outer loop that does not converge (iteration limit) is data, as [`crate::fit::FitStatus`]
//! is: [`VarProReport::is_estimate`] is false, and the report shows the last trial as
//! such, without intervals.

mod bootstrap;
mod fixed_weights;
mod joint;
mod levenberg_marquardt;
mod outer;
mod problem;
mod profile;

use std::fmt;
use std::sync::Arc;

use crate::analysis::bootstrap::BootstrapSettings;
use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::record::Record;
use crate::regressor::Regressor;
pub use crate::report::varpro::{
    JointEstimate, NonlinearEstimate, OuterLoop, ProfileInterval, Resampled, VarProBootstrap,
    VarProReport,
};

/// One nonlinear parameter to estimate: its name, initial value and bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct NonlinearParameter {
    /// Name (e.g. `exponent`, `vs`; reports prefix it with the term's coefficient name
    /// where the model file builds it).
    pub name: String,
    /// Initial value, within [lower, upper] (the start of Levenberg–Marquardt, with the multistart corners; bounded Brent,
    /// used for a single parameter, searches the whole interval).
    pub initial: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// A nuisance parameter (a stepped-sine table's residual receptance): estimated with
    /// the others and reported with its joint Wald interval, but given no profile
    /// interval of its own. The profiles of the other parameters still minimise over it.
    pub nuisance: bool,
}

impl NonlinearParameter {
    /// A parameter `name` starting at `initial` within [`lower`, `upper`].
    pub fn new(name: impl Into<String>, initial: f64, lower: f64, upper: f64) -> Self {
        NonlinearParameter {
            name: name.into(),
            initial,
            lower,
            upper,
            nuisance: false,
        }
    }

    /// The same parameter as a nuisance one ([`NonlinearParameter::nuisance`]).
    pub fn as_nuisance(self) -> Self {
        NonlinearParameter {
            nuisance: true,
            ..self
        }
    }

    /// Finite bounds with lower < upper and the initial value within them.
    pub fn validate(&self) -> Result<()> {
        let name = |what: &str| format!("{what} of estimated parameter '{}'", self.name);
        for (what, value) in [
            ("lower bound", self.lower),
            ("upper bound", self.upper),
            ("initial value", self.initial),
        ] {
            if !value.is_finite() {
                return Err(Error::invalid(
                    &name(what),
                    value,
                    "an estimated parameter needs finite `initial`, `lower` and `upper`",
                ));
            }
        }
        if self.lower >= self.upper {
            return Err(Error::invalid(
                &name("lower bound"),
                self.lower,
                &format!("must be below the upper bound {}", self.upper),
            ));
        }
        if !(self.lower..=self.upper).contains(&self.initial) {
            return Err(Error::invalid(
                &name("initial value"),
                self.initial,
                &format!("must lie within [{}, {}]", self.lower, self.upper),
            ));
        }
        Ok(())
    }
}

/// Builds the damping model for given nonlinear parameter values (in the order of
/// [`ParametricModel::parameters`]).
pub type ModelBuilder = Arc<dyn Fn(&[f64]) -> Result<DampingModel> + Send + Sync>;

/// A damping model with nonlinear parameters: their specs and a builder η → model.
#[derive(Clone)]
pub struct ParametricModel {
    parameters: Vec<NonlinearParameter>,
    builder: ModelBuilder,
}

impl fmt::Debug for ParametricModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ParametricModel")
            .field("parameters", &self.parameters)
            .finish_non_exhaustive()
    }
}

impl ParametricModel {
    /// `parameters` (at least one, unique names, each valid) and the `builder`.
    pub fn new(
        parameters: Vec<NonlinearParameter>,
        builder: impl Fn(&[f64]) -> Result<DampingModel> + Send + Sync + 'static,
    ) -> Result<Self> {
        validate_parameters(&parameters, "a parametric model")?;
        Ok(ParametricModel {
            parameters,
            builder: Arc::new(builder),
        })
    }

    /// The nonlinear parameters.
    pub fn parameters(&self) -> &[NonlinearParameter] {
        &self.parameters
    }

    /// The damping model at `values` (one per parameter).
    pub fn model(&self, values: &[f64]) -> Result<DampingModel> {
        check_values(&self.parameters, values)?;
        (self.builder)(values)
    }

    /// The model at the initial values.
    pub fn initial_model(&self) -> Result<DampingModel> {
        let initial: Vec<f64> = self.parameters.iter().map(|p| p.initial).collect();
        self.model(&initial)
    }
}

/// One value per parameter.
fn check_values<T>(parameters: &[NonlinearParameter], values: &[T]) -> Result<()> {
    if values.len() == parameters.len() {
        Ok(())
    } else {
        Err(Error::mismatch(
            "nonlinear parameter values vs parameters",
            parameters.len(),
            values.len(),
        ))
    }
}

/// At least one parameter, unique names, each valid.
fn validate_parameters(parameters: &[NonlinearParameter], of: &str) -> Result<()> {
    if parameters.is_empty() {
        return Err(Error::Empty {
            what: format!("estimated parameters of {of}"),
        });
    }
    for (i, p) in parameters.iter().enumerate() {
        p.validate()?;
        if parameters[..i].iter().any(|q| q.name == p.name) {
            return Err(Error::choice(
                "estimated parameter",
                format!("'{}'", p.name),
                "given twice: every estimated parameter needs its own name",
            ));
        }
    }
    Ok(())
}

/// Builds the whole regressor for given nonlinear parameter values (in the order of
/// [`ParametricRegressor::parameters`]).
pub type RegressorBuilder = Arc<dyn Fn(&[f64]) -> Result<Regressor> + Send + Sync>;

/// A regressor with nonlinear parameters: their specs and a builder η → regressor, for
/// problems whose η changes more than the damping model (a stepped-sine table's
/// residual receptances, [`crate::prep::harmonic::residual`], with or without
/// estimated law parameters). A [`ParametricModel`] on records is one such builder.
#[derive(Clone)]
pub struct ParametricRegressor {
    parameters: Vec<NonlinearParameter>,
    builder: RegressorBuilder,
}

impl fmt::Debug for ParametricRegressor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ParametricRegressor")
            .field("parameters", &self.parameters)
            .finish_non_exhaustive()
    }
}

impl ParametricRegressor {
    /// `parameters` (at least one, unique names, each valid) and the `builder`.
    pub fn new(
        parameters: Vec<NonlinearParameter>,
        builder: impl Fn(&[f64]) -> Result<Regressor> + Send + Sync + 'static,
    ) -> Result<Self> {
        validate_parameters(&parameters, "a parametric regressor")?;
        Ok(ParametricRegressor {
            parameters,
            builder: Arc::new(builder),
        })
    }

    /// The nonlinear parameters.
    pub fn parameters(&self) -> &[NonlinearParameter] {
        &self.parameters
    }

    /// The regressor at `values` (one per parameter).
    pub fn regressor(&self, values: &[f64]) -> Result<Regressor> {
        check_values(&self.parameters, values)?;
        (self.builder)(values)
    }
}

/// Settings of the outer loop and the intervals.
///
/// | setting | default | what |
/// |---|---|---|
/// | `tolerance` | 1e-8 | Brent: relative tolerance on η; Levenberg–Marquardt: an accepted step that lowers the cost by at most this fraction of it ends the loop (its square root for the first, fixed-weight search of a weighted fit, `fixed_weights.rs`) |
/// | `max_iterations` | 200 | outer iterations (Brent, or Levenberg–Marquardt iterations of q + 1 trials each plus rejected steps) |
/// | `level` | 0.95 | confidence level of the profile and joint intervals |
/// | `profile` | true | compute the profile-likelihood intervals (each end is a root search, with a nested optimisation of the other parameters when there are several) |
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VarProSettings {
    /// Convergence tolerance of the outer loop.
    pub tolerance: f64,
    /// Iteration limit of the outer loop.
    pub max_iterations: u64,
    /// Confidence level of the intervals, in (0, 1).
    pub level: f64,
    /// Whether to compute the profile-likelihood intervals.
    pub profile: bool,
}

impl Default for VarProSettings {
    fn default() -> Self {
        VarProSettings {
            tolerance: 1e-8,
            max_iterations: 200,
            level: 0.95,
            profile: true,
        }
    }
}

impl VarProSettings {
    /// Tolerance in (0, 1e-2], at least one iteration, level in (0, 1).
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance > 0.0 && self.tolerance <= 1e-2) {
            return Err(Error::invalid(
                "outer tolerance",
                self.tolerance,
                "must be in (0, 1e-2]",
            ));
        }
        if self.max_iterations == 0 {
            return Err(Error::invalid(
                "outer max_iterations",
                0.0,
                "must be at least 1",
            ));
        }
        if !(self.level > 0.0 && self.level < 1.0) {
            return Err(Error::invalid("level", self.level, "must be in (0, 1)"));
        }
        Ok(())
    }
}

/// Identifies the linear coefficients and the nonlinear parameters of `model` from
/// `records` by variable projection; the inner fits use `settings` as
/// [`crate::identify::identify`] does.
pub fn identify_varpro(
    model: &ParametricModel,
    records: &[Record],
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> Result<VarProReport> {
    identify_varpro_with_regressor(model, records, settings, varpro).map(|(_, _, report)| report)
}

/// [`identify_varpro`], also returning the regressor and the damping model at the
/// estimate η̂ (`model.model(η̂)`, the last trial when the outer loop did not converge),
/// as [`crate::identify::identify_with_regressor`] does, for plots and the equivalent
/// damping without a rebuild.
pub fn identify_varpro_with_regressor(
    model: &ParametricModel,
    records: &[Record],
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> Result<(Regressor, DampingModel, VarProReport)> {
    settings.fit.validate()?;
    varpro.validate()?;
    let problem = problem::Problem::new(model, records, settings);
    let (regressor, report) = run(&problem, settings, varpro)?;
    let values: Vec<f64> = report.parameters.iter().map(|p| p.value).collect();
    Ok((regressor, model.model(&values)?, report))
}

/// [`identify_varpro`] for a regressor built directly from η (`model`'s builder); the
/// inner fits use `settings.fit` (its regressor settings are the builder's business).
pub fn identify_varpro_regressor(
    model: &ParametricRegressor,
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> Result<VarProReport> {
    identify_varpro_regressor_with_regressor(model, settings, varpro).map(|(_, report)| report)
}

/// [`identify_varpro_regressor`], also returning the regressor at the estimate η̂ (the
/// last trial when the outer loop did not converge).
pub fn identify_varpro_regressor_with_regressor(
    model: &ParametricRegressor,
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> Result<(Regressor, VarProReport)> {
    settings.fit.validate()?;
    varpro.validate()?;
    let problem = problem::Problem::with_builder(
        model.parameters(),
        Box::new(|eta: &[f64]| model.regressor(eta)),
        settings,
    );
    run(&problem, settings, varpro)
}

/// The bootstrap of a variable-projection fit of `model` on `records`
/// ([`identify_varpro`]'s `report` of the same inputs): every replicate draws the
/// windows (equations) with replacement and refits the whole variable projection from
/// the report's estimate η̂ (the method: `varpro/bootstrap.rs`). `progress(done,
/// total)` counts replicates; [`crate::cancel::check`] runs before each. Add the result
/// to the report with [`VarProReport::with_bootstrap`].
pub fn bootstrap_varpro(
    model: &ParametricModel,
    records: &[Record],
    settings: &IdentifySettings,
    varpro: &VarProSettings,
    report: &VarProReport,
    bootstrap: &BootstrapSettings,
    progress: Progress<'_>,
) -> Result<VarProBootstrap> {
    let problem = problem::Problem::new(model, records, settings);
    let estimate = estimate_of(model.parameters(), report)?;
    bootstrap::bootstrap(&problem, &estimate, None, varpro, bootstrap, progress)
}

/// [`bootstrap_varpro`] for a regressor built directly from η
/// ([`identify_varpro_regressor`]'s `report` of the same inputs). With `groups`,
/// `groups[r]` the group of equation r (a stepped-sine table's sweeps,
/// [`crate::model_file::Job::sweeps`]), a replicate draws whole groups; without, single
/// equations. Fewer than two groups is [`Error::InvalidChoice`]: one sweep cannot be
/// resampled as a whole.
pub fn bootstrap_varpro_regressor(
    model: &ParametricRegressor,
    groups: Option<&[usize]>,
    settings: &IdentifySettings,
    varpro: &VarProSettings,
    report: &VarProReport,
    bootstrap: &BootstrapSettings,
    progress: Progress<'_>,
) -> Result<VarProBootstrap> {
    let problem = problem::Problem::with_builder(
        model.parameters(),
        Box::new(|eta: &[f64]| model.regressor(eta)),
        settings,
    );
    let estimate = estimate_of(model.parameters(), report)?;
    bootstrap::bootstrap(&problem, &estimate, groups, varpro, bootstrap, progress)
}

/// η̂ of `report`, whose parameters must be `specs` (by name, in order) and whose outer
/// loop must have converged to an estimate.
fn estimate_of(specs: &[NonlinearParameter], report: &VarProReport) -> Result<Vec<f64>> {
    check_values(specs, &report.parameters)?;
    if let Some((spec, found)) = specs
        .iter()
        .zip(&report.parameters)
        .find(|(spec, found)| spec.name != found.name)
    {
        return Err(Error::choice(
            "variable-projection report to bootstrap",
            format!("parameter '{}'", found.name),
            &format!(
                "the problem's parameter there is '{}': bootstrap the report of the same problem",
                spec.name
            ),
        ));
    }
    if !report.is_estimate() {
        return Err(Error::choice(
            "variable-projection report to bootstrap",
            "a fit that is not an estimate".to_string(),
            "its outer loop did not converge or its linear fit failed: there is no estimate to resample around",
        ));
    }
    Ok(report.parameters.iter().map(|p| p.value).collect())
}

/// The outer loop, the fit at its minimum and the intervals of `problem`, with the
/// regressor at the minimum.
fn run(
    problem: &problem::Problem<'_>,
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> Result<(Regressor, VarProReport)> {
    let specs = problem.parameters();
    let minimum = if specs.len() == 1 {
        outer::minimise(&|eta: &[f64]| problem.residuals(eta), specs, varpro, true)?
    } else {
        fixed_weights::minimise(problem, &settings.fit, varpro, true)?
    };
    let best = problem.trial(&minimum.values)?;
    let fit_report = crate::identify::identify_regressor(
        &best.regressor,
        &crate::fit::FitSettings {
            nonlinear_parameters: minimum.values.len(),
            ..settings.fit.clone()
        },
    )?;
    let converged = minimum.converged && best.fit.status.is_usable();
    let dof = best
        .regressor
        .equations()
        .checked_sub(best.regressor.columns().len() + minimum.values.len())
        .filter(|&d| d > 0);
    let variance = problem::Variance::of(&fit_report, best.cost, dof);
    let joint = match (converged, dof) {
        (true, Some(dof)) => {
            joint::covariance(problem, &best, &minimum.values, variance, dof, varpro.level)?
        }
        _ => None,
    };
    let mut parameters = Vec::with_capacity(minimum.values.len());
    for (j, spec) in specs.iter().enumerate() {
        let value = minimum.values[j];
        let interval = match (converged && varpro.profile && !spec.nuisance, dof) {
            (true, Some(dof)) => Some(profile::interval(
                problem,
                specs,
                &minimum.values,
                j,
                best.cost,
                variance,
                dof,
                varpro,
            )?),
            _ => None,
        };
        let span = spec.upper - spec.lower;
        parameters.push(NonlinearEstimate {
            name: spec.name.clone(),
            value,
            initial: spec.initial,
            lower_bound: spec.lower,
            upper_bound: spec.upper,
            at_bound: (value - spec.lower).abs() <= 1e-6 * span
                || (spec.upper - value).abs() <= 1e-6 * span,
            std_error: joint
                .as_ref()
                .and_then(|joint| joint.std_errors[best.fit.coefficients.len() + j]),
            joint_interval: joint.as_ref().and_then(|joint| {
                joint.std_errors[best.fit.coefficients.len() + j]
                    .map(|s| [value - joint.quantile * s, value + joint.quantile * s])
            }),
            interval,
        });
    }
    let coefficients = best
        .regressor
        .columns()
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let std_error = joint.as_ref().and_then(|j| j.std_errors[k]);
            let half = std_error.zip(joint.as_ref()).map(|(s, j)| s * j.quantile);
            let value = best.fit.coefficients[k];
            JointEstimate {
                name: name.clone(),
                value,
                std_error,
                lower: half.map(|h| value - h),
                upper: half.map(|h| value + h),
            }
        })
        .collect();
    let report = VarProReport {
        status: OuterLoop {
            converged: minimum.converged,
            method: minimum.method.into(),
            iterations: minimum.iterations,
            evaluations: problem.evaluations(),
            reason: minimum.reason,
        },
        level: varpro.level,
        cost: best.cost,
        weighted: best.fit.residual_std.is_some(),
        degrees_of_freedom: dof.unwrap_or(0),
        parameters,
        coefficients,
        covariance: joint.and_then(|j| j.covariance),
        fit: fit_report,
        bootstrap: None,
    };
    Ok((best.regressor, report))
}
