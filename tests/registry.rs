//! The law registry, used the way a newcomer adds a law: a cubic law f = v³ written in
//! this file, registered in one line, named in a model file parsed with the extended
//! registry, simulated and identified, and its regressor column checked against its
//! closed form. Then: unknown names list the known ones (a registered law included);
//! `parameters = { exponent = p }` and the top-level `exponent = p` build the same power
//! law; wrong parameters get typed errors naming them; README's law table is the
//! registry.
//!
//! The cubic law's cycle integral, for x = X cos ωt, v = −Xω sin ωt over T = 2π/ω:
//!
//!   ∮ v · v³ dt = ∮ v⁴ dt = X⁴ω⁴ ∫_0^T sin⁴ωt dt = X⁴ω⁴ · (3/8) T = (3π/4) ω³ X⁴,
//!
//! since sin⁴θ = 3/8 − cos 2θ / 2 + cos 4θ / 8, whose mean over a period is 3/8.

mod support;

use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

use dampid::Error;
use dampid::model_file::{Job, Options, parse};
use dampid::prelude::*;
use dampid::terms::ElementTerm;
use dampid::terms::laws::{BUILTIN, NAMES, by_name};
use support::{Harmonic, rel, row};

/// Cubic damping, f(v) = v³: a law dampid does not have.
#[derive(Debug)]
struct Cubic;

impl Law for Cubic {
    fn name(&self) -> String {
        "cubic".into()
    }
    fn force(&self, _x: f64, v: f64) -> f64 {
        v * v * v
    }
    fn weighted_power(&self, _x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        w.iter().zip(v).map(|(w, v)| w * v.powi(4)).sum()
    }
}

const CUBIC: LawRegistration = LawRegistration::new("cubic", "f = v³", |_| Ok(Arc::new(Cubic)));

/// A unit oscillator, m = k = 1, with cubic damping c₃ v³ = 0.4 v³, driven below
/// resonance at two amplitudes; identified from measured velocities.
const CUBIC_MODEL: &str = r#"
dofs = 1

[[terms]]
kind = "law"
law = "cubic"
elements = "each_dof"
coefficient = "c3"

[identification]
velocity = "measured"
quadrature = "trapezoid"

[simulation]
mass = [[1.0]]
stiffness = [[1.0]]
coefficients = { c3 = 0.4 }
step = 0.02
transient_steps = 5000
recorded_steps = 800
experiments = [
    { force_dof = 1, amplitude = 0.3, frequency = 0.8 },
    { force_dof = 1, amplitude = 0.6, frequency = 0.8 },
]
"#;

fn parse_text(text: &str) -> dampid::Result<Job> {
    parse(text, "test.toml", Path::new("models"), Default::default())
}

/// The model-file error's line and message, after checking it names test.toml.
fn line_and_message(error: Error) -> (usize, String) {
    match error {
        Error::ModelFile {
            file,
            line,
            column,
            message,
            ..
        } => {
            assert_eq!(file, "test.toml");
            assert!(column >= 1, "{message}");
            (line, message)
        }
        other => panic!("expected a model-file error, got {other:?}"),
    }
}

/// A one-DOF law term (the `[[terms]]` table on line 2) with `keys` added, and data
/// from no record.
fn law_term(keys: &str) -> String {
    format!(
        "dofs = 1\n[[terms]]\nkind = \"law\"\n{keys}\nelements = \"each_dof\"\ncoefficient = \"k\"\n[data]\nrecords = []\n"
    )
}

#[test]
fn a_law_written_in_a_test_file_and_registered_in_one_line_is_simulated_and_identified() {
    let laws = Registry::builtin().with(CUBIC);
    let job = parse(
        CUBIC_MODEL,
        "cubic.toml",
        Path::new("models"),
        Options {
            laws: Some(&laws),
            ..Default::default()
        },
    )
    .unwrap();
    let report = identify(&job.problem(), &job.settings, &silent)
        .unwrap()
        .report;
    let estimate = report.coefficient("c3").unwrap();
    assert!(rel(estimate, 0.4) < 1e-6, "c3 = {estimate}");
}

#[test]
fn a_registered_law_column_is_three_pi_over_four_omega_cubed_x_to_the_fourth() {
    let laws = Registry::builtin().with(CUBIC);
    let job = parse(
        CUBIC_MODEL,
        "cubic.toml",
        Path::new("models"),
        Options {
            laws: Some(&laws),
            ..Default::default()
        },
    )
    .unwrap();
    let (x, w) = (1.3, 0.9);
    let record = Harmonic::one_dof(x, w, 400.0).record();
    let exact = 3.0 * PI / 4.0 * w.powi(3) * x.powi(4);
    for rule in [Quadrature::Rectangular, Quadrature::Trapezoid] {
        let (a, _) = row(&job.model, &record, rule, VelocitySource::Measured);
        // v⁴ is a trigonometric polynomial of degree 4: exact with 400 samples a period.
        assert!(rel(a[0], exact) < 1e-12, "{rule:?}: {} vs {exact}", a[0]);
    }
}

