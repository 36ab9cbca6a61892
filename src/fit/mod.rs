//! Fitting the regressor: plain least squares ([`least_squares`]) or least squares
//! under physical constraints (bounds, fixed values, linear relations between
//! coefficients) through clarabel ([`constrained`]). [`solve`] picks the
//! one the settings call for. A solver's status is data: a fit that did not converge
//! says so in [`Fit::status`], and the report carries it. [`ScaledSvd`] is the one
//! factorization of the column-scaled regressor that least squares, the diagnostics,
//! the identifiability analysis and model comparison share.

mod constrained;
mod constraints;
mod least_squares;
pub(crate) mod scaling;
pub mod svd;
mod weighted;

pub use constrained::constrained;
pub use constraints::{Bound, Constraints, Fixed, LinearConstraint, LinearTerm, Relation};
pub(crate) use least_squares::factored_least_squares;
pub use least_squares::least_squares;
pub use svd::ScaledSvd;
pub(crate) use weighted::inverse_std;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::regressor::Regressor;

/// How the fit ended. New statuses may be added (`#[non_exhaustive]`): read
/// [`FitStatus::is_usable`] rather than matching every one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum FitStatus {
    /// Converged to the requested tolerance.
    Solved,
    /// Converged to a reduced tolerance: numbers usable, with care.
    AlmostSolved,
    /// The constraints cannot be met together.
    Infeasible,
    /// The iteration limit was reached: numbers are not a solution.
    MaxIterations,
    /// The time limit was reached: numbers are not a solution.
    MaxTime,
    /// The solver stopped making progress.
    InsufficientProgress,
    /// The solver failed numerically.
    NumericalError,
}

impl FitStatus {
    /// True when the coefficients are a solution (possibly of reduced accuracy).
    pub fn is_usable(&self) -> bool {
        matches!(self, FitStatus::Solved | FitStatus::AlmostSolved)
    }
}

/// Which method produced the fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitMethod {
    /// Plain least squares (SVD).
    LeastSquares,
    /// Constrained least squares (clarabel, with polish).
    Constrained,
}

/// Which side of its interval a coefficient sits on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundSide {
    /// At its lower bound (0 for nonnegativity).
    Lower,
    /// At its upper bound.
    Upper,
    /// Held at a fixed value.
    Fixed,
}

/// A constraint the solution touches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ActiveConstraint {
    /// Coefficient name.
    pub name: String,
    /// Which bound.
    pub side: BoundSide,
    /// The bound's value.
    pub value: f64,
}

/// What the constrained solver reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SolverInfo {
    /// Interior-point iterations.
    pub iterations: u32,
    /// Whether the active-set polish replaced the interior-point solution.
    pub polished: bool,
}

/// A fitted coefficient vector and how it was obtained.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// θ, in the regressor's column order.
    pub coefficients: Vec<f64>,
    /// How the fit ended.
    pub status: FitStatus,
    /// Which method.
    pub method: FitMethod,
    /// Constraints the solution touches.
    pub active: Vec<ActiveConstraint>,
    /// Constrained solver details.
    pub solver: Option<SolverInfo>,
    /// With propagated weighting: the standard deviation of each equation's residual
    /// at the final coefficients (the equations were weighted by its inverse).
    pub residual_std: Option<Vec<f64>>,
}

/// How the equations are weighted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Weighting {
    /// Propagated when the regressor carries a noise model, ordinary otherwise.
    #[default]
    Auto,
    /// Every equation counts the same (ordinary least squares).
    Ordinary,
    /// Each equation weighted by the inverse standard deviation of its residual,
    /// propagated from the estimated sensor noise (needs the noise-robust pipeline;
    /// see [`crate::regressor::robust`]).
    Propagated,
}

/// Settings of the constrained solver.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SolverSettings {
    /// Gap and feasibility tolerance given to clarabel (default 1e-10).
    pub tolerance: f64,
    /// Iteration limit (default 200).
    pub max_iterations: u32,
    /// Run the active-set polish (default true).
    pub polish: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-10,
            max_iterations: 200,
            polish: true,
        }
    }
}

