//! The fit report: coefficients with names and standard errors, residuals and their
//! bias, conditioning, identifiability (near-null directions and determined
//! combinations by name), active constraints, bootstrap confidence intervals when
//! asked for, and warnings in words. `Display` prints a table; serde gives the JSON
//! (schema in README.md and docs/identifiability.md). A coefficient the data cannot
//! separate from others is marked `determined: false` and printed as "not determined":
//! its number is a least-squares artefact, not an estimate.

pub mod html;
mod truth;

pub use truth::AgainstTruth;

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::analysis::bootstrap::{Bootstrap, BootstrapSummary, ConfidenceInterval};
use crate::analysis::diagnostics::{Correlation, Diagnostics, ResidualBias};
use crate::analysis::identifiability::{Identifiability, list};
use crate::fit::{ActiveConstraint, Fit, FitMethod, FitStatus, SolverInfo};
use crate::regressor::robust::WindowNoise;
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
    /// Standard error, when the data have redundancy and the coefficient is free: the
    /// plug-in √diag((AᵀWA)⁻¹) when the fit was weighted by propagated variances (see
    /// [`FitReport::noise`]), else from the residual variance.
    pub std_error: Option<f64>,
    /// The standard error from the residual variance s²(AᵀWA)⁻¹ of the weighted fit, next
    /// to the plug-in one (None for an unweighted fit, where it is `std_error`).
    #[serde(default)]
    pub residual_std_error: Option<f64>,
    /// False when the data cannot separate this coefficient from others: `value` is
    /// then not an estimate.
    pub determined: bool,
    /// Bootstrap confidence interval, when a bootstrap was run.
    pub interval: Option<ConfidenceInterval>,
}

/// What the noise-robust pipeline estimated and how well the model explains the data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseSummary {
    /// Per window: harmonics kept, noise per displacement and force channel.
    pub windows: Vec<WindowNoise>,
    /// The propagated standard deviation of each equation's residual.
    pub residual_std: Vec<f64>,
    /// χ² = Σ (e_r/s_r)², the weighted residual sum of squares.
    pub chi_square: f64,
    /// Its degrees of freedom, equations − free coefficients.
    pub degrees_of_freedom: usize,
    /// P(χ² > observed) for an adequate model with white noise (None without degrees
    /// of freedom).
    pub p_value: Option<f64>,
}

