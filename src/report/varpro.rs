//! The report of a variable-projection fit ([`crate::varpro`]): the nonlinear
//! parameters with their profile-likelihood intervals, the linear coefficients with
//! intervals from the joint covariance (which include the uncertainty of the nonlinear
//! parameters), the outer loop's status, and the ordinary [`FitReport`] of the linear
//! fit at the estimated parameters (its errors conditional on them); and, when one
//! was run, the bootstrap of the whole variable projection ([`crate::varpro::bootstrap_varpro`]):
//! percentile intervals of every parameter and coefficient from refits of resampled
//! windows or whole sweeps.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::FitReport;
use crate::analysis::bootstrap::ConfidenceInterval;

/// How the outer loop ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OuterLoop {
    /// True when the outer optimiser met its tolerance.
    pub converged: bool,
    /// `brent` (one parameter) or `levenberg_marquardt` (several).
    pub method: String,
    /// Outer iterations.
    pub iterations: u64,
    /// Regressors built (trials, Jacobian differences and profile searches).
    pub evaluations: u64,
    /// Why it stopped.
    pub reason: String,
}

/// A profile-likelihood interval; an end is `None` when the profiled cost has not
/// risen by `rise` at the parameter's bound (the data do not bound it there).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProfileInterval {
    /// Lower end.
    pub lower: Option<f64>,
    /// Upper end.
    pub upper: Option<f64>,
    /// Confidence level.
    pub level: f64,
    /// The rise of the cost that bounds the interval, F₁,ν(level)·s² or χ²₁(level)·σ².
    pub rise: f64,
}

/// One estimated nonlinear parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NonlinearEstimate {
    /// Name.
    pub name: String,
    /// Estimate (the last trial when the outer loop did not converge).
    pub value: f64,
    /// Initial value given.
    pub initial: f64,
    /// Lower bound given.
    pub lower_bound: f64,
    /// Upper bound given.
    pub upper_bound: f64,
    /// True when the estimate sits on a bound (within 10⁻⁶ of the interval).
    pub at_bound: bool,
    /// Wald standard error from the joint covariance.
    pub std_error: Option<f64>,
    /// Profile-likelihood interval.
    pub interval: Option<ProfileInterval>,
    /// The Wald interval value ± q·se of the joint covariance (q as the coefficients'
    /// joint intervals), reported where no profile interval is computed.
    #[serde(default)]
    pub joint_interval: Option<[f64; 2]>,
}

/// A linear coefficient with its joint (nonlinear-aware) interval.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointEstimate {
    /// Name.
    pub name: String,
    /// Estimate.
    pub value: f64,
    /// Standard error from the joint covariance.
    pub std_error: Option<f64>,
    /// Lower end of the interval.
    pub lower: Option<f64>,
    /// Upper end of the interval.
    pub upper: Option<f64>,
}

/// What a variable-projection fit found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VarProReport {
    /// The outer loop's status.
    pub status: OuterLoop,
    /// Confidence level of the intervals.
    pub level: f64,
    /// The projected cost at the estimate: Σ e² (unweighted) or χ² (weighted).
    pub cost: f64,
    /// Whether the inner fit was weighted by the propagated noise model.
    pub weighted: bool,
    /// m − p − q (0 when there are none).
    pub degrees_of_freedom: usize,
    /// The nonlinear parameters.
    pub parameters: Vec<NonlinearEstimate>,
    /// The linear coefficients (and nuisance unknowns), in column order.
    pub coefficients: Vec<JointEstimate>,
    /// The joint covariance of (θ, η) at the optimum, (p + q) × (p + q): the
    /// coefficients in column order, then the nonlinear parameters in order
    /// (σ²(JᵀJ)⁻¹ of [`crate::varpro`]); `None` when it is not computed (no convergence,
    /// no degrees of freedom, a rank-deficient Jacobian).
    #[serde(default)]
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The linear fit at the estimated parameters.
    pub fit: FitReport,
    /// The bootstrap of the whole variable projection, when one was run.
    #[serde(default)]
    pub bootstrap: Option<VarProBootstrap>,
}

