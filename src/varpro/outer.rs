//! The outer loop: minimise the projected cost φ(η) = ‖r(η)‖² over the box l ≤ η ≤ u.
//!
//! - One parameter: Brent's bounded minimiser (argmin; parabolic interpolation with
//!   golden-section safeguards) on [l, u]; converged when the bracket around the minimum
//!   is below 2(ε|η| + t), ε = `tolerance`, t = 10⁻¹²(u − l).
//! - Several: a bounded Levenberg–Marquardt on the projected residual r(η)
//!   (`levenberg_marquardt.rs`), started from the best point of a coarse multistart set.
//!
//! An error of a trial (a model the builder refuses, a regressor build that fails) ends
//! the loop with that error.

use argmin::core::{
    CostFunction, Error as ArgminError, Executor, State, TerminationReason, TerminationStatus,
};
use argmin::solver::brent::BrentOpt;

use crate::error::{Error, Result};

use super::levenberg_marquardt::levenberg_marquardt;
use super::minimum::{Minimum, Residuals, Shifted};
use super::{NonlinearParameter, VarProSettings};

struct Scalar<'a>(Residuals<'a>);

impl CostFunction for Scalar<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, eta: &f64) -> std::result::Result<f64, ArgminError> {
        (self.0)(&[*eta])
            .map(|r| r.iter().map(|e| e * e).sum())
            .map_err(ArgminError::new)
    }
}

/// A dampid error back from argmin's error, or a numerical error naming it.
pub(super) fn back(error: ArgminError) -> Error {
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

/// Minimises ‖`residuals`‖² over the box of `parameters`, starting from their initial
/// values (and, with several parameters and `multistart`, from the best of a coarse
/// set of starts); `shifted` answers the Levenberg–Marquardt Jacobian's differences it
/// can.
pub(super) fn minimise(
    residuals: Residuals<'_>,
    shifted: Option<Shifted<'_>>,
    parameters: &[NonlinearParameter],
    settings: &VarProSettings,
    multistart: bool,
) -> Result<Minimum> {
    if let [p] = parameters {
        let solver = BrentOpt::new(p.lower, p.upper)
            .set_tolerance(settings.tolerance, 1e-12 * (p.upper - p.lower));
        let result = Executor::new(Scalar(residuals), solver)
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
    levenberg_marquardt(residuals, shifted, parameters, settings, multistart)
}
