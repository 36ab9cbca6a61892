//! The bootstrap of `--bootstrap`, for every fit: how many replicates were kept, what
//! each drew with replacement (windows, or a table's whole sweeps) and what it refitted
//! (the coefficients, or the whole variable projection from the estimate), and the
//! percentile intervals with the replicates' standard deviation, every estimated
//! nonlinear parameter first, then every determined coefficient.

use std::fmt::Write as _;

use super::{HtmlReport, escape};
use crate::analysis::bootstrap::{BootstrapSummary, Resampled};

impl HtmlReport<'_> {
    /// The bootstrap section (module doc).
    pub(super) fn bootstrap_section(&self, b: &BootstrapSummary) -> String {
        let percent = (100.0 * b.level * 1e6).round() / 1e6;
        let estimation = self.report.estimation.as_ref();
        let (dropped, refitted) = match estimation {
            Some(_) => (
                format!(
                    "{} not converged, {} with an unusable linear fit",
                    b.not_converged, b.unusable
                ),
                "the whole variable projection from the estimate",
            ),
            None => (
                format!("{} with an unusable fit", b.unusable),
                "the coefficients",
            ),
        };
        // A sweep's residual receptance sees only its own sweep's points.
        let own_unknowns = self
            .source
            .stepped_sine()
            .is_some_and(|t| !t.residual_parameters.is_empty());
        let caveat = if b.resampled == Resampled::Sweeps && own_unknowns {
            " A sweep's own unknown (its residual receptance) sees the same points in every replicate that draws its sweep: its interval understates its uncertainty, read its joint interval above."
        } else {
            ""
        };
        let mut out = format!(
            "\n<h2>Bootstrap</h2>\n<p>{} of {} replicates kept ({dropped}), seed {}; each drew {} {} with replacement from the {} there are and refitted {refitted}. Percentile intervals at {percent}%.{caveat}</p>\n<table><tr><th>quantity</th><th>bootstrap std error</th><th>{percent}% percentile interval</th></tr>\n",
            b.used, b.replicates, b.seed, b.groups, b.resampled, b.groups,
        );
        let parameters = estimation
            .into_iter()
            .flat_map(|e| &e.parameters)
            .filter_map(|p| p.bootstrap.as_ref());
        let coefficients = self
            .report
            .coefficients
            .iter()
            .chain(&self.report.nuisance)
            .filter_map(|c| c.interval.as_ref());
        for i in parameters.chain(coefficients) {
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{:.3e}</td><td>[{:.6e}, {:.6e}]</td></tr>",
                escape(&i.name),
                i.std_error,
                i.lower,
                i.upper
            );
        }
        out.push_str("</table>\n");
        out
    }
}
