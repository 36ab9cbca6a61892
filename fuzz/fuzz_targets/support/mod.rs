//! What every fuzz target that fits checks of the outcome (of
//! `dampid::identify::identify` or `identify_regressor`, the pipeline the CLI runs).

use dampid::report::FitReport;

/// A usable fit has finite coefficients; the report always formats.
pub fn check(report: &FitReport) {
    if report.status.is_usable() {
        for c in &report.coefficients {
            assert!(
                c.value.is_finite(),
                "usable fit with {} = {}",
                c.name,
                c.value
            );
        }
    }
    let _ = report.to_string();
}
