//! The outer loop for several parameters with the row weights held fixed.
//!
//! With propagated weighting the inner fit weights equation r by 1/s_r(θ̂), s_r the
//! propagated residual standard deviation at its own coefficients, so the projected
//! cost φ(η) = Σ_r (e_r/s_r(θ̂(η)))² changes its weights with every trial and has
//! spurious minima where large coefficients inflate every s_r (noise-free records of
//! the four-mass chain with two exponents: χ² = 4e10 at (1.03, 1.05), coefficients
//! −3.2, 7.5, −1.1, where the truth (1.5, 2.5) fits to round-off). With q ≥ 2
//! parameters the search therefore runs on a cost whose weights w are fixed:
//!
//! ```text
//!   ψ_w(η) = ‖W^{1/2}(A(η) θ̂_w(η) − b)‖²,   θ̂_w(η) = argmin_θ ‖W^{1/2}(A(η) θ − b)‖²,
//! ```
//!
//! W = diag(w_r²), θ̂_w the inner fit of the weighted rows as they are (least squares or
//! the user's constrained fit; no reweighting), a smooth function of η with its
//! minimum at the truth for noise-free data whatever the weights. Three stages:
//!
//! 1. w⁽⁰⁾ = 1/s(θ̂(η₀)) from the propagated fit at the initial values η₀;
//! 2. Levenberg–Marquardt with its multistart on ψ_w⁽⁰⁾ → η₁, to the square root of
//!    `tolerance` (it only has to reach the basin: measured on the two-exponent data,
//!    BENCHMARKS.md §10);
//! 3. w⁽¹⁾ = 1/s(θ̂(η₁)) from the propagated fit at η₁, and Levenberg–Marquardt on
//!    ψ_w⁽¹⁾ from η₁ (no multistart) → η̂ (one refinement: the weights of the report's
//!    fit at η̂ are those of its own propagated fit, as for a linear fit).
//!
//! The regressor last built is kept, so the weights at η₀ and η₁ and the first cost of
//! the search that starts there read one build (equal η to 4 ulp: the unit-box round
//! trip of the Levenberg–Marquardt). The searches' own trials read no noise model (their
//! weights are fixed): they are built without it where the problem can
//! ([`Problem::equations`]: a table with residual unknowns, A and b the whole build's
//! bit for bit), and the weights at η₁ read the whole build at the η of that kept trial
//! (its rows made again with the noise model's perturbed copies): the same numbers as
//! before, one build more.
//!
//! Unweighted inner fits (ordinary weighting, or rows without a noise model) have no
//! weights to fix: the Levenberg–Marquardt runs on φ as before. One parameter keeps the
//! bounded Brent on φ (`outer.rs`).

use std::cell::RefCell;
use std::sync::Arc;

use crate::error::Result;
use crate::fit::{FitSettings, Weighting, inverse_std};
use crate::regressor::Regressor;

use super::levenberg_marquardt::levenberg_marquardt;
use super::minimum::{Column, Minimum};
use super::problem::{Problem, weighted_residuals};
use super::projected_jacobian::{Projections, column};
use super::{NonlinearParameter, VarProSettings};

