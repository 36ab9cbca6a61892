//! Candidate damping models named on the command line (`dampid compare MODEL --laws
//! linear,coulomb,linear+coulomb,power:1.5,linear+power:est`): each candidate is one or
//! more laws of the law registry joined by `+`, each on every DOF to ground with one
//! shared coefficient named after the law; `law:p` sets a power law's exponent p, and
//! `law:est` estimates it within [`ESTIMATED_EXPONENT`] from 1 (Brent's bounded search,
//! used for one such law, scans the whole interval), named `<law>.exponent`, by
//! variable projection on the job's equations ([`super::Job::compared`]).

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::regressor::{NonlinearParameter, ParametricModel};
use crate::terms::laws::{LawParameters, Registry};
use crate::terms::{Coefficients, Element, ElementTerm, Term};

/// The bounds of an exponent a candidate estimates (`power:est`): from nearly Coulomb
/// (0.1) to beyond quadratic (5), which covers what joints and dampers show.
pub const ESTIMATED_EXPONENT: [f64; 2] = [0.1, 5.0];

/// The exponent a part of a candidate gives.
#[derive(Debug, Clone, Copy)]
enum Exponent {
    Default,
    Fixed(f64),
    Estimated,
}

/// The model of candidate `spec` (e.g. `linear+power:2.5`) on `dofs` DOFs; an estimated
/// exponent (`power:est`) stands at 1.
pub fn candidate_model(spec: &str, dofs: usize, laws: &Registry) -> Result<DampingModel> {
    candidate(spec, dofs, laws).map(|(model, _)| model)
}

/// The model of candidate `spec` with its estimated exponents, if it has any (`law:est`),
/// as a [`ParametricModel`] (fixed when none is estimated; the model at exponent 1
/// beside it).
pub fn candidate(
    spec: &str,
    dofs: usize,
    laws: &Registry,
) -> Result<(DampingModel, ParametricModel)> {
    let parts = parse(spec)?;
    let estimated: Vec<NonlinearParameter> = parts
        .iter()
        .filter(|(_, e)| matches!(e, Exponent::Estimated))
        .map(|(name, _)| {
            let [lower, upper] = ESTIMATED_EXPONENT;
            NonlinearParameter::new(format!("{name}.exponent"), 1.0, lower, upper)
        })
        .collect();
    let model = build(&parts, dofs, laws, &vec![1.0; estimated.len()])?;
    if estimated.is_empty() {
        return Ok((model.clone(), ParametricModel::fixed(model)));
    }
    let registry = laws.clone();
    let parametric = ParametricModel::new(estimated, move |values: &[f64]| {
        build(&parts, dofs, &registry, values)
    })?;
    Ok((model, parametric))
}

/// The laws of `spec` with their exponents.
fn parse(spec: &str) -> Result<Vec<(String, Exponent)>> {
    spec.split('+')
        .map(str::trim)
        .map(|part| {
            let (name, exponent) = match part.split_once(':') {
                Some((name, p)) if p.trim() == "est" => (name.trim(), Exponent::Estimated),
                Some((name, p)) => {
                    let value: f64 = p.trim().parse().map_err(|_| {
                        Error::choice(
                            "candidate law",
                            format!("'{part}'"),
                            "write law:exponent with a number, e.g. power:1.5, or law:est to estimate it",
                        )
                    })?;
                    (name.trim(), Exponent::Fixed(value))
                }
                None => (part, Exponent::Default),
            };
            if name.is_empty() {
                return Err(Error::choice(
                    "candidate law",
                    format!("'{spec}'"),
                    "an empty law name; join laws with + and separate candidates with ,",
                ));
            }
            Ok((name.to_string(), exponent))
        })
        .collect()
}

/// The model of `parts`, the estimated exponents at `values` (in order).
fn build(
    parts: &[(String, Exponent)],
    dofs: usize,
    laws: &Registry,
    values: &[f64],
) -> Result<DampingModel> {
    let mut model = DampingModel::new();
    let mut values = values.iter();
    for (name, exponent) in parts {
        let mut parameters = LawParameters::new();
        let coefficient = match exponent {
            Exponent::Fixed(p) => {
                parameters = parameters.with("exponent", *p);
                format!("{name}({p})")
            }
            Exponent::Estimated => {
                let p = values
                    .next()
                    .copied()
                    .ok_or_else(|| Error::mismatch("estimated exponents of a candidate", 1, 0))?;
                parameters = parameters.with("exponent", p);
                name.clone()
            }
            Exponent::Default => name.clone(),
        };
        let law = laws.build(name, &parameters)?;
        model = model.with(Term::Elements(ElementTerm::new(
            law,
            Element::each_dof(dofs),
            Coefficients::Shared(coefficient),
        )));
    }
    model.validate(dofs)?;
    Ok(model)
}
