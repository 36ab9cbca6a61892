//! The whole pipeline on arbitrary records: a `Record` built from fuzzed dims, step,
//! period and values (harmonic motion, constants, raw bytes, with any entry patched to
//! NaN, ±Inf, zero or a huge value), an arbitrary damping model (its laws picked from
//! the law registry by index, so a new law is fuzzed as soon as it is registered, with
//! arbitrary parameters and one of `EXPRESSIONS`), arbitrary settings and
//! constraints, then `identify`, or in the non-periodic mode (arbitrary window, skip,
//! rule, velocity, work form, kinetic and potential energy models and offsets)
//! `nonperiodic::build` and the fit. Any `Err` is fine (a force that reads zero, as
//! `Fill::Constant` and empty `Fill::Raw` often give, is `NoInputWork`, and a model
//! whose columns all vanish is `NoInformation`); a panic is a bug, and so is a fit that
//! claims success with a non-finite coefficient or calls coefficients determined below
//! a positive threshold (`support::check`).
//!
//! Sizes are capped (4 DOFs, 400 samples, 4 terms) to keep executions fast; the cap is
//! the harness's, not the library's.

#![no_main]

use arbitrary::{Arbitrary, Unstructured};
use dampid::fit::{Bound, Constraints, Fixed};
use dampid::prelude::*;
use dampid::regressor::SpanWindows;
use dampid::regressor::WorkForm;
use dampid::regressor::nonperiodic::{Kinetic, Potential, StorageModel};
use dampid::regressor::{NoiseTreatment, RegressorSettings, Windows};
use dampid::terms::ElementTerm;
use dampid::terms::laws::{BUILTIN, by_name};
use faer::Mat;
use libfuzzer_sys::fuzz_target;

mod support;

const MAX_DOFS: usize = 4;
const MAX_SAMPLES: usize = 400;
const MAX_TERMS: usize = 4;

/// A scalar: raw bits (anything, NaN and ±Inf included) or a tame value k/16.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Scalar {
    Raw(f64),
    Tame(u8),
}

impl Scalar {
    fn value(self) -> f64 {
        match self {
            Scalar::Raw(v) => v,
            Scalar::Tame(k) => f64::from(k) / 16.0,
        }
    }
}

/// How a block of N × c values is filled.
#[derive(Arbitrary, Debug)]
enum Fill {
    /// a_j cos(ω t + φ_j) + b_j cos(3ω t): periodic motion.
    Harmonic {
        amplitudes: Vec<Scalar>,
        phases: Vec<u8>,
        third: Vec<Scalar>,
    },
    /// Every entry the same.
    Constant(Scalar),
    /// Raw values, repeated to fill.
    Raw(Vec<f64>),
}

#[derive(Arbitrary, Debug)]
struct Block {
    fill: Fill,
    /// (row, column, value) overwrites.
    patches: Vec<(u16, u8, f64)>,
}

impl Block {
    fn build(&self, rows: usize, cols: usize, omega: f64, step: f64) -> Mat<f64> {
        let mut m = Mat::from_fn(rows, cols, |i, j| match &self.fill {
            Fill::Harmonic {
                amplitudes,
                phases,
                third,
            } => {
                let a = amplitudes.get(j).map_or(1.0, |s| s.value());
                let phi = phases.get(j).map_or(0.0, |&p| f64::from(p) / 40.0);
                let b = third.get(j).map_or(0.0, |s| s.value());
                let t = i as f64 * step;
                a * (omega * t + phi).cos() + b * (3.0 * omega * t).cos()
            }
            Fill::Constant(s) => s.value(),
            Fill::Raw(values) if values.is_empty() => 0.0,
            Fill::Raw(values) => values[(i * cols + j) % values.len()],
        });
        if rows > 0 && cols > 0 {
            for &(i, j, v) in self.patches.iter().take(8) {
                m[(usize::from(i) % rows, usize::from(j) % cols)] = v;
            }
        }
        m
    }
}

#[derive(Arbitrary, Debug)]
enum ForcingChoice {
    Generalized(Block),
    OnDofs {
        signals: Block,
        dofs: Vec<u8>,
    },
    Distributed {
        signals: Block,
        channels: u8,
        rows: u8,
        matrix: Vec<f64>,
    },
}

#[derive(Arbitrary, Debug)]
enum MatrixChoice {
    Identity,
    Chain,
    Raw {
        rows: u8,
        cols: u8,
        values: Vec<f64>,
    },
}