/// What a replicate of a variable-projection bootstrap drew with replacement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Resampled {
    /// Single equations (windows of whole periods of records, or single points).
    Windows,
    /// Whole groups of equations: the sweeps of a stepped-sine table.
    Sweeps,
}

impl fmt::Display for Resampled {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Resampled::Windows => "windows",
            Resampled::Sweeps => "whole sweeps",
        })
    }
}

/// The bootstrap of a variable-projection fit: each replicate refits η and θ on
/// resampled equations ([`crate::varpro::bootstrap_varpro`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VarProBootstrap {
    /// Replicates drawn (B).
    pub replicates: usize,
    /// Replicates kept: outer loop converged, linear fit usable at full rank.
    pub used: usize,
    /// Replicates dropped because their outer loop did not converge.
    pub not_converged: usize,
    /// Replicates dropped because the linear fit at their η* was not usable (solver
    /// status, a numerical failure, or a rank below the full data's).
    pub unusable: usize,
    /// Master seed.
    pub seed: u64,
    /// Confidence level of the percentile intervals.
    pub level: f64,
    /// What a replicate drew.
    pub resampled: Resampled,
    /// Regressors built by the replicates' outer loops (all replicates).
    pub evaluations: u64,
    /// How many units (windows or sweeps) there are to draw from; a replicate draws as
    /// many, with replacement.
    pub groups: usize,
    /// One interval per nonlinear parameter, in parameter order.
    pub parameters: Vec<ConfidenceInterval>,
    /// One interval per linear coefficient, in column order.
    pub coefficients: Vec<ConfidenceInterval>,
    /// (η*, θ*) of each kept replicate, η* first, in replicate order (not serialised).
    #[serde(skip)]
    pub samples: Vec<Vec<f64>>,
    /// The units each replicate drew (indices in 0..`groups`), every replicate in
    /// replicate order, kept or not (not serialised).
    #[serde(skip)]
    pub drawn: Vec<Vec<usize>>,
}

impl VarProReport {
    /// True when the outer loop converged and the linear fit at its end is an estimate.
    pub fn is_estimate(&self) -> bool {
        self.status.converged && self.fit.is_estimate()
    }

    /// What `dampid identify --strict` refuses in this fit: the linear fit's own
    /// failures at η̂ ([`FitReport::strict_failures`]), an outer loop that did not
    /// converge, and an estimated parameter on one of its bounds (not an interior
    /// estimate).
    pub fn strict_failures(&self) -> Vec<String> {
        let mut failures = self.fit.strict_failures();
        if !self.status.converged {
            failures.push(format!(
                "the outer loop did not converge: {}",
                self.status.reason
            ));
        }
        for p in self.parameters.iter().filter(|p| p.at_bound) {
            failures.push(format!(
                "estimated parameter {} = {} sits on a bound of [{}, {}]",
                p.name,
                p.value,
                bound(p.lower_bound),
                bound(p.upper_bound)
            ));
        }
        failures
    }

    /// The value of nonlinear parameter `name`.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.value)
    }

    /// The value of linear coefficient `name`.
    pub fn coefficient(&self, name: &str) -> Option<f64> {
        self.fit.coefficient(name)
    }

    /// This report with the bootstrap `bootstrap` (run on the same problem).
    pub fn with_bootstrap(mut self, bootstrap: VarProBootstrap) -> Self {
        self.bootstrap = Some(bootstrap);
        self
    }
}

fn end(value: Option<f64>, bound: f64) -> String {
    match value {
        Some(v) => format!("{v:.6e}"),
        None => format!("beyond {bound}"),
    }
}

