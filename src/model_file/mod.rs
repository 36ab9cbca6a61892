//! Model files: one TOML file describes the damping model (terms on elements or
//! matrices, shared or per-element coefficients, custom laws as expressions), how to
//! identify (windows, quadrature, velocity source, constraints), and where the records
//! come from: a `[simulation]` section that generates them (so a model file runs on a
//! fresh machine) or a `[data]` section that reads measured CSV files.
//!
//! Errors carry the file and the line and column of the offending table or key.

mod reduction;
mod spec;
mod string;

use std::collections::BTreeMap;
use std::path::Path;

use faer::Mat;
use toml::Spanned;

pub use spec::*;

use crate::analysis::design::DesignSettings;
use crate::error::{Error, Result};
use crate::fit::{Bound, Constraints, Fixed, LinearConstraint, LinearTerm};
use crate::identify::IdentifySettings;
use crate::io::table::Table;
use crate::model::DampingModel;
use crate::prep::harmonic::{HarmonicApproximation, SteppedSineTable};
use crate::prep::period::{PeriodEstimate, detect_period};
use crate::prep::pod::Reduction;
use crate::prep::steady_state::{SteadyStateReport, SteadyStateSettings, StoredEnergy};
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::progress::Progress;
use crate::record::{Forcing, Record, RecordParts};
use crate::reference::chain_stiffness;
use crate::regressor::nonperiodic::{Kinetic, NonPeriodicSettings, Potential, StorageModel};
use crate::regressor::{Regressor, RegressorSettings};
use crate::simulate::{
    ConservativeForce, HarmonicForce, SimSettings, System, simulate_with_progress,
};
use crate::terms::laws::{Coulomb, Expression, Linear, PowerLaw, Quadratic};
use crate::terms::{Coefficients, Element, Term};

/// Everything a model file asks for, ready to run.
#[derive(Debug)]
pub struct Job {
    /// Title for reports.
    pub title: String,
    /// The damping model.
    pub model: DampingModel,
    /// The records identification runs on: the source records, reduced by `[pod]` and
    /// synthesized by `[harmonic_approximation]` when asked.
    pub records: Vec<Record>,
    /// The records as simulated or read (before any reduction).
    pub source_records: Vec<Record>,
    /// The period detected from the force of each source record, where the model file
    /// gave none (`None`: given or simulated).
    pub detected_periods: Vec<Option<PeriodEstimate>>,
    /// Identification settings (for a harmonic approximation, those of the synthesized
    /// records).
    pub settings: IdentifySettings,
    /// How windows are cut from the source records (`[identification]`).
    pub source_windows: RegressorSettings,
    /// True coefficients, in model order, when the records were simulated.
    pub truth: Option<Vec<(String, f64)>>,
    /// Experiment-design settings from `[design]` (start indices 0-based).
    pub design: Option<DesignSettings>,
    /// Mass, stiffness and cubic springs, when known (`[simulation]` or `[system]`).
    pub stored_energy: Option<StoredEnergy>,
    /// Steady-state thresholds and whether transients are accepted.
    pub steady_state: SteadyStateSettings,
    /// The POD reduction, when `[pod]` asks for one.
    pub pod: Option<Reduction>,
    /// The stepped-sine table of a harmonic approximation.
    pub harmonic: Option<SteppedSineTable>,
    /// Windows and stored-energy unknowns, when `[non_periodic]` asks for that mode.
    pub non_periodic: Option<NonPeriodicSettings>,
}

impl Job {
    /// How far each window of the source records is from periodic motion
    /// ([`crate::prep::steady_state`]); `None` in the non-periodic mode, whose balance holds
    /// over any window.
    pub fn steady_state(&self) -> Result<Option<SteadyStateReport>> {
        if self.non_periodic.is_some() {
            return Ok(None);
        }
        crate::prep::steady_state::check(
            &self.source_records,
            &self.source_windows,
            self.stored_energy.as_ref(),
            &self.steady_state,
        )
        .map(Some)
    }

    /// The regressor the job identifies from: periodic windows
    /// ([`Regressor::build`]) or the non-periodic balance ([`crate::regressor::nonperiodic::build`]).
    pub fn regressor(&self) -> Result<Regressor> {
        self.regressor_of(&self.model)
    }

