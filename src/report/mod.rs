//! The fit report: coefficients with names and standard errors, residuals and their
//! bias, conditioning, identifiability (near-null directions and determined
//! combinations by name), active constraints, bootstrap confidence intervals when
//! asked for, and warnings in words. `Display` prints a table; serde gives the JSON
//! (schema in README.md and docs/identifiability.md). A coefficient the data cannot
//! separate from others is marked `determined: false` and printed as "not determined":
//! its number is a least-squares artefact, not an estimate, so it gets no standard
//! error and no interval (`null` in the JSON). Each record's share of the residual
//! ([`records`]) is reported, with a warning naming a record that dominates.

mod display;
pub mod estimation;
pub mod explains;
pub mod html;
pub mod outliers;
pub mod provenance;
pub mod records;
mod truth;
pub mod units;
mod warning;

pub use truth::AgainstTruth;

/// `n` and the noun, singular for one: "1 record", "4 records".
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}
pub use warning::{ILL_CONDITIONED, INADEQUATE_P_VALUE, Warning};

use serde::{Deserialize, Serialize};

use crate::analysis::bootstrap::{Bootstrap, BootstrapSummary, ConfidenceInterval};
use crate::analysis::diagnostics::{Correlation, Diagnostics, ResidualBias, StandardErrorBasis};
use crate::analysis::identifiability::Identifiability;
use crate::analysis::velocity_noise::VelocityNoise;
use crate::fit::{ActiveConstraint, Fit, FitMethod, FitStatus, SolverInfo};
use crate::prep::steady_state::SteadyStateReport;
use crate::regressor::robust::WindowNoise;
use crate::regressor::{Regressor, RowLabel};
pub use estimation::Estimation;

