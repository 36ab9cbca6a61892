//! A damping law written as an expression of the element's relative displacement `x`
//! and relative velocity `v`, e.g. `sign(v)*abs(v)^1.5` or `x^2*v`; power v · f(x, v).
//!
//! Parsed once by exmex into a flat expression and evaluated per sample. The operators
//! are exmex's float defaults (`+ - * / ^`, `abs`, `sqrt`, `exp`, `ln`, `sin`, `cos`,
//! `tanh`, …, constants `PI`, `E`) plus `sign(v)`, which is 0 at 0 (exmex's `signum`
//! is 1 there). Numbers are every decimal literal Rust's f64 parser reads (`2.5e-1`,
//! `1E3`, `.5`, `5.`, `1e+3`; one beyond f64 is refused); a call of a function that is
//! not one of these is refused naming it and listing the known ones. Identifiers other than `x`, `v` and the law's named constants
//! (`parameters = { vs = 0.01 }` in model files, fixed or estimated by variable
//! projection) are rejected when parsing, so a typo cannot become a silent free
//! variable; a named constant the expression does not use is rejected too.
//!
//! Length is capped at [`MAX_EXPRESSION_BYTES`]. exmex evaluates a flat expression by
//! applying its operators in priority order and finding each operand's nearest
//! unconsumed neighbour in a bit set; after k additions the accumulated sum sits k
//! operands back, so a sum of n terms costs O(n²/64) word scans per sample (measured:
//! `examples/expression_length.rs`). A real damping law is a few dozen characters; the
//! cap keeps every evaluation at microseconds and refuses a generated megabyte up front
//! instead of running for minutes.

use std::sync::Arc;

use exmex::prelude::*;
use exmex::{FloatOpsFactory, MakeOperators, MatchLiteral, Operator};

use super::LawRegistration;
use crate::error::{Error, Result};
use crate::terms::law::{Law, sign};

/// exmex's float operators plus `sign` with sign(0) = 0.
#[derive(Clone, Debug)]
struct LawOperators;

impl MakeOperators<f64> for LawOperators {
    fn make<'a>() -> Vec<Operator<'a, f64>> {
        let mut operators = FloatOpsFactory::<f64>::make();
        operators.push(Operator::make_unary("sign", sign));
        operators
    }
}

// Numeric literals: every decimal form Rust's f64 parser reads (`2.5e-1`, `1E3`, `.5`,
// `5.`, `1e+3`), where exmex's own matcher takes digits and one dot only (`2.5e-1*v`
// was "2 ops and 4 nodes"). `inf` and `NaN` are identifiers here, not numbers.
exmex::literal_matcher_from_pattern!(
    FloatLiteral,
    r"^(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
);

type Parsed = FlatEx<f64, LawOperators, FloatLiteral>;

/// The functions an expression may call (exmex's unary operators and `sign`).
fn known_functions() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = LawOperators::make()
        .iter()
        .filter(|op| op.has_unary() && op.repr().chars().all(|c| c.is_ascii_alphanumeric()))
        .map(|op| op.repr())
        .collect();
    names.sort_unstable();
    names.dedup();
    names
}

/// The first name in `text` written as a call, `name(`, that is not a known function.
fn unknown_function(text: &str) -> Option<String> {
    let known = known_functions();
    let bytes = text.as_bytes();
    let mut k = 0;
    while k < bytes.len() {
        let starts = (bytes[k].is_ascii_alphabetic() || bytes[k] == b'_')
            && (k == 0 || !(bytes[k - 1].is_ascii_alphanumeric() || bytes[k - 1] == b'_' || bytes[k - 1] == b'.'));
        if !starts {
            k += 1;
            continue;
        }
        let end = (k..bytes.len())
            .find(|&j| !(bytes[j].is_ascii_alphanumeric() || bytes[j] == b'_'))
            .unwrap_or(bytes.len());
        let name = &text[k..end];
        let called = text[end..].trim_start().starts_with('(');
        if called && !known.contains(&name) {
            return Some(name.to_string());
        }
        k = end;
    }
    None
}