/// Minimises the projected cost over several parameters (see the module doc); without
/// `multistart` the first search starts from the initial values alone (a bootstrap
/// replicate starting from the full data's estimate, `bootstrap.rs`).
pub(super) fn minimise(
    problem: &Problem<'_>,
    fit: &FitSettings,
    settings: &VarProSettings,
    multistart: bool,
) -> Result<Minimum> {
    let parameters = problem.parameters();
    if fit.weighting == Weighting::Ordinary {
        // the Jacobian's columns of a table's residual unknowns, exact
        // (`projected_jacobian.rs`)
        let kept = Projections::default();
        let shifted = |eta: &[f64], j: usize, h: f64| -> Result<Option<Column>> {
            let base = problem.shared(eta)?;
            column(problem, &kept, &base, None, fit, eta, j, h)
        };
        return levenberg_marquardt(
            &|eta| problem.residuals(eta),
            Some(&shifted),
            parameters,
            settings,
            multistart,
        );
    }
    // the weights at η₀ and η₁ and the first residual of the search from there read
    // one regressor: the last one built is kept
    // (shared, not copied: the Jacobian's differences at η read it q times)
    // (the η it was built at, it, whether it is the whole build: with the noise model)
    type Kept = (Vec<f64>, Arc<Regressor>, bool);
    let last: RefCell<Option<Kept>> = RefCell::new(None);
    // the regressor at η, the whole build when `whole` (the propagated fit reads its
    // noise model), else maybe without the noise model (a fit on fixed weights)
    let regressor = |eta: &[f64], whole: bool| -> Result<Arc<Regressor>> {
        let mut at = eta.to_vec();
        if let Some((kept, regressor, complete)) = last.borrow().as_ref()
            && kept
                .iter()
                .zip(eta)
                .all(|(a, b)| (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()))
        {
            if *complete || !whole {
                return Ok(Arc::clone(regressor));
            }
            // the whole build of the kept trial: at its own η, as it was kept before
            at.clone_from(kept);
        }
        let (regressor, complete) = if whole {
            (problem.regressor(&at)?, true)
        } else {
            let bare = problem.equations(&at)?;
            let complete = bare.noise().is_some();
            (bare, complete)
        };
        let regressor = Arc::new(regressor);
        *last.borrow_mut() = Some((at, Arc::clone(&regressor), complete));
        Ok(regressor)
    };
    // 1/s_r of the propagated fit at η, or `None` when the inner fit is unweighted
    let row_weights = |eta: &[f64]| -> Result<Option<Vec<f64>>> {
        let fit = crate::fit::solve(&*regressor(eta, true)?, fit)?;
        Ok(fit.residual_std.as_deref().map(inverse_std))
    };
    let initial: Vec<f64> = parameters.iter().map(|p| p.initial).collect();
    let Some(weights) = row_weights(&initial)? else {
        // rows without a noise model: φ itself, its first trial the regressor just built
        let unweighted = |eta: &[f64]| -> Result<Vec<f64>> {
            let rows = regressor(eta, true)?;
            let fit = crate::fit::solve(&rows, fit)?;
            Ok(weighted_residuals(
                &rows,
                &fit.coefficients,
                fit.residual_std.as_deref(),
            ))
        };
        return levenberg_marquardt(&unweighted, None, parameters, settings, multistart);
    };
    let ordinary = FitSettings {
        weighting: Weighting::Ordinary,
        ..fit.clone()
    };
    let fixed = |weights: &[f64], eta: &[f64]| -> Result<Vec<f64>> {
        let rows = regressor(eta, false)?.weighted(weights)?;
        let fit = crate::fit::solve(&rows, &ordinary)?;
        Ok(weighted_residuals(&rows, &fit.coefficients, None))
    };
    // the Jacobian's columns of a table's residual unknowns for the fixed-weight fit,
    // exact (`projected_jacobian.rs`; each search keeps its own factored fit)
    let fixed_shifted = |kept: &Projections,
                         weights: &[f64],
                         eta: &[f64],
                         j: usize,
                         h: f64|
     -> Result<Option<Column>> {
        let base = regressor(eta, false)?;
        column(problem, kept, &base, Some(weights), &ordinary, eta, j, h)
    };
    // the first search only has to reach the basin: the refinement converges to
    // `tolerance`
    let loose = VarProSettings {
        tolerance: settings.tolerance.sqrt(),
        ..*settings
    };
    let kept = Projections::default();
    let first = levenberg_marquardt(
        &|eta| fixed(&weights, eta),
        Some(&|eta, j, h| fixed_shifted(&kept, &weights, eta, j, h)),
        parameters,
        &loose,
        multistart,
    )?;
    if !first.converged {
        return Ok(first);
    }
    let Some(weights) = row_weights(&first.values)? else {
        return Ok(first);
    };
    let from_first: Vec<NonlinearParameter> = parameters
        .iter()
        .zip(&first.values)
        .map(|(p, &value)| NonlinearParameter {
            initial: value,
            ..p.clone()
        })
        .collect();
    let kept = Projections::default();
    let second = levenberg_marquardt(
        &|eta| fixed(&weights, eta),
        Some(&|eta, j, h| fixed_shifted(&kept, &weights, eta, j, h)),
        &from_first,
        settings,
        false,
    )?;
    Ok(Minimum {
        iterations: first.iterations + second.iterations,
        ..second
    })
}
