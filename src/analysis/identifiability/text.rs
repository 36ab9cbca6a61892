//! The identifiability analysis in words ([`super::Identifiability`]'s `Display`): a
//! combination written as `c0 + 0.198 c1 − d`, a trade-off as the proportion that
//! leaves the fit unchanged, and for many coefficients the digest of the largest VIFs,
//! the undetermined coefficients by term and the smallest null directions
//! ([`crate::analysis::digest`]).

use std::fmt;

use super::{Combination, CombinationTerm, DeterminedCombination, FULL_TEXT, Identifiability};
use crate::analysis::digest::{self, CONTRIBUTORS, FULL_LISTING, LISTED};

/// `c0 + 0.198 c1 − d`: the terms with their signed weights, 1 left out.
pub(super) fn written(terms: &[CombinationTerm]) -> String {
    let mut text = String::new();
    for (k, t) in terms.iter().enumerate() {
        let sign = if t.weight < 0.0 { "−" } else { "+" };
        let magnitude = t.weight.abs();
        let number = if (magnitude - 1.0).abs() < 5e-4 {
            String::new()
        } else {
            format!("{} ", significant(magnitude))
        };
        match (k, t.weight < 0.0) {
            (0, false) => text.push_str(&format!("{number}{}", t.name)),
            (0, true) => text.push_str(&format!("−{number}{}", t.name)),
            _ => text.push_str(&format!(" {sign} {number}{}", t.name)),
        }
    }
    text
}

/// Three significant digits for numbers below 1, three decimals otherwise.
fn significant(x: f64) -> String {
    let decimals = if x > 0.0 && x < 1.0 {
        (2.0 - x.log10().floor()).max(3.0) as usize
    } else {
        3
    };
    format!("{x:.decimals$}")
}

pub(super) fn trade_off_text(direction: &Combination) -> String {
    let names: Vec<&str> = direction.terms.iter().map(|t| t.name.as_str()).collect();
    if names.len() > FULL_TEXT {
        return format!(
            "{} coefficients trade off against each other: changing them along {} leaves the fit unchanged",
            names.len(),
            direction.text
        );
    }
    let ratio = direction
        .terms
        .iter()
        .map(|t| {
            let magnitude = if (t.weight.abs() - 1.0).abs() < 5e-4 {
                "1".to_string()
            } else {
                significant(t.weight.abs())
            };
            if t.weight < 0.0 {
                format!("−{magnitude}")
            } else {
                magnitude
            }
        })
        .collect::<Vec<_>>()
        .join(" : ");
    match names.as_slice() {
        [] => "a direction with no significant component".into(),
        [one] => format!("{one} is not determined: changing it leaves the fit unchanged"),
        _ => format!(
            "{} trade off against each other: changing them in the proportion {} = {ratio} leaves the fit unchanged",
            list(&names),
            names.join(" : ")
        ),
    }
}

/// "a", "a and b", "a, b and c".
pub(crate) fn list(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

impl fmt::Display for Identifiability {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.noise_level {
            Some(s) => writeln!(
                f,
                "noise level of the scaled equations: s = {s:.3e}; singular values below {:.3e} are practically zero",
                self.threshold
            )?,
            None => writeln!(
                f,
                "no redundancy, so no noise level; singular values below {:.3e} are practically zero",
                self.threshold
            )?,
        }
        if let Some(w) = self.window_scatter {
            writeln!(
                f,
                "the windows of one record are replicates: their scaled rows scatter by s_w = {w:.3e}, more than the residual shows, and set the threshold"
            )?;
        }
        if let Some(n) = self.experiments {
            writeln!(
                f,
                "the windows of one record repeat one experiment: {n} experiment(s) determine at most {n} combination(s), whatever the singular values above the threshold"
            )?;
        }
        writeln!(
            f,
            "practical rank: {} of {}",
            self.practical_rank,
            self.names.len()
        )?;
        if self.names.len() > FULL_LISTING {
            return self.digest(f);
        }
        let vif: Vec<String> = self
            .names
            .iter()
            .zip(&self.variance_inflation)
            .map(|(n, v)| match v {
                Some(v) => format!("{n} {v:.3e}"),
                None => format!("{n} infinite"),
            })
            .collect();
        writeln!(f, "variance inflation factors: {}", vif.join(", "))?;
        if self.separable() {
            return writeln!(f, "every coefficient is determined by these data");
        }
        let names: Vec<&str> = self.unidentifiable.iter().map(String::as_str).collect();
        writeln!(
            f,
            "these data cannot separate {} (practically unidentifiable):",
            list(&names)
        )?;
        for d in &self.null_directions {
            writeln!(f, "  {} (σ = {:.3e})", d.text, d.singular_value)?;
        }
        if !self.determined.is_empty() {
            writeln!(f, "only these combinations are determined by these data:")?;
            for d in &self.determined {
                write_determined(f, d)?;
            }
        }
        Ok(())
    }
}

