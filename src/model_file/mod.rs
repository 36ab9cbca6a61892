//! Model files: one TOML file describes the damping model (terms on elements or
//! matrices, shared or per-element coefficients, custom laws as expressions), how to
//! identify (windows, quadrature, velocity source, constraints), and where the records
//! come from: a `[simulation]` section that generates them (so a model file runs on a
//! fresh machine) or a `[data]` section that reads measured CSV files.
//!
//! Errors carry the file and the line and column of the offending table or key.

mod spec;

use std::path::Path;

use faer::Mat;
use toml::Spanned;

pub use spec::*;

use crate::design::DesignSettings;
use crate::error::{Error, Result};
use crate::fit::{Bound, Constraints, Fixed, LinearConstraint, LinearTerm};
use crate::identify::IdentifySettings;
use crate::io::csv_table::Table;
use crate::model::DampingModel;
use crate::record::{Forcing, Record, RecordParts};
use crate::reference::chain_stiffness;
use crate::regressor::RegressorSettings;
use crate::simulate::{ConservativeForce, HarmonicForce, SimSettings, System, simulate};
use crate::terms::laws::{Coulomb, Expression, Linear, PowerLaw, Quadratic};
use crate::terms::{Coefficients, Element, Term};
use crate::velocity::VelocitySource;
use crate::window::WindowSpec;

/// Everything a model file asks for, ready to run.
#[derive(Debug)]
pub struct Job {
    /// Title for reports.
    pub title: String,
    /// The damping model.
    pub model: DampingModel,
    /// The records (simulated or read).
    pub records: Vec<Record>,
    /// Identification settings.
    pub settings: IdentifySettings,
    /// True coefficients, in model order, when the records were simulated.
    pub truth: Option<Vec<(String, f64)>>,
    /// Experiment-design settings from `[design]` (start indices 0-based).
    pub design: Option<DesignSettings>,
}

/// Reads and builds the model file at `path` (data paths are relative to its folder).
pub fn load(path: &Path) -> Result<Job> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::ModelFile {
        file: path.display().to_string(),
        line: 0,
        column: 0,
        message: e.to_string(),
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse(&text, &path.display().to_string(), base)
}

/// Parses model-file `text` (named `file` in errors) and builds the job.
pub fn parse(text: &str, file: &str, base: &Path) -> Result<Job> {
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
    context.build(&spec, base)
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

    fn build(&self, spec: &ModelFileSpec, base: &Path) -> Result<Job> {
        let n = spec.dofs;
        if n == 0 {
            return Err(Error::ModelFile {
                file: self.file.to_string(),
                line: 0,
                column: 0,
                message: "dofs must be at least 1".into(),
            });
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
        let settings = identification_settings(&spec.identification);
        let (records, truth) = match (&spec.simulation, &spec.data) {
            (Some(sim), None) => {
                let (records, truth) = self.at(sim, |s| simulate_records(s, &model, n, &matrix))?;
                (records, Some(truth))
            }
            (None, Some(data)) => (self.read_records(data, n, base)?, None),
            _ => {
                return Err(Error::ModelFile {
                    file: self.file.to_string(),
                    line: 0,
                    column: 0,
                    message: "give exactly one of [simulation] (generate the records) or [data] (read them)".into(),
                });
            }
        };
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
            settings,
            truth,
            design,
        })
    }

    fn read_records(&self, data: &Spanned<DataSpec>, n: usize, base: &Path) -> Result<Vec<Record>> {
        data.get_ref()
            .records
            .iter()
            .map(|r| self.at(r, |spec| read_record(spec, n, base)))
            .collect()
    }
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

fn identification_settings(spec: &IdentificationSpec) -> IdentifySettings {
    let velocity = match spec.velocity {
        VelocityName::Measured => VelocitySource::Measured,
        VelocityName::CentralDifference => VelocitySource::CentralDifference,
        VelocityName::Spectral => VelocitySource::Spectral {
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
        },
        ..IdentifySettings::default()
    };
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

fn simulate_records(
    spec: &SimulationSpec,
    model: &DampingModel,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<(Vec<Record>, Truth)> {
    let names = model.coefficient_names();
    for name in spec.coefficients.keys() {
        if !names.contains(name) {
            return Err(Error::UnknownCoefficient {
                name: name.clone(),
                known: names.join(", "),
            });
        }
    }
    let truth: Truth = names
        .iter()
        .map(|name| {
            spec.coefficients
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
        .collect::<Result<_>>()?;
    let one_based = |dof: usize, what: &str| {
        dof.checked_sub(1)
            .filter(|d| *d < n)
            .ok_or_else(|| Error::DofOutOfRange {
                what: format!("{what} (DOFs are numbered 1..{n} in model files)"),
                dof,
                dofs: n,
            })
    };
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
    let records = spec
        .experiments
        .iter()
        .map(|experiment| {
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
            let mut parts = simulate(&system, &settings)?.into_parts();
            parts.label = format!("a={} ω={} on DOF {}", e.amplitude, e.frequency, e.force_dof);
            Record::new(parts)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((records, truth))
}

fn read_record(spec: &RecordSpec, n: usize, base: &Path) -> Result<Record> {
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
    let period = match (spec.period, spec.frequency) {
        (Some(period), None) => period,
        (None, Some(omega)) => 2.0 * std::f64::consts::PI / omega,
        _ => {
            return Err(Error::invalid(
                "period",
                f64::NAN,
                "give exactly one of `period` or `frequency` (rad per unit time)",
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
    Record::new(RecordParts {
        label: spec.label.clone().unwrap_or_else(|| spec.file.clone()),
        step,
        start_time,
        displacements,
        velocities,
        forcing: Forcing::on_dofs(columns(&force_names)?, dofs),
        period,
    })
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