/// A numeric literal of `text` that does not fit an f64 (`1e999`), if any.
fn overflowing_literal(text: &str) -> Option<String> {
    let literal = exmex::regex::Regex::new(r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
        .ok()?;
    literal.find_iter(text).find_map(|m| {
        let before = text[..m.start()].chars().next_back();
        let inside_name = before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        let value: f64 = m.as_str().parse().ok()?;
        (!inside_name && !value.is_finite()).then(|| m.as_str().to_string())
    })
}

/// Which of (v, x) the expression reads, in exmex's alphabetical variable order.
#[derive(Debug, Clone)]
enum Variables {
    None,
    V,
    X,
    VX,
    /// With named constants: each slot in exmex's order.
    Slots(Box<[Option<Slot>; MAX_CONSTANTS + 2]>),
}

/// `law = "expression"` with `expression = "..."` in model files, and named constants
/// in `parameters`.
pub(super) const REGISTRATION: LawRegistration = LawRegistration::new(
    "expression",
    "f(x, v) written in `expression`, a text of x, v and named constants",
    |parameters| {
        let constants: Vec<(&str, f64)> = parameters.numbers().collect();
        Ok(Arc::new(Expression::with_constants(
            parameters.expression()?,
            &constants,
        )?))
    },
)
.with_expression()
.with_named_constants();

/// Most named constants an expression takes.
const MAX_CONSTANTS: usize = 14;

/// What fills each of exmex's variable slots (alphabetical order).
#[derive(Debug, Clone, Copy)]
enum Slot {
    X,
    V,
    Constant(f64),
}

/// The longest expression accepted, in bytes (about 700 terms such as `0.5*v*abs(v)+`):
/// beyond it, evaluation cost grows with the square of the length (module docs).
pub const MAX_EXPRESSION_BYTES: usize = 10_000;

/// The first characters of a long expression, for messages.
fn excerpt(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((end, _)) => format!("{}… ({} bytes)", &text[..end], text.len()),
        None => text.to_string(),
    }
}

/// A damping law f(x, v) given as text.
#[derive(Debug, Clone)]
pub struct Expression {
    text: String,
    parsed: Parsed,
    variables: Variables,
}

impl Expression {
    /// Parses `text`; only the variables `x` and `v` are allowed.
    pub fn parse(text: &str) -> Result<Self> {
        Self::with_constants(text, &[])
    }