/// Upper-tail probability of χ² below which the report warns that the residuals are
/// larger than the estimated noise explains.
pub const INADEQUATE_P_VALUE: f64 = 0.01;

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
    /// The weighted residuals are larger than the propagated noise explains.
    ModelInadequate {
        /// χ².
        chi_square: f64,
        /// Its degrees of freedom.
        degrees_of_freedom: usize,
        /// Its upper-tail probability.
        p_value: f64,
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
            Warning::ModelInadequate {
                chi_square,
                degrees_of_freedom,
                p_value,
            } => write!(
                f,
                "the weighted residual sum of squares is {chi_square:.3e} for {degrees_of_freedom} degrees of freedom (P = {p_value:.1e}): the residuals are larger than the estimated sensor noise explains, so the model may miss a mechanism, the records may not be in steady state, or the noise is not white; the plug-in standard errors are then too small"
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
    /// Damping coefficients, in model order.
    pub coefficients: Vec<CoefficientEstimate>,
    /// Nuisance unknowns of a non-periodic balance (`mass[i]`, `stiffness[e]`,
    /// `offset[i]`, see [`crate::regressor::nonperiodic`]), reported apart from the damping.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nuisance: Vec<CoefficientEstimate>,
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
    /// The noise-robust pipeline's estimates and model check, when it ran.
    #[serde(default)]
    pub noise: Option<NoiseSummary>,
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
        if let Some(w) = &diagnostics.weighted
            && let Some(p_value) = w.p_value
            && p_value < INADEQUATE_P_VALUE
        {
            warnings.push(Warning::ModelInadequate {
                chi_square: w.chi_square,
                degrees_of_freedom: w.degrees_of_freedom,
                p_value,
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
        let weighted = diagnostics.weighted.as_ref();
        let mut coefficients: Vec<CoefficientEstimate> = regressor
            .columns()
            .iter()
            .zip(&fit.coefficients)
            .zip(&diagnostics.std_errors)
            .enumerate()
            .map(|(k, ((name, value), se))| CoefficientEstimate {
                name: name.clone(),
                value: *value,
                std_error: weighted.map_or(*se, |w| w.plug_in_std_errors[k]),
                residual_std_error: weighted.and(*se),
                determined: identifiability.is_identifiable(name),
                interval: None,
            })
            .collect();
        let nuisance = coefficients.split_off(p - regressor.nuisance_count());
        let noise = match (regressor.noise(), diagnostics.weighted) {
            (Some(model), Some(w)) => Some(NoiseSummary {
                windows: model.windows.clone(),
                residual_std: w.residual_std,
                chi_square: w.chi_square,
                degrees_of_freedom: w.degrees_of_freedom,
                p_value: w.p_value,
            }),
            _ => None,
        };
        FitReport {
            status: fit.status,
            method: fit.method,
            coefficients,
            nuisance,
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
            noise,
            warnings,
        }
    }

    /// Adds the confidence intervals of `bootstrap` (run on the same regressor and fit
    /// settings) to the coefficients, matched by name.
    pub fn with_bootstrap(mut self, bootstrap: Bootstrap) -> Self {
        for c in self.coefficients.iter_mut().chain(&mut self.nuisance) {
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

    /// The estimate of coefficient `name` (damping or nuisance), if the model has it.
    pub fn coefficient(&self, name: &str) -> Option<f64> {
        self.coefficients
            .iter()
            .chain(&self.nuisance)
            .find(|c| c.name == name)
            .map(|c| c.value)
    }
}

impl FitReport {
    /// One line of the coefficient table.
    fn write_estimate(
        &self,
        f: &mut fmt::Formatter<'_>,
        c: &CoefficientEstimate,
        weighted: bool,
        level: Option<f64>,
    ) -> fmt::Result {
        let (se, rel) = match c.std_error {
            _ if !c.determined => ("not determined".into(), String::new()),
            Some(se) if c.value != 0.0 => (
                format!("{se:.3e}"),
                format!("{:.2}%", 100.0 * se / c.value.abs()),
            ),
            Some(se) => (format!("{se:.3e}"), "-".into()),
            None => ("-".into(), "-".into()),
        };
        let wald = match (weighted, c.std_error) {
            (true, Some(se)) if c.determined => format!(
                "  [{:>12.5e}, {:>12.5e}]",
                c.value - 1.959_963_985 * se,
                c.value + 1.959_963_985 * se
            ),
            (true, _) => format!("  {:>27}", "-"),
            (false, _) => String::new(),
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
            "{:<20} {:>14.6e} {:>12} {:>9}{wald}{interval}{held}",
            c.name, c.value, se, rel
        )?;
        Ok(())
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
        let weighted = self.noise.is_some();
        let wald_header = if weighted {
            format!("  {:>27}", "95% plug-in interval")
        } else {
            String::new()
        };
        writeln!(
            f,
            "{:<20} {:>14} {:>12} {:>9}{wald_header}{interval_header}",
            "coefficient",
            "value",
            if weighted { "plug-in se" } else { "std error" },
            "rel. se"
        )?;
        for c in &self.coefficients {
            self.write_estimate(f, c, weighted, level)?;
        }
        if !self.nuisance.is_empty() {
            writeln!(
                f,
                "stored energy and constant forces (nuisance unknowns of the non-periodic balance):"
            )?;
            for c in &self.nuisance {
                self.write_estimate(f, c, weighted, level)?;
            }
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
        if let Some(noise) = &self.noise {
            write!(f, "{noise}")?;
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

impl fmt::Display for NoiseSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "noise-robust fit: equations weighted by their propagated residual standard deviation"
        )?;
        match self.p_value {
            Some(p) => writeln!(
                f,
                "  weighted residual sum of squares χ² = {:.3} for {} degrees of freedom (P = {p:.3})",
                self.chi_square, self.degrees_of_freedom
            )?,
            None => writeln!(
                f,
                "  no degrees of freedom left: no check of the model against the noise"
            )?,
        }
        let all: Vec<f64> = self
            .windows
            .iter()
            .flat_map(|w| w.displacement_noise.iter().copied())
            .collect();
        if let (Some(lo), Some(hi)) = (
            all.iter().copied().reduce(f64::min),
            all.iter().copied().reduce(f64::max),
        ) {
            writeln!(
                f,
                "  displacement noise (per sample, estimated per window and channel): {lo:.3e} to {hi:.3e}"
            )?;
        }
        let most = self.windows.iter().map(|w| w.harmonics.len()).max();
        let fewest = self.windows.iter().map(|w| w.harmonics.len()).min();
        if let (Some(lo), Some(hi)) = (fewest, most) {
            writeln!(
                f,
                "  harmonics kept per window: {lo} to {hi} (listed per window in the JSON report)"
            )?;
        }
        Ok(())
    }
}
