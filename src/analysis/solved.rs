//! The one solve path every reader of a fit goes through: refuse a regressor without
//! information ([`require_information`]), solve it as the fit settings say
//! ([`crate::fit::solve`]: ordinary least squares, constrained, or weighted by the
//! propagated noise model, W = diag(1/s_r²)), then diagnose the rows the fit solved
//! ([`crate::analysis::diagnostics`]: the weighted rows W^{1/2} A when it was weighted).
//!
//! `identify` builds its report from it and `dampid check`
//! ([`crate::analysis::check::RegressorCheck`]) its conditioning and identifiability,
//! so the two always report the same numbers for the same regressor and settings. Every
//! conditioning figure is of the column-scaled solved rows
//!
//! ```text
//!   A_s = W^{1/2} A S⁻¹,   S = diag ‖(W^{1/2} A)_j‖,   κ = σ_1(A_s) / σ_p(A_s),
//! ```
//!
//! with W = I for an unweighted fit.

use crate::analysis::diagnostics::{Diagnostics, diagnose_factored};
use crate::analysis::identifiability::require_information;
use crate::error::Result;
use crate::fit::{Fit, FitSettings, solve_factored};
use crate::regressor::Regressor;

/// What [`solved`] returns: the fit and its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// The fit as `identify` makes it.
    pub fit: Fit,
    /// Its diagnostics, on the rows it solved.
    pub diagnostics: Diagnostics,
}

impl Solved {
    /// Whether the rows were weighted by the propagated noise model (W ≠ I).
    pub fn weighted(&self) -> bool {
        self.diagnostics.weighted.is_some()
    }
}

/// Solves `regressor` with `settings` and diagnoses the fit; the rows are factored
/// once when the fit is plain least squares. A regressor whose every column is zero is
/// [`crate::Error::NoInformation`]; one whose input work is negative beyond its noise
/// is [`crate::Error::NegativeInputWork`] unless `settings.accept_negative_work`
/// ([`crate::regressor::passive`]).
pub fn solved(regressor: &Regressor, settings: &FitSettings) -> Result<Solved> {
    require_information(regressor)?;
    crate::regressor::passive::require_passive(regressor, settings.accept_negative_work)?;
    let (fit, factorization) = solve_factored(regressor, settings)?;
    let diagnostics = diagnose_factored(
        regressor,
        &fit,
        settings.rank_tolerance,
        factorization,
        settings.nonlinear_parameters,
    );
    Ok(Solved { fit, diagnostics })
}

/// The matrix every reported singular value, rank and condition number is of, in
/// words, for the report and `dampid check`: A_s = W^{1/2} A S⁻¹.
pub fn conditioning_basis(weighted: bool) -> &'static str {
    if weighted {
        "column-scaled regressor, rows weighted by their propagated noise"
    } else {
        "column-scaled regressor"
    }
}
