//! What every fuzz target that fits checks of the outcome.

use dampid::fit::FitSettings;
use dampid::regressor::Regressor;
use dampid::report::FitReport;

/// Fits `regressor` as `dampid identify` does (solve, diagnose, report) and checks the
/// report: a usable fit has finite coefficients, and the report always formats. Any
/// `Err` is fine.
pub fn fit_and_check(regressor: &Regressor, settings: &FitSettings) {
    let Ok(fit) = dampid::fit::solve(regressor, settings) else {
        return;
    };
    let diagnostics = dampid::analysis::diagnostics::diagnose(regressor, &fit, settings.rank_tolerance);
    check(&FitReport::new(regressor, fit, diagnostics));
}

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