/// A built-in law: `BUILTIN[law % BUILTIN.len()]`, its declared parameters taken in
/// order from `parameters` (1 when too few are given), and `EXPRESSIONS[expression %
/// EXPRESSIONS.len()]` when it takes an expression.
#[derive(Arbitrary, Debug)]
struct LawChoice {
    law: u8,
    parameters: Vec<Scalar>,
    expression: u8,
}

impl LawChoice {
    fn build(&self) -> dampid::Result<std::sync::Arc<dyn Law>> {
        let registration = &BUILTIN[usize::from(self.law) % BUILTIN.len()];
        let mut parameters = LawParameters::new();
        for (k, &name) in registration.parameters().iter().enumerate() {
            let value = self.parameters.get(k).map_or(1.0, |s| s.value());
            parameters = parameters.with(name, value);
        }
        if registration.takes_expression() {
            let text = EXPRESSIONS[usize::from(self.expression) % EXPRESSIONS.len()];
            parameters = parameters.with_expression(text);
        }
        by_name(registration.name(), &parameters)
    }
}

const EXPRESSIONS: [&str; 6] = [
    "sign(v)*abs(v)^1.5",
    "x^2*v",
    "v/x",
    "ln(abs(v))",
    "exp(v*v)",
    "1",
];

#[derive(Arbitrary, Debug)]
enum ElementsChoice {
    EachDof,
    Chain,
    Pairs(Vec<(u8, Option<u8>)>),
}

#[derive(Arbitrary, Debug)]
enum TermChoice {
    Viscous(u8, MatrixChoice),
    Stiffness(u8, MatrixChoice),
    Mass(u8, MatrixChoice),
    Law {
        name: u8,
        law: LawChoice,
        elements: ElementsChoice,
        per_element: bool,
        weights: Option<Vec<f64>>,
    },
}

#[derive(Arbitrary, Debug)]
enum VelocityChoice {
    Measured,
    CentralDifference,
    Spectral(Option<u8>),
    HarmonicProjection(Option<u8>),
}

#[derive(Arbitrary, Debug)]
struct Settings {
    quadrature: u8,
    velocity: VelocityChoice,
    skip: u16,
    cycles: u8,
    count: Option<u8>,
    nonnegative: bool,
    bounds: Vec<(u8, Option<f64>, Option<f64>)>,
    fixed: Vec<(u8, f64)>,
    rank_tolerance: Option<Scalar>,
    solver_tolerance: Option<f64>,
    max_iterations: Option<u8>,
    polish: bool,
    non_periodic: Option<NonPeriodicChoice>,
}

/// The non-periodic mode's settings.
#[derive(Arbitrary, Debug)]
struct NonPeriodicChoice {
    /// Window in samples (tame: 1 + k) times the step, or a raw length.
    window: Scalar,
    skip: u16,
    trapezoid: bool,
    measured: bool,
    derivative_free: bool,
    kinetic: KineticChoice,
    potential: PotentialChoice,
    offsets: Vec<u8>,
}

#[derive(Arbitrary, Debug)]
enum KineticChoice {
    LumpedPerDof,
    Known(MatrixChoice),
    Neglected,
}

#[derive(Arbitrary, Debug)]
enum PotentialChoice {
    Neglected,
    Chain,
    Known(MatrixChoice),
}

#[derive(Arbitrary, Debug)]
struct Experiment {
    samples: u16,
    step: Scalar,
    /// Samples per period (tame: 2 + k/7), or the raw period.
    period: Scalar,
    start_time: Scalar,
    displacements: Block,
    velocities: Option<Block>,
    forcing: ForcingChoice,
}

#[derive(Debug)]
struct Input {
    dofs: usize,
    experiments: Vec<Experiment>,
    terms: Vec<TermChoice>,
    settings: Settings,
}

impl<'a> Arbitrary<'a> for Input {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        let dofs = 1 + usize::from(u.arbitrary::<u8>()?) % MAX_DOFS;
        let count = 1 + usize::from(u.arbitrary::<u8>()?) % 3;
        let experiments = (0..count)
            .map(|_| u.arbitrary())
            .collect::<arbitrary::Result<_>>()?;
        let terms = u
            .arbitrary_iter()?
            .take(MAX_TERMS)
            .collect::<arbitrary::Result<_>>()?;
        Ok(Input {
            dofs,
            experiments,
            terms,
            settings: u.arbitrary()?,
        })
    }
}

