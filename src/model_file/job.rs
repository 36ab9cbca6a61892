//! The job a model file describes: the model, the records (simulated or read, then
//! reduced or synthesized), and the settings, assembled from the parsed spec in the
//! order the sections depend on each other.

use std::path::Path;
use std::sync::Arc;

use faer::Mat;

use super::context::Context;
use super::measured::{Mode, RecordInputs, read_record};
use super::records::{Truth, simulate_records};
use super::settings::{
    design_settings, identification_settings, periodic_only_key, span_settings,
    steady_state_settings, stored_energy,
};
use super::spec::{MatrixRef, ModelFileSpec};
use super::terms::{build_term, resolve_matrix};
use super::{reduction, string};
use crate::analysis::design::DesignSettings;
use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::io::data_file::DataFiles;
use crate::model::DampingModel;
use crate::prep::harmonic::SteppedSineTable;
use crate::prep::period::PeriodEstimate;
use crate::prep::pod::Reduction;
use crate::prep::steady_state::{SteadyStateReport, StoredEnergy};
use crate::progress::Progress;
use crate::record::Record;
use crate::regressor::{
    KnownModal, ParametricModel, ParametricRegressor, Regressor, RegressorSettings,
    SteppedSineSource,
};
use crate::report::units::Units;
use crate::terms::laws::Registry;

/// Everything a model file asks for, ready to run: a problem ([`Job::problem`]: the
/// damping law on the records or the stepped-sine table) and its settings.
#[derive(Debug)]
pub struct Job {
    /// Title for reports.
    pub title: String,
    /// The damping model (at the initial values of any estimated law parameters).
    pub model: DampingModel,
    /// The damping model as a function of its estimated law parameters
    /// (`{ estimate = true, … }`; none: the fixed `model`).
    pub law: ParametricModel,
    /// The records identification runs on: the source records, reduced by `[pod]` and
    /// synthesized by `[harmonic_approximation]` when asked (none for a
    /// `[stepped_sine]` table, whose equations are its points). Shared with
    /// `source_records` when neither applies (a record of 100 DOFs × 2·10⁵ samples
    /// is 160 MB per signal: kept once, not twice).
    pub records: Arc<[Record]>,
    /// The records as simulated or read (before any reduction).
    pub source_records: Arc<[Record]>,
    /// How the columns of each data record were read (gains, sensors); empty for
    /// simulated records.
    pub inputs: Vec<RecordInputs>,
    /// The period detected from the force of each source record, where the model file
    /// gave none (`None`: given or simulated).
    pub detected_periods: Vec<Option<PeriodEstimate>>,
    /// The jitter of each source record's time column, max |Δt − h|/h with h the mean
    /// step (`None`: no time column).
    pub time_jitter: Vec<Option<f64>>,
    /// Identification settings (for a harmonic approximation, those of the synthesized
    /// records; for `[non_periodic]`, fixed spans with the stored-energy unknowns), with
    /// the steady-state thresholds of `[identification]`.
    pub settings: IdentifySettings,
    /// How windows are cut from the source records (`[identification]`, and
    /// `[non_periodic]`): the steady-state check reads them.
    pub source_windows: RegressorSettings,
    /// True coefficients, in model order, when the records were simulated.
    pub truth: Option<Vec<(String, f64)>>,
    /// Experiment-design settings from `[design]` (start indices 0-based).
    pub design: Option<DesignSettings>,
    /// Mass, stiffness and cubic springs, when known (`[simulation]` or `[system]`).
    pub stored_energy: Option<StoredEnergy>,
    /// The POD reduction, when `[pod]` asks for one.
    pub pod: Option<Reduction>,
    /// The stepped-sine table of a harmonic approximation.
    pub harmonic: Option<SteppedSineTable>,
    /// The measured stepped-sine table of `[stepped_sine]`: the job's equations.
    pub stepped_sine: Option<SteppedSineSource>,
    /// The `[[simulation.experiments]]`, one per simulated record (DOFs 0-based); empty
    /// without a `[simulation]`.
    pub experiments: Vec<crate::simulate::HarmonicForce>,
    /// The units of `[units]` (empty when not given).
    pub units: Units,
    /// The data files of `[data]`, as resolved against the model file's folder.
    pub data_files: Vec<std::path::PathBuf>,
    /// What isolating each record's mode found, for `[free_decay]` (empty otherwise).
    pub free_decay: Vec<crate::prep::free_decay::DecaySummary>,
}

