//! The bootstrap of a variable-projection fit: percentile intervals of every nonlinear
//! parameter η_j and linear coefficient θ_k from refits of the whole variable
//! projection on resampled equations.
//!
//! Replicate k draws, with replacement, as many units as there are (the pairs bootstrap
//! of [`crate::analysis::bootstrap`]): single equations (a window of whole periods of a
//! record is a unit of its own), or whole sweeps of a stepped-sine table (the cluster
//! bootstrap of [`crate::analysis::bootstrap::bootstrap`] with groups: errors correlated within a sweep, such as its
//! residual receptance or a drift over the sweep, are resampled as they occur). With
//! R the drawn rows (repeats kept), the replicate minimises the projected cost of those
//! rows alone,
//!
//! ```text
//!   (η*, θ*) = argmin_{η ∈ [l, u]} min_θ ‖W_R^{1/2} (A_R(η) θ − b_R)‖²,
//! ```
//!
//! every trial η rebuilding the whole regressor with the problem's builder and keeping
//! the rows R with their noise model ([`crate::regressor::Regressor::select_rows`], so
//! a weighted inner fit stays weighted by the same rows' propagated noise). The outer
//! loop starts from the full data's estimate η̂, the standard choice (a replicate's
//! minimum lies near η̂, so the search saves the multistart and most iterations): a
//! bounded Levenberg–Marquardt on the projected residual from η̂ without the
//! multistart corners, for one parameter too (the full fit's Brent has no start: it
//! searches the whole bracket), with the weights of a weighted inner fit held fixed for
//! several parameters as in `fixed_weights.rs`. No profile and no joint covariance are
//! computed inside replicates.
//!
//! A replicate whose outer loop does not converge, or whose linear fit at η* is not
//! usable (solver status, a numerical failure, or a numerical rank below the full
//! data's at η̂), is dropped and counted; fewer than half kept is an error. From the B'
//! kept (η*, θ*), each quantity's interval is the type-7 percentile interval and its
//! bootstrap standard error the standard deviation of its replicates
//! ([`crate::analysis::bootstrap::ConfidenceInterval`]).
//!
//! Whole sweeps keep each sweep's points together, so an unknown of one sweep alone (a
//! stepped-sine sweep's residual receptance r_k) sees the same points in every
//! replicate that draws its sweep and varies only through the shared parameters (on
//! the table of tests/varpro_bootstrap.rs: bootstrap se 1e-9 to 1e-8 m/N against joint
//! Wald se 8e-6): its percentile interval understates its uncertainty, and the report
//! says to read its joint interval instead. A sweep a replicate did not draw leaves its
//! unknown out of the cost: it stays at its start η̂ (a zero Jacobian column gives a
//! zero Levenberg–Marquardt step). The law parameters and the coefficients, which every
//! sweep informs, are what the sweep bootstrap is for.
//!
//! Deterministic: replicate k draws from its own generator (splitmix64 seeding, as the
//! linear bootstrap), replicates run in parallel and are collected in replicate order,
//! so the result does not depend on the number of threads.

use crate::analysis::bootstrap::{
    Bootstrap, BootstrapSettings, BootstrapSummary, Groups, Resampled, percentile_interval,
    rank_of, replicate_rng, run_replicates,
};
use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::regressor::NonlinearParameter;

use super::levenberg_marquardt::levenberg_marquardt;
use super::problem::Problem;
use super::{VarProSettings, fixed_weights};

/// What became of one replicate.
enum Outcome {
    /// (η*, θ*).
    Kept(Vec<f64>),
    NotConverged,
    Unusable,
}