impl Identifiability {
    /// The text form for more than [`FULL_LISTING`] coefficients, after the noise level
    /// and the practical rank: VIFs as a top list and a histogram, the undetermined
    /// coefficients counted by term, the [`LISTED`] smallest null directions and the
    /// [`LISTED`] best-determined combinations, each by its largest contributors.
    fn digest(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.names.len();
        let finite: Vec<f64> = self.variance_inflation.iter().flatten().copied().collect();
        if finite.is_empty() {
            writeln!(
                f,
                "variance inflation factors: infinite for all {p} (the regressor is rank deficient)"
            )?;
        } else {
            let top: Vec<String> = digest::largest(&finite, LISTED)
                .into_iter()
                .map(|k| {
                    let j = (0..p)
                        .filter(|&j| self.variance_inflation[j].is_some())
                        .nth(k)
                        .unwrap_or(0);
                    format!("{} {:.3e}", self.names[j], finite[k])
                })
                .collect();
            writeln!(
                f,
                "variance inflation factors, largest {} of {p}: {}",
                top.len(),
                top.join(", ")
            )?;
            writeln!(
                f,
                "  by decade: {}",
                digest::decade_histogram_text(&self.variance_inflation)
            )?;
        }
        if self.separable() {
            return writeln!(f, "every coefficient is determined by these data");
        }
        let names: Vec<&str> = self.unidentifiable.iter().map(String::as_str).collect();
        writeln!(
            f,
            "these data cannot separate {} of {p} coefficients (practically unidentifiable; by term: {}; names in the JSON)",
            names.len(),
            digest::by_term_text(names.iter().copied())
        )?;
        let nulls = self.null_directions.len();
        if nulls > 0 {
            writeln!(
                f,
                "{nulls} direction(s) not determined (σ below {:.3e}); {}each by its {CONTRIBUTORS} largest components:",
                self.threshold,
                if nulls > LISTED {
                    format!("the {LISTED} smallest, ")
                } else {
                    String::new()
                }
            )?;
            for d in self.null_directions.iter().take(LISTED) {
                writeln!(f, "  σ = {:.3e}: {}", d.singular_value, d.direction.text)?;
            }
            if nulls > LISTED {
                writeln!(
                    f,
                    "  + {} more (identifiability.null_directions in the JSON)",
                    nulls - LISTED
                )?;
            }
        }
        let determined = self.determined.len();
        if determined > 0 {
            writeln!(
                f,
                "{determined} combination(s) determined by these data; {}each by its {CONTRIBUTORS} largest weights:",
                if determined > LISTED {
                    format!("the {LISTED} best determined, ")
                } else {
                    String::new()
                }
            )?;
            for d in self.determined.iter().take(LISTED) {
                write_determined(f, d)?;
            }
            if determined > LISTED {
                writeln!(
                    f,
                    "  + {} more (identifiability.determined in the JSON)",
                    determined - LISTED
                )?;
            }
        }
        Ok(())
    }
}

/// One determined combination's line: its value, ± its standard error when known, and
/// its singular value.
fn write_determined(f: &mut fmt::Formatter<'_>, d: &DeterminedCombination) -> fmt::Result {
    match d.std_error {
        Some(se) => writeln!(
            f,
            "  {} = {:.6e} ± {se:.2e} (σ = {:.3e})",
            d.combination.text, d.value, d.singular_value
        ),
        None => writeln!(
            f,
            "  {} = {:.6e} (σ = {:.3e})",
            d.combination.text, d.value, d.singular_value
        ),
    }
}