impl Job {
    /// The problem the job identifies: its law on its equations (the table, or the
    /// records with their steady-state check on the source records and the stored
    /// energy when known).
    pub fn problem(&self) -> ParametricRegressor<'_> {
        self.problem_of(&self.law)
    }

    /// Another `law` on this job's equations (to compare models on the same data).
    pub fn problem_of(&self, law: &ParametricModel) -> ParametricRegressor<'_> {
        match &self.stepped_sine {
            Some(table) => ParametricRegressor::new(law.clone(), table),
            None => ParametricRegressor::new(law.clone(), &self.records).with_steady_state_of(
                &self.source_records,
                &self.source_windows,
                self.stored_energy.as_ref(),
            ),
        }
    }

    /// The regressor at the initial values of every estimated parameter, as `dampid
    /// check` examines it.
    pub fn initial_regressor(&self) -> Result<Regressor> {
        let problem = self.problem();
        problem.regressor(&problem.initial_values(), &self.settings.regressor)
    }

    /// The steady-state report of the job's windows (`None` where there is none to
    /// check: a table, fixed spans), with the thresholds of its settings.
    pub fn steady_state(&self) -> Result<Option<SteadyStateReport>> {
        match &self.settings.steady_state {
            Some(thresholds) => self
                .problem()
                .steady_state(&self.settings.regressor, thresholds),
            None => Ok(None),
        }
    }

    /// Whether windows that are not in steady state are accepted (a warning) rather
    /// than refused.
    pub fn accept_transient(&mut self, accept: bool) {
        if let Some(steady) = &mut self.settings.steady_state {
            steady.accept_transient |= accept;
        }
    }
}

impl Sources {
    /// Records simulated from the model (their truth known, nothing detected or read),
    /// with the stored energy when the simulation knows it.
    fn simulated(records: Vec<Record>, truth: Truth, stored_energy: Option<StoredEnergy>) -> Self {
        Sources {
            detected_periods: vec![None; records.len()],
            time_jitter: vec![None; records.len()],
            inputs: Vec::new(),
            records,
            truth: Some(truth),
            stored_energy,
            stepped_sine: None,
        }
    }
}

/// Where the records come from, and what is known with them.
struct Sources {
    records: Vec<Record>,
    truth: Option<Truth>,
    inputs: Vec<RecordInputs>,
    detected_periods: Vec<Option<PeriodEstimate>>,
    time_jitter: Vec<Option<f64>>,
    stored_energy: Option<StoredEnergy>,
    stepped_sine: Option<SteppedSineSource>,
}