fn matrix(choice: &MatrixChoice, n: usize) -> Mat<f64> {
    match choice {
        MatrixChoice::Identity => Mat::identity(n, n),
        MatrixChoice::Chain => dampid::simulate::chain_stiffness(n),
        MatrixChoice::Raw { rows, cols, values } => {
            // Mostly n × n; any size up to MAX_DOFS + 1 otherwise.
            let r = if *rows < 200 {
                n
            } else {
                usize::from(*rows) % (MAX_DOFS + 2)
            };
            let c = if *cols < 200 {
                n
            } else {
                usize::from(*cols) % (MAX_DOFS + 2)
            };
            Mat::from_fn(r, c, |i, j| {
                if values.is_empty() {
                    0.0
                } else {
                    values[(i * c + j) % values.len()]
                }
            })
        }
    }
}

fn name(k: u8) -> String {
    format!("c{}", k % 6)
}

fn term(choice: &TermChoice, n: usize) -> Option<Term> {
    Some(match choice {
        TermChoice::Viscous(k, m) => Term::viscous(name(*k), matrix(m, n)),
        TermChoice::Stiffness(k, m) => Term::stiffness_proportional(name(*k), matrix(m, n)),
        TermChoice::Mass(k, m) => Term::mass_proportional(name(*k), matrix(m, n)),
        TermChoice::Law {
            name: k,
            law,
            elements,
            per_element,
            weights,
        } => {
            let elements = match elements {
                ElementsChoice::EachDof => Element::each_dof(n),
                ElementsChoice::Chain => Element::chain_fixed_both_ends(n),
                ElementsChoice::Pairs(pairs) => pairs
                    .iter()
                    .take(8)
                    .map(|&(a, b)| {
                        let a = usize::from(a) % (n + 1);
                        match b {
                            None => Element::to_ground(a),
                            Some(b) => Element::between(a, usize::from(b) % (n + 1)),
                        }
                    })
                    .collect(),
            };
            let coefficients = if *per_element {
                Coefficients::PerElement(name(*k))
            } else {
                Coefficients::Shared(name(*k))
            };
            let term = ElementTerm::new(law.build().ok()?, elements, coefficients);
            Term::Elements(match weights {
                // Any count and any values: the library checks them.
                Some(w) => term.with_weights(w.iter().take(9).copied().collect()),
                None => term,
            })
        }
    })
}

fn record(e: &Experiment, n: usize) -> dampid::Result<Record> {
    let samples = usize::from(e.samples) % (MAX_SAMPLES + 1);
    let step = match e.step {
        Scalar::Tame(k) => (1.0 + f64::from(k)) / 64.0,
        Scalar::Raw(v) => v,
    };
    let period = match e.period {
        Scalar::Tame(k) => step * (2.0 + f64::from(k) / 7.0),
        Scalar::Raw(v) => v,
    };
    let omega = 2.0 * std::f64::consts::PI / period;
    let forcing = match &e.forcing {
        ForcingChoice::Generalized(b) => Forcing::generalized(b.build(samples, n, omega, step)),
        ForcingChoice::OnDofs { signals, dofs } => {
            let dofs: Vec<usize> = dofs
                .iter()
                .take(4)
                .map(|&d| usize::from(d) % (n + 2))
                .collect();
            let channels = dofs.len().max(1);
            Forcing::on_dofs(signals.build(samples, channels, omega, step), dofs)
        }
        ForcingChoice::Distributed {
            signals,
            channels,
            rows,
            matrix,
        } => {
            let c = 1 + usize::from(*channels) % 3;
            let r = if *rows < 200 {
                n
            } else {
                usize::from(*rows) % (MAX_DOFS + 2)
            };
            let d = Mat::from_fn(r, c, |i, j| {
                if matrix.is_empty() {
                    1.0
                } else {
                    matrix[(i * c + j) % matrix.len()]
                }
            });
            Forcing::distributed(signals.build(samples, c, omega, step), d)
        }
    };
    Record::new(RecordParts {
        label: "fuzz".into(),
        step,
        start_time: e.start_time.value(),
        displacements: e.displacements.build(samples, n, omega, step),
        velocities: e
            .velocities
            .as_ref()
            .map(|b| b.build(samples, n, omega, step)),
        forcing,
        period,
    })
}

