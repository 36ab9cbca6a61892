//! The fit report: coefficients with names and standard errors, residuals and their
//! bias, conditioning, active constraints, and warnings in words. `Display` prints a
//! table; serde gives the JSON (schema in README.md).

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::diagnostics::{Correlation, Diagnostics, ResidualBias};
use crate::fit::{ActiveConstraint, Fit, FitMethod, FitStatus, SolverInfo};
use crate::regressor::{Regressor, RowLabel};

/// Condition number of the column-scaled regressor above which the report warns.
pub const ILL_CONDITIONED: f64 = 1e8;

/// One identified coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoefficientEstimate {
    /// Name (e.g. `c`, `dashpot[2-3]`).
    pub name: String,
    /// Estimate.
    pub value: f64,
    /// Standard error, when the data have redundancy and the coefficient is free.
    pub std_error: Option<f64>,
}

/// Something the user must know before trusting the numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Warning {
    /// The solver did not reach a solution: the coefficients are not estimates.
    NotConverged {
        /// The solver's status.
        status: FitStatus,
    },
    /// The regressor is rank deficient: the data cannot separate the coefficients.
    RankDeficient {
        /// Numerical rank.
        rank: usize,
        /// Number of coefficients.
        coefficients: usize,
    },
    /// The column-scaled regressor is badly conditioned.
    IllConditioned {
        /// Its condition number.
        condition_number: f64,
    },
    /// As many equations as free coefficients: no redundancy, no uncertainty estimate.
    NoRedundancy {
        /// Equations.
        equations: usize,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::NotConverged { status } => write!(
                f,
                "the solver ended with status {status:?}: these numbers are not a solution"
            ),
            Warning::RankDeficient { rank, coefficients } => write!(
                f,
                "the regressor has rank {rank} for {coefficients} coefficients: these data cannot separate the coefficients, and the values shown are a minimum-norm least-squares solution, not estimates; add experiments at other frequencies, amplitudes or forcing points"
            ),
            Warning::IllConditioned { condition_number } => write!(
                f,
                "the column-scaled regressor has condition number {condition_number:.3e}: some combination of coefficients is barely determined by these data"
            ),
            Warning::NoRedundancy { equations } => write!(
                f,
                "{equations} equations for as many free coefficients: the fit is exact by construction and gives no uncertainty; add windows or records"
            ),
        }
    }
}

/// Everything a fit produced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// How the fit ended.
    pub status: FitStatus,
    /// Which method.
    pub method: FitMethod,
    /// Coefficients, in model order.
    pub coefficients: Vec<CoefficientEstimate>,
    /// Condition number of the column-scaled regressor (`null` when rank deficient).
    pub condition_number: Option<f64>,
    /// Its singular values, descending.
    pub singular_values: Vec<f64>,
    /// Its numerical rank.
    pub rank: usize,
    /// Residual per equation, b − Aθ.
    pub residuals: Vec<f64>,
    /// Where each equation came from.
    pub rows: Vec<RowLabel>,
    /// ‖b − Aθ‖ / ‖b‖.
    pub relative_residual: f64,
    /// Bias of the residuals.
    pub residual_bias: ResidualBias,
    /// Correlation of the free coefficients.
    pub correlation: Option<Correlation>,
    /// Constraints the solution touches.
    pub active_constraints: Vec<ActiveConstraint>,
    /// Constrained-solver details.
    pub solver: Option<SolverInfo>,
    /// What to be careful about.
    pub warnings: Vec<Warning>,
}

impl FitReport {
    /// Assembles the report of `fit` on `regressor` with its diagnostics.
    pub fn new(regressor: &Regressor, fit: Fit, diagnostics: Diagnostics) -> Self {
        let p = regressor.columns().len();
        let free = p - fit.active.len();
        let mut warnings = Vec::new();
        if !fit.status.is_usable() {
            warnings.push(Warning::NotConverged { status: fit.status });
        }
        if diagnostics.rank < p && fit.active.is_empty() {
            warnings.push(Warning::RankDeficient {
                rank: diagnostics.rank,
                coefficients: p,
            });
        } else if diagnostics.condition_number.is_finite()
            && diagnostics.condition_number > ILL_CONDITIONED
        {
            warnings.push(Warning::IllConditioned {
                condition_number: diagnostics.condition_number,
            });
        }
        if regressor.equations() == free {
            warnings.push(Warning::NoRedundancy {
                equations: regressor.equations(),
            });
        }
        let coefficients = regressor
            .columns()
            .iter()
            .zip(&fit.coefficients)
            .zip(&diagnostics.std_errors)
            .map(|((name, value), se)| CoefficientEstimate {
                name: name.clone(),
                value: *value,
                std_error: *se,
            })
            .collect();
        FitReport {
            status: fit.status,
            method: fit.method,
            coefficients,
            condition_number: diagnostics
                .condition_number
                .is_finite()
                .then_some(diagnostics.condition_number),
            singular_values: diagnostics.singular_values,
            rank: diagnostics.rank,
            residuals: diagnostics.residuals,
            rows: regressor.rows().to_vec(),
            relative_residual: diagnostics.relative_residual,
            residual_bias: diagnostics.residual_bias,
            correlation: diagnostics.correlation,
            active_constraints: fit.active,
            solver: fit.solver,
            warnings,
        }
    }

    /// The estimate of coefficient `name`, if the model has it.
    pub fn coefficient(&self, name: &str) -> Option<f64> {
        self.coefficients
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.value)
    }
}

impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "status: {:?} ({:?})", self.status, self.method)?;
        writeln!(
            f,
            "{:<20} {:>14} {:>12} {:>9}",
            "coefficient", "value", "std error", "rel. se"
        )?;
        for c in &self.coefficients {
            let (se, rel) = match c.std_error {
                Some(se) if c.value != 0.0 => (
                    format!("{se:.3e}"),
                    format!("{:.2}%", 100.0 * se / c.value.abs()),
                ),
                Some(se) => (format!("{se:.3e}"), "-".into()),
                None => ("-".into(), "-".into()),
            };
            let held = self
                .active_constraints
                .iter()
                .find(|a| a.name == c.name)
                .map(|a| format!("  (at {:?} bound)", a.side).to_lowercase())
                .unwrap_or_default();
            writeln!(
                f,
                "{:<20} {:>14.6e} {:>12} {:>9}{held}",
                c.name, c.value, se, rel
            )?;
        }
        writeln!(
            f,
            "equations: {}, rank: {}",
            self.residuals.len(),
            self.rank
        )?;
        match self.condition_number {
            Some(k) => writeln!(f, "condition number (column-scaled): {k:.3e}")?,
            None => writeln!(f, "condition number (column-scaled): infinite")?,
        }
        let sv: Vec<String> = self
            .singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect();
        writeln!(f, "singular values: [{}]", sv.join(", "))?;
        writeln!(f, "relative residual: {:.3e}", self.relative_residual)?;
        writeln!(
            f,
            "residual bias: {:+.3e} of mean |input work| ({} positive, {} negative)",
            self.residual_bias.relative_mean,
            self.residual_bias.positive,
            self.residual_bias.negative
        )?;
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}
