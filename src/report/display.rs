//! The fit report as text: the coefficient table (value, standard error, relative
//! standard error, 95% interval est ± 1.96 se with propagated weights, bootstrap
//! percentile interval) and the basis of its standard errors in words
//! ([`StandardErrorBasis`]: residual variance, plug-in, or plug-in scaled by √(χ²/dof)),
//! conditioning, identifiability, correlation, the noise check, the residual and its
//! bias, and the warnings. Long lists (more than [`digest::FULL_LISTING`] coefficients)
//! are summarised ([`crate::analysis::digest`]).

use std::fmt;

use crate::analysis::bootstrap::{BootstrapSummary, Resampled};
use crate::analysis::diagnostics::StandardErrorBasis;
use crate::analysis::digest;
use crate::report::{CoefficientEstimate, FitReport, NoiseSummary};

/// `x` with three significant digits, in plain notation between 0.01 and 10⁵
/// ("840", "29.0", "1.23"), else in exponent notation.
pub(crate) fn significant(x: f64) -> String {
    let a = x.abs();
    if a.is_finite() && (0.01..1e5).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    }
}

impl fmt::Display for StandardErrorBasis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StandardErrorBasis::ResidualVariance => write!(
                f,
                "standard errors from the residual variance: se = √(s² diag((AᵀA)⁻¹)), s² = ‖b − Aθ‖²/(equations − free coefficients)"
            ),
            StandardErrorBasis::PlugIn => write!(
                f,
                "standard errors are plug-in, from the propagated sensor noise: se = √diag((AᵀWA)⁻¹), W = diag(1/Var e_r); the χ² check passes"
            ),
            StandardErrorBasis::ScaledPlugIn {
                chi_square_per_dof,
                scale,
            } => write!(
                f,
                "χ²/dof = {}: the residual is not noise; standard errors are scaled by √(χ²/dof) = {}, se = √(χ²/dof) · √diag((AᵀWA)⁻¹), from the residual scatter",
                significant(*chi_square_per_dof),
                significant(*scale)
            ),
            StandardErrorBasis::BetweenRecords { f_statistic, scale } => write!(
                f,
                "the records' mean residuals differ far more than their windows scatter (lack of fit, F = {}): standard errors are from the records' means, the residual-variance ones scaled by {}, se = {} · √(s² diag((AᵀA)⁻¹))",
                f_statistic.map_or("∞".to_string(), significant),
                significant(*scale),
                significant(*scale)
            ),
        }
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
            (Some(i), Some(_)) => format!("  [{:>12.5e}, {:>12.5e}]", i.lower, i.upper),
            (None, Some(_)) => format!("  {:>27}", "-"),
            (_, None) => String::new(),
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

impl FitReport {
    /// The coefficient rows; with more than [`digest::FULL_LISTING`] coefficients, the
    /// undetermined ones (whose values are not estimates) are counted by term in one
    /// line instead of a row each (all of them are in the JSON).
    fn write_coefficients(
        &self,
        f: &mut fmt::Formatter<'_>,
        weighted: bool,
        level: Option<f64>,
    ) -> fmt::Result {
        let many = self.coefficients.len() > digest::FULL_LISTING;
        for c in self.coefficients.iter().filter(|c| !many || c.determined) {
            self.write_estimate(f, c, weighted, level)?;
        }
        let undetermined = self.undetermined();
        if many && !undetermined.is_empty() {
            writeln!(
                f,
                "not determined: {} of {} coefficients (by term: {}); their values are not estimates (all in the JSON)",
                undetermined.len(),
                self.coefficients.len(),
                digest::by_term_text(undetermined.iter().copied())
            )?;
        }
        Ok(())
    }
}

