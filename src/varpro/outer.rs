//! The outer loop: minimise the projected cost φ(η) over the box l ≤ η ≤ u with argmin.
//!
//! - One parameter: Brent's bounded minimiser (parabolic interpolation with golden-
//!   section safeguards) on [l, u]; converged when the bracket around the minimum is
//!   below 2(ε|η| + t), ε = `tolerance`, t = 10⁻¹²(u − l).
//! - Several: Nelder–Mead in s ∈ ℝ^q with η_j = l_j + (u_j − l_j)/(1 + e^{−s_j}) (the
//!   box maps onto all of ℝ, so every vertex is feasible), started at the initial
//!   values (nudged 10⁻⁶ of the range inside a bound) with steps of 1 in s, the cost
//!   divided by φ(η₀) so that the stopping rule, the standard deviation of the
//!   simplex's costs below `tolerance`, is relative; restarted from its best vertex
//!   with a fresh simplex until a restart gains less than `tolerance` (at most 10).
//!
//! An error of a trial (a model the builder refuses, a regressor build that fails) ends
//! the loop with that error.

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, State, TerminationReason, TerminationStatus,
};
use argmin::solver::brent::BrentOpt;
use argmin::solver::neldermead::NelderMead;

use crate::error::{Error, Result};

use super::{NonlinearParameter, VarProSettings};

/// The cost of one trial.
pub(super) type Cost<'a> = &'a dyn Fn(&[f64]) -> Result<f64>;

/// Where the outer loop ended.
pub(super) struct Minimum {
    pub values: Vec<f64>,
    pub converged: bool,
    pub iterations: u64,
    pub method: &'static str,
    pub reason: String,
}

struct Scalar<'a>(Cost<'a>);

impl CostFunction for Scalar<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, eta: &f64) -> std::result::Result<f64, ArgminError> {
        (self.0)(&[*eta]).map_err(ArgminError::new)
    }
}

struct Transformed<'a> {
    cost: Cost<'a>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    scale: f64,
}

/// η_j = l_j + (u_j − l_j)/(1 + e^{−s_j}).
fn eta_of(s: &[f64], lower: &[f64], upper: &[f64]) -> Vec<f64> {
    s.iter()
        .zip(lower.iter().zip(upper))
        .map(|(s, (l, u))| l + (u - l) / (1.0 + (-s).exp()))
        .collect()
}

impl Transformed<'_> {
    fn eta(&self, s: &[f64]) -> Vec<f64> {
        eta_of(s, &self.lower, &self.upper)
    }
}

impl CostFunction for Transformed<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, s: &Vec<f64>) -> std::result::Result<f64, ArgminError> {
        (self.cost)(&self.eta(s))
            .map(|c| c / self.scale)
            .map_err(ArgminError::new)
    }
}

/// A dampid error back from argmin's error, or a numerical error naming it.
fn back(error: ArgminError) -> Error {
    match error.downcast::<Error>() {
        Ok(e) => e,
        Err(other) => Error::Numerical {
            stage: "outer optimisation of the nonlinear parameters".into(),
            detail: other.to_string(),
        },
    }
}

fn ended(status: &TerminationStatus) -> (bool, String) {
    match status {
        TerminationStatus::Terminated(TerminationReason::SolverConverged) => {
            (true, "converged".into())
        }
        TerminationStatus::Terminated(reason) => (false, reason.text().to_lowercase()),
        TerminationStatus::NotTerminated => (false, "not terminated".into()),
    }
}

/// Minimises `cost` over the box of `parameters`, starting from their initial values.
pub(super) fn minimise(
    cost: Cost<'_>,
    parameters: &[NonlinearParameter],
    settings: &VarProSettings,
) -> Result<Minimum> {
    if let [p] = parameters {
        let solver = BrentOpt::new(p.lower, p.upper)
            .set_tolerance(settings.tolerance, 1e-12 * (p.upper - p.lower));
        let result = Executor::new(Scalar(cost), solver)
            .configure(|s| s.max_iters(settings.max_iterations))
            .run()
            .map_err(back)?;
        let state = result.state();
        let (converged, reason) = ended(state.get_termination_status());
        let value = state
            .get_best_param()
            .copied()
            .unwrap_or(p.initial)
            .clamp(p.lower, p.upper);
        return Ok(Minimum {
            values: vec![value],
            converged,
            iterations: state.get_iter(),
            method: "brent",
            reason,
        });
    }
    let lower: Vec<f64> = parameters.iter().map(|p| p.lower).collect();
    let upper: Vec<f64> = parameters.iter().map(|p| p.upper).collect();
    let start: Vec<f64> = parameters
        .iter()
        .map(|p| {
            let span = p.upper - p.lower;
            let fraction = ((p.initial - p.lower) / span).clamp(1e-6, 1.0 - 1e-6);
            (fraction / (1.0 - fraction)).ln()
        })
        .collect();
    let mut problem = Transformed {
        cost,
        lower: lower.clone(),
        upper: upper.clone(),
        scale: 1.0,
    };
    let initial_cost = cost(&problem.eta(&start))?;
    if initial_cost > 0.0 && initial_cost.is_finite() {
        problem.scale = initial_cost;
    }
    // Nelder–Mead can collapse its simplex in a curved valley far from the minimum:
    // restart from the best vertex with a fresh simplex until a restart improves the
    // cost by less than `tolerance` (relative), at most RESTARTS times.
    const RESTARTS: usize = 10;
    let (mut best, mut best_cost) = (start, initial_cost / problem.scale);
    let (mut converged, mut reason, mut iterations) = (false, String::new(), 0);
    for _ in 0..RESTARTS {
        let mut simplex = vec![best.clone()];
        for j in 0..best.len() {
            let mut vertex = best.clone();
            vertex[j] += 1.0;
            simplex.push(vertex);
        }
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(settings.tolerance)
            .map_err(back)?;
        let result = Executor::new(problem, solver)
            .configure(|s| s.max_iters(settings.max_iterations))
            .run()
            .map_err(back)?;
        let state = result.state();
        (converged, reason) = ended(state.get_termination_status());
        iterations += state.get_iter();
        let found = state.get_best_cost();
        let improved = best_cost - found;
        if found < best_cost {
            best = state.get_best_param().cloned().unwrap_or(best);
            best_cost = found;
        }
        problem = result.problem.problem.ok_or_else(|| Error::Numerical {
            stage: "outer optimisation of the nonlinear parameters".into(),
            detail: "argmin did not return the problem".into(),
        })?;
        if !converged || improved <= settings.tolerance * best_cost.abs().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    Ok(Minimum {
        values: eta_of(&best, &lower, &upper),
        converged,
        iterations,
        method: "nelder_mead",
        reason,
    })
}
