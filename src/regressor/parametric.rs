//! A regressor that may carry nonlinear parameters: A(η) θ = b(η).
//!
//! The damping coefficients θ are linear; a law may also have nonlinear parameters η (a
//! power law's exponent, a constant inside an expression law, a hysteresis shape), and a
//! stepped-sine table has its residual receptances (nuisance unknowns that correct the
//! measured response, [`crate::prep::harmonic::residual`]). Each η has an initial value
//! and bounds ([`NonlinearParameter`]). A job with nothing estimated is the case q = 0
//! of the same type: [`Parametric::fixed`].
//!
//! [`Parametric<T>`] is a builder η → T with its parameters: a [`ParametricModel`]
//! (η → damping model) or any other thing built from η. [`ParametricRegressor`] is the
//! problem `identify` solves: a law on an equation source ([`Source`]: records or a
//! stepped-sine table), with the regressor settings of records; its parameters are the
//! law's, then the table's residual receptances.

use std::fmt;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::steady_state::{SteadyStateReport, SteadyStateSettings, StoredEnergy};
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings, Source};

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

/// The problem `identify` solves: a damping law (perhaps with estimated parameters) on
/// an equation source (records with their regressor settings, or a stepped-sine table
/// with perhaps its residual receptances). Its nonlinear parameters η are the law's,
/// then the table's residual unknowns; with none it is a linear problem whose one
/// regressor is [`ParametricRegressor::regressor`]`(&[], ..)`.
#[derive(Debug, Clone)]
pub struct ParametricRegressor<'a> {
    law: ParametricModel,
    source: Source<'a>,
    steady: Option<SteadyStateInput<'a>>,
}

/// What the steady-state check of a problem reads when it is not the problem's own
/// records (a POD reduction or a harmonic approximation identifies transformed
/// records; the check reads the records as measured, with their stored energy when
/// known).
#[derive(Debug, Clone, Copy)]
struct SteadyStateInput<'a> {
    records: &'a [Record],
    settings: &'a RegressorSettings,
    energy: Option<&'a StoredEnergy>,
}

impl<'a> ParametricRegressor<'a> {
    /// `law` on the equations of `source`.
    pub fn new(law: ParametricModel, source: impl Into<Source<'a>>) -> Self {
        let source = match source.into() {
            // The table as measured: its residual unknowns are parameters here.
            Source::Table { table, .. } => Source::table(table),
            records => records,
        };
        ParametricRegressor {
            law,
            source,
            steady: None,
        }
    }

    /// This problem with its steady-state check reading `records` cut by `settings`
    /// (windows and rule), with their stored `energy` when known, instead of the
    /// problem's own records (a table alone has none to check).
    pub fn with_steady_state_of(
        mut self,
        records: &'a [Record],
        settings: &'a RegressorSettings,
        energy: Option<&'a StoredEnergy>,
    ) -> Self {
        self.steady = Some(SteadyStateInput {
            records,
            settings,
            energy,
        });
        self
    }

    /// How far each window of whole periods is from steady state
    /// ([`crate::prep::steady_state::check`] with `thresholds`): of the records set by
    /// [`Self::with_steady_state_of`], else of the problem's own records cut by
    /// `settings`. `None` where there is nothing to check: fixed spans of non-periodic
    /// records (their balance holds over any window) and a table.
    pub fn steady_state(
        &self,
        settings: &RegressorSettings,
        thresholds: &SteadyStateSettings,
    ) -> Result<Option<SteadyStateReport>> {
        let (records, settings, energy) = match (self.steady, self.source) {
            (Some(input), _) => (input.records, input.settings, input.energy),
            (None, Source::Records(records)) => (records, settings, None),
            (None, _) => return Ok(None),
        };
        let Some(windows) = settings.windows.cycles() else {
            return Ok(None);
        };
        crate::prep::steady_state::check(records, windows, settings.quadrature, energy, thresholds)
            .map(Some)
    }

    /// A damping model with nothing estimated on the equations of `source`.
    pub fn linear(model: &DampingModel, source: impl Into<Source<'a>>) -> Self {
        Self::new(Parametric::fixed(model.clone()), source)
    }

    /// A regressor built already (by hand, or rows stacked from many records): the
    /// problem of fitting it as it is, with no damping model behind it.
    pub fn rows(regressor: &'a Regressor) -> Self {
        Self::new(Parametric::fixed(DampingModel::new()), regressor)
    }

    /// The law (the damping model as a function of its own parameters).
    pub fn law(&self) -> &ParametricModel {
        &self.law
    }

    /// Where the equations come from.
    pub fn source(&self) -> Source<'a> {
        self.source
    }

    /// Every nonlinear parameter: the law's, then the table's residual unknowns.
    pub fn parameters(&self) -> Vec<NonlinearParameter> {
        let mut all = self.law.parameters().to_vec();
        if let Some(table) = self.source.stepped_sine() {
            all.extend(table.residual_parameters.iter().cloned());
        }
        all
    }

    /// The number of nonlinear parameters.
    pub fn parameter_count(&self) -> usize {
        self.law.parameters().len()
            + self
                .source
                .stepped_sine()
                .map_or(0, |t| t.residual_parameters.len())
    }

    /// True when nothing is estimated (a linear problem).
    pub fn is_linear(&self) -> bool {
        self.parameter_count() == 0
    }

    /// The initial values of every parameter, in order.
    pub fn initial_values(&self) -> Vec<f64> {
        self.parameters().iter().map(|p| p.initial).collect()
    }

    /// The damping model at `values` (every parameter; the law takes its own).
    pub fn model(&self, values: &[f64]) -> Result<DampingModel> {
        check_values(&self.parameters(), values)?;
        self.law.at(&values[..self.law.parameters().len()])
    }

    /// The regressor at `values` (every parameter), the records' windows cut by
    /// `settings` (a table ignores them).
    pub fn regressor(&self, values: &[f64], settings: &RegressorSettings) -> Result<Regressor> {
        let model = self.model(values)?;
        let residual = &values[self.law.parameters().len()..];
        let source = match self.source {
            Source::Table { table, .. } => Source::Table { table, residual },
            Source::Rows(_) if !self.law.is_fixed() => {
                return Err(Error::choice(
                    "estimated parameters",
                    "on rows built already".to_string(),
                    "a regressor built already cannot be rebuilt at other parameter values: give the records (or the table) and the parametric model",
                ));
            }
            other => other,
        };
        Regressor::build(&model, source, settings)
    }

    /// The group of each equation whose errors may be correlated and which a bootstrap
    /// resamples whole: the sweep of every point of a table (`None` for records, whose
    /// windows are resampled one by one).
    pub fn groups(&self) -> Option<&'a [usize]> {
        self.source
            .stepped_sine()
            .map(|t| t.table.sweeps.as_slice())
    }
}
