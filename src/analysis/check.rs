//! What a regressor says before any fit is trusted: its size, the singular values of
//! the column-scaled solved rows, the numerical rank, the condition number, the
//! identifiability analysis ([`crate::analysis::identifiability`]) and the correlation
//! of the estimates. `dampid check` prints it.
//!
//! Every number comes from the fit `identify` makes with the same settings
//! ([`crate::analysis::solved::solved`]): the same rows, weighted by the propagated
//! noise model when the fit is, so that `check` and `identify` agree on the rank, the
//! condition number and what is determined. With W the row weights (W = I for an
//! unweighted fit):
//!
//! ```text
//!   A_s = W^{1/2} A S⁻¹,  S = diag ‖(W^{1/2} A)_j‖,   r = #{σ_i > tol·σ_1},
//!   κ = σ_1/σ_p   (infinite when r < p).
//! ```

use std::fmt;

use serde::Serialize;

use crate::analysis::diagnostics::Correlation;
use crate::analysis::identifiability::Identifiability;
use crate::analysis::lack_of_fit::LackOfFit;
use crate::analysis::solved::{conditioning_basis, solved};
use crate::error::Result;
use crate::fit::FitSettings;
use crate::regressor::Regressor;

/// The conditioning and identifiability of a regressor, from the fit `identify` makes
/// of it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegressorCheck {
    /// Equations m.
    pub equations: usize,
    /// Coefficient names, one per column.
    pub coefficients: Vec<String>,
    /// Whether the rows are weighted by the propagated noise model (W ≠ I), as the fit
    /// weights them.
    pub weighted: bool,
    /// Singular values of the column-scaled (weighted) rows A_s, descending.
    pub singular_values: Vec<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// σ_1/σ_p of A_s; `None` (infinite) when rank deficient.
    pub condition_number: Option<f64>,
    /// What the data can and cannot determine.
    pub identifiability: Identifiability,
    /// Correlation of the estimates, when they have standard errors.
    pub correlation: Option<Correlation>,
    /// The lack-of-fit test of an unweighted fit, when it rejects the fit
    /// ([`crate::analysis::lack_of_fit`]): the noise level above then includes the
    /// records' disagreement.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lack_of_fit: Option<LackOfFit>,
}

impl RegressorCheck {
    /// Checks `regressor` as [`crate::identify::identify`] fits it with
    /// `settings` (its weighting, constraints and rank tolerance); a regressor whose
    /// every column is zero is [`crate::Error::NoInformation`].
    pub fn new(regressor: &Regressor, settings: &FitSettings) -> Result<Self> {
        let solved = solved(regressor, settings)?;
        let weighted = solved.weighted();
        let diagnostics = solved.diagnostics;
        Ok(RegressorCheck {
            equations: regressor.equations(),
            coefficients: regressor.columns().to_vec(),
            weighted,
            singular_values: diagnostics.singular_values,
            rank: diagnostics.rank,
            condition_number: diagnostics
                .condition_number
                .is_finite()
                .then_some(diagnostics.condition_number),
            identifiability: diagnostics.identifiability,
            correlation: diagnostics.correlation,
            lack_of_fit: diagnostics.lack_of_fit.filter(LackOfFit::rejects),
        })
    }
}

impl fmt::Display for RegressorCheck {
    /// From the singular values on: the caller says how many records gave the equations.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let basis = conditioning_basis(self.weighted);
        writeln!(
            f,
            "singular values of the {basis}: {}",
            crate::analysis::digest::sequence(&self.singular_values)
        )?;
        writeln!(
            f,
            "numerical rank: {} of {}",
            self.rank,
            self.coefficients.len()
        )?;
        match self.condition_number {
            Some(k) => writeln!(f, "condition number σ₁/σₚ of the {basis}: {k:.3e}")?,
            None => writeln!(
                f,
                "condition number σ₁/σₚ of the {basis}: infinite: these data cannot separate the coefficients"
            )?,
        }
        if let Some(l) = &self.lack_of_fit {
            let records: Vec<String> = l
                .records
                .iter()
                .map(|(name, share)| format!("'{name}' ({:.0} %)", 100.0 * share))
                .collect();
            writeln!(
                f,
                "lack of fit: the records' mean residuals leave {:.3} % of the input work unexplained, far beyond the scatter of their windows (F = {}, P = {:.1e}), most of it in {}; the noise level below includes it (a model that misses a mechanism, or records that are not what their files say)",
                100.0 * l.relative_misfit,
                l.f_statistic
                    .map_or("∞".to_string(), |v| format!("{v:.3e}")),
                l.p_value,
                records.join(", ")
            )?;
        }
        write!(f, "{}", self.identifiability)?;
        if let Some(c) = self.correlation.as_ref().filter(|c| c.names.len() > 1) {
            write!(f, "{c}")?;
        }
        Ok(())
    }
}