impl fmt::Display for VarProReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.status;
        writeln!(
            f,
            "variable projection: {} ({}, {} iterations, {} regressors built)",
            s.reason, s.method, s.iterations, s.evaluations
        )?;
        if !self.is_estimate() {
            writeln!(
                f,
                "NOT AN ESTIMATE: the outer optimisation did not converge or the linear fit failed; the values below are the last trial"
            )?;
        }
        let percent = (100.0 * self.level * 1e6).round() / 1e6;
        let joint_only = self
            .parameters
            .iter()
            .any(|p| p.interval.is_none() && p.joint_interval.is_some());
        writeln!(
            f,
            "{:<20} {:>14} {:>12}  {:>34}  bounds",
            "estimated parameter",
            "value",
            "std error",
            if joint_only {
                format!("{percent}% profile (or joint) interval")
            } else {
                format!("{percent}% profile interval")
            },
        )?;
        for p in &self.parameters {
            let se = p
                .std_error
                .map_or_else(|| "-".into(), |s| format!("{s:.3e}"));
            let interval = match (&p.interval, p.joint_interval) {
                (Some(i), _) => format!(
                    "[{}, {}]",
                    end(i.lower, p.lower_bound),
                    end(i.upper, p.upper_bound)
                ),
                (None, Some([l, u])) => format!("joint [{l:.6e}, {u:.6e}]"),
                (None, None) => "-".into(),
            };
            let flag = if p.at_bound { " (on a bound)" } else { "" };
            writeln!(
                f,
                "{:<20} {:>14.6e} {se:>12}  {interval:>34}  [{}, {}]{flag}",
                p.name,
                p.value,
                bound(p.lower_bound),
                bound(p.upper_bound)
            )?;
        }
        writeln!(
            f,
            "{:<20} {:>14} {:>12}  {:>34}",
            "coefficient",
            "value",
            "joint se",
            format!("{percent}% joint interval")
        )?;
        for c in &self.coefficients {
            let se = c
                .std_error
                .map_or_else(|| "-".into(), |s| format!("{s:.3e}"));
            let interval = match (c.lower, c.upper) {
                (Some(l), Some(u)) => format!("[{l:.6e}, {u:.6e}]"),
                _ => "-".into(),
            };
            writeln!(
                f,
                "{:<20} {:>14.6e} {se:>12}  {interval:>34}",
                c.name, c.value
            )?;
        }
        writeln!(
            f,
            "joint errors: covariance of the full Jacobian [∂r/∂θ, ∂r/∂η] at the optimum, {} degrees of freedom",
            self.degrees_of_freedom
        )?;
        if let Some(b) = &self.bootstrap {
            write!(f, "{b}")?;
        }
        writeln!(
            f,
            "linear fit at the estimated parameters (its errors hold them fixed):"
        )?;
        write!(f, "{}", self.fit)
    }
}

impl fmt::Display for VarProBootstrap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let percent = (100.0 * self.level * 1e6).round() / 1e6;
        writeln!(
            f,
            "bootstrap: {} of {} replicates kept, {} resampled ({} to draw from), seed {}, {} regressors built",
            self.used, self.replicates, self.resampled, self.groups, self.seed, self.evaluations
        )?;
        if self.used < self.replicates {
            writeln!(
                f,
                "  dropped: {} whose outer loop did not converge, {} whose linear fit was not usable",
                self.not_converged, self.unusable
            )?;
        }
        writeln!(
            f,
            "{:<20} {:>14}  {:>34}",
            "parameter",
            "bootstrap se",
            format!("{percent}% percentile interval")
        )?;
        for i in self.parameters.iter().chain(&self.coefficients) {
            writeln!(
                f,
                "{:<20} {:>14.3e}  {:>34}",
                i.name,
                i.std_error,
                format!("[{:.6e}, {:.6e}]", i.lower, i.upper)
            )?;
        }
        writeln!(
            f,
            "bootstrap: each replicate refits the whole variable projection (η and θ) on the resampled equations, from the full data's estimate"
        )?;
        if self.resampled == Resampled::Sweeps {
            writeln!(
                f,
                "  whole sweeps keep each sweep's points together: an unknown of one sweep (its residual receptance) varies here only through the shared parameters, so read its joint interval above"
            )?;
        }
        Ok(())
    }
}

/// A bound as the user wrote it when that is short (`0.5`, `4`), else with 5 significant
/// digits (a bound the program derived from the data, `-1.6519e-4`, not 17 digits).
pub(crate) fn bound(x: f64) -> String {
    let shortest = format!("{x}");
    if shortest.len() <= 8 {
        shortest
    } else {
        format!("{x:.4e}")
    }
}