/// Bootstraps `problem` around its full-data estimate `estimate` (η̂), resampling
/// single equations (`groups` `None`) or whole groups, `groups[r]` the group of
/// equation r (see the module doc).
pub(super) fn bootstrap(
    problem: &Problem<'_>,
    estimate: &[f64],
    groups: Option<&[usize]>,
    varpro: &VarProSettings,
    settings: &BootstrapSettings,
    progress: Progress<'_>,
) -> Result<Bootstrap> {
    settings.validate()?;
    varpro.validate()?;
    let fit = problem.fit();
    fit.validate()?;
    let specs = problem.parameters();
    crate::regressor::nonlinear::check_values(specs, estimate)?;
    let full = problem.regressor(estimate)?;
    let m = full.equations();
    let p = full.columns().len();
    let q = specs.len();
    if m < p + q {
        return Err(Error::TooFewEquations {
            equations: m,
            coefficients: p + q,
        });
    }
    let (units, resampled) = match groups {
        None => (Groups::rows(m), Resampled::Windows),
        Some(groups) => (Groups::of(groups, m)?, Resampled::Sweeps),
    };
    crate::budget::require(
        &format!(
            "{} bootstrap replicates of {} parameters and coefficients",
            settings.replicates,
            p + q
        ),
        // Each replicate: its p + q values and the units it drew, with their Vec
        // headers and allocator overhead (about 12 words).
        crate::budget::f64s(
            (settings.replicates as u128).saturating_mul((p + q + units.count() + 12) as u128),
        ),
        "reduce the replicates (--bootstrap N); 1000 to 2000 give 95% intervals",
    )?;
    let full_rank = rank_of(&full, fit.rank_tolerance);
    let built_before = problem.evaluations();
    // every replicate's outer loop starts from η̂
    let start: Vec<NonlinearParameter> = specs
        .iter()
        .zip(estimate)
        .map(|(spec, &value)| NonlinearParameter {
            initial: value.clamp(spec.lower, spec.upper),
            ..spec.clone()
        })
        .collect();
    let one = |k: usize| -> Result<(Vec<usize>, Outcome)> {
        let mut rng = replicate_rng(settings.seed, k);
        let drawn = units.draw(&mut rng);
        let rows = units.rows_of(&drawn);
        let replicate = Problem::with_builder(
            start.clone(),
            Box::new(|eta: &[f64]| problem.regressor(eta)?.select_rows(&rows)),
            problem.fit(),
        )
        .with_derivatives_of(problem, &rows);
        let outcome = match refit(&replicate, varpro, full_rank) {
            Ok(outcome) => outcome,
            Err(Error::Numerical { .. }) => Outcome::Unusable,
            Err(e) => return Err(e),
        };
        Ok((drawn, outcome))
    };
    let outcomes = run_replicates(settings, progress, &one)?;
    let (mut not_converged, mut unusable) = (0, 0);
    let mut samples = Vec::with_capacity(outcomes.len());
    let mut drawn = Vec::with_capacity(outcomes.len());
    for (units_drawn, outcome) in outcomes {
        drawn.push(units_drawn);
        match outcome {
            Outcome::Kept(values) => samples.push(values),
            Outcome::NotConverged => not_converged += 1,
            Outcome::Unusable => unusable += 1,
        }
    }
    let used = samples.len();
    if 2 * used < settings.replicates {
        return Err(Error::Numerical {
            stage: "bootstrap of the variable projection".into(),
            detail: format!(
                "only {used} of {} replicates kept ({not_converged} outer loops did not converge, {unusable} linear fits were not usable); add {} before bootstrapping",
                settings.replicates,
                match resampled {
                    Resampled::Windows => "windows (equations)",
                    Resampled::Sweeps => "sweeps",
                }
            ),
        });
    }
    let interval = |j: usize, name: &str| {
        percentile_interval(name, samples.iter().map(|s| s[j]), settings.level)
    };
    let parameters = specs
        .iter()
        .enumerate()
        .map(|(j, spec)| interval(j, &spec.name))
        .collect();
    let coefficients = full
        .columns()
        .iter()
        .enumerate()
        .map(|(k, name)| interval(q + k, name))
        .collect();
    Ok(Bootstrap {
        summary: BootstrapSummary {
            not_converged,
            unusable,
            evaluations: problem.evaluations() - built_before,
            ..BootstrapSummary::of(settings, fit, used, &units, resampled)
        },
        parameters,
        coefficients,
        samples,
        drawn,
    })
}

/// The outer loop of one replicate from its parameters' initial values (η̂), without
/// multistart, and the linear fit at its end.
fn refit(replicate: &Problem<'_>, varpro: &VarProSettings, full_rank: usize) -> Result<Outcome> {
    let fit = replicate.fit();
    let parameters = replicate.parameters();
    let minimum = if parameters.len() == 1 {
        levenberg_marquardt(
            &|eta| replicate.residuals(eta),
            None,
            parameters,
            varpro,
            false,
        )?
    } else {
        fixed_weights::minimise(replicate, fit, varpro, false)?
    };
    if !minimum.converged {
        return Ok(Outcome::NotConverged);
    }
    let trial = replicate.trial(&minimum.values)?;
    if !trial.fit.status.is_usable() || rank_of(&trial.regressor, fit.rank_tolerance) < full_rank {
        return Ok(Outcome::Unusable);
    }
    let mut values = minimum.values;
    values.extend(trial.fit.coefficients);
    Ok(Outcome::Kept(values))
}
