//! One target of a reference study: a computed figure compared with the paper's printed
//! value or with the truth, as an error measured one of these ways,
//!
//! ```text
//!   absolute, percentage points:  e = |ours − reference|             passes when e ≤ tol
//!   relative (to truth):          e = |ours − reference| / |reference|  passes when e ≤ tol
//!   ratio, at least:              e = ours / other                   passes when e ≥ tol
//! ```
//!
//! The studies keep their checks as data (serialized in their JSON) and print them in
//! their own tables.

use std::fmt;

use serde::{Serialize, Serializer};

/// How a [`Check`]'s error is measured and compared with its tolerance. Serialized as
/// its `Display` text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// |ours − reference|, in the quantity's unit ("absolute").
    Absolute,
    /// |ours − reference| with values in percent ("percentage points").
    PercentagePoints,
    /// |ours − reference| / |reference| ("relative").
    Relative,
    /// |ours − truth| / |truth|, the truth not recorded in the check ("relative to truth").
    RelativeToTruth,
    /// A ratio that must reach the tolerance; the text names what is divided by what
    /// ("ratio {0}, at least").
    RatioAtLeast(&'static str),
}

impl Measure {
    /// Whether `error` meets `tolerance`: at least it for ratios, at most otherwise.
    pub fn passes(self, error: f64, tolerance: f64) -> bool {
        match self {
            Measure::RatioAtLeast(_) => error >= tolerance,
            _ => error <= tolerance,
        }
    }
}

impl fmt::Display for Measure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Measure::Absolute => f.write_str("absolute"),
            Measure::PercentagePoints => f.write_str("percentage points"),
            Measure::Relative => f.write_str("relative"),
            Measure::RelativeToTruth => f.write_str("relative to truth"),
            Measure::RatioAtLeast(what) => write!(f, "ratio {what}, at least"),
        }
    }
}

impl Serialize for Measure {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// One comparison with a target.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// What is compared.
    pub quantity: String,
    /// The paper's value (NaN when it prints none).
    pub paper: f64,
    /// The value the error is measured from, where the check records it (the paper's
    /// value or the truth); not serialized when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// Ours.
    pub ours: f64,
    /// The error (or the ratio compared with the threshold), as `measure` says.
    pub error: f64,
    /// The threshold.
    pub tolerance: f64,
    /// How `error` is measured and compared.
    pub measure: Measure,
    /// Whether the target is met.
    pub passes: bool,
}

impl Check {
    /// `ours` against a recorded `reference`: |ours − reference| for
    /// [`Measure::Absolute`] and [`Measure::PercentagePoints`] (values already in
    /// percent), |ours − reference| / |reference| otherwise.
    pub fn against(
        quantity: impl Into<String>,
        paper: f64,
        reference: f64,
        ours: f64,
        measure: Measure,
        tolerance: f64,
    ) -> Self {
        let error = match measure {
            Measure::Absolute | Measure::PercentagePoints => (ours - reference).abs(),
            _ => (ours - reference).abs() / reference.abs(),
        };
        Check {
            quantity: quantity.into(),
            paper,
            reference: Some(reference),
            ours,
            error,
            tolerance,
            measure,
            passes: measure.passes(error, tolerance),
        }
    }

    /// Shares given as fractions, compared in percentage points against the paper's:
    /// error = 100 |ours − paper|; `paper` and `ours` are kept in percent.
    pub fn percentage_points(
        quantity: impl Into<String>,
        paper: f64,
        ours: f64,
        tolerance: f64,
    ) -> Self {
        let error = 100.0 * (ours - paper).abs();
        Check {
            quantity: quantity.into(),
            paper: 100.0 * paper,
            reference: None,
            ours: 100.0 * ours,
            error,
            tolerance,
            measure: Measure::PercentagePoints,
            passes: error <= tolerance,
        }
    }

    /// |ours − truth| / |truth| ≤ tolerance, beside the paper's value.
    pub fn relative_to_truth(
        quantity: impl Into<String>,
        paper: f64,
        truth: f64,
        ours: f64,
        tolerance: f64,
    ) -> Self {
        let error = (ours - truth).abs() / truth.abs();
        Check {
            quantity: quantity.into(),
            paper,
            reference: None,
            ours,
            error,
            tolerance,
            measure: Measure::RelativeToTruth,
            passes: error <= tolerance,
        }
    }

    /// numerator / denominator ≥ threshold (no paper value); `ratio` names the two,
    /// e.g. "one mode / two modes".
    pub fn ratio_at_least(
        quantity: impl Into<String>,
        ratio: &'static str,
        numerator: f64,
        denominator: f64,
        threshold: f64,
    ) -> Self {
        let error = numerator / denominator;
        Check {
            quantity: quantity.into(),
            paper: f64::NAN,
            reference: None,
            ours: numerator,
            error,
            tolerance: threshold,
            measure: Measure::RatioAtLeast(ratio),
            passes: error >= threshold,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_serialize_as_their_text_and_ratios_pass_from_above() {
        let ratio = Check::ratio_at_least("r", "a / b", 3.0, 1.0, 3.0);
        assert!(ratio.passes);
        let json = serde_json::to_value(&ratio).unwrap();
        assert_eq!(json["measure"], "ratio a / b, at least");
        assert!(json.get("reference").is_none());
        // 0.02 / 0.1 = 0.2 relative error, above 0.1.
        let relative = Check::against("c", 0.1, 0.1, 0.12, Measure::Relative, 0.1);
        assert!(!relative.passes);
        assert_eq!(serde_json::to_value(&relative).unwrap()["reference"], 0.1);
    }
}