    /// Parses `text` with the named constants `constants` (each used in `text`, none
    /// called `x` or `v`, at most 14).
    pub fn with_constants(text: &str, constants: &[(&str, f64)]) -> Result<Self> {
        if text.len() > MAX_EXPRESSION_BYTES {
            return Err(Error::Expression {
                expression: excerpt(text),
                message: format!(
                    "the expression is {} bytes long, beyond the limit of {MAX_EXPRESSION_BYTES} bytes (evaluation time grows with the square of the length): write the law in fewer terms, or as a custom law in Rust (terms::laws::Custom)",
                    text.len()
                ),
            });
        }
        let error = |message: String| Error::Expression {
            expression: text.to_string(),
            message,
        };
        if constants.len() > MAX_CONSTANTS {
            return Err(error(format!(
                "{} named constants: an expression takes at most {MAX_CONSTANTS}",
                constants.len()
            )));
        }
        if let Some((name, _)) = constants.iter().find(|(n, _)| matches!(*n, "x" | "v")) {
            return Err(error(format!(
                "a named constant may not be called '{name}': x and v are the element's motion"
            )));
        }
        if let Some(name) = unknown_function(text) {
            return Err(error(format!(
                "unknown function '{name}': the functions are {}",
                known_functions().join(", ")
            )));
        }
        if let Some(literal) = overflowing_literal(text) {
            return Err(error(format!(
                "the number {literal} is beyond the largest floating-point number (about 1.8e308)"
            )));
        }
        let parsed = Parsed::parse(text).map_err(|e| {
            error(format!(
                "not a valid expression ({e}); write it with x, v, numbers (2.5e-1), the operators + - * / ^, parentheses and the functions {}",
                known_functions().join(", ")
            ))
        })?;
        let names: Vec<&str> = parsed.var_names().iter().map(String::as_str).collect();
        if let Some(unknown) = names
            .iter()
            .find(|n| !matches!(**n, "x" | "v") && !constants.iter().any(|(c, _)| c == *n))
        {
            return Err(error(format!(
                "unknown identifier '{unknown}': a law may use only x (relative displacement), v (relative velocity) and its named constants"
            )));
        }
        if let Some((unused, _)) = constants.iter().find(|(c, _)| !names.contains(c)) {
            return Err(error(format!(
                "the named constant '{unused}' is not used in the expression"
            )));
        }
        let variables = if constants.is_empty() {
            match names.as_slice() {
                [] => Variables::None,
                ["v"] => Variables::V,
                ["x"] => Variables::X,
                _ => Variables::VX,
            }
        } else {
            let mut slots = [None; MAX_CONSTANTS + 2];
            for (slot, name) in slots.iter_mut().zip(&names) {
                *slot = Some(match *name {
                    "x" => Slot::X,
                    "v" => Slot::V,
                    c => Slot::Constant(
                        constants
                            .iter()
                            .find(|(n, _)| *n == c)
                            .map_or(f64::NAN, |(_, value)| *value),
                    ),
                });
            }
            Variables::Slots(Box::new(slots))
        };
        let law = Expression {
            text: text.to_string(),
            parsed,
            variables,
        };
        // Evaluate once so that an expression that cannot be evaluated fails here.
        law.try_force(0.5, 0.5)?;
        Ok(law)
    }

    fn try_force(&self, x: f64, v: f64) -> Result<f64> {
        let result = match &self.variables {
            Variables::None => self.parsed.eval(&[]),
            Variables::V => self.parsed.eval(&[v]),
            Variables::X => self.parsed.eval(&[x]),
            Variables::VX => self.parsed.eval(&[v, x]),
            Variables::Slots(slots) => {
                let mut values = [0.0; MAX_CONSTANTS + 2];
                let mut count = 0;
                for (value, slot) in values.iter_mut().zip(slots.iter().map_while(|s| *s)) {
                    *value = match slot {
                        Slot::X => x,
                        Slot::V => v,
                        Slot::Constant(c) => c,
                    };
                    count += 1;
                }
                self.parsed.eval(&values[..count])
            }
        };
        result.map_err(|e| Error::Expression {
            expression: self.text.clone(),
            message: e.to_string(),
        })
    }
}

