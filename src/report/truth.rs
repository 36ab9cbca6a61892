//! A fit against known true coefficients (a simulation's): per coefficient the true
//! value, the estimate, and the error, relative (e − θ)/|θ| in percent, or absolute
//! e − θ for a true value of 0. Past [`crate::analysis::digest::FULL_LISTING`]
//! coefficients, only the determined ones are compared.

use std::fmt;

use crate::report::FitReport;

/// A report beside the true coefficients ([`FitReport::against`]).
pub struct AgainstTruth<'a> {
    report: &'a FitReport,
    truth: &'a [(String, f64)],
}

impl FitReport {
    /// This report against the true coefficients `truth` (name, value), for printing.
    pub fn against<'a>(&'a self, truth: &'a [(String, f64)]) -> AgainstTruth<'a> {
        AgainstTruth {
            report: self,
            truth,
        }
    }
}

impl fmt::Display for AgainstTruth<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "against the simulation's true coefficients:")?;
        // Past digest::FULL_LISTING coefficients, the undetermined ones (whose values are
        // not estimates) are counted, not listed, as in the coefficient table.
        let many = self.truth.len() > crate::analysis::digest::FULL_LISTING;
        let determined = |name: &str| {
            self.report
                .coefficients
                .iter()
                .any(|c| c.name == name && c.determined)
        };
        let skipped = self
            .truth
            .iter()
            .filter(|(name, _)| many && !determined(name))
            .count();
        for (name, value) in self.truth {
            if many && !determined(name) {
                continue;
            }
            if let Some(estimate) = self.report.coefficient(name) {
                let error = if *value != 0.0 {
                    format!("{:+.3}%", 100.0 * (estimate - value) / value.abs())
                } else {
                    format!("{:+.3e}", estimate - value)
                };
                writeln!(
                    f,
                    "  {name:<18} true {value:<12} estimate {estimate:<14.6e} error {error}"
                )?;
            }
        }
        if skipped > 0 {
            writeln!(
                f,
                "  and {skipped} coefficients not determined by these data (not compared)"
            )?;
        }
        Ok(())
    }
}
