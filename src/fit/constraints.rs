//! Physical constraints on coefficients: nonnegativity, per-coefficient bounds, fixed
//! values, and linear relations between coefficients. Bounds and fixed values are
//! resolved against the model's coefficient names into one interval [lower, upper] per
//! coefficient (lower = upper for a fixed one); a linear constraint
//!
//! ```text
//!   Σ_k a_k θ_{name_k}  (= | ≤ | ≥)  value
//! ```
//!
//! into one dense row a over all coefficients (symmetric dashpots equal:
//! θ_{dashpot[0-1]} − θ_{dashpot[4-5]} = 0; one coefficient at most twice another:
//! θ_a − 2 θ_b ≤ 0).

use std::fmt;

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

/// How the two sides of a linear constraint relate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Relation {
    /// Σ a_k θ_k = value.
    #[serde(rename = "=")]
    Equal,
    /// Σ a_k θ_k ≤ value.
    #[serde(rename = "<=")]
    AtMost,
    /// Σ a_k θ_k ≥ value.
    #[serde(rename = ">=")]
    AtLeast,
}

/// One named coefficient of a linear constraint and its multiplier a_k.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearTerm {
    /// Coefficient name.
    pub name: String,
    /// Its multiplier.
    pub coefficient: f64,
}

/// Σ_k a_k θ_{name_k} (= | ≤ | ≥) value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearConstraint {
    /// The terms (each name once).
    pub terms: Vec<LinearTerm>,
    /// The relation.
    pub relation: Relation,
    /// The right-hand side.
    pub value: f64,
}

impl LinearConstraint {
    /// The constraint Σ a_k θ_{name_k} `relation` `value` from (name, a_k) pairs.
    pub fn new(terms: &[(&str, f64)], relation: Relation, value: f64) -> Self {
        LinearConstraint {
            terms: terms
                .iter()
                .map(|(name, coefficient)| LinearTerm {
                    name: (*name).to_string(),
                    coefficient: *coefficient,
                })
                .collect(),
            relation,
            value,
        }
    }

    /// θ_a = θ_b.
    pub fn equal(a: &str, b: &str) -> Self {
        Self::new(&[(a, 1.0), (b, -1.0)], Relation::Equal, 0.0)
    }

    /// θ_a ≤ factor · θ_b.
    pub fn at_most_multiple(a: &str, factor: f64, b: &str) -> Self {
        Self::new(&[(a, 1.0), (b, -factor)], Relation::AtMost, 0.0)
    }
}

impl fmt::Display for LinearConstraint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, t) in self.terms.iter().enumerate() {
            let (sign, magnitude) = if t.coefficient < 0.0 {
                ("−", -t.coefficient)
            } else {
                ("+", t.coefficient)
            };
            let number = if magnitude == 1.0 {
                String::new()
            } else {
                format!("{magnitude} ")
            };
            match (k, sign) {
                (0, "+") => write!(f, "{number}{}", t.name)?,
                (0, _) => write!(f, "−{number}{}", t.name)?,
                _ => write!(f, " {sign} {number}{}", t.name)?,
            }
        }
        let relation = match self.relation {
            Relation::Equal => "=",
            Relation::AtMost => "≤",
            Relation::AtLeast => "≥",
        };
        write!(f, " {relation} {}", self.value)
    }
}

/// Constraints for a fit. The default (none) gives plain least squares.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Constraints {
    /// Every damping coefficient ≥ 0 (dissipative laws); the nuisance unknowns of a
    /// non-periodic regressor (stored energy, constant forces) stay free.
    pub nonnegative: bool,
    /// Per-coefficient bounds.
    pub bounds: Vec<Bound>,
    /// Per-coefficient fixed values.
    pub fixed: Vec<Fixed>,
    /// Linear equalities and inequalities between coefficients.
    #[serde(default)]
    pub linear: Vec<LinearConstraint>,
}

