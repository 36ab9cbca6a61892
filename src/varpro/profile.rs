//! Profile-likelihood interval of one nonlinear parameter η_j: the set of η_j whose
//! profiled cost P(η_j) = min_{θ, η_{k≠j}} φ stays within Δ of the minimum φ̂,
//!
//! ```text
//!   Δ = F_{1,ν}⁻¹(level) · s²,  s² = φ̂/ν          (unweighted fit)
//!   Δ = χ²₁⁻¹(level) · σ²,      σ² = 1 or χ²/ν    (weighted fit: plug-in, or scaled when
//!                                                   its χ² check rejects it)
//! ```
//!
//! Each end is the root of P(η_j) − φ̂ − Δ between η̂_j and the bound, found by Brent's
//! root finder (argmin) to 10⁻⁶ of the bound interval; with several parameters every
//! P evaluation is a nested outer optimisation of the others, started at their values
//! at the nearest η_j solved so far (the optimum first: a continuation along the
//! profile, which saves most of the nested iterations; the nested minimum is the same
//! to the outer tolerance, so the ends move in their last digits, BENCHMARKS.md §14).
//! An end where P is still below φ̂ + Δ at the bound is open (`None`): the data do not
//! bound the parameter on that side within the bounds given. An optimum on a bound
//! closes that side at the bound.

use std::cell::RefCell;

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::brent::BrentRoot;
use statrs::distribution::{ChiSquared, ContinuousCDF, FisherSnedecor};

use super::minimum::Cost;
use super::minimum::{Column, Shifted};
use super::outer::minimise;
use super::problem::{Problem, Variance};
use super::projected_jacobian::{Projections, column};
use super::{NonlinearParameter, ProfileInterval, VarProSettings};
use crate::error::{Error, Result};
use crate::fit::Weighting;

struct Excess<'a> {
    profile: Cost<'a>,
    threshold: f64,
}

impl CostFunction for Excess<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, t: &f64) -> std::result::Result<f64, ArgminError> {
        (self.profile)(&[*t])
            .map(|p| p - self.threshold)
            .map_err(ArgminError::new)
    }
}

/// The rise Δ of the cost that bounds the interval at `level`.
pub(super) fn rise(variance: Variance, dof: usize, level: f64) -> Result<f64> {
    let quantile = if variance.estimated {
        FisherSnedecor::new(1.0, dof as f64)
            .map(|d| d.inverse_cdf(level))
            .map_err(|e| e.to_string())
    } else {
        ChiSquared::new(1.0)
            .map(|d| d.inverse_cdf(level))
            .map_err(|e| e.to_string())
    }
    .map_err(|e| Error::Numerical {
        stage: "profile interval".into(),
        detail: e,
    })?;
    Ok(quantile * variance.scale)
}

/// The profile interval of parameter `j` around `optimum` (cost `minimum`).
#[allow(clippy::too_many_arguments)]
pub(super) fn interval(
    problem: &Problem<'_>,
    parameters: &[NonlinearParameter],
    optimum: &[f64],
    j: usize,
    minimum: f64,
    variance: Variance,
    dof: usize,
    settings: &VarProSettings,
) -> Result<ProfileInterval> {
    let delta = rise(variance, dof, settings.level)?;
    let others: Vec<NonlinearParameter> = parameters
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != j)
        .map(|(k, p)| NonlinearParameter {
            initial: optimum[k],
            ..p.clone()
        })
        .collect();
    let full = |t: f64, rest: &[f64]| -> Vec<f64> {
        let mut eta = rest.to_vec();
        eta.insert(j, t);
        eta
    };
    // the profile points solved so far, (η_j, the others' values), the optimum first
    let solved: RefCell<Vec<(f64, Vec<f64>)>> = RefCell::new(vec![(
        optimum[j],
        others.iter().map(|p| p.initial).collect(),
    )]);
    let profile = |t: &[f64]| -> Result<f64> {
        if others.is_empty() {
            return problem.cost(t);
        }
        let inner = |rest: &[f64]| problem.residuals(&full(t[0], rest));
        // started at the others' values of the nearest point solved (continuation): no
        // multistart
        let start: Vec<NonlinearParameter> = {
            let solved = solved.borrow();
            // cannot fail: `solved` holds the optimum at least.
            let (_, nearest) = solved
                .iter()
                .min_by(|a, b| (a.0 - t[0]).abs().total_cmp(&(b.0 - t[0]).abs()))
                .expect("the optimum is solved");
            others
                .iter()
                .zip(nearest)
                .map(|(p, &v)| NonlinearParameter {
                    initial: v,
                    ..p.clone()
                })
                .collect()
        };
        // the Jacobian's columns of a table's residual unknowns for an unweighted fit,
        // exact (`projected_jacobian.rs`); a weighted fit differences whole trials (its
        // weights move with η, which the closed form leaves out)
        let kept = Projections::default();
        let shifted = |rest: &[f64], k: usize, h: f64| -> Result<Option<Column>> {
            let eta = full(t[0], rest);
            let base = problem.shared(&eta)?;
            let k = if k >= j { k + 1 } else { k };
            column(problem, &kept, &base, None, problem.fit(), &eta, k, h)
        };
        let unweighted = problem.fit().weighting == Weighting::Ordinary;
        let best = minimise(
            &inner,
            unweighted.then_some(&shifted as Shifted<'_>),
            &start,
            settings,
            false,
        )?;
        solved.borrow_mut().push((t[0], best.values.clone()));
        problem.cost(&full(t[0], &best.values))
    };
    let spec = &parameters[j];
    let span = spec.upper - spec.lower;
    let threshold = minimum + delta;
    let end = |bound: f64| -> Result<Option<f64>> {
        // On the bound as the report's `at_bound` flag counts it (within 10⁻⁶ of the
        // interval): that side closes at the bound.
        if (bound - optimum[j]).abs() <= 1e-6 * span {
            return Ok(Some(bound));
        }
        if profile(&[bound])? < threshold {
            return Ok(None);
        }
        let (a, b) = if bound < optimum[j] {
            (bound, optimum[j])
        } else {
            (optimum[j], bound)
        };
        let result = Executor::new(
            Excess {
                profile: &profile,
                threshold,
            },
            BrentRoot::new(a, b, 1e-6 * span),
        )
        .configure(|s| s.max_iters(100))
        .run()
        .map_err(|e| match e.downcast::<Error>() {
            Ok(e) => e,
            Err(other) => Error::Numerical {
                stage: "profile interval".into(),
                detail: other.to_string(),
            },
        })?;
        Ok(result.state().get_best_param().copied())
    };
    Ok(ProfileInterval {
        lower: end(spec.lower)?,
        upper: end(spec.upper)?,
        level: settings.level,
        rise: delta,
    })
}
