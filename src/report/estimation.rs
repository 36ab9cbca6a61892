//! The estimated nonlinear parameters of a fit ([`crate::varpro`]): each parameter with
//! its profile-likelihood interval, the linear coefficients with intervals from the
//! joint covariance (which include the uncertainty of the nonlinear parameters), and
//! the outer loop's status. A [`FitReport`](super::FitReport) carries it as
//! `estimation` when something was estimated; the report's own coefficients are then
//! those of the linear fit at the estimate, their errors conditional on it.

use std::fmt;

use serde::{Deserialize, Serialize};

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
    /// The bootstrap percentile interval, when a bootstrap was run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bootstrap: Option<ConfidenceInterval>,
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

/// What the outer loop of a variable projection found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimation {
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
    /// The linear coefficients (and nuisance unknowns), in column order, with their
    /// joint intervals.
    pub coefficients: Vec<JointEstimate>,
    /// The joint covariance of (θ, η) at the optimum, (p + q) × (p + q): the
    /// coefficients in column order, then the nonlinear parameters in order
    /// (σ²(JᵀJ)⁻¹ of [`crate::varpro`]); `None` when it is not computed (no convergence,
    /// no degrees of freedom, a rank-deficient Jacobian).
    #[serde(default)]
    pub covariance: Option<Vec<Vec<f64>>>,
}

impl Estimation {
    /// The value of nonlinear parameter `name`.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.value)
    }

    /// η̂, in parameter order.
    pub fn values(&self) -> Vec<f64> {
        self.parameters.iter().map(|p| p.value).collect()
    }

    /// What `--strict` refuses besides the linear fit's failures: an outer loop that did
    /// not converge, and an estimated parameter on one of its bounds (not an interior
    /// estimate).
    pub fn strict_failures(&self) -> Vec<String> {
        let mut failures = Vec::new();
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

    /// The estimation's part of the text report: the outer loop, the parameter table
    /// and the coefficients' joint intervals; `estimate` says whether the whole fit is
    /// an estimate.
    pub(crate) fn write(&self, f: &mut fmt::Formatter<'_>, estimate: bool) -> fmt::Result {
        let s = &self.status;
        writeln!(
            f,
            "variable projection: {} ({}, {} iterations, {} regressors built)",
            s.reason, s.method, s.iterations, s.evaluations
        )?;
        if !estimate {
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
        )
    }
}

fn end(value: Option<f64>, bound: f64) -> String {
    match value {
        Some(v) => format!("{v:.6e}"),
        None => format!("beyond {bound}"),
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