impl Context<'_> {
    /// The model `[simulation]` simulates: `model`, or with estimated law parameters the
    /// parametric model at `[simulation] parameters` (each one not given at its initial
    /// value; a name that is not an estimated parameter is an error at the section).
    fn simulated_model(
        &self,
        spec: &ModelFileSpec,
        model: &DampingModel,
        law: &ParametricModel,
    ) -> Result<DampingModel> {
        let Some(simulation) = &spec.simulation else {
            return Ok(model.clone());
        };
        self.at(simulation, |s| {
            let known: Vec<&str> = law.parameters().iter().map(|q| q.name.as_str()).collect();
            if let Some(name) = s.parameters.keys().find(|n| !known.contains(&n.as_str())) {
                return Err(Error::UnknownName {
                    what: "estimated law parameter".into(),
                    name: name.clone(),
                    known: if known.is_empty() {
                        "none: no law parameter is estimated".into()
                    } else {
                        known.join(", ")
                    },
                });
            }
            if law.is_fixed() {
                return Ok(model.clone());
            }
            let values: Vec<f64> = law
                .parameters()
                .iter()
                .map(|q| s.parameters.get(&q.name).copied().unwrap_or(q.initial))
                .collect();
            law.at(&values)
        })
    }

    pub(super) fn build(
        &self,
        spec: &ModelFileSpec,
        base: &Path,
        laws: &Registry,
        progress: Progress<'_>,
    ) -> Result<Job> {
        let n = spec.dofs;
        let (model, law) = self.damping_model(spec, laws)?;
        let matrix = |r: &MatrixRef| resolve_matrix(r, spec, n);
        let mut units = Units::default();
        for (dimension, unit) in &spec.units {
            self.at(unit, |u| units.set(dimension, u))?;
        }
        let mut settings =
            identification_settings(&spec.identification, spec.non_periodic.is_some());
        if spec.non_periodic.is_some()
            && let Some((value, error)) = periodic_only_key(self.text)
        {
            return Err(self.typed_error_at(&value, error));
        }
        if let Some(decay) = &spec.free_decay {
            if spec.data.is_none()
                || spec.pod.is_some()
                || spec.harmonic_approximation.is_some()
                || spec.non_periodic.is_some()
            {
                return Err(self.error_at(
                    decay,
                    "[free_decay] reads ringdowns from [data]; it does not combine with [simulation], [stepped_sine], [pod], [harmonic_approximation] or [non_periodic]",
                ));
            }
            self.refuse_periodic_keys_beside_free_decay()?;
        }
        let steady_state = steady_state_settings(&spec.identification);
        steady_state
            .validate()
            .map_err(|e| self.whole_file_typed_error("[identification]", e))?;
        settings.steady_state = spec.free_decay.is_none().then_some(steady_state);
        let simulated = self.simulated_model(spec, &model, &law)?;
        let sources = self.sources(spec, &simulated, n, base, &matrix, progress)?;
        if let Some(np) = &spec.non_periodic {
            if spec.pod.is_some() || spec.harmonic_approximation.is_some() {
                return Err(self.error_at(
                    np,
                    "[non_periodic] works on the records themselves; it does not combine with [pod] or [harmonic_approximation]",
                ));
            }
            settings.regressor =
                self.at(np, |np| span_settings(np, &settings.regressor, n, &matrix))?;
        }
        if let Some(table) = &spec.stepped_sine
            && (spec.pod.is_some()
                || spec.harmonic_approximation.is_some()
                || spec.non_periodic.is_some())
        {
            return Err(self.error_at(
                table,
                "[stepped_sine] is a table of amplitudes and phases; it does not combine with [pod], [harmonic_approximation] or [non_periodic]",
            ));
        }
        if sources.stepped_sine.is_some() {
            settings.regressor = RegressorSettings::harmonic_approximation();
        }
        let mut free_decay = Vec::new();
        let mut isolated_records = None;
        if let Some(decay) = &spec.free_decay {
            let (decay_settings, regressor) =
                self.free_decay_settings(decay, &settings.regressor)?;
            settings.regressor = regressor;
            let filter = self.modal_filter(decay.get_ref())?;
            self.check_mode_shape(decay.get_ref(), &sources.records)?;
            let decays = self.at(decay, |_| {
                super::free_decay::isolated(&sources.records, filter.as_ref(), &decay_settings)
            })?;
            free_decay = decays
                .iter()
                .zip(&sources.records)
                .map(|(d, r)| d.summary(r))
                .collect();
            isolated_records = Some(decays.into_iter().map(|d| d.record).collect::<Vec<_>>());
        }
        let source_windows = settings.regressor.clone();
        let source_records: Arc<[Record]> = sources.records.into();
        // A table's equations are its points: no records to identify from.
        let mut records = if sources.stepped_sine.is_some() {
            Arc::from(Vec::new())
        } else if let Some(modes) = isolated_records {
            Arc::from(modes)
        } else {
            Arc::clone(&source_records)
        };
        let pod = spec
            .pod
            .as_ref()
            .map(|p| {
                self.at(p, |p| {
                    crate::prep::pod::reduce(&records, &reduction::pod_settings(p)?)
                })
            })
            .transpose()?;
        if let Some(reduction) = &pod {
            records = reduction.records.clone().into();
        }
        let harmonic = spec
            .harmonic_approximation
            .as_ref()
            .map(|h| {
                self.at(h, |h| {
                    // [non_periodic] does not combine with it (checked above).
                    let whole_periods =
                        source_windows.windows.cycles().cloned().unwrap_or_default();
                    let approximation = reduction::harmonic_settings(h, n)?;
                    let table = SteppedSineTable::from_records(&records, &whole_periods)?;
                    Ok((approximation.records(&table)?, table))
                })
            })
            .transpose()?
            .map(|(synthesized, table)| {
                records = synthesized.into();
                settings.regressor = RegressorSettings::harmonic_approximation();
                table
            });
        let design = spec
            .design
            .as_ref()
            .map(|d| {
                let experiments = spec
                    .simulation
                    .as_ref()
                    .map(|s| s.get_ref().experiments.len());
                self.at(d, |d| design_settings(d, experiments))
            })
            .transpose()?;
        // The data files read: each record's of `[data]`, or the table of `[stepped_sine]`.
        let data_files = spec
            .data
            .iter()
            .flat_map(|d| d.get_ref().records.iter())
            .map(|r| base.join(&r.get_ref().file))
            .chain(
                spec.stepped_sine
                    .iter()
                    .map(|t| base.join(&t.get_ref().file)),
            )
            .collect();
        Ok(Job {
            title: spec.title.clone().unwrap_or_else(|| self.file.to_string()),
            model,
            law,
            records,
            source_records,
            inputs: sources.inputs,
            detected_periods: sources.detected_periods,
            time_jitter: sources.time_jitter,
            settings,
            source_windows,
            truth: sources.truth,
            design,
            stored_energy: sources.stored_energy,
            pod,
            harmonic,
            stepped_sine: sources.stepped_sine,
            experiments: spec
                .simulation
                .iter()
                .flat_map(|s| &s.get_ref().experiments)
                .map(|e| {
                    let e = e.get_ref();
                    crate::simulate::HarmonicForce {
                        // Checked ≥ 1 when the records were simulated.
                        dof: e.force_dof.saturating_sub(1),
                        amplitude: e.amplitude,
                        frequency: e.frequency,
                        phase: e.phase,
                    }
                })
                .collect(),
            units,
            data_files,
            free_decay,
        })
    }

    /// The damping model of `spec` alone: `dofs`, `[matrices]` and `[[terms]]`, each
    /// term checked at its own block (including a coefficient name an earlier block
    /// already uses).
    pub(super) fn damping_model(
        &self,
        spec: &ModelFileSpec,
        laws: &Registry,
    ) -> Result<(DampingModel, ParametricModel)> {
        let n = spec.dofs;
        if n == 0 {
            return Err(self.whole_file_error("dofs must be at least 1"));
        }
        let matrix = |r: &MatrixRef| resolve_matrix(r, spec, n);
        if spec.terms.is_empty() {
            let empty = Error::Empty {
                what: "the damping model".into(),
            };
            return Err(self.whole_file_typed_error("[[terms]]", empty));
        }
        // Each term is checked at its own [[terms]] block, including a coefficient name
        // that an earlier block already uses.
        let mut model = DampingModel::new();
        let mut names = std::collections::HashSet::new();
        let mut recipes = Vec::with_capacity(spec.terms.len());
        let mut estimated = Vec::new();
        for term in &spec.terms {
            let built = self.at(term, |t| {
                let first = estimated.len();
                let recipe = build_term(t, n, &matrix, laws, &mut estimated)?;
                let initial: Vec<f64> = estimated.iter().map(|p| p.initial).collect();
                let built = recipe.build(&initial)?;
                built.validate(n)?;
                for name in built.coefficient_names() {
                    if !names.insert(name.clone()) {
                        return Err(Error::DuplicateCoefficient { name });
                    }
                }
                for p in &estimated[first..] {
                    if estimated[..first].iter().any(|q| q.name == p.name) {
                        return Err(Error::choice(
                            "estimated parameter",
                            format!("'{}'", p.name),
                            "given twice: every estimated parameter needs its own name",
                        ));
                    }
                }
                recipes.push(recipe);
                Ok(built)
            })?;
            model = model.with(built);
        }
        let law = if estimated.is_empty() {
            ParametricModel::fixed(model.clone())
        } else {
            ParametricModel::new(estimated, move |eta| {
                recipes
                    .iter()
                    .try_fold(DampingModel::new(), |m, r| Ok(m.with(r.build(eta)?)))
            })?
        };
        Ok((model, law))
    }

    /// The records from `[simulation]`, `[string_simulation]` or `[data]` (exactly one),
    /// with the truth, detected periods, and M and K when known.
    fn sources(
        &self,
        spec: &ModelFileSpec,
        model: &DampingModel,
        n: usize,
        base: &Path,
        matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
        progress: Progress<'_>,
    ) -> Result<Sources> {
        let given = [
            spec.simulation.is_some(),
            spec.string_simulation.is_some(),
            spec.data.is_some(),
            spec.stepped_sine.is_some(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(self.whole_file_error(
                "give exactly one of [simulation] (generate the records), [string_simulation] (the paper's string), [data] (read them) or [stepped_sine] (a measured table)",
            ));
        }
        let system = spec
            .system
            .as_ref()
            .map(|s| {
                self.at(s, |s| {
                    if spec.data.is_none() && spec.stepped_sine.is_none() {
                        return Err(Error::choice(
                            "system",
                            "a [system] section beside a simulation",
                            "[system] describes measured data; a [simulation] gives its own mass and stiffness",
                        ));
                    }
                    stored_energy(&s.mass, &s.stiffness, &s.cubic_springs, n, matrix)
                })
            })
            .transpose()?;
        if let Some(sim) = &spec.simulation {
            let (records, truth) =
                self.at(sim, |s| simulate_records(s, model, n, matrix, progress))?;
            let energy = self.at(sim, |s| {
                stored_energy(&s.mass, &s.stiffness, &s.cubic_springs, n, matrix)
            })?;
            return Ok(Sources::simulated(records, truth, Some(energy)));
        }
        if let Some(string) = &spec.string_simulation {
            let (records, truth) =
                self.at(string, |s| string::string_records(s, model, n, progress))?;
            return Ok(Sources::simulated(records, truth, None));
        }
        if let Some(table) = &spec.stepped_sine {
            let mut source = self.at(table, |t| self.stepped_sine(t, n, base))?;
            source.system = system
                .as_ref()
                .filter(|s| s.mass.nrows() == 1)
                .map(|s| KnownModal {
                    mass: s.mass[(0, 0)],
                    stiffness: s.stiffness[(0, 0)],
                });
            return Ok(Sources {
                detected_periods: Vec::new(),
                time_jitter: Vec::new(),
                inputs: Vec::new(),
                records: Vec::new(),
                truth: None,
                stored_energy: system,
                stepped_sine: Some(source),
            });
        }
        let data = spec
            .data
            .as_ref()
            .ok_or_else(|| self.whole_file_error("no records"))?;
        let list = &data.get_ref().records;
        let total = list.len() as u64;
        let mut records = Vec::new();
        let mut detected_periods = Vec::new();
        let mut time_jitter = Vec::new();
        let mut inputs = Vec::new();
        // Each data file once, however many records name it.
        let paths: Vec<std::path::PathBuf> =
            list.iter().map(|r| base.join(&r.get_ref().file)).collect();
        let mut files = DataFiles::new(paths.iter().map(|p| p.as_path()));
        for (k, r) in list.iter().enumerate() {
            crate::cancel::check("reading the records")?;
            let read = self.at(r, |r| {
                let mode = match (&spec.non_periodic, &spec.free_decay) {
                    (_, Some(_)) => Mode::FreeDecay,
                    (None, None) => Mode::Periodic,
                    (Some(np), None) => Mode::NonPeriodic(np.get_ref().high_pass.as_ref()),
                };
                // A modal filter reads every sensor of the record, then projects them
                // onto the model's one mode.
                let dofs = match &spec.free_decay {
                    Some(d)
                        if d.get_ref().mode_shape.is_some()
                            || d.get_ref().modal_filter.is_some() =>
                    {
                        super::free_decay::listed_channels(r)
                    }
                    _ => n,
                };
                read_record(self, r, dofs, (base, &mut files), mode)
            })?;
            records.push(read.record);
            detected_periods.push(read.detected);
            time_jitter.push(read.jitter);
            inputs.push(read.inputs);
            progress(k as u64 + 1, total);
        }
        Ok(Sources {
            records,
            inputs,
            truth: None,
            detected_periods,
            time_jitter,
            stored_energy: system,
            stepped_sine: None,
        })
    }
}