/// A linear constraint resolved against the coefficient names: one dense row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LinearRow {
    /// a, one entry per coefficient.
    pub weights: Vec<f64>,
    pub relation: Relation,
    pub value: f64,
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
        !self.nonnegative
            && self.bounds.is_empty()
            && self.fixed.is_empty()
            && self.linear.is_empty()
    }

    /// One dense row per linear constraint over the coefficients `names`, checking
    /// names (known, each once per constraint) and values (finite, not all zero).
    pub(crate) fn resolve_linear(&self, names: &[String]) -> Result<Vec<LinearRow>> {
        self.linear
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let label = format!("linear constraint {} ({c})", k + 1);
                if c.terms.is_empty() {
                    return Err(Error::Empty {
                        what: format!("the terms of {label}"),
                    });
                }
                if !c.value.is_finite() {
                    return Err(Error::invalid(
                        &format!("right-hand side of {label}"),
                        c.value,
                        "must be finite",
                    ));
                }
                let mut weights = vec![0.0; names.len()];
                let mut seen = vec![false; names.len()];
                for t in &c.terms {
                    let j = names.iter().position(|n| *n == t.name).ok_or_else(|| {
                        Error::UnknownCoefficient {
                            name: t.name.clone(),
                            known: names.join(", "),
                        }
                    })?;
                    if seen[j] {
                        return Err(Error::DuplicateCoefficient {
                            name: t.name.clone(),
                        });
                    }
                    if !t.coefficient.is_finite() {
                        return Err(Error::invalid(
                            &format!("multiplier of '{}' in {label}", t.name),
                            t.coefficient,
                            "must be finite",
                        ));
                    }
                    seen[j] = true;
                    weights[j] = t.coefficient;
                }
                if weights.iter().all(|w| *w == 0.0) {
                    return Err(Error::invalid(
                        &format!("multipliers of {label}"),
                        0.0,
                        "at least one must be nonzero",
                    ));
                }
                Ok(LinearRow {
                    weights,
                    relation: c.relation,
                    value: c.value,
                })
            })
            .collect()
    }

    /// One interval per coefficient of `names`, checking names and feasibility.
    /// `nonnegative` applies to the first `damping` coefficients only: the rest are
    /// nuisance unknowns (stored energy, constant forces) of either sign.
    pub(crate) fn resolve(&self, names: &[String], damping: usize) -> Result<Vec<Interval>> {
        let mut intervals: Vec<Interval> = (0..names.len())
            .map(|k| Interval {
                lower: if self.nonnegative && k < damping {
                    0.0
                } else {
                    f64::NEG_INFINITY
                },
                upper: f64::INFINITY,
            })
            .collect();
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
            let explicit_lower = self
                .bounds
                .iter()
                .filter(|b| b.name == f.name)
                .filter_map(|b| b.lower)
                .fold(f64::NEG_INFINITY, f64::max);
            if !within && self.nonnegative && i < damping && f.value < 0.0 && explicit_lower < 0.0 {
                return Err(Error::invalid(
                    &format!("fixed value of '{}'", f.name),
                    f.value,
                    "is negative, but nonnegative = true keeps every damping coefficient ≥ 0: remove `nonnegative` (and bound the others one by one in [identification.bounds]) or fix it at a value ≥ 0",
                ));
            }
            if !within {
                let side = |v: f64| {
                    if v.is_infinite() {
                        "∞".to_string()
                    } else {
                        crate::format::number(v)
                    }
                };
                return Err(Error::invalid(
                    &format!("fixed value of '{}'", f.name),
                    f.value,
                    &format!(
                        "lies outside its bounds [{}{}, {}] (from [identification.bounds]{}); a fixed coefficient must satisfy them",
                        if intervals[i].lower.is_infinite() {
                            "−"
                        } else {
                            ""
                        },
                        side(intervals[i].lower),
                        side(intervals[i].upper),
                        if self.nonnegative && i < damping {
                            " and nonnegative = true"
                        } else {
                            ""
                        }
                    ),
                ));
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