impl Law for Expression {
    fn name(&self) -> String {
        self.text.clone()
    }
    fn force(&self, x: f64, v: f64) -> f64 {
        // Parsing proved that evaluation succeeds; a failure would be exmex's bug, and
        // NaN is then caught by the regressor's finiteness check.
        self.try_force(x, v).unwrap_or(f64::NAN)
    }
    fn uses_displacement(&self) -> bool {
        match &self.variables {
            Variables::X | Variables::VX => true,
            Variables::Slots(slots) => slots.iter().any(|s| matches!(s, Some(Slot::X))),
            Variables::None | Variables::V => false,
        }
    }
    fn weighted_power(&self, x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        if self.uses_displacement() {
            w.iter()
                .zip(x.iter().zip(v))
                .map(|(w, (&x, &v))| w * v * self.force(x, v))
                .sum()
        } else {
            w.iter()
                .zip(v)
                .map(|(w, &v)| w * v * self.force(0.0, v))
                .sum()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluates_laws_of_x_and_v() {
        let law = Expression::parse("sign(v)*abs(v)^1.5").unwrap();
        assert!((law.force(0.0, -4.0) + 8.0).abs() < 1e-12);
        assert_eq!(law.force(0.0, 0.0), 0.0);
        assert!(!law.uses_displacement());
        let law = Expression::parse("x^2*v").unwrap();
        assert!((law.force(3.0, 2.0) - 18.0).abs() < 1e-12);
        assert!(law.uses_displacement());
    }

    #[test]
    fn rejects_unknown_identifiers_and_bad_syntax() {
        match Expression::parse("abs(v)*q") {
            Err(Error::Expression {
                expression,
                message,
            }) => {
                assert_eq!(expression, "abs(v)*q");
                assert!(message.contains("'q'"), "{message}");
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            Expression::parse("v*(x"),
            Err(Error::Expression { .. })
        ));
    }

    /// Every decimal literal Rust's f64 parser reads is a number of the expression,
    /// with the value that parser gives (issue 29, item 10: `2.5e-1*v` was "we have 2
    /// ops and 4 node").
    #[test]
    fn float_literals_read_as_rust_reads_them() {
        for literal in [
            "2.5e-1", "1E3", ".5", "5.", "1e+3", "0", "007", "1.5E-300", "6.02e23", "3.",
            "0.000001", "1e0",
        ] {
            let law = Expression::parse(&format!("{literal}*v")).unwrap();
            let value: f64 = literal.parse().unwrap();
            assert_eq!(law.force(0.0, 1.0), value, "{literal}");
            let law = Expression::parse(&format!("v-{literal}")).unwrap();
            assert_eq!(law.force(0.0, 1.0), 1.0 - value, "{literal}");
        }
        assert!((Expression::parse("2*E").unwrap().force(0.0, 0.0) - 2.0 * std::f64::consts::E).abs() < 1e-15);
        let overflow = Expression::parse("1e999*v").unwrap_err().to_string();
        assert!(overflow.contains("1e999"), "{overflow}");
    }

    /// A call of an unknown function names it and lists the known ones, instead of
    /// exmex's "a number/variable cannot be on the right of a closing parenthesis".
    #[test]
    fn unknown_functions_are_named() {
        for (text, name) in [("foo(v)", "foo"), ("2*sgn (v)", "sgn"), ("abs(v)*Sqrt(x)", "Sqrt")] {
            let message = Expression::parse(text).unwrap_err().to_string();
            assert!(message.contains(&format!("unknown function '{name}'")), "{message}");
            assert!(message.contains("abs") && message.contains("sign"), "{message}");
        }
        // Known functions and a constant beside parentheses still parse.
        Expression::parse("sqrt(abs(v))*sign(v)+PI*(x)").unwrap();
    }

    /// At the cap an expression parses; one byte more is refused, naming the limit,
    /// with a short excerpt instead of the whole text.
    #[test]
    fn length_is_capped() {
        // "v+" repeated, ending in "v": 2k + 1 bytes.
        let at_cap = format!("{}v", "v+".repeat((MAX_EXPRESSION_BYTES - 1) / 2));
        assert!(at_cap.len() <= MAX_EXPRESSION_BYTES);
        let law = Expression::parse(&at_cap).unwrap();
        // n = 5000 terms of v: f = 5000 v.
        let n = at_cap.len().div_ceil(2) as f64;
        assert!((law.force(0.0, 0.5) - 0.5 * n).abs() < 1e-9 * n);
        let over = format!("{}v", "v+".repeat(MAX_EXPRESSION_BYTES / 2));
        assert!(over.len() > MAX_EXPRESSION_BYTES);
        match Expression::parse(&over) {
            Err(Error::Expression {
                expression,
                message,
            }) => {
                assert!(message.contains("10000 bytes"), "{message}");
                assert!(expression.len() < 100, "{expression}");
            }
            other => panic!("{other:?}"),
        }
    }
}
