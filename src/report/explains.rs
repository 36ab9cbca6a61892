//! A fit that explains nothing. Two signs that the numbers are not estimates whatever
//! their standard errors say, raised as [`Warning::FitExplainsNothing`] (which
//! `identify --strict` turns into exit 1):
//!
//! - the relative residual ‖b − Aθ‖/‖b‖ is at least [`NOTHING_EXPLAINED`] = 0.5: the
//!   model accounts for at most 1 − 0.5² = 75 % of the squared input work (with the
//!   wrong sign of a force or a motion, and `nonnegative = true`, every coefficient is
//!   0 and the relative residual is exactly 1); with data of any quality that identify
//!   the damping the residual is the noise's and the model error's, a few percent;
//! - every coefficient sits on a bound of the constrained fit: the constraints, not the
//!   data, set every value.
//!
//! Columns that were round-off of their inputs ([`crate::regressor::round_off`]) are
//! named in [`Warning::RoundOffColumn`], which then replaces the rank-deficiency and
//! "cannot separate … add experiments" warnings they alone cause: more experiments at
//! other frequencies do not give a term that does no work any.

use super::Warning;
use crate::fit::Fit;
use crate::regressor::Regressor;

/// Relative residual from which a fit explains nothing.
pub const NOTHING_EXPLAINED: f64 = 0.5;

/// The warning for `fit` of `regressor` with relative residual `relative_residual`, if
/// it explains nothing (module doc).
pub(crate) fn explains_nothing(
    regressor: &Regressor,
    fit: &Fit,
    relative_residual: f64,
) -> Option<Warning> {
    let columns = regressor.columns();
    let every_at_bound = !columns.is_empty()
        && columns
            .iter()
            .all(|name| fit.active.iter().any(|a| &a.name == name));
    (every_at_bound || relative_residual >= NOTHING_EXPLAINED).then(|| {
        Warning::FitExplainsNothing {
            relative_residual,
            at_bounds: if every_at_bound {
                columns.to_vec()
            } else {
                Vec::new()
            },
        }
    })
}

/// Adds [`Warning::RoundOffColumn`] for the round-off columns of `regressor` and drops
/// the rank and identifiability warnings they alone cause (module doc); `rank` is the
/// numerical rank of the fitted rows.
pub(crate) fn round_off(regressor: &Regressor, rank: usize, warnings: &mut Vec<Warning>) {
    let zeroed = regressor.round_off_columns();
    if zeroed.is_empty() {
        return;
    }
    let p = regressor.columns().len();
    warnings.retain(|w| match w {
        Warning::RankDeficient { .. } => rank + zeroed.len() < p,
        Warning::Unidentifiable { coefficients, .. } => {
            !coefficients.iter().all(|c| zeroed.contains(c))
        }
        _ => true,
    });
    warnings.push(Warning::RoundOffColumn {
        coefficients: zeroed.to_vec(),
    });
}