#[test]
fn an_unknown_law_name_lists_every_built_in_law_at_the_terms_line() {
    let (line, message) = line_and_message(parse_text(CUBIC_MODEL).unwrap_err());
    assert_eq!(line, 4, "{message}");
    assert!(
        message
            .contains("unknown law 'cubic'; known: linear, quadratic, coulomb, power, expression"),
        "{message}"
    );
    match by_name("cubic", &LawParameters::new()) {
        Err(Error::UnknownName { what, name, known }) => {
            assert_eq!((what.as_str(), name.as_str()), ("law", "cubic"));
            assert_eq!(known, NAMES.join(", "));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn an_unknown_law_name_lists_the_laws_a_program_registered() {
    let laws = Registry::builtin().with(CUBIC);
    let text = law_term("law = \"quartic\"");
    let error = parse(
        &text,
        "test.toml",
        Path::new("."),
        Options {
            laws: Some(&laws),
            ..Default::default()
        },
    )
    .unwrap_err();
    let (line, message) = line_and_message(error);
    assert_eq!(line, 2, "{message}");
    assert!(
        message.contains("known: linear, quadratic, coulomb, power, expression, cubic"),
        "{message}"
    );
    match laws.build("quartic", &LawParameters::new()) {
        Err(Error::UnknownName { known, .. }) => assert!(known.ends_with(", cubic"), "{known}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_registry_builds_the_power_law_its_constructor_builds() {
    let record = Harmonic::one_dof(1.1, 1.4, 500.0).record();
    let model = |law: Arc<dyn Law>| {
        DampingModel::new().with(Term::Elements(ElementTerm::new(
            law,
            Element::each_dof(1),
            Coefficients::Shared("k".into()),
        )))
    };
    let registered = by_name("power", &LawParameters::new().with("exponent", 1.5)).unwrap();
    assert_eq!(registered.name(), "power(1.5)");
    let direct = Arc::new(PowerLaw::new(1.5).unwrap());
    for rule in [Quadrature::Trapezoid, Quadrature::Spectral] {
        let (a, _) = row(
            &model(registered.clone()),
            &record,
            rule,
            VelocitySource::Measured,
        );
        let (b, _) = row(
            &model(direct.clone()),
            &record,
            rule,
            VelocitySource::Measured,
        );
        assert_eq!(a[0].to_bits(), b[0].to_bits(), "{rule:?}");
    }
}

#[test]
fn the_parameters_table_and_the_top_level_exponent_give_the_same_power_law() {
    let simulated = |keys: &str| {
        CUBIC_MODEL
            .replace("law = \"cubic\"", &format!("law = \"power\"\n{keys}"))
            .replace("c3 = 0.4", "c3 = 0.2")
    };
    let from_table = parse_text(&simulated("parameters = { exponent = 2.5 }")).unwrap();
    let from_key = parse_text(&simulated("exponent = 2.5")).unwrap();
    for job in [&from_table, &from_key] {
        match &job.model.terms()[0] {
            Term::Elements(term) => assert_eq!(term.law().name(), "power(2.5)"),
            other => panic!("{other:?}"),
        }
    }
    let regressor = |job: &Job| job.initial_regressor().unwrap();
    let (a, b) = (regressor(&from_table), regressor(&from_key));
    assert_eq!(a.matrix().nrows(), b.matrix().nrows());
    for i in 0..a.matrix().nrows() {
        assert_eq!(a.matrix()[(i, 0)].to_bits(), b.matrix()[(i, 0)].to_bits());
        assert_eq!(a.rhs()[i].to_bits(), b.rhs()[i].to_bits());
    }
}

#[test]
fn an_exponent_given_both_ways_is_rejected() {
    let text = law_term("law = \"power\"\nexponent = 1.5\nparameters = { exponent = 1.5 }");
    let (line, message) = line_and_message(parse_text(&text).unwrap_err());
    assert_eq!(line, 5, "at the key's line");
    assert!(
        message.contains("invalid exponent = 1.5: given twice"),
        "{message}"
    );
}

#[test]
fn a_missing_parameter_is_a_missing_error_naming_it() {
    match by_name("power", &LawParameters::new()) {
        Err(Error::Missing { name, reason }) => {
            assert_eq!(name, "exponent");
            assert!(
                reason.contains("the power law needs `exponent`"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    let (line, message) = line_and_message(parse_text(&law_term("law = \"power\"")).unwrap_err());
    assert_eq!(line, 2);
    assert!(message.contains("needs `exponent`"), "{message}");
}

#[test]
fn a_parameter_the_law_does_not_declare_is_an_invalid_parameter_naming_it() {
    match by_name(
        "power",
        &LawParameters::new().with("exponent", 1.0).with("gain", 2.0),
    ) {
        Err(Error::InvalidParameter { name, value, .. }) => {
            assert_eq!((name.as_str(), value), ("gain", 2.0));
        }
        other => panic!("{other:?}"),
    }
    // The legacy top-level exponent on a law without one.
    let (line, message) =
        line_and_message(parse_text(&law_term("law = \"linear\"\nexponent = 2.0")).unwrap_err());
    assert_eq!(line, 5, "at the key's line");
    assert!(
        message.contains("the linear law has no parameter `exponent`; its parameters: none"),
        "{message}"
    );
    let (_, message) = line_and_message(
        parse_text(&law_term(
            "law = \"power\"\nparameters = { exponent = 1.0, exponnent = 2.0 }",
        ))
        .unwrap_err(),
    );
    assert!(
        message.contains("invalid exponnent = 2: the power law has no parameter `exponnent`; its parameters: exponent"),
        "{message}"
    );
}

#[test]
fn an_expression_given_to_a_law_that_takes_none_is_an_invalid_choice_named_expression() {
    match by_name("quadratic", &LawParameters::new().with_expression("v")) {
        Err(Error::InvalidChoice {
            name,
            given,
            reason,
            ..
        }) => {
            assert_eq!((name.as_str(), given.as_str()), ("expression", "v"));
            assert!(
                reason.contains("the quadratic law takes no `expression`"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    let text = law_term("law = \"coulomb\"\nexpression = \"sign(v)\"");
    let (line, message) = line_and_message(parse_text(&text).unwrap_err());
    assert_eq!(line, 5, "at the key's line");
    assert!(message.contains("takes no `expression`"), "{message}");
}

#[test]
fn an_expression_law_without_its_text_is_an_expression_error() {
    match by_name("expression", &LawParameters::new()) {
        Err(Error::Expression {
            expression,
            message,
        }) => {
            assert_eq!(expression, "");
            assert!(message.contains("needs `expression"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let law = by_name("expression", &LawParameters::new().with_expression("x^2*v")).unwrap();
    assert_eq!(law.force(3.0, 2.0), 18.0);
}

#[test]
fn registering_a_name_again_replaces_the_law_in_place() {
    const LOUD_LINEAR: LawRegistration = LawRegistration::new("linear", "f = 2v", |_| {
        Ok(Arc::new(Custom::new("2v", |_, v| 2.0 * v)))
    });
    let laws = Registry::builtin().with(LOUD_LINEAR);
    assert_eq!(laws.names(), NAMES);
    assert_eq!(laws.get("linear").unwrap().description(), "f = 2v");
    let law = laws.build("linear", &LawParameters::new()).unwrap();
    assert_eq!(law.force(0.0, 1.5), 3.0);
}

#[test]
fn built_in_names_are_unique_and_every_built_in_law_builds() {
    let registry = Registry::builtin();
    assert_eq!(registry.names(), NAMES);
    for (k, name) in NAMES.iter().enumerate() {
        assert!(!NAMES[..k].contains(name), "{name} twice");
    }
    for registration in BUILTIN {
        let mut parameters = LawParameters::new();
        for &parameter in registration.parameters() {
            parameters = parameters.with(parameter, 1.0);
        }
        if registration.takes_expression() {
            parameters = parameters.with_expression("v");
        }
        let law = registry.build(registration.name(), &parameters).unwrap();
        assert_eq!(law.force(0.0, 0.0), 0.0, "{}", registration.name());
    }
}

/// README.md's law table has one row per built-in law, in registry order, with its
/// parameters, whether it takes an expression and its description (`|` escaped).
#[test]
fn the_readme_law_table_is_the_registry() {
    let readme = std::fs::read_to_string("README.md").unwrap();
    let header = "| law | parameters | expression | force |";
    let table: Vec<&str> = readme
        .lines()
        .skip_while(|l| *l != header)
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .collect();
    let expected: Vec<String> = BUILTIN
        .iter()
        .map(|r| {
            let parameters: Vec<String> = r.parameters().iter().map(|p| format!("`{p}`")).collect();
            let cells = [
                format!("`{}`", r.name()),
                parameters.join(", "),
                if r.takes_expression() { "required" } else { "" }.to_string(),
                r.description().replace('|', "\\|"),
            ];
            let cells: Vec<String> = cells
                .iter()
                .map(|c| {
                    if c.is_empty() {
                        " |".into()
                    } else {
                        format!(" {c} |")
                    }
                })
                .collect();
            format!("|{}", cells.concat())
        })
        .collect();
    assert_eq!(table, expected);
}
