//! The fit report: coefficients with names and standard errors, residuals and their
//! bias, conditioning, identifiability (near-null directions and determined
//! combinations by name), active constraints, bootstrap confidence intervals when
//! asked for, and warnings in words. `Display` prints a table; serde gives the JSON
//! (schema in README.md and docs/identifiability.md). A coefficient the data cannot
//! separate from others is marked `determined: false` and printed as "not determined":
//! its number is a least-squares artefact, not an estimate.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::bootstrap::{Bootstrap, BootstrapSummary, ConfidenceInterval};
use crate::diagnostics::{Correlation, Diagnostics, ResidualBias};
use crate::fit::{ActiveConstraint, Fit, FitMethod, FitStatus, SolverInfo};
use crate::identifiability::{Identifiability, list};
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
    /// False when the data cannot separate this coefficient from others: `value` is
    /// then not an estimate.
    pub determined: bool,
    /// Bootstrap confidence interval, when a bootstrap was run.
    pub interval: Option<ConfidenceInterval>,
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
    /// Some directions of the column-scaled regressor are practically null (below the
    /// level the equation noise can resolve): these coefficients are not separated.
    Unidentifiable {
        /// The coefficients that appear in a near-null direction.
        coefficients: Vec<String>,
        /// Each near-null direction in words.
        trade_offs: Vec<String>,
        /// The combinations that are determined (when any).
        determined: Vec<String>,
        /// The fit was constrained: the constraints, not the data, place the solution
        /// along the near-null directions.
        constrained: bool,
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
            Warning::Unidentifiable {
                coefficients,
                trade_offs,
                determined,
                constrained,
            } => {
                let names: Vec<&str> = coefficients.iter().map(String::as_str).collect();
                write!(
                    f,
                    "these data cannot separate {}: {}",
                    list(&names),
                    trade_offs.join("; ")
                )?;
                match determined.len() {
                    0 => {}
                    1 | 2 => {
                        let combos: Vec<&str> = determined.iter().map(String::as_str).collect();
                        let verb = if determined.len() == 1 { "is" } else { "are" };
                        write!(f, "; only {} {verb} determined", list(&combos))?;
                    }
                    k => write!(
                        f,
                        "; only {k} combinations of the coefficients are determined (listed with the identifiability diagnostics)"
                    )?,
                }
                if *constrained {
                    write!(
                        f,
                        "; the constraints, not the data, decide where the solution lies along these directions"
                    )?;
                }
                write!(
                    f,
                    "; the values shown for {} are not estimates; add experiments at other frequencies, amplitudes or forcing points (`dampid design`)",
                    list(&names)
                )
            }
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
    /// What the data can and cannot determine.
    pub identifiability: Identifiability,
    /// The bootstrap behind the confidence intervals, when one was run.
    pub bootstrap: Option<BootstrapSummary>,
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
        let identifiability = diagnostics.identifiability;
        if !identifiability.separable() {
            warnings.push(Warning::Unidentifiable {
                coefficients: identifiability.unidentifiable.clone(),
                trade_offs: identifiability
                    .null_directions
                    .iter()
                    .map(|d| d.text.clone())
                    .collect(),
                determined: identifiability
                    .determined
                    .iter()
                    .map(|d| d.combination.text.clone())
                    .collect(),
                constrained: fit.method == FitMethod::Constrained,
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
                determined: identifiability.is_identifiable(name),
                interval: None,
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
            identifiability,
            bootstrap: None,
            warnings,
        }
    }

    /// Adds the confidence intervals of `bootstrap` (run on the same regressor and fit
    /// settings) to the coefficients, matched by name.
    pub fn with_bootstrap(mut self, bootstrap: Bootstrap) -> Self {
        for c in &mut self.coefficients {
            c.interval = bootstrap
                .intervals
                .iter()
                .find(|i| i.name == c.name)
                .cloned();
        }
        self.bootstrap = Some(bootstrap.summary);
        self
    }

    /// True when the data determine every coefficient and the fit converged: the
    /// values are estimates.
    pub fn is_estimate(&self) -> bool {
        self.status.is_usable() && self.coefficients.iter().all(|c| c.determined)
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
        let level = self.bootstrap.as_ref().map(|b| b.level);
        let interval_header = level
            .map(|l| {
                let percent = (100.0 * l * 1e6).round() / 1e6;
                format!("  {:>27}", format!("{percent}% interval"))
            })
            .unwrap_or_default();
        writeln!(
            f,
            "{:<20} {:>14} {:>12} {:>9}{interval_header}",
            "coefficient", "value", "std error", "rel. se"
        )?;
        for c in &self.coefficients {
            let (se, rel) = match c.std_error {
                _ if !c.determined => ("not determined".into(), String::new()),
                Some(se) if c.value != 0.0 => (
                    format!("{se:.3e}"),
                    format!("{:.2}%", 100.0 * se / c.value.abs()),
                ),
                Some(se) => (format!("{se:.3e}"), "-".into()),
                None => ("-".into(), "-".into()),
            };
            let interval = match (&c.interval, level) {
                (Some(i), _) => format!("  [{:>12.5e}, {:>12.5e}]", i.lower, i.upper),
                (None, Some(_)) => format!("  {:>27}", "-"),
                (None, None) => String::new(),
            };
            let held = self
                .active_constraints
                .iter()
                .find(|a| a.name == c.name)
                .map(|a| format!("  (at {:?} bound)", a.side).to_lowercase())
                .unwrap_or_default();
            writeln!(
                f,
                "{:<20} {:>14.6e} {:>12} {:>9}{interval}{held}",
                c.name, c.value, se, rel
            )?;
        }
        if let Some(b) = &self.bootstrap {
            writeln!(
                f,
                "bootstrap: {} of {} resampled regressors used (windows resampled with replacement, seed {}); percentile intervals",
                b.used, b.replicates, b.seed
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
        write!(f, "{}", self.identifiability)?;
        if let Some(c) = &self.correlation
            && c.names.len() > 1
        {
            write!(f, "{c}")?;
        }
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
