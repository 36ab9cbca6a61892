//! What every fuzz target that fits checks of the outcome (of
//! `dampid::identify::identify`, the pipeline the CLI runs).

use dampid::report::FitReport;

/// A usable fit has finite coefficients; a coefficient is called determined only above
/// a positive threshold (a regressor with no information is an error, never a report
/// of "determined" zeros), and every coefficient only when every singular value is
/// above it; the report always formats.
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
    let identifiability = &report.identifiability;
    assert!(
        identifiability.threshold > 0.0,
        "identifiability threshold {}",
        identifiability.threshold
    );
    if identifiability.separable() {
        assert_eq!(
            identifiability.practical_rank,
            identifiability.names.len(),
            "every coefficient called determined at practical rank {}",
            identifiability.practical_rank
        );
    }
    let _ = report.to_string();
}