impl FitReport {
    /// The bootstrap of a fit with estimated parameters: one table of every parameter's
    /// and coefficient's percentile interval (the coefficient table of the linear fit
    /// at η̂ then shows none).
    fn write_estimated_bootstrap(
        &self,
        f: &mut fmt::Formatter<'_>,
        b: &BootstrapSummary,
    ) -> fmt::Result {
        let percent = (100.0 * b.level * 1e6).round() / 1e6;
        writeln!(
            f,
            "bootstrap: {} of {} replicates kept, {} resampled ({} to draw from), seed {}, {} regressors built",
            b.used, b.replicates, b.resampled, b.groups, b.seed, b.evaluations
        )?;
        if b.used < b.replicates {
            writeln!(
                f,
                "  dropped: {} whose outer loop did not converge, {} whose linear fit was not usable",
                b.not_converged, b.unusable
            )?;
        }
        writeln!(
            f,
            "{:<20} {:>14}  {:>34}",
            "parameter",
            "bootstrap se",
            format!("{percent}% percentile interval")
        )?;
        let parameters = self
            .estimation
            .iter()
            .flat_map(|e| &e.parameters)
            .filter_map(|p| p.bootstrap.as_ref());
        let coefficients = self
            .coefficients
            .iter()
            .chain(&self.nuisance)
            .filter_map(|c| c.interval.as_ref());
        for i in parameters.chain(coefficients) {
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
        if b.resampled == Resampled::Sweeps {
            writeln!(
                f,
                "  whole sweeps keep each sweep's points together: an unknown of one sweep (its residual receptance) varies here only through the shared parameters, so read its joint interval above"
            )?;
        }
        Ok(())
    }
}

impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(estimation) = &self.estimation {
            estimation.write(f, self.is_estimate())?;
            if let Some(b) = &self.bootstrap {
                self.write_estimated_bootstrap(f, b)?;
            }
            writeln!(
                f,
                "linear fit at the estimated parameters (its errors hold them fixed):"
            )?;
        }
        writeln!(f, "status: {:?} ({:?})", self.status, self.method)?;
        // With estimated parameters the bootstrap is shown above, with theirs.
        let bootstrap = self
            .bootstrap
            .as_ref()
            .filter(|_| self.estimation.is_none());
        let level = bootstrap.map(|b| b.level);
        let interval_header = level
            .map(|l| {
                let percent = (100.0 * l * 1e6).round() / 1e6;
                format!("  {:>27}", format!("{percent}% interval"))
            })
            .unwrap_or_default();
        let weighted = self.noise.is_some();
        let (se_header, wald_header) = match self.std_error_basis {
            StandardErrorBasis::ResidualVariance => ("std error", "95% interval"),
            StandardErrorBasis::PlugIn => ("plug-in se", "95% plug-in interval"),
            StandardErrorBasis::ScaledPlugIn { .. } => ("scaled se", "95% scaled interval"),
            StandardErrorBasis::BetweenRecords { .. } => ("scaled se", "95% interval"),
        };
        let wald_header = if weighted {
            format!("  {wald_header:>27}")
        } else {
            String::new()
        };
        writeln!(
            f,
            "{:<20} {:>14} {:>12} {:>9}{wald_header}{interval_header}",
            "coefficient", "value", se_header, "rel. se"
        )?;
        self.write_coefficients(f, weighted, level)?;
        if !self.nuisance.is_empty() {
            writeln!(
                f,
                "nuisance unknowns of the energy balance (stored energy, constant forces, a free decay's start energy):"
            )?;
            for c in &self.nuisance {
                self.write_estimate(f, c, weighted, level)?;
            }
        }
        if self.coefficients.iter().any(|c| c.std_error.is_some()) {
            let unchecked = self.noise.as_ref().is_some_and(|n| n.p_value.is_none());
            if unchecked && self.std_error_basis == StandardErrorBasis::PlugIn {
                writeln!(
                    f,
                    "standard errors are plug-in, from the propagated sensor noise: se = √diag((AᵀWA)⁻¹), W = diag(1/Var e_r); no degrees of freedom are left to check them (χ²)"
                )?;
            } else {
                writeln!(f, "{}", self.std_error_basis)?;
            }
        }
        if let Some(b) = bootstrap {
            writeln!(
                f,
                "bootstrap: {} of {} resampled regressors used ({} resampled with replacement, seed {}); percentile intervals",
                b.used, b.replicates, b.resampled, b.seed
            )?;
        }
        writeln!(
            f,
            "equations: {}, rank: {}",
            self.residuals.len(),
            self.rank
        )?;
        // One definition, shared with `dampid check` (analysis::solved).
        let basis = crate::analysis::solved::conditioning_basis(self.noise.is_some());
        match self.condition_number {
            Some(k) => writeln!(f, "condition number σ₁/σₚ of the {basis}: {k:.3e}")?,
            None => writeln!(f, "condition number σ₁/σₚ of the {basis}: infinite")?,
        }
        writeln!(
            f,
            "singular values: {}",
            crate::analysis::digest::sequence(&self.singular_values)
        )?;
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
        if self.records.len() > 1
            && let Some(worst) = self
                .records
                .iter()
                .max_by(|a, b| a.residual_share.total_cmp(&b.residual_share))
        {
            let z = worst
                .standardised_residual
                .map(|z| format!(", standardised residual {z:.2}"))
                .unwrap_or_default();
            writeln!(
                f,
                "largest residual share: '{}', {:.1}% of the squared residual from {:.1}% of the equations{z}",
                worst.record,
                100.0 * worst.residual_share,
                100.0 * worst.equations as f64 / self.residuals.len().max(1) as f64
            )?;
        }
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
            .flat_map(|w| {
                let plain = w.sensors.is_empty();
                w.displacement_noise
                    .iter()
                    .enumerate()
                    .filter(move |(j, _)| {
                        plain || w.sensors[*j] == crate::record::Sensor::Displacement
                    })
                    .map(|(_, s)| *s)
            })
            .collect();
        for kind in [
            crate::record::Sensor::Velocity,
            crate::record::Sensor::Acceleration,
        ] {
            let of_kind: Vec<f64> = self
                .windows
                .iter()
                .flat_map(|w| {
                    w.sensors
                        .iter()
                        .zip(&w.displacement_noise)
                        .filter(|(s, _)| **s == kind)
                        .map(|(_, n)| *n)
                })
                .collect();
            if let (Some(lo), Some(hi)) = (
                of_kind.iter().copied().reduce(f64::min),
                of_kind.iter().copied().reduce(f64::max),
            ) {
                writeln!(
                    f,
                    "  {} noise (per sample, estimated per window and channel): {lo:.3e} to {hi:.3e}; integrated per kept harmonic, the mean of x and v over each window set to zero (k = 0 removed)",
                    kind.name()
                )?;
            }
        }
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
