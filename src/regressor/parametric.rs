//! A regressor that may carry nonlinear parameters: A(η) θ = b(η).
//!
//! The damping coefficients θ are linear; a law may also have nonlinear parameters η
//! ([`crate::regressor::nonlinear`]), and a stepped-sine table has its residual
//! receptances (nuisance unknowns that correct the measured response,
//! [`crate::prep::harmonic::residual`]). [`ParametricRegressor`] is the problem
//! `identify` solves: a law on an equation source ([`Source`]: records, a stepped-sine
//! table, or rows built already); its parameters are the law's, then the table's
//! residual unknowns. A job with nothing estimated is the case q = 0 of the same type,
//! whose one regressor is `regressor(&[], settings)`.

use std::sync::{Arc, OnceLock};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::fourier::RecordNoises;
use crate::prep::steady_state::{SteadyStateReport, SteadyStateSettings, StoredEnergy};
use crate::record::Record;
use crate::regressor::nonlinear::{NonlinearParameter, Parametric, ParametricModel};
use crate::regressor::source::Source;
use crate::regressor::{Regressor, RegressorSettings};

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
    /// A free decay's cycles and weights, made at the first trial (`free_decay.rs`).
    decay: super::DecayCache,
    /// The harmonics and noise of the problem's records, estimated by its steady-state
    /// check or its first build of noise-robust rows, whichever comes first, and read by
    /// every later one (`prep/fourier/record_noise.rs`).
    noises: Arc<OnceLock<RecordNoises>>,
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
            decay: super::DecayCache::default(),
            noises: Arc::default(),
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
        let (records, checked, energy) = match (self.steady, self.source) {
            (Some(input), _) => (input.records, input.settings, input.energy),
            (None, Source::Records(records)) => (records, settings, None),
            (None, _) => return Ok(None),
        };
        let Some(windows) = checked.windows.cycles() else {
            return Ok(None);
        };
        // the problem's own records: their noise, estimated here, serves its rows too
        let own = matches!(self.source, Source::Records(r) if std::ptr::eq(r, records));
        let noises = own.then(|| self.noises.get_or_init(|| RecordNoises::of(records)));
        crate::prep::steady_state::check_with(
            records,
            windows,
            checked.quadrature,
            energy,
            thresholds,
            noises,
        )
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
        if values.len() != self.parameter_count() {
            return Err(Error::mismatch(
                "nonlinear parameter values vs parameters",
                self.parameter_count(),
                values.len(),
            ));
        }
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
        // the records' noise once per problem, for noise-robust rows
        let noises = match source {
            Source::Records(records) if settings.noise_robust().unwrap_or(false) => {
                Some(self.noises.get_or_init(|| RecordNoises::of(records)))
            }
            _ => None,
        };
        Regressor::build_with(&model, source, settings, Some(&self.decay), noises)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::quadrature::Quadrature;
    use crate::prep::velocity::VelocitySource;
    use crate::prep::window::WindowSpec;
    use crate::record::{MeasuredMotion, Sensor};
    use crate::reference::{four_mass_model, four_mass_records_with, with_displacement_noise};
    use crate::regressor::Windows;
    use crate::regressor::settings::{NoiseTreatment, WorkForm};
    use crate::simulate::SimSettings;

    /// The noise-robust rows of a problem, which estimates its records' noise once (at
    /// its steady-state check or its first build) and keeps it, are the rows built
    /// alone, bit for bit (the regressor with its noise model, as JSON), at the first
    /// build and at the next, on records with displacement sensors and with velocity
    /// and acceleration sensors, on the noise floor's harmonics and on 1..K, in both
    /// work forms. Plain rows estimate no noise.
    #[test]
    fn rows_on_the_problems_record_noise_are_the_rows_alone() {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let step = period / 64.0;
        let settings = SimSettings {
            step,
            transient_steps: (300.0 / step) as usize,
            recorded_steps: 12 * 64 + 3,
            ..SimSettings::default()
        };
        let clean = four_mass_records_with(false, &settings).unwrap();
        let noisy = with_displacement_noise(&clean, 0.01, 5).unwrap();
        let sensors = vec![
            Sensor::Displacement,
            Sensor::Velocity,
            Sensor::Acceleration,
            Sensor::Velocity,
        ];
        let measured: Vec<Record> = noisy
            .iter()
            .zip(&clean)
            .map(|(record, truth)| {
                let (x, v) = (record.displacements(), truth.velocities().unwrap());
                let signals = faer::Mat::from_fn(record.samples(), 4, |i, j| match sensors[j] {
                    Sensor::Displacement => x[(i, j)],
                    Sensor::Velocity => v[(i, j)] + 0.001 * x[(i, j)],
                    Sensor::Acceleration => -0.618 * 0.618 * x[(i, j)],
                });
                let motion = MeasuredMotion {
                    sensors: sensors.clone(),
                    signals,
                };
                record.clone().with_measured_motion(motion).unwrap()
            })
            .collect();
        let model = four_mass_model();
        let thresholds = SteadyStateSettings {
            accept_transient: true,
            ..SteadyStateSettings::default()
        };
        for records in [&noisy, &measured] {
            for harmonics in [None, Some(3)] {
                for work_form in [WorkForm::Velocity, WorkForm::DerivativeFree] {
                    let settings = RegressorSettings {
                        windows: Windows::Cycles(WindowSpec::cycles(1)),
                        quadrature: Quadrature::Trapezoid,
                        velocity: VelocitySource::HarmonicProjection { harmonics },
                        noise: NoiseTreatment::Auto,
                        work_form,
                    };
                    let json = |r: &Regressor| serde_json::to_string(r).unwrap();
                    let alone = Regressor::build(&model, records.as_slice(), &settings).unwrap();
                    // estimated by the first build, or by the check before it
                    for checked in [false, true] {
                        let problem = ParametricRegressor::linear(&model, records.as_slice());
                        if checked {
                            problem.steady_state(&settings, &thresholds).unwrap();
                            assert!(problem.noises.get().is_some(), "estimated by the check");
                        }
                        let first = problem.regressor(&[], &settings).unwrap();
                        let noises = problem.noises.get().expect("estimated once");
                        let after = problem.regressor(&[], &settings).unwrap();
                        assert!(std::ptr::eq(noises, problem.noises.get().unwrap()));
                        assert_eq!(json(&first), json(&after));
                        assert_eq!(json(&after), json(&alone), "{harmonics:?}, {work_form:?}");
                    }
                }
            }
        }
        // plain rows estimate no noise
        let plain = RegressorSettings::plain(
            WindowSpec::cycles(1),
            Quadrature::Trapezoid,
            VelocitySource::Measured,
        );
        let problem = ParametricRegressor::linear(&model, clean.as_slice());
        problem.regressor(&[], &plain).unwrap();
        assert!(problem.noises.get().is_none());
    }
}
