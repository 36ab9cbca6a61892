//! The law registry: the memoryless laws a model file can name in `law = "..."`, each
//! with the names of its numeric parameters, whether it takes an expression text, a
//! one-line description, and a constructor f(parameters) → law.
//!
//! [`LawRegistration::build`] checks the given [`LawParameters`] against what the law
//! declares before calling its constructor, so a constructor reads each declared
//! parameter knowing it is there. The checks and their errors:
//!
//! - a name no registration has: [`Error::UnknownName`] (`what = "law"`) listing every
//!   known name;
//! - a parameter the law does not declare: [`Error::InvalidParameter`] named after it,
//!   with its value;
//! - an expression given to a law that takes none: [`Error::InvalidParameter`] named
//!   `expression`;
//! - a declared parameter missing: [`Error::InvalidParameter`] named after it, value NaN;
//! - no expression for a law that takes one: [`Error::Expression`] with an empty text.
//!
//! The built-in laws register themselves in their own files and are listed once in
//! `laws/mod.rs` ([`super::BUILTIN`]); a program adds its own laws at run time with
//! [`Registry::with`] and hands the registry to
//! [`crate::model_file::parse`] with [`crate::model_file::Options::laws`].

use std::collections::BTreeMap;
use std::sync::Arc;

use super::BUILTIN;
use crate::error::{Error, Result};
use crate::terms::law::Law;

/// The parameters a law is built from: numbers by name (a power law's `exponent`) and,
/// for a law that takes one, an expression text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LawParameters {
    numbers: BTreeMap<String, f64>,
    expression: Option<String>,
}

impl LawParameters {
    /// No parameters and no expression.
    pub fn new() -> Self {
        LawParameters::default()
    }

    /// These parameters with the number `name = value` (replacing an earlier one).
    pub fn with(mut self, name: impl Into<String>, value: f64) -> Self {
        self.numbers.insert(name.into(), value);
        self
    }

    /// These parameters with the expression `text`.
    pub fn with_expression(mut self, text: impl Into<String>) -> Self {
        self.expression = Some(text.into());
        self
    }

    /// The number called `name`; [`Error::InvalidParameter`] when it is not given.
    pub fn number(&self, name: &str) -> Result<f64> {
        self.numbers
            .get(name)
            .copied()
            .ok_or_else(|| Error::missing(name, "not given"))
    }

    /// The expression text; [`Error::Expression`] when none is given.
    pub fn expression(&self) -> Result<&str> {
        self.expression.as_deref().ok_or_else(|| Error::Expression {
            expression: String::new(),
            message: "no expression given".into(),
        })
    }

    /// Every number given, by name in alphabetical order.
    pub fn numbers(&self) -> impl Iterator<Item = (&str, f64)> {
        self.numbers
            .iter()
            .map(|(name, &value)| (name.as_str(), value))
    }
}

/// Builds a law from its checked parameters.
pub type LawConstructor = fn(&LawParameters) -> Result<Arc<dyn Law>>;

/// One law as a model file names it: its name, parameters, expression, description and
/// constructor. Written as a constant next to the law's `impl Law`:
///
/// ```
/// use std::sync::Arc;
/// use dampid::terms::laws::{LawRegistration, PowerLaw};
///
/// const SQUARE_ROOT: LawRegistration =
///     LawRegistration::new("square_root", "f = |v|^½ sign(v)", |_| {
///         Ok(Arc::new(PowerLaw::new(0.5)?))
///     });
/// # assert_eq!(SQUARE_ROOT.name(), "square_root");
/// ```
#[derive(Clone, Copy)]
pub struct LawRegistration {
    name: &'static str,
    parameters: &'static [&'static str],
    expression: bool,
    named_constants: bool,
    description: &'static str,
    constructor: LawConstructor,
}

impl LawRegistration {
    /// The law `name` (as written in model files), described by `description` (one
    /// line, e.g. its force), with no parameters and no expression, built by
    /// `constructor`.
    pub const fn new(
        name: &'static str,
        description: &'static str,
        constructor: LawConstructor,
    ) -> Self {
        LawRegistration {
            name,
            parameters: &[],
            expression: false,
            named_constants: false,
            description,
            constructor,
        }
    }