    /// The regressor of another damping `model` on this job's records, windows and
    /// mode (to compare models on the same equations).
    pub fn regressor_of(&self, model: &DampingModel) -> Result<Regressor> {
        match &self.non_periodic {
            Some(settings) => crate::regressor::nonperiodic::build(model, &self.records, settings),
            None => Regressor::build(model, &self.records, &self.settings.regressor),
        }
    }
}

/// Reads and builds the model file at `path` (data paths are relative to its folder).
pub fn load(path: &Path) -> Result<Job> {
    load_with_progress(path, &crate::progress::silent)
}

/// [`load`], reporting the progress of simulating or reading the records.
pub fn load_with_progress(path: &Path, progress: Progress<'_>) -> Result<Job> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::ModelFile {
        file: path.display().to_string(),
        line: 0,
        column: 0,
        message: e.to_string(),
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse_with_progress(&text, &path.display().to_string(), base, progress)
}

/// Parses model-file `text` (named `file` in errors) and builds the job.
pub fn parse(text: &str, file: &str, base: &Path) -> Result<Job> {
    parse_with_progress(text, file, base, &crate::progress::silent)
}

/// [`parse`], reporting the progress of simulating or reading the records.
pub fn parse_with_progress(
    text: &str,
    file: &str,
    base: &Path,
    progress: Progress<'_>,
) -> Result<Job> {
    let context = Context { file, text };
    let spec: ModelFileSpec = toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map_or((0, 0), |s| context.position(s.start));
        Error::ModelFile {
            file: file.to_string(),
            line,
            column,
            message: e.message().to_string(),
        }
    })?;
    context.build(&spec, base, progress)
}

/// Where the records come from, and what is known with them.
struct Sources {
    records: Vec<Record>,
    truth: Option<Truth>,
    detected_periods: Vec<Option<PeriodEstimate>>,
    stored_energy: Option<StoredEnergy>,
}

struct Context<'a> {
    file: &'a str,
    text: &'a str,
}

