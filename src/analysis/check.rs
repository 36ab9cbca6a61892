//! What a regressor says before any fit is trusted: its size, the singular values of
//! the column-scaled regressor A_s = A S⁻¹ (S = diag ‖A_j‖), the numerical rank
//! r = #{σ_i > tol·σ_1}, the condition number κ = σ_1/σ_p (infinite when r < p), the
//! identifiability analysis ([`crate::analysis::identifiability`]) and the correlation
//! of the ordinary least-squares estimates. `dampid check` prints it.

use std::fmt;

use serde::Serialize;

use crate::analysis::diagnostics::{Correlation, diagnose};
use crate::analysis::identifiability::{Identifiability, require_information};
use crate::error::Result;
use crate::fit::least_squares;
use crate::regressor::Regressor;

/// The conditioning and identifiability of a regressor, from its ordinary
/// least-squares fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegressorCheck {
    /// Equations m.
    pub equations: usize,
    /// Coefficient names, one per column.
    pub coefficients: Vec<String>,
    /// Singular values of the column-scaled regressor, descending.
    pub singular_values: Vec<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// σ_1/σ_p; `None` (infinite) when rank deficient.
    pub condition_number: Option<f64>,
    /// What the data can and cannot determine.
    pub identifiability: Identifiability,
    /// Correlation of the least-squares estimates, when they have standard errors.
    pub correlation: Option<Correlation>,
}

impl RegressorCheck {
    /// Checks `regressor` with numerical rank tolerance `rank_tolerance`; a regressor
    /// whose every column is zero is [`crate::Error::NoInformation`].
    pub fn new(regressor: &Regressor, rank_tolerance: f64) -> Result<Self> {
        require_information(regressor)?;
        let fit = least_squares(regressor, rank_tolerance)?;
        let diagnostics = diagnose(regressor, &fit, rank_tolerance);
        Ok(RegressorCheck {
            equations: regressor.equations(),
            coefficients: regressor.columns().to_vec(),
            singular_values: diagnostics.singular_values,
            rank: diagnostics.rank,
            condition_number: diagnostics
                .condition_number
                .is_finite()
                .then_some(diagnostics.condition_number),
            identifiability: diagnostics.identifiability,
            correlation: diagnostics.correlation,
        })
    }
}

impl fmt::Display for RegressorCheck {
    /// From the singular values on: the caller says how many records gave the equations.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sv: Vec<String> = self
            .singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect();
        writeln!(
            f,
            "singular values of the column-scaled regressor: [{}]",
            sv.join(", ")
        )?;
        writeln!(
            f,
            "numerical rank: {} of {}",
            self.rank,
            self.coefficients.len()
        )?;
        match self.condition_number {
            Some(k) => writeln!(f, "condition number: {k:.3e}")?,
            None => writeln!(
                f,
                "condition number: infinite: these data cannot separate the coefficients"
            )?,
        }
        write!(f, "{}", self.identifiability)?;
        if let Some(c) = self.correlation.as_ref().filter(|c| c.names.len() > 1) {
            write!(f, "{c}")?;
        }
        Ok(())
    }
}
