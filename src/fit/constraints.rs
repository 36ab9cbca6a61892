//! Physical constraints on coefficients: nonnegativity, per-coefficient bounds, and
//! fixed values. Resolved against the model's coefficient names into one interval
//! [lower, upper] per coefficient (lower = upper for a fixed one).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Bounds on one named coefficient; `None` leaves that side open.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bound {
    /// Coefficient name.
    pub name: String,
    /// Lower bound.
    pub lower: Option<f64>,
    /// Upper bound.
    pub upper: Option<f64>,
}

/// A coefficient held at a known value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fixed {
    /// Coefficient name.
    pub name: String,
    /// Its value.
    pub value: f64,
}

/// Constraints for a fit. The default (none) gives plain least squares.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Constraints {
    /// Every coefficient ≥ 0 (dissipative laws).
    pub nonnegative: bool,
    /// Per-coefficient bounds.
    pub bounds: Vec<Bound>,
    /// Per-coefficient fixed values.
    pub fixed: Vec<Fixed>,
}

/// The feasible interval of one coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Interval {
    pub lower: f64,
    pub upper: f64,
}

impl Interval {
    pub fn is_fixed(&self) -> bool {
        self.lower == self.upper
    }
}

impl Constraints {
    /// Nonnegative coefficients, nothing else.
    pub fn nonnegative() -> Self {
        Constraints {
            nonnegative: true,
            ..Self::default()
        }
    }

    /// True when nothing is constrained.
    pub fn is_empty(&self) -> bool {
        !self.nonnegative && self.bounds.is_empty() && self.fixed.is_empty()
    }

    /// One interval per coefficient of `names`, checking names and feasibility.
    pub(crate) fn resolve(&self, names: &[String]) -> Result<Vec<Interval>> {
        let lower0 = if self.nonnegative {
            0.0
        } else {
            f64::NEG_INFINITY
        };
        let mut intervals = vec![
            Interval {
                lower: lower0,
                upper: f64::INFINITY
            };
            names.len()
        ];
        let index = |name: &str| {
            names
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| Error::UnknownCoefficient {
                    name: name.to_string(),
                    known: names.join(", "),
                })
        };
        for b in &self.bounds {
            let i = index(&b.name)?;
            for (side, value) in [("lower bound", b.lower), ("upper bound", b.upper)] {
                if let Some(v) = value
                    && v.is_nan()
                {
                    return Err(Error::invalid(
                        &format!("{side} of '{}'", b.name),
                        v,
                        "is NaN",
                    ));
                }
            }
            if b.lower == Some(f64::INFINITY) {
                return Err(Error::invalid(
                    &format!("lower bound of '{}'", b.name),
                    f64::INFINITY,
                    "must be finite (or absent)",
                ));
            }
            if b.upper == Some(f64::NEG_INFINITY) {
                return Err(Error::invalid(
                    &format!("upper bound of '{}'", b.name),
                    f64::NEG_INFINITY,
                    "must be finite (or absent)",
                ));
            }
            if let Some(l) = b.lower {
                intervals[i].lower = intervals[i].lower.max(l);
            }
            if let Some(u) = b.upper {
                intervals[i].upper = intervals[i].upper.min(u);
            }
        }
        for f in &self.fixed {
            let i = index(&f.name)?;
            if !f.value.is_finite() {
                return Err(Error::invalid(
                    &format!("fixed value of '{}'", f.name),
                    f.value,
                    "must be finite",
                ));
            }
            let within = intervals[i].lower <= f.value && f.value <= intervals[i].upper;
            if !within {
                return Err(Error::InfeasibleBounds {
                    name: f.name.clone(),
                    lower: f.value.max(intervals[i].lower),
                    upper: f.value.min(intervals[i].upper),
                });
            }
            intervals[i] = Interval {
                lower: f.value,
                upper: f.value,
            };
        }
        for (name, iv) in names.iter().zip(&intervals) {
            if iv.lower > iv.upper {
                return Err(Error::InfeasibleBounds {
                    name: name.clone(),
                    lower: iv.lower,
                    upper: iv.upper,
                });
            }
        }
        Ok(intervals)
    }
}
