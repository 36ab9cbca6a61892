//! Nonlinear parameters and the things built from them: each parameter η has a name,
//! an initial value and bounds ([`NonlinearParameter`]), and a [`Parametric<T>`] is a
//! builder η → T with its parameters, such as a damping model whose law has estimated
//! parameters ([`ParametricModel`]: a power law's exponent, a constant inside an
//! expression law, a hysteresis shape). With no parameters ([`Parametric::fixed`]) it
//! is one fixed value: a model with nothing estimated is the same type.

use std::fmt;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::model::DampingModel;

/// One nonlinear parameter to estimate: its name, initial value and bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct NonlinearParameter {
    /// Name (e.g. `exponent`, `vs`; reports prefix it with the term's coefficient name
    /// where the model file builds it).
    pub name: String,
    /// Initial value, within [lower, upper] (the start of Levenberg–Marquardt, with the
    /// multistart corners; bounded Brent, used for a single parameter, searches the
    /// whole interval).
    pub initial: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// A nuisance parameter (a stepped-sine table's residual receptance): estimated with
    /// the others and reported with its joint Wald interval, but given no profile
    /// interval of its own. The profiles of the other parameters still minimise over it.
    pub nuisance: bool,
}

impl NonlinearParameter {
    /// A parameter `name` starting at `initial` within [`lower`, `upper`].
    pub fn new(name: impl Into<String>, initial: f64, lower: f64, upper: f64) -> Self {
        NonlinearParameter {
            name: name.into(),
            initial,
            lower,
            upper,
            nuisance: false,
        }
    }

    /// The same parameter as a nuisance one ([`NonlinearParameter::nuisance`]).
    pub fn as_nuisance(self) -> Self {
        NonlinearParameter {
            nuisance: true,
            ..self
        }
    }

    /// Finite bounds with lower < upper and the initial value within them.
    pub fn validate(&self) -> Result<()> {
        let name = |what: &str| format!("{what} of estimated parameter '{}'", self.name);
        for (what, value) in [
            ("lower bound", self.lower),
            ("upper bound", self.upper),
            ("initial value", self.initial),
        ] {
            if !value.is_finite() {
                return Err(Error::invalid(
                    &name(what),
                    value,
                    "an estimated parameter needs finite `initial`, `lower` and `upper`",
                ));
            }
        }
        if self.lower >= self.upper {
            return Err(Error::invalid(
                &name("lower bound"),
                self.lower,
                &format!("must be below the upper bound {}", self.upper),
            ));
        }
        if !(self.lower..=self.upper).contains(&self.initial) {
            return Err(Error::invalid(
                &name("initial value"),
                self.initial,
                &format!("must lie within [{}, {}]", self.lower, self.upper),
            ));
        }
        Ok(())
    }
}

/// Builds a `T` for given nonlinear parameter values (in the order of the parameters).
pub type Builder<T> = Arc<dyn Fn(&[f64]) -> Result<T> + Send + Sync>;

/// A `T` that depends on nonlinear parameters: their specs and a builder η → T. With no
/// parameters ([`Parametric::fixed`]) it is one fixed value.
pub struct Parametric<T> {
    parameters: Vec<NonlinearParameter>,
    builder: Builder<T>,
}

/// A damping model with (possibly no) estimated law parameters.
pub type ParametricModel = Parametric<DampingModel>;

impl<T> Clone for Parametric<T> {
    fn clone(&self) -> Self {
        Parametric {
            parameters: self.parameters.clone(),
            builder: Arc::clone(&self.builder),
        }
    }
}

impl<T> fmt::Debug for Parametric<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Parametric")
            .field("parameters", &self.parameters)
            .finish_non_exhaustive()
    }
}

impl<T> Parametric<T> {
    /// `parameters` (at least one, unique names, each valid) and the `builder`.
    pub fn new(
        parameters: Vec<NonlinearParameter>,
        builder: impl Fn(&[f64]) -> Result<T> + Send + Sync + 'static,
    ) -> Result<Self> {
        if parameters.is_empty() {
            return Err(Error::Empty {
                what: "estimated parameters of a parametric model".into(),
            });
        }
        validate_parameters(&parameters)?;
        Ok(Parametric {
            parameters,
            builder: Arc::new(builder),
        })
    }

    /// One fixed `value`: no parameters.
    pub fn fixed(value: T) -> Self
    where
        T: Clone + Send + Sync + 'static,
    {
        Parametric {
            parameters: Vec::new(),
            builder: Arc::new(move |_: &[f64]| Ok(value.clone())),
        }
    }

    /// The nonlinear parameters (none for a fixed value).
    pub fn parameters(&self) -> &[NonlinearParameter] {
        &self.parameters
    }

    /// True when nothing is estimated.
    pub fn is_fixed(&self) -> bool {
        self.parameters.is_empty()
    }

    /// The value at `values` (one per parameter).
    pub fn at(&self, values: &[f64]) -> Result<T> {
        check_values(&self.parameters, values)?;
        (self.builder)(values)
    }

    /// The initial values of the parameters, in order.
    pub fn initial_values(&self) -> Vec<f64> {
        self.parameters.iter().map(|p| p.initial).collect()
    }

    /// The value at the initial values.
    pub fn initial(&self) -> Result<T> {
        self.at(&self.initial_values())
    }
}

/// One value per parameter.
pub(crate) fn check_values<T>(parameters: &[NonlinearParameter], values: &[T]) -> Result<()> {
    if values.len() == parameters.len() {
        Ok(())
    } else {
        Err(Error::mismatch(
            "nonlinear parameter values vs parameters",
            parameters.len(),
            values.len(),
        ))
    }
}

/// Unique names, each parameter valid.
pub(crate) fn validate_parameters(parameters: &[NonlinearParameter]) -> Result<()> {
    for (i, p) in parameters.iter().enumerate() {
        p.validate()?;
        if parameters[..i].iter().any(|q| q.name == p.name) {
            return Err(Error::choice(
                "estimated parameter",
                format!("'{}'", p.name),
                "given twice: every estimated parameter needs its own name",
            ));
        }
    }
    Ok(())
}