/// One identified coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoefficientEstimate {
    /// Name (e.g. `c`, `dashpot[2-3]`).
    pub name: String,
    /// Estimate.
    pub value: f64,
    /// The standard error, when the data have redundancy and the coefficient is free,
    /// by one rule ([`crate::analysis::diagnostics`], its basis in
    /// [`FitReport::std_error_basis`]): from the residual variance for an unweighted
    /// fit; for a fit weighted by propagated variances, `plug_in_std_error` when the χ²
    /// check passes and `residual_std_error` when it rejects the fit.
    pub std_error: Option<f64>,
    /// Weighted fits: the plug-in √diag((AᵀWA)⁻¹) of the propagated noise (None for an
    /// unweighted fit).
    #[serde(default)]
    pub plug_in_std_error: Option<f64>,
    /// Weighted fits: the plug-in standard error times √(χ²/dof), from the residual
    /// scatter, s²(AᵀWA)⁻¹ with s² = χ²/dof (None for an unweighted fit, where
    /// `std_error` is the residual one).
    #[serde(default)]
    pub residual_std_error: Option<f64>,
    /// False when the data cannot separate this coefficient from others: `value` is
    /// then not an estimate.
    pub determined: bool,
    /// Bootstrap confidence interval, when a bootstrap was run and the coefficient is
    /// determined.
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
    /// Where the standard errors come from: the residual variance, the plug-in noise
    /// model, or the plug-in scaled by √(χ²/dof) when the model check rejects the fit.
    #[serde(default)]
    pub std_error_basis: StandardErrorBasis,
    /// Constraints the solution touches.
    pub active_constraints: Vec<ActiveConstraint>,
    /// Constrained-solver details.
    pub solver: Option<SolverInfo>,
    /// What the data can and cannot determine.
    pub identifiability: Identifiability,
    /// The bootstrap behind the confidence intervals, when one was run (the
    /// coefficients' percentile intervals are in `coefficients`, the nonlinear
    /// parameters' in `estimation`).
    pub bootstrap: Option<BootstrapSummary>,
    /// The estimated nonlinear parameters (law parameters, a table's residual
    /// receptances), when the fit estimated any: the coefficients above are then those
    /// of the linear fit at the estimate, their standard errors holding it fixed, and
    /// the estimation's joint intervals include its uncertainty.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimation: Option<Estimation>,
    /// The noise-robust pipeline's estimates and model check, when it ran.
    #[serde(default)]
    pub noise: Option<NoiseSummary>,
    /// The noise bias of a differencing velocity estimator, when one was assessed
    /// ([`crate::analysis::velocity_noise`], [`FitReport::with_velocity_noise`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_noise: Option<VelocityNoise>,
    /// Per record: its share of the residual and its standardised residual
    /// ([`records`]).
    #[serde(default)]
    pub records: Vec<records::RecordResidual>,
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
        if regressor.equations() == free
            || (diagnostics.degrees_of_freedom == 0 && regressor.equations() > free)
        {
            warnings.push(Warning::NoRedundancy {
                equations: regressor.equations(),
            });
        }
        let parameters = free + diagnostics.nonlinear_parameters;
        if free > 0 && regressor.equations() > parameters {
            let experiments = crate::analysis::replicates::experiments(regressor);
            let free_columns: Vec<usize> = (0..p)
                .filter(|j| !fit.active.iter().any(|c| c.name == regressor.columns()[*j]))
                .collect();
            let unchecked = crate::analysis::replicates::unchecked(regressor, &free_columns);
            if experiments <= parameters || !unchecked.is_empty() {
                warnings.push(Warning::NoRecordRedundancy {
                    experiments,
                    parameters,
                    unchecked,
                });
            }
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
        if let Some(l) = diagnostics.lack_of_fit.as_ref().filter(|l| l.rejects()) {
            warnings.push(Warning::LackOfFit {
                relative_misfit: l.relative_misfit,
                coefficient_bound: l.coefficient_bound,
                f_statistic: l.f_statistic,
                degrees_of_freedom: (l.degrees_of_freedom, l.pure_error_degrees_of_freedom),
                p_value: l.p_value,
                scale: l.scale,
                records: l.records.clone(),
            });
        }
        warnings.extend(explains::explains_nothing(
            regressor,
            &fit,
            diagnostics.relative_residual,
        ));
        warnings.extend(
            crate::analysis::bound_set::bound_set(regressor, &fit, &diagnostics)
                .into_iter()
                .map(|b| Warning::BoundSetsCoefficients {
                    coefficient: b.coefficient,
                    side: b.side,
                    bound: b.bound,
                    free_estimate: b.free_estimate,
                    free_std_error: b.free_std_error,
                    allowed: b.allowed,
                    moved: b.moved,
                }),
        );
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
                misfit: warnings
                    .iter()
                    .any(|w| matches!(w, Warning::LackOfFit { .. })),
            });
        }
        explains::round_off(regressor, diagnostics.rank, &mut warnings);
        let weighted = diagnostics.weighted.as_ref();
        let mut coefficients: Vec<CoefficientEstimate> = regressor
            .columns()
            .iter()
            .zip(&fit.coefficients)
            .zip(&diagnostics.std_errors)
            .enumerate()
            .map(|(k, ((name, value), se))| {
                // A coefficient the data do not determine has no standard error: its
                // value is one point on a line of equally good fits.
                let determined = identifiability.is_identifiable(name);
                let keep = |se: Option<f64>| se.filter(|_| determined);
                CoefficientEstimate {
                    name: name.clone(),
                    value: *value,
                    std_error: keep(*se),
                    plug_in_std_error: keep(weighted.and_then(|w| w.plug_in_std_errors[k])),
                    residual_std_error: keep(weighted.and_then(|w| w.scaled_std_errors[k])),
                    determined,
                    interval: None,
                }
            })
            .collect();
        let nuisance = coefficients.split_off(p - regressor.nuisance_count());
        let negative: Vec<(String, f64, Option<f64>)> = coefficients
            .iter()
            .filter(|c| c.value < 0.0 && c.determined)
            .map(|c| (c.name.clone(), c.value, c.std_error))
            .collect();
        if fit.method == FitMethod::LeastSquares && fit.status.is_usable() && !negative.is_empty() {
            warnings.push(Warning::NegativeDamping {
                coefficients: negative,
            });
        }
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
        let records = records::per_record(
            regressor.rows(),
            &diagnostics.residuals,
            noise.as_ref().map(|n| n.residual_std.as_slice()),
            free,
        );
        let equations = regressor.equations();
        for r in &records {
            if r.dominates(records.len(), equations) {
                warnings.push(Warning::RecordDominates {
                    record: r.record.clone(),
                    residual_share: r.residual_share,
                    equation_share: r.equations as f64 / equations as f64,
                    standardised_residual: r.standardised_residual,
                });
            }
        }
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
            std_error_basis: diagnostics.std_error_basis,
            active_constraints: fit.active,
            solver: fit.solver,
            identifiability,
            bootstrap: None,
            estimation: None,
            noise,
            velocity_noise: None,
            records,
            warnings,
        }
    }

    /// Adds the percentile intervals of `bootstrap` (run on the same problem and
    /// settings) to the coefficients and the estimated parameters, matched by name.
    pub fn with_bootstrap(mut self, bootstrap: &Bootstrap) -> Self {
        for c in self.coefficients.iter_mut().chain(&mut self.nuisance) {
            c.interval = bootstrap
                .coefficients
                .iter()
                .find(|i| i.name == c.name && c.determined)
                .cloned();
        }
        if let Some(estimation) = &mut self.estimation {
            for p in &mut estimation.parameters {
                p.bootstrap = bootstrap
                    .parameters
                    .iter()
                    .find(|i| i.name == p.name)
                    .cloned();
            }
        }
        self.bootstrap = Some(bootstrap.summary);
        self
    }

    /// This report with the `estimation` of its nonlinear parameters (the report is the
    /// linear fit's at the estimate).
    pub fn with_estimation(mut self, estimation: Estimation) -> Self {
        self.estimation = Some(estimation);
        self
    }

    /// Adds the assessment of the velocity estimator's noise bias
    /// ([`crate::analysis::velocity_noise::assess`] on the records and settings this
    /// report's regressor was built from); when the bias is material the report warns
    /// first ([`Warning::VelocityNoiseBias`]), naming the estimator to use.
    pub fn with_velocity_noise(mut self, assessment: Option<VelocityNoise>) -> Self {
        if let Some(noise) = &assessment
            && noise.material
            && let Some(worst) = noise.worst()
        {
            self.warnings.insert(
                0,
                Warning::VelocityNoiseBias {
                    estimator: noise.estimator.clone(),
                    gain: noise.gain,
                    displacement_noise: noise.displacement_noise[1],
                    worst: worst.name.clone(),
                    share: worst.share,
                    shifts: noise
                        .columns
                        .iter()
                        .map(|c| (c.name.clone(), c.corrected))
                        .collect(),
                    recommended: noise.recommended.clone(),
                },
            );
        }
        self.velocity_noise = assessment;
        self
    }

    /// Adds a warning when `steady` accepted windows that are not in steady state
    /// ([`Warning::TransientAccepted`]); `None` (the non-periodic mode) adds nothing.
    pub fn with_steady_state(mut self, steady: Option<&SteadyStateReport>) -> Self {
        if let Some(steady) = steady {
            let rejected: Vec<_> = steady.rejected().collect();
            if !rejected.is_empty() {
                let mut records: Vec<String> = Vec::new();
                for w in &rejected {
                    if !records.contains(&w.record) {
                        records.push(w.record.clone());
                    }
                }
                self.warnings.push(Warning::TransientAccepted {
                    windows: rejected.len(),
                    records,
                });
            }
        }
        self
    }

    /// Why `identify --strict` fails, one line each (empty: it passes): a coefficient
    /// that is not determined, windows accepted as transient, the model check (χ²)
    /// failing, or a fit that did not converge.
    pub fn strict_failures(&self) -> Vec<String> {
        let mut failures = Vec::new();
        let undetermined = self.undetermined();
        if !undetermined.is_empty() {
            failures.push(format!(
                "not determined: {}",
                crate::analysis::identifiability::list(&undetermined)
            ));
        }
        for w in &self.warnings {
            match w {
                Warning::TransientAccepted { windows, .. } => failures.push(format!(
                    "{windows} window(s) accepted although not in steady state"
                )),
                Warning::ModelInadequate { p_value, .. } => failures.push(format!(
                    "the model check fails: χ² P = {p_value:.1e} < {INADEQUATE_P_VALUE}"
                )),
                Warning::NotConverged { status } => {
                    failures.push(format!("the fit ended with status {status:?}"))
                }
                Warning::LackOfFit { p_value, .. } => failures.push(format!(
                    "the lack-of-fit test fails: P = {p_value:.1e} < {INADEQUATE_P_VALUE}"
                )),
                Warning::FitExplainsNothing { .. }
                | Warning::InconsistentRecord { .. }
                | Warning::RoundOffColumn { .. } => failures.push(w.to_string()),
                _ => {}
            }
        }
        if let Some(estimation) = &self.estimation {
            failures.extend(estimation.strict_failures());
        }
        failures
    }

    /// The names of the coefficients the data do not determine.
    pub fn undetermined(&self) -> Vec<&str> {
        self.coefficients
            .iter()
            .filter(|c| !c.determined)
            .map(|c| c.name.as_str())
            .collect()
    }

    /// True when the fit converged (its solver, and the outer loop of any estimated
    /// parameters): the numbers are a solution, which the exit status of `dampid
    /// identify` says (1 otherwise). Whether the data determine each coefficient is
    /// [`Self::is_estimate`].
    pub fn is_usable(&self) -> bool {
        self.status.is_usable() && self.estimation.as_ref().is_none_or(|e| e.status.converged)
    }

    /// True when the fit converged ([`Self::is_usable`]) and the data determine every
    /// coefficient: the values are estimates.
    pub fn is_estimate(&self) -> bool {
        self.is_usable() && self.coefficients.iter().all(|c| c.determined)
    }

    /// The covariance of the coefficients (in column order, nuisance unknowns after the
    /// damping coefficients): the joint one of an estimation (its first p rows and
    /// columns: θ, holding nothing fixed) when it has one, else the linear fit's,
    /// Σ_ij = se_i se_j ρ_ij from the standard errors and the correlation; `None` when
    /// a coefficient has no standard error.
    pub fn covariance(&self) -> Option<Vec<Vec<f64>>> {
        if let Some(estimation) = &self.estimation {
            return estimation.covariance.clone();
        }
        let all: Vec<&CoefficientEstimate> =
            self.coefficients.iter().chain(&self.nuisance).collect();
        let p = all.len();
        let se: Vec<f64> = all.iter().map(|c| c.std_error).collect::<Option<_>>()?;
        let mut c = vec![vec![0.0; p]; p];
        for (i, row) in c.iter_mut().enumerate() {
            row[i] = se[i] * se[i];
        }
        if let Some(corr) = &self.correlation {
            let index = |name: &str| all.iter().position(|c| c.name == name);
            for (a, na) in corr.names.iter().enumerate() {
                for (b, nb) in corr.names.iter().enumerate() {
                    if let (Some(i), Some(j)) = (index(na), index(nb)) {
                        c[i][j] = se[i] * se[j] * corr.matrix[a][b];
                    }
                }
            }
        }
        Some(c)
    }

    /// The value of estimated nonlinear parameter `name`, if the fit estimated it.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.estimation.as_ref()?.parameter(name)
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