impl SolverSettings {
    /// Rejects tolerances outside (0, 1e-2] and a zero iteration limit.
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance > 0.0 && self.tolerance <= 1e-2) {
            return Err(Error::invalid(
                "solver tolerance",
                self.tolerance,
                "must be in (0, 1e-2]",
            ));
        }
        if self.max_iterations == 0 {
            return Err(Error::invalid("max_iterations", 0.0, "must be at least 1"));
        }
        Ok(())
    }
}

/// Settings of a fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSettings {
    /// Constraints; none gives plain least squares.
    pub constraints: Constraints,
    /// Constrained-solver settings.
    pub solver: SolverSettings,
    /// Singular values below `rank_tolerance · σ_1` of the column-scaled regressor
    /// count as zero (default 1e-10).
    pub rank_tolerance: f64,
    /// How the equations are weighted.
    #[serde(default)]
    pub weighting: Weighting,
    /// Fit rows whose input work is negative beyond its noise (a passive structure
    /// cannot give out energy, so [`crate::analysis::solved::solved`] refuses them
    /// otherwise: [`crate::regressor::passive`]).
    #[serde(default)]
    pub accept_negative_work: bool,
    /// Parameters estimated from the same equations outside this linear fit (the law
    /// parameters η of variable projection): they use degrees of freedom too, so the
    /// residual variance, the χ² check and the noise level of the identifiability
    /// analysis count m − (free coefficients) − this many.
    #[serde(default)]
    pub nonlinear_parameters: usize,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            constraints: Constraints::default(),
            solver: SolverSettings::default(),
            rank_tolerance: 1e-10,
            weighting: Weighting::Auto,
            accept_negative_work: false,
            nonlinear_parameters: 0,
        }
    }
}

impl FitSettings {
    /// Checks the settings themselves.
    pub fn validate(&self) -> Result<()> {
        if !(self.rank_tolerance > 0.0 && self.rank_tolerance < 1.0) {
            return Err(Error::invalid(
                "rank_tolerance",
                self.rank_tolerance,
                "must be in (0, 1)",
            ));
        }
        self.solver.validate()
    }
}

/// Least squares when there are no constraints, clarabel otherwise; weighted by the
/// propagated residual variances when the settings and the regressor call for it.
pub fn solve(regressor: &Regressor, settings: &FitSettings) -> Result<Fit> {
    solve_factored(regressor, settings).map(|(fit, _)| fit)
}

/// [`solve`], also returning the factorization of the rows when the fit made one of
/// the rows its diagnostics read (plain least squares on unweighted rows), so that
/// they need not factor them again.
pub(crate) fn solve_factored(
    regressor: &Regressor,
    settings: &FitSettings,
) -> Result<(Fit, Option<ScaledSvd>)> {
    settings.validate()?;
    match (settings.weighting, regressor.noise()) {
        (Weighting::Ordinary, _) | (Weighting::Auto, None) if settings.constraints.is_empty() => {
            let (fit, svd) =
                least_squares::factored_least_squares(regressor, settings.rank_tolerance)?;
            Ok((checked(regressor, fit)?, Some(svd)))
        }
        (Weighting::Ordinary, _) | (Weighting::Auto, None) => {
            Ok((solve_rows(regressor, settings)?, None))
        }
        (_, Some(noise)) => Ok((weighted::solve(regressor, noise, settings)?, None)),
        (Weighting::Propagated, None) => Err(Error::choice(
            "weighting",
            "propagated",
            "propagated weights need the regressor's noise model: use velocity = harmonic projection with noise correction, or weighting = ordinary",
        )),
    }
}

/// [`solve`] on the rows as they are.
pub(crate) fn solve_rows(regressor: &Regressor, settings: &FitSettings) -> Result<Fit> {
    let fit = if settings.constraints.is_empty() {
        least_squares(regressor, settings.rank_tolerance)?
    } else {
        constrained(regressor, &settings.constraints, &settings.solver)?
    };
    checked(regressor, fit)
}

/// `fit`, unless it claims success with a non-finite coefficient: never a silent NaN.
fn checked(regressor: &Regressor, fit: Fit) -> Result<Fit> {
    if fit.status.is_usable()
        && let Some((j, value)) = fit
            .coefficients
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
    {
        return Err(Error::Numerical {
            stage: "fit".into(),
            detail: format!("coefficient '{}' came out {value}", regressor.columns()[j]),
        });
    }
    Ok(fit)
}
