//! A comparison in words: the verdict of the F-test (or why there is none), what AIC,
//! BIC and leave-one-out cross-validation prefer, what k means for models with
//! estimated parameters, and a caution when the preferred model wins with negative
//! damping; and the comparison as the text `dampid compare` prints.

use std::fmt;

use super::{Comparison, ModelFit, Verdict, Which};

/// What k and the leave-one-out refits mean for models with estimated parameters.
pub(super) fn estimated_note<'a>(models: impl IntoIterator<Item = &'a ModelFit>) -> Option<String> {
    let with: Vec<&str> = models
        .into_iter()
        .filter(|m| !m.estimated.is_empty() || !m.nuisance.is_empty())
        .map(|m| m.label.as_str())
        .collect();
    (!with.is_empty()).then(|| {
        format!(
            "; k counts the estimated parameters of {}, and their leave-one-out refits hold them at their estimates (which favours them slightly)",
            with.join(", ")
        )
    })
}

/// `name = value` of each estimated parameter, then the count of nuisance ones.
pub(super) fn estimated_values(m: &ModelFit) -> Vec<String> {
    m.estimated
        .iter()
        .map(|(n, v)| format!("{n} = {v:.4e} (estimated)"))
        .chain((!m.nuisance.is_empty()).then(|| {
            format!(
                "+ {} residual receptances (estimated; --json lists them)",
                m.nuisance.len()
            )
        }))
        .collect()
}

pub(super) fn other(which: Which) -> Which {
    match which {
        Which::First => Which::Second,
        Which::Second => Which::First,
    }
}

pub(super) fn conclusion(c: &Comparison, small: Which, large: Which) -> String {
    let (s, l) = (c.model(small), c.model(large));
    let extra: Vec<&str> = l
        .coefficients
        .iter()
        .filter(|n| !s.coefficients.contains(n))
        .map(String::as_str)
        .collect();
    let extra = if !extra.is_empty() && s.coefficients.iter().all(|n| l.coefficients.contains(n)) {
        format!(
            "its extra terms ({})",
            crate::analysis::identifiability::list(&extra)
        )
    } else {
        "its extra freedom".to_string()
    };
    let mut text = match (c.verdict, &c.f_test) {
        (Verdict::LargerNeeded, Some(t)) => format!(
            "{} is needed: {extra} reduce the residual sum of squares from {:.4e} to {:.4e} (F = {:.4e} with ({}, {}) degrees of freedom, p = {:.3e} < {})",
            l.label,
            s.residual_sum_of_squares,
            l.residual_sum_of_squares,
            t.statistic,
            t.numerator_degrees,
            t.denominator_degrees,
            t.p_value,
            c.level
        ),
        (Verdict::SmallerSuffices, Some(t)) => format!(
            "{} suffices: the extra terms of {} do not reduce the residual beyond the noise (F = {:.4e} with ({}, {}) degrees of freedom, p = {:.3} ≥ {})",
            s.label,
            l.label,
            t.statistic,
            t.numerator_degrees,
            t.denominator_degrees,
            t.p_value,
            c.level
        ),
        (Verdict::Equivalent, _) => format!(
            "{} adds nothing these data can see: both models span the same equations",
            l.label
        ),
        (Verdict::NoRedundancy, _) => format!(
            "the models are nested, but {} fits the {} equations exactly: no equations are left to test it; add windows or records",
            l.label, c.equations
        ),
        _ => "the models are not nested, so no F-test; compare them by AIC and BIC".to_string(),
    };
    let name = |w: Which| c.model(w).label.clone();
    match (c.aic_prefers == c.bic_prefers, c.verdict) {
        (true, Verdict::LargerNeeded) if c.aic_prefers != large => text.push_str(&format!(
            "; but AIC and BIC prefer {}: the improvement is small for its cost",
            name(c.aic_prefers)
        )),
        (true, Verdict::SmallerSuffices) if c.aic_prefers != small => {
            text.push_str(&format!("; but AIC and BIC prefer {}", name(c.aic_prefers)))
        }
        (true, _) => text.push_str(&format!("; AIC and BIC prefer {}", name(c.aic_prefers))),
        (false, _) => text.push_str(&format!(
            "; AIC prefers {}, BIC prefers {}",
            name(c.aic_prefers),
            name(c.bic_prefers)
        )),
    }
    if let Some(w) = c.cross_validation_prefers {
        text.push_str(&format!(
            "; leave-one-out cross-validation prefers {}",
            name(w)
        ));
    }
    if let Some(note) = estimated_note([&c.first, &c.second]) {
        text.push_str(&note);
    }
    // A model that wins with a negative coefficient wins unphysically: say so.
    let winner = match c.verdict {
        Verdict::LargerNeeded => large,
        Verdict::SmallerSuffices => small,
        _ => c.aic_prefers,
    };
    let negative = |w: Which| -> Vec<String> {
        let m = c.model(w);
        m.coefficients
            .iter()
            .zip(&m.values)
            .filter(|(_, v)| **v < 0.0)
            .map(|(n, v)| format!("{n} = {v:.4e}"))
            .collect()
    };
    let (win, lose) = (negative(winner), negative(other(winner)));
    if !win.is_empty() {
        text.push_str(&format!(
            "; caution: {} is preferred with negative damping ({}){}, which feeds energy in: it is not a physical preference; compare fits with nonnegative = true",
            name(winner),
            win.join(", "),
            if lose.is_empty() {
                format!(", while {} is physical", name(other(winner)))
            } else {
                String::new()
            }
        ));
    }
    text
}

impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} equations", self.equations)?;
        let width = self
            .first
            .label
            .chars()
            .count()
            .max(self.second.label.chars().count())
            .max(5);
        writeln!(
            f,
            "{:<width$} {:>6} {:>13} {:>11} {:>13} {:>13} {:>13}",
            "model", "k", "RSS", "rel. resid.", "AIC", "BIC", "LOO PRESS"
        )?;
        for m in [&self.first, &self.second] {
            let press = m
                .cross_validation
                .map_or("-".to_string(), |p| format!("{p:.4e}"));
            writeln!(
                f,
                "{:<width$} {:>6} {:>13.4e} {:>11.3e} {:>13.4e} {:>13.4e} {:>13}",
                m.label,
                m.parameters,
                m.residual_sum_of_squares,
                m.relative_residual,
                m.aic,
                m.bic,
                press
            )?;
        }
        for m in [&self.first, &self.second] {
            if !m.estimated.is_empty() || !m.nuisance.is_empty() {
                writeln!(
                    f,
                    "{}: at its least-squares {}",
                    m.label,
                    estimated_values(m).join(", ")
                )?;
            }
        }
        match self.nested_in {
            Some(w) => writeln!(
                f,
                "{} is nested in {}",
                self.model(w).label,
                self.model(other(w)).label
            )?,
            None => writeln!(f, "the models are not nested")?,
        }
        writeln!(f, "{}", self.text)
    }
}