    /// This law with numeric parameters named `parameters`, all required.
    pub const fn with_parameters(mut self, parameters: &'static [&'static str]) -> Self {
        self.parameters = parameters;
        self
    }

    /// This law taking an expression text (`expression = "..."`), required.
    pub const fn with_expression(mut self) -> Self {
        self.expression = true;
        self
    }

    /// This law taking numeric parameters of any name besides the declared ones: the
    /// named constants of an expression law (`parameters = { vs = 0.01 }`, read as `vs`
    /// in the expression).
    pub const fn with_named_constants(mut self) -> Self {
        self.named_constants = true;
        self
    }

    /// Whether the law takes numeric parameters of any name (named constants).
    pub const fn takes_named_constants(&self) -> bool {
        self.named_constants
    }

    /// The name model files use, `law = "<name>"`.
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// The names of the numeric parameters, all required.
    pub const fn parameters(&self) -> &'static [&'static str] {
        self.parameters
    }

    /// Whether the law takes an expression text.
    pub const fn takes_expression(&self) -> bool {
        self.expression
    }

    /// A one-line description.
    pub const fn description(&self) -> &'static str {
        self.description
    }

    /// The law built from `parameters`, after checking them against the declared ones
    /// (the module documentation lists the errors).
    pub fn build(&self, parameters: &LawParameters) -> Result<Arc<dyn Law>> {
        let name = self.name;
        if let Some((unknown, value)) = parameters
            .numbers()
            .find(|(given, _)| !self.named_constants && !self.parameters.contains(given))
        {
            return Err(Error::invalid(
                unknown,
                value,
                &format!(
                    "the {name} law has no parameter `{unknown}`; its parameters: {}",
                    self.parameter_list()
                ),
            ));
        }
        if parameters.expression.is_some() && !self.expression {
            return Err(Error::choice(
                "expression",
                parameters.expression.as_deref().unwrap_or_default(),
                &format!("the {name} law takes no `expression`"),
            ));
        }
        if let Some(missing) = self
            .parameters
            .iter()
            .find(|declared| !parameters.numbers.contains_key(**declared))
        {
            return Err(Error::missing(
                *missing,
                &format!("the {name} law needs `{missing}` (parameters = {{ {missing} = ... }})"),
            ));
        }
        if self.expression && parameters.expression.is_none() {
            return Err(Error::Expression {
                expression: String::new(),
                message: format!("the {name} law needs `expression = \"...\"`"),
            });
        }
        (self.constructor)(parameters)
    }

    fn parameter_list(&self) -> String {
        if self.parameters.is_empty() {
            "none".into()
        } else {
            self.parameters.join(", ")
        }
    }
}

impl std::fmt::Debug for LawRegistration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LawRegistration")
            .field("name", &self.name)
            .field("parameters", &self.parameters)
            .field("expression", &self.expression)
            .field("named_constants", &self.named_constants)
            .field("description", &self.description)
            .finish_non_exhaustive()
    }
}

/// The laws a model file may name: the built-in ones ([`Registry::builtin`]) and any a
/// program adds ([`Registry::with`]).
#[derive(Debug, Clone)]
pub struct Registry {
    laws: Vec<LawRegistration>,
}

impl Default for Registry {
    /// The built-in laws.
    fn default() -> Self {
        Registry::builtin()
    }
}

impl Registry {
    /// The built-in laws ([`super::BUILTIN`]).
    pub fn builtin() -> Self {
        Registry {
            laws: BUILTIN.to_vec(),
        }
    }

    /// This registry with `registration` added; a registration of the same name is
    /// replaced in place.
    pub fn with(mut self, registration: LawRegistration) -> Self {
        match self.laws.iter_mut().find(|l| l.name == registration.name) {
            Some(existing) => *existing = registration,
            None => self.laws.push(registration),
        }
        self
    }

    /// Every registration, built-in ones first, in the order they were added.
    pub fn registrations(&self) -> &[LawRegistration] {
        &self.laws
    }

    /// Every law's name, in [`Registry::registrations`] order.
    pub fn names(&self) -> Vec<&'static str> {
        self.laws.iter().map(|l| l.name).collect()
    }

    /// The registration called `name`; [`Error::UnknownName`] listing the known names
    /// otherwise.
    pub fn get(&self, name: &str) -> Result<&LawRegistration> {
        find(&self.laws, name)
    }

    /// The law called `name`, built from `parameters` ([`LawRegistration::build`]).
    pub fn build(&self, name: &str, parameters: &LawParameters) -> Result<Arc<dyn Law>> {
        self.get(name)?.build(parameters)
    }
}

/// The built-in law called `name`, built from `parameters`:
/// `Registry::builtin().build(name, parameters)` without copying the registry.
pub fn by_name(name: &str, parameters: &LawParameters) -> Result<Arc<dyn Law>> {
    find(BUILTIN, name)?.build(parameters)
}

fn find<'a>(laws: &'a [LawRegistration], name: &str) -> Result<&'a LawRegistration> {
    laws.iter()
        .find(|l| l.name == name)
        .ok_or_else(|| Error::UnknownName {
            what: "law".into(),
            name: name.to_string(),
            known: laws.iter().map(|l| l.name).collect::<Vec<_>>().join(", "),
        })
}