impl Context<'_> {
    /// 1-based line and column of byte `offset`.
    fn position(&self, offset: usize) -> (usize, usize) {
        let before = &self.text[..offset.min(self.text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    fn error_at<T>(&self, spanned: &Spanned<T>, message: impl std::fmt::Display) -> Error {
        let (line, column) = self.position(spanned.span().start);
        Error::ModelFile {
            file: self.file.to_string(),
            line,
            column,
            message: message.to_string(),
        }
    }

    /// Runs `f`, turning its error into a model-file error at `spanned`.
    fn at<S, T>(&self, spanned: &Spanned<S>, f: impl FnOnce(&S) -> Result<T>) -> Result<T> {
        f(spanned.get_ref()).map_err(|e| self.error_at(spanned, e))
    }

    fn whole_file_error(&self, message: impl Into<String>) -> Error {
        Error::ModelFile {
            file: self.file.to_string(),
            line: 0,
            column: 0,
            message: message.into(),
        }
    }

    fn build(&self, spec: &ModelFileSpec, base: &Path, progress: Progress<'_>) -> Result<Job> {
        let n = spec.dofs;
        if n == 0 {
            return Err(self.whole_file_error("dofs must be at least 1"));
        }
        let matrix = |r: &MatrixRef| resolve_matrix(r, spec, n);
        let mut model = DampingModel::new();
        for term in &spec.terms {
            model = model.with(self.at(term, |t| build_term(t, n, &matrix))?);
        }
        self.at(
            spec.terms.first().ok_or_else(|| Error::Empty {
                what: "terms".into(),
            })?,
            |_| model.validate(n),
        )?;
        let mut settings =
            identification_settings(&spec.identification, spec.non_periodic.is_some());
        let steady_state = SteadyStateSettings {
            max_energy_mismatch: spec.identification.max_energy_mismatch,
            max_state_mismatch: spec.identification.max_state_mismatch,
            accept_transient: spec.identification.accept_transient,
        };
        steady_state
            .validate()
            .map_err(|e| self.whole_file_error(format!("[identification]: {e}")))?;
        let sources = self.sources(spec, &model, n, base, &matrix, progress)?;
        let source_windows = settings.regressor;
        let non_periodic = spec
            .non_periodic
            .as_ref()
            .map(|np| {
                if spec.pod.is_some() || spec.harmonic_approximation.is_some() {
                    return Err(self.error_at(
                        np,
                        "[non_periodic] works on the records themselves; it does not combine with [pod] or [harmonic_approximation]",
                    ));
                }
                self.at(np, |np| non_periodic_settings(np, &settings.regressor, n, &matrix))
            })
            .transpose()?;
        let mut records = sources.records.clone();
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
            records = reduction.records.clone();
        }
        let harmonic = spec
            .harmonic_approximation
            .as_ref()
            .map(|h| {
                self.at(h, |h| {
                    let approximation = reduction::harmonic_settings(h, n)?;
                    let table = SteppedSineTable::from_records(&records, &source_windows.windows)?;
                    Ok((approximation.records(&table)?, table))
                })
            })
            .transpose()?
            .map(|(synthesized, table)| {
                records = synthesized;
                settings.regressor = HarmonicApproximation::regressor_settings();
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
        Ok(Job {
            title: spec.title.clone().unwrap_or_else(|| self.file.to_string()),
            model,
            records,
            source_records: sources.records,
            detected_periods: sources.detected_periods,
            settings,
            source_windows,
            truth: sources.truth,
            design,
            stored_energy: sources.stored_energy,
            steady_state,
            pod,
            harmonic,
            non_periodic,
        })
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
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(self.whole_file_error(
                "give exactly one of [simulation] (generate the records), [string_simulation] (the paper's string) or [data] (read them)",
            ));
        }
        let system = spec
            .system
            .as_ref()
            .map(|s| {
                self.at(s, |s| {
                    if spec.data.is_none() {
                        return Err(Error::invalid(
                            "system",
                            f64::NAN,
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
            return Ok(Sources {
                detected_periods: vec![None; records.len()],
                records,
                truth: Some(truth),
                stored_energy: Some(energy),
            });
        }
        if let Some(string) = &spec.string_simulation {
            let (records, truth) =
                self.at(string, |s| string::string_records(s, model, n, progress))?;
            return Ok(Sources {
                detected_periods: vec![None; records.len()],
                records,
                truth: Some(truth),
                stored_energy: None,
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
        for (k, r) in list.iter().enumerate() {
            let (record, detected) =
                self.at(r, |r| read_record(r, n, base, spec.non_periodic.is_none()))?;
            records.push(record);
            detected_periods.push(detected);
            progress(k as u64 + 1, total);
        }
        Ok(Sources {
            records,
            truth: None,
            detected_periods,
            stored_energy: system,
        })
    }
}

/// `[non_periodic]` with the quadrature, velocity, work form and skip of
/// `[identification]`.
fn non_periodic_settings(
    spec: &NonPeriodicSpec,
    identification: &RegressorSettings,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<NonPeriodicSettings> {
    let kinetic = match &spec.mass {
        None => Kinetic::LumpedPerDof,
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "each_dof" => {
            Kinetic::LumpedPerDof
        }
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "none" => {
            Kinetic::Neglected
        }
        Some(StorageSpec::Known { known }) => Kinetic::Known(matrix(known)?),
        Some(StorageSpec::Elements(other)) => {
            return Err(Error::UnknownName {
                what: "mass".into(),
                name: match other {
                    ElementsSpec::Named(name) => name.clone(),
                    ElementsSpec::Pairs(_) => "a list of DOF pairs".into(),
                },
                known: "\"each_dof\", \"none\", { known = <matrix> }".into(),
            });
        }
    };
    let potential = match &spec.stiffness {
        None => Potential::Neglected,
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "none" => {
            Potential::Neglected
        }
        Some(StorageSpec::Elements(elements)) => Potential::Elements(build_elements(elements, n)?),
        Some(StorageSpec::Known { known }) => Potential::Known(matrix(known)?),
    };
    let offsets = match &spec.offsets {
        None => Vec::new(),
        Some(OffsetsSpec::Named(name)) if name == "none" => Vec::new(),
        Some(OffsetsSpec::Named(name)) if name == "each_dof" => (0..n).collect(),
        Some(OffsetsSpec::Named(name)) => {
            return Err(Error::UnknownName {
                what: "offsets".into(),
                name: name.clone(),
                known: "\"each_dof\", \"none\", a list of 1-based DOFs".into(),
            });
        }
        Some(OffsetsSpec::Dofs(dofs)) => dofs
            .iter()
            .map(|&d| one_based(d, n, "offset"))
            .collect::<Result<_>>()?,
    };
    let settings = NonPeriodicSettings {
        window: spec.window,
        skip: identification.windows.skip,
        quadrature: identification.quadrature,
        velocity: identification.velocity,
        work_form: identification.work_form,
        storage: StorageModel {
            kinetic,
            potential,
            offsets,
        },
    };
    settings.validate()?;
    settings.storage.validate(n)?;
    Ok(settings)
}

/// M, K and cubic springs from a model file's matrices (DOFs 1-based in the file).
fn stored_energy(
    mass: &MatrixRef,
    stiffness: &MatrixRef,
    cubic: &[CubicSpec],
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<StoredEnergy> {
    let cubic_springs = cubic
        .iter()
        .map(|c| Ok((one_based(c.dof, n, "cubic spring")?, c.coefficient)))
        .collect::<Result<_>>()?;
    Ok(StoredEnergy {
        mass: matrix(mass)?,
        stiffness: matrix(stiffness)?,
        cubic_springs,
    })
}

/// A 1-based model-file DOF as a 0-based index.
fn one_based(dof: usize, n: usize, what: &str) -> Result<usize> {
    dof.checked_sub(1)
        .filter(|d| *d < n)
        .ok_or_else(|| Error::DofOutOfRange {
            what: format!("{what} (DOFs are numbered 1..{n} in model files)"),
            dof,
            dofs: n,
        })
}

fn resolve_matrix(reference: &MatrixRef, spec: &ModelFileSpec, n: usize) -> Result<Mat<f64>> {
    let rows: &Vec<Vec<f64>> = match reference {
        MatrixRef::Name(name) if name == "identity" => return Ok(Mat::identity(n, n)),
        MatrixRef::Name(name) if name == "chain" => return Ok(chain_stiffness(n)),
        MatrixRef::Name(name) => spec
            .matrices
            .get(name)
            .map(|m| m.get_ref())
            .ok_or_else(|| Error::UnknownName {
                what: "matrix".into(),
                name: name.clone(),
                known: ["identity", "chain"]
                    .into_iter()
                    .map(String::from)
                    .chain(spec.matrices.keys().cloned())
                    .collect::<Vec<_>>()
                    .join(", "),
            })?,
        MatrixRef::Rows(rows) => rows,
    };
    if rows.len() != n {
        return Err(Error::mismatch("matrix rows vs dofs", n, rows.len()));
    }
    for row in rows {
        if row.len() != n {
            return Err(Error::mismatch("matrix columns vs dofs", n, row.len()));
        }
    }
    Ok(Mat::from_fn(n, n, |i, j| rows[i][j]))
}

fn build_term(
    spec: &TermSpec,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<Term> {
    Ok(match spec {
        TermSpec::Viscous {
            coefficient,
            matrix: m,
        } => Term::viscous(coefficient.clone(), matrix(m)?),
        TermSpec::StiffnessProportional {
            coefficient,
            matrix: m,
        } => Term::stiffness_proportional(coefficient.clone(), matrix(m)?),
        TermSpec::MassProportional {
            coefficient,
            matrix: m,
        } => Term::mass_proportional(coefficient.clone(), matrix(m)?),
        TermSpec::Law {
            law,
            exponent,
            expression,
            elements,
            coefficient,
            per_element,
            weights,
        } => {
            let law: Box<dyn Fn(Vec<Element>, Coefficients) -> Term> = match (
                law, exponent, expression,
            ) {
                (LawName::Linear, None, None) => Box::new(|e, c| Term::on_elements(Linear, e, c)),
                (LawName::Quadratic, None, None) => {
                    Box::new(|e, c| Term::on_elements(Quadratic, e, c))
                }
                (LawName::Coulomb, None, None) => Box::new(|e, c| Term::on_elements(Coulomb, e, c)),
                (LawName::Power, Some(p), None) => {
                    let law = PowerLaw::new(*p)?;
                    Box::new(move |e, c| Term::on_elements(law, e, c))
                }
                (LawName::Expression, None, Some(text)) => {
                    let law = Expression::parse(text)?;
                    Box::new(move |e, c| Term::on_elements(law.clone(), e, c))
                }
                (LawName::Power, None, _) => {
                    return Err(Error::invalid(
                        "exponent",
                        f64::NAN,
                        "a power law needs `exponent`",
                    ));
                }
                (LawName::Expression, _, None) => {
                    return Err(Error::Expression {
                        expression: String::new(),
                        message: "an expression law needs `expression = \"...\"`".into(),
                    });
                }
                (name, _, _) => {
                    return Err(Error::invalid(
                        "law",
                        f64::NAN,
                        &format!(
                            "`exponent` belongs to power laws and `expression` to expression laws, not to {name:?}"
                        ),
                    ));
                }
            };
            let coefficients = match (coefficient, per_element) {
                (Some(name), None) => Coefficients::Shared(name.clone()),
                (None, Some(prefix)) => Coefficients::PerElement(prefix.clone()),
                _ => {
                    return Err(Error::invalid(
                        "coefficient",
                        f64::NAN,
                        "give exactly one of `coefficient` (shared) or `per_element` (one per element)",
                    ));
                }
            };
            let elements = build_elements(elements, n)?;
            let term = law(elements, coefficients);
            match (term, weights) {
                (Term::Elements(t), Some(w)) => Term::Elements(t.with_weights(w.clone())),
                (term, _) => term,
            }
        }
    })
}

fn build_elements(spec: &ElementsSpec, n: usize) -> Result<Vec<Element>> {
    match spec {
        ElementsSpec::Named(name) if name == "each_dof" => Ok(Element::each_dof(n)),
        ElementsSpec::Named(name) if name == "chain" => Ok(Element::chain_fixed_both_ends(n)),
        ElementsSpec::Named(name) => Err(Error::UnknownName {
            what: "element set".into(),
            name: name.clone(),
            known: "each_dof, chain, or a list of [a, b] DOF pairs".into(),
        }),
        ElementsSpec::Pairs(pairs) => pairs
            .iter()
            .map(|&[a, b]| {
                let label = format!("{a}-{b}");
                let element = match (a, b) {
                    (0, 0) => {
                        return Err(Error::invalid(
                            "element",
                            0.0,
                            "[0, 0] joins ground to ground",
                        ));
                    }
                    (0, b) => Element::to_ground(b - 1),
                    (a, 0) => Element::to_ground(a - 1),
                    (a, b) => Element::between(a - 1, b - 1),
                };
                let element = element.labelled(label);
                element.validate(n, "model file")?;
                Ok(element)
            })
            .collect(),
    }
}

fn identification_settings(spec: &IdentificationSpec, non_periodic: bool) -> IdentifySettings {
    let default = if non_periodic {
        VelocityName::CentralDifference
    } else {
        VelocityName::HarmonicProjection
    };
    let velocity = match spec.velocity.unwrap_or(default) {
        VelocityName::Measured => VelocitySource::Measured,
        VelocityName::CentralDifference => VelocitySource::CentralDifference,
        VelocityName::Spectral => VelocitySource::Spectral {
            harmonics: spec.harmonics,
        },
        VelocityName::HarmonicProjection => VelocitySource::HarmonicProjection {
            harmonics: spec.harmonics,
        },
    };
    let mut settings = IdentifySettings {
        regressor: RegressorSettings {
            windows: WindowSpec {
                skip: spec.skip,
                cycles: spec.cycles,
                count: spec.windows,
            },
            quadrature: spec.quadrature,
            velocity,
            noise: spec.noise,
            work_form: spec.work_form,
        },
        ..IdentifySettings::default()
    };
    settings.fit.weighting = spec.weighting;
    settings.fit.constraints = Constraints {
        nonnegative: spec.nonnegative,
        bounds: spec
            .bounds
            .iter()
            .map(|(name, b)| Bound {
                name: name.clone(),
                lower: b.lower,
                upper: b.upper,
            })
            .collect(),
        fixed: spec
            .fixed
            .iter()
            .map(|(name, value)| Fixed {
                name: name.clone(),
                value: *value,
            })
            .collect(),
        linear: spec
            .constraints
            .iter()
            .map(|c| LinearConstraint {
                terms: c
                    .terms
                    .iter()
                    .map(|(name, coefficient)| LinearTerm {
                        name: name.clone(),
                        coefficient: *coefficient,
                    })
                    .collect(),
                relation: c.relation,
                value: c.value,
            })
            .collect(),
    };
    settings
}

/// `[design]` against the number of `[simulation]` experiments (none without one).
fn design_settings(spec: &DesignSpec, experiments: Option<usize>) -> Result<DesignSettings> {
    let Some(count) = experiments else {
        return Err(Error::Empty {
            what: "[simulation] experiments: a [design] chooses among them, so it needs a [simulation] section".into(),
        });
    };
    let start = spec
        .start
        .iter()
        .map(|&k| {
            k.checked_sub(1).filter(|k| *k < count).ok_or_else(|| {
                Error::invalid(
                    "design start",
                    k as f64,
                    &format!("experiments are numbered 1..{count}"),
                )
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let settings = DesignSettings {
        criterion: spec.criterion,
        picks: spec.picks.unwrap_or(DesignSettings::default().picks),
        start,
        target_condition: spec.target_condition,
        ..DesignSettings::default()
    };
    settings.validate(count)?;
    Ok(settings)
}

type Truth = Vec<(String, f64)>;

/// The true value of every coefficient of `model`, in model order, from a table that
/// must name each of them and nothing else.
fn truth_of(coefficients: &BTreeMap<String, f64>, model: &DampingModel) -> Result<Truth> {
    let names = model.coefficient_names();
    for name in coefficients.keys() {
        if !names.contains(name) {
            return Err(Error::UnknownCoefficient {
                name: name.clone(),
                known: names.join(", "),
            });
        }
    }
    names
        .iter()
        .map(|name| {
            coefficients
                .get(name)
                .map(|v| (name.clone(), *v))
                .ok_or_else(|| {
                    Error::invalid(
                        &format!("simulation coefficient '{name}'"),
                        f64::NAN,
                        "is missing",
                    )
                })
        })
        .collect()
}

/// Simulates every experiment; progress counts integration steps over all of them.
fn simulate_records(
    spec: &SimulationSpec,
    model: &DampingModel,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
    progress: Progress<'_>,
) -> Result<(Vec<Record>, Truth)> {
    let truth = truth_of(&spec.coefficients, model)?;
    let one_based = |dof: usize, what: &str| one_based(dof, n, what);
    let conservative = spec
        .cubic_springs
        .iter()
        .map(|c| {
            Ok(ConservativeForce::Cubic {
                dof: one_based(c.dof, "cubic spring")?,
                coefficient: c.coefficient,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let settings = SimSettings {
        step: spec.step,
        substeps: spec.substeps,
        transient_steps: spec.transient_steps,
        recorded_steps: spec.recorded_steps,
    };
    let (mass, stiffness) = (matrix(&spec.mass)?, matrix(&spec.stiffness)?);
    let steps = spec.transient_steps.saturating_add(spec.recorded_steps) as u64;
    let total = steps.saturating_mul(spec.experiments.len() as u64);
    let records = spec
        .experiments
        .iter()
        .enumerate()
        .map(|(k, experiment)| {
            let e = experiment.get_ref();
            let system = System {
                mass: mass.clone(),
                stiffness: stiffness.clone(),
                damping: model.clone(),
                damping_coefficients: truth.iter().map(|(_, v)| *v).collect(),
                conservative: conservative.clone(),
                forcing: vec![HarmonicForce {
                    dof: one_based(e.force_dof, "experiment force")?,
                    amplitude: e.amplitude,
                    frequency: e.frequency,
                    phase: e.phase,
                }],
            };
            let offset = k as u64 * steps;
            let mut parts = simulate_with_progress(&system, &settings, &|done, _| {
                progress(offset + done, total)
            })?
            .into_parts();
            parts.label = format!("a={} ω={} on DOF {}", e.amplitude, e.frequency, e.force_dof);
            Record::new(parts)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((records, truth))
}

/// Reads one record; a `periodic` record without a period or frequency gets one detected
/// from its force, a non-periodic one gets its duration (which nothing uses).
fn read_record(
    spec: &RecordSpec,
    n: usize,
    base: &Path,
    periodic: bool,
) -> Result<(Record, Option<PeriodEstimate>)> {
    let path = base.join(&spec.file);
    let table = crate::io::read_table(&path)?;
    if spec.displacements.len() != n {
        return Err(Error::mismatch(
            "displacement columns vs dofs",
            n,
            spec.displacements.len(),
        ));
    }
    let step = match (&spec.time, spec.step) {
        (Some(time), None) => uniform_step(&table, time)?,
        (None, Some(step)) => step,
        _ => {
            return Err(Error::invalid(
                "step",
                f64::NAN,
                "give exactly one of `time` (a column) or `step`",
            ));
        }
    };
    let columns = |names: &[String]| -> Result<Mat<f64>> {
        let cols = names
            .iter()
            .map(|name| table.column(name))
            .collect::<Result<Vec<_>>>()?;
        Ok(Mat::from_fn(table.rows(), cols.len(), |i, j| cols[j][i]))
    };
    let displacements = columns(&spec.displacements)?;
    let velocities = spec.velocities.as_deref().map(columns).transpose()?;
    let force_names: Vec<String> = spec.forces.iter().map(|f| f.column.clone()).collect();
    let dofs = spec
        .forces
        .iter()
        .map(|f| {
            f.dof
                .checked_sub(1)
                .filter(|d| *d < n)
                .ok_or_else(|| Error::DofOutOfRange {
                    what: format!(
                        "force column '{}' (DOFs are numbered 1..{n} in model files)",
                        f.column
                    ),
                    dof: f.dof,
                    dofs: n,
                })
        })
        .collect::<Result<Vec<_>>>()?;
    let start_time = spec
        .time
        .as_deref()
        .map_or(Ok(0.0), |t| table.column(t).map(|c| c[0]))?;
    let label = spec.label.clone().unwrap_or_else(|| spec.file.clone());
    let signals = columns(&force_names)?;
    let (period, detected) = match (spec.period, spec.frequency) {
        (Some(period), None) => (period, None),
        (None, Some(omega)) => (2.0 * std::f64::consts::PI / omega, None),
        (None, None) if !periodic => (step * (signals.nrows().max(2) - 1) as f64, None),
        (None, None) => {
            let estimate = detect_period(signals.as_ref(), step, &label)?;
            (estimate.period, Some(estimate))
        }
        (Some(period), Some(_)) => {
            return Err(Error::invalid(
                "period",
                period,
                "give at most one of `period` or `frequency` (rad per unit time); with neither, the period is detected from the force",
            ));
        }
    };
    let record = Record::new(RecordParts {
        label,
        step,
        start_time,
        displacements,
        velocities,
        forcing: Forcing::on_dofs(signals, dofs),
        period,
    })?;
    Ok((record, detected))
}

/// The step of a uniformly sampled time column; rows whose spacing departs from it by
/// more than 1e-6 h are reported.
fn uniform_step(table: &Table, name: &str) -> Result<f64> {
    let t = table.column(name)?;
    if t.len() < 2 {
        return Err(Error::Data {
            file: table.file.clone(),
            row: 1,
            column: name.to_string(),
            message: "a time column needs at least two rows".into(),
        });
    }
    let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    for (i, pair) in t.windows(2).enumerate() {
        let dt = pair[1] - pair[0];
        // Values are finite (the table rejects others), so a plain comparison is safe.
        if (dt - step).abs() > 1e-6 * step.abs() || step <= 0.0 {
            return Err(Error::Data {
                file: table.file.clone(),
                row: i + 2,
                column: name.to_string(),
                message: format!("time step {dt} departs from the uniform step {step}"),
            });
        }
    }
    Ok(step)
}