fn settings(s: &Settings, names: &[String]) -> IdentifySettings {
    let pick = |k: u8| {
        names
            .get(usize::from(k) % (names.len() + 1))
            .cloned()
            .unwrap_or_else(|| "unknown".into())
    };
    let mut settings = IdentifySettings::default();
    settings.regressor.quadrature = match s.quadrature % 3 {
        0 => Quadrature::Rectangular,
        1 => Quadrature::Trapezoid,
        _ => Quadrature::Spectral,
    };
    settings.regressor.velocity = match s.velocity {
        VelocityChoice::Measured => VelocitySource::Measured,
        VelocityChoice::CentralDifference => VelocitySource::CentralDifference,
        VelocityChoice::Spectral(k) => VelocitySource::Spectral {
            harmonics: k.map(usize::from),
        },
        VelocityChoice::HarmonicProjection(k) => VelocitySource::HarmonicProjection {
            harmonics: k.map(usize::from),
        },
    };
    settings.regressor.windows = WindowSpec {
        skip: usize::from(s.skip),
        cycles: usize::from(s.cycles % 8),
        count: s.count.map(usize::from),
    }
    .into();
    settings.fit.constraints = Constraints {
        nonnegative: s.nonnegative,
        bounds: s
            .bounds
            .iter()
            .take(4)
            .map(|&(k, lower, upper)| Bound {
                name: pick(k),
                lower,
                upper,
            })
            .collect(),
        fixed: s
            .fixed
            .iter()
            .take(4)
            .map(|&(k, value)| Fixed {
                name: pick(k),
                value,
            })
            .collect(),
        ..Constraints::default()
    };
    if let Some(t) = s.rank_tolerance {
        settings.fit.rank_tolerance = t.value();
    }
    if let Some(t) = s.solver_tolerance {
        settings.fit.solver.tolerance = t;
    }
    if let Some(m) = s.max_iterations {
        settings.fit.solver.max_iterations = u32::from(m);
    }
    settings.fit.solver.polish = s.polish;
    settings
}

/// The fixed spans of the non-periodic mode, with their rule, velocities and work form.
fn non_periodic(choice: &NonPeriodicChoice, n: usize, step: f64) -> RegressorSettings {
    RegressorSettings {
        windows: Windows::Spans(SpanWindows {
            length: match choice.window {
                Scalar::Tame(k) => (1.0 + f64::from(k)) * step,
                Scalar::Raw(v) => v,
            },
            skip: usize::from(choice.skip),
            storage: storage(choice, n),
        }),
        noise: NoiseTreatment::Auto,
        quadrature: if choice.trapezoid {
            Quadrature::Trapezoid
        } else {
            Quadrature::Rectangular
        },
        velocity: if choice.measured {
            VelocitySource::Measured
        } else {
            VelocitySource::CentralDifference
        },
        work_form: if choice.derivative_free {
            WorkForm::DerivativeFree
        } else {
            WorkForm::Velocity
        },
    }
}

fn storage(choice: &NonPeriodicChoice, n: usize) -> StorageModel {
    StorageModel {
        kinetic: match &choice.kinetic {
            KineticChoice::LumpedPerDof => Kinetic::LumpedPerDof,
            KineticChoice::Known(m) => Kinetic::Known(matrix(m, n)),
            KineticChoice::Neglected => Kinetic::Neglected,
        },
        potential: match &choice.potential {
            PotentialChoice::Neglected => Potential::Neglected,
            PotentialChoice::Chain => Potential::Elements(Element::chain_fixed_both_ends(n)),
            PotentialChoice::Known(m) => Potential::Known(matrix(m, n)),
        },
        offsets: choice
            .offsets
            .iter()
            .take(3)
            .map(|&d| usize::from(d) % (n + 2))
            .collect(),
    }
}

fuzz_target!(|input: Input| {
    let n = input.dofs;
    let Ok(records) = input
        .experiments
        .iter()
        .map(|e| record(e, n))
        .collect::<dampid::Result<Vec<_>>>()
    else {
        return;
    };
    let Some(terms) = input
        .terms
        .iter()
        .map(|t| term(t, n))
        .collect::<Option<Vec<_>>>()
    else {
        return;
    };
    let model = terms
        .into_iter()
        .fold(DampingModel::new(), DampingModel::with);
    let mut settings = settings(&input.settings, &model.coefficient_names());
    if let Some(choice) = &input.settings.non_periodic {
        let step = records.first().map_or(1.0, Record::step);
        settings.regressor = non_periodic(choice, n, step);
    }
    if let Ok(found) = identify(
        &ParametricRegressor::linear(&model, &records),
        &settings,
        &silent,
    ) {
        support::check(&found.report);
    }
});
