//! `[[terms]]` as damping terms: matrices by name or inline, laws on elements (DOF
//! pairs 1-based, 0 = ground), shared or per-element coefficients. A law is looked up
//! by name in a law registry and built from its `parameters` table (or the top-level
//! `exponent` shorthand) and `expression`. A parameter written as
//! `{ estimate = true, initial, lower, upper }` is estimated by variable projection
//! (`crate::varpro`): the term becomes a recipe built again at each trial value.

use std::collections::BTreeMap;

use faer::Mat;

use super::spec::{ElementsSpec, EstimatedSpec, MatrixRef, ModelFileSpec, ParameterSpec, TermSpec};
use crate::error::{Error, Result};
use crate::simulate::chain_stiffness;
use crate::terms::laws::{LawParameters, Registry};
use crate::terms::{Coefficients, Element, ElementTerm, Term};
use crate::varpro::NonlinearParameter;

pub(super) fn resolve_matrix(
    reference: &MatrixRef,
    spec: &ModelFileSpec,
    n: usize,
) -> Result<Mat<f64>> {
    if matches!(reference, MatrixRef::Name(_)) {
        crate::budget::require(
            &format!("a {n} × {n} matrix"),
            crate::budget::f64s((n as u128).pow(2)),
            "reduce `dofs`; systems of many DOFs are reduced with [pod] or described by elements",
        )?;
    }
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

/// A term as the model file describes it, ready to build at any values of its
/// estimated law parameters (a term without any builds one fixed [`Term`]).
#[derive(Debug, Clone)]
pub(super) enum TermRecipe {
    /// A term without estimated parameters.
    Fixed(Term),
    /// A law term with estimated parameters.
    Law {
        laws: Registry,
        law: String,
        fixed: LawParameters,
        /// (law parameter name, index into the model's estimated parameters).
        estimated: Vec<(String, usize)>,
        elements: Vec<Element>,
        coefficients: Coefficients,
        weights: Option<Vec<f64>>,
    },
}

impl TermRecipe {
    /// The term at `eta`, the values of every estimated parameter of the model.
    pub(super) fn build(&self, eta: &[f64]) -> Result<Term> {
        match self {
            TermRecipe::Fixed(term) => Ok(term.clone()),
            TermRecipe::Law {
                laws,
                law,
                fixed,
                estimated,
                elements,
                coefficients,
                weights,
            } => {
                let parameters = estimated
                    .iter()
                    .fold(fixed.clone(), |p, (name, i)| p.with(name.clone(), eta[*i]));
                let law = laws.build(law, &parameters)?;
                Ok(law_term(
                    law,
                    elements.clone(),
                    coefficients.clone(),
                    weights,
                ))
            }
        }
    }
}

fn law_term(
    law: std::sync::Arc<dyn crate::terms::Law>,
    elements: Vec<Element>,
    coefficients: Coefficients,
    weights: &Option<Vec<f64>>,
) -> Term {
    let term = ElementTerm::new(law, elements, coefficients);
    Term::Elements(match weights {
        Some(w) => term.with_weights(w.clone()),
        None => term,
    })
}

/// The recipe of one `[[terms]]` block; its estimated parameters are appended to
/// `estimated`, named `<coefficient>.<parameter>` (the shared coefficient's name or the
/// per-element prefix).
pub(super) fn build_term(
    spec: &TermSpec,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
    laws: &Registry,
    estimated: &mut Vec<NonlinearParameter>,
) -> Result<TermRecipe> {
    Ok(match spec {
        TermSpec::Viscous {
            coefficient,
            matrix: m,
        } => TermRecipe::Fixed(Term::viscous(coefficient.clone(), matrix(m)?)),
        TermSpec::StiffnessProportional {
            coefficient,
            matrix: m,
        } => TermRecipe::Fixed(Term::stiffness_proportional(
            coefficient.clone(),
            matrix(m)?,
        )),
        TermSpec::MassProportional {
            coefficient,
            matrix: m,
        } => TermRecipe::Fixed(Term::mass_proportional(coefficient.clone(), matrix(m)?)),
        TermSpec::Law {
            law,
            parameters,
            exponent,
            expression,
            elements,
            coefficient,
            per_element,
            weights,
        } => {
            let coefficients = match (coefficient, per_element) {
                (Some(name), None) => Coefficients::Shared(name.clone()),
                (None, Some(prefix)) => Coefficients::PerElement(prefix.clone()),
                (shared, _) => {
                    let given = if shared.is_some() {
                        "both `coefficient` and `per_element`"
                    } else {
                        "neither `coefficient` nor `per_element`"
                    };
                    return Err(Error::choice(
                        "coefficient",
                        given,
                        "give exactly one of `coefficient` (shared) or `per_element` (one per element)",
                    ));
                }
            };
            let owner = coefficient
                .as_ref()
                .or(per_element.as_ref())
                .cloned()
                .unwrap_or_default();
            let (fixed, free) =
                law_parameters(parameters, exponent.as_ref(), expression.as_deref())?;
            let elements = build_elements(elements, n)?;
            if free.is_empty() {
                let law = laws.build(law, &fixed)?;
                return Ok(TermRecipe::Fixed(law_term(
                    law,
                    elements,
                    coefficients,
                    weights,
                )));
            }
            let mut indices = Vec::with_capacity(free.len());
            let mut initial = fixed.clone();
            for (name, spec) in free {
                let parameter = estimated_parameter(&owner, &name, &spec)?;
                initial = initial.with(name.clone(), parameter.initial);
                indices.push((name, estimated.len()));
                estimated.push(parameter);
            }
            // the law must build at its initial values (unknown parameter names and
            // values the law refuses are reported here, at the term's line)
            laws.build(law, &initial)?;
            TermRecipe::Law {
                laws: laws.clone(),
                law: law.clone(),
                fixed,
                estimated: indices,
                elements,
                coefficients,
                weights: weights.clone(),
            }
        }
    })
}

/// An estimated parameter's spec as a [`NonlinearParameter`] named `owner.name`:
/// `estimate = true` and `initial`, `lower`, `upper` all given, the bounds ordered and
/// the initial value within them.
fn estimated_parameter(
    owner: &str,
    name: &str,
    spec: &EstimatedSpec,
) -> Result<NonlinearParameter> {
    let full = format!("{owner}.{name}");
    if !spec.estimate {
        return Err(Error::choice(
            &format!("estimate of parameter '{name}'"),
            "false",
            "a fixed parameter is written as a number; a table asks for `estimate = true`",
        ));
    }
    let need = |value: Option<f64>, key: &str| {
        value.ok_or_else(|| {
            Error::missing(
                format!("`{key}` of estimated parameter '{name}'"),
                "an estimated parameter needs `initial`, `lower` and `upper`",
            )
        })
    };
    let parameter = NonlinearParameter::new(
        full,
        need(spec.initial, "initial")?,
        need(spec.lower, "lower")?,
        need(spec.upper, "upper")?,
    );
    parameter.validate()?;
    Ok(parameter)
}

/// A law's parameters: the `parameters` table, the top-level `exponent` (shorthand for
/// `parameters = { exponent = p }`, which it may not repeat) and the `expression`; the
/// fixed ones as [`LawParameters`], the estimated ones by name.
fn law_parameters(
    table: &BTreeMap<String, ParameterSpec>,
    exponent: Option<&ParameterSpec>,
    expression: Option<&str>,
) -> Result<(LawParameters, Vec<(String, EstimatedSpec)>)> {
    let mut parameters = LawParameters::new();
    let mut estimated = Vec::new();
    let mut add = |name: &str, spec: &ParameterSpec| match spec {
        ParameterSpec::Value(value) => {
            parameters = std::mem::take(&mut parameters).with(name.to_string(), *value)
        }
        ParameterSpec::Estimated(e) => estimated.push((name.to_string(), e.clone())),
    };
    for (name, spec) in table {
        add(name, spec);
    }
    if let Some(p) = exponent {
        if table.contains_key("exponent") {
            let value = match p {
                ParameterSpec::Value(v) => *v,
                ParameterSpec::Estimated(e) => e.initial.unwrap_or(f64::NAN),
            };
            return Err(Error::invalid(
                "exponent",
                value,
                "given twice: as `exponent` and in `parameters`",
            ));
        }
        add("exponent", p);
    }
    if let Some(text) = expression {
        parameters = parameters.with_expression(text);
    }
    Ok((parameters, estimated))
}

pub(super) fn build_elements(spec: &ElementsSpec, n: usize) -> Result<Vec<Element>> {
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
                        return Err(Error::choice(
                            "element",
                            "[0, 0]",
                            "it joins ground to ground",
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
