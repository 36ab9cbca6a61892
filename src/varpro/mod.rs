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
//! and rebuilding only the affected columns would need the kernel's plan per column),
//! except a stepped-sine table with residual unknowns per sweep, which rebuilds only
//! the sweeps whose unknowns moved and gives the Jacobian columns of those unknowns in
//! closed form to the searches whose row weights are fixed (`sweep_blocks.rs`).
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
//!   include the uncertainty of η; ∂r/∂η by central differences of rebuilt regressors
//!   (a table's sweeps rebuilt one at a time, `sweep_blocks.rs`).
//!
//! An outer loop that does not converge (iteration limit) is data, as [`crate::fit::FitStatus`]
//! is: [`crate::report::FitReport::is_estimate`] is false, and the report shows the last
//! trial as such, without intervals.
//!
//! [`crate::identify::identify`] runs it for a problem with nonlinear parameters
//! ([`ParametricRegressor`]); the bootstrap of the whole variable projection
//! (`bootstrap.rs`) runs through it too.

mod bootstrap;
mod fixed_weights;
mod joint;
mod levenberg_marquardt;
mod minimum;
mod outer;
mod problem;
mod profile;
mod projected_jacobian;
mod sweep_blocks;

use crate::analysis::bootstrap::{Bootstrap, BootstrapSettings};
use crate::error::{Error, Result};
use crate::fit::FitSettings;
use crate::progress::Progress;
pub use crate::regressor::{NonlinearParameter, ParametricModel};
use crate::regressor::{ParametricRegressor, Regressor, RegressorSettings};
use crate::report::FitReport;
pub use crate::report::estimation::{
    Estimation, JointEstimate, NonlinearEstimate, OuterLoop, ProfileInterval,
};

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

/// The variable projection of `problem` (at least one nonlinear parameter): its records'
/// windows cut by `regressor`, each inner fit by `fit`. Returns the regressor at the
/// estimate η̂ (the last trial when the outer loop did not converge) and the report of
/// the linear fit there, carrying the [`Estimation`]. A stage of
/// [`crate::identify::identify`], public for research use.
pub fn estimate(
    problem: &ParametricRegressor<'_>,
    regressor: &RegressorSettings,
    fit: &FitSettings,
    varpro: &VarProSettings,
) -> Result<(Regressor, FitReport)> {
    varpro.validate()?;
    let problem = problem::Problem::new(problem, regressor, fit);
    run(&problem, fit, varpro)
}

/// The bootstrap of the variable projection of `problem` around its estimate η̂
/// (`estimate`, every parameter): every replicate draws the windows (or, with `groups`,
/// whole groups: a table's sweeps) with replacement and refits the whole variable
/// projection from η̂ (the method: `varpro/bootstrap.rs`). `progress(done, total)`
/// counts replicates; [`crate::cancel::check`] runs before each. A stage of
/// [`crate::identify::identify`] (which runs it around its own estimate with its own
/// settings), public for research use: a bootstrap around a given η̂ or under other
/// outer-loop settings.
#[allow(clippy::too_many_arguments)]
pub fn bootstrap(
    problem: &ParametricRegressor<'_>,
    regressor: &RegressorSettings,
    fit: &FitSettings,
    varpro: &VarProSettings,
    estimate: &[f64],
    bootstrap: &BootstrapSettings,
    progress: Progress<'_>,
) -> Result<Bootstrap> {
    let groups = problem.groups();
    let problem = problem::Problem::new(problem, regressor, fit);
    bootstrap::bootstrap(&problem, estimate, groups, varpro, bootstrap, progress)
}

/// The outer loop, the fit at its minimum and the intervals of `problem`, with the
/// regressor at the minimum.
fn run(
    problem: &problem::Problem<'_>,
    fit: &FitSettings,
    varpro: &VarProSettings,
) -> Result<(Regressor, FitReport)> {
    let specs = problem.parameters();
    let minimum = if specs.len() == 1 {
        outer::minimise(
            &|eta: &[f64]| problem.residuals(eta),
            None,
            specs,
            varpro,
            true,
        )?
    } else {
        fixed_weights::minimise(problem, fit, varpro, true)?
    };
    let best = problem.trial(&minimum.values)?;
    // The law parameters use degrees of freedom of the same equations.
    let fit_report = crate::report::outliers::reported(
        &best.regressor,
        &FitSettings {
            nonlinear_parameters: minimum.values.len(),
            ..fit.clone()
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
            bootstrap: None,
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
    let estimation = Estimation {
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
    };
    Ok((best.regressor, fit_report.with_estimation(estimation)))
}
