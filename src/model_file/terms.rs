//! `[[terms]]` as damping terms: matrices by name or inline, laws on elements (DOF
//! pairs 1-based, 0 = ground), shared or per-element coefficients. A law is looked up
//! by name in a law registry and built from its `parameters` table (or the top-level
//! `exponent` shorthand) and `expression`. A parameter written as
//! `{ estimate = true, initial, lower, upper }` is estimated by variable projection
//! (`crate::varpro`): the term becomes a recipe built again at each trial value.
//! `kind = "bouc_wen"`, `"dahl"` and `"iwan"` are history terms
//! ([`crate::terms::history`]) with their shape parameters in `parameters`, fixed or
//! estimated the same way. `kind = "structural"` is a loss factor on elements of given
//! `stiffness` ([`crate::terms::structural`]).

use std::collections::BTreeMap;

use faer::Mat;

use super::spec::{
    ElementsSpec, EstimatedSpec, HistorySpec, MatrixRef, ModelFileSpec, ParameterSpec,
    StiffnessSpec, StructuralTermSpec, TermSpec,
};
use crate::error::{Error, Result};
use crate::simulate::chain_stiffness;
use crate::terms::history::{self, HistoryKind, HistoryTerm};
use crate::terms::laws::{LawParameters, Registry};
use crate::terms::{Coefficients, Element, ElementTerm, StructuralDamping, Term};
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
    /// A history term with estimated shape parameters.
    History {
        kind: &'static HistoryKind,
        /// Every shape parameter's value (the estimated ones' replaced at each trial).
        fixed: Vec<f64>,
        /// (shape parameter index, index into the model's estimated parameters).
        estimated: Vec<(usize, usize)>,
        elements: Vec<Element>,
        coefficients: Coefficients,
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
            TermRecipe::History {
                kind,
                fixed,
                estimated,
                elements,
                coefficients,
            } => {
                let mut values = fixed.clone();
                for &(p, i) in estimated {
                    values[p] = eta[i];
                }
                Ok(Term::History(HistoryTerm::new(
                    (kind.build)(&values)?,
                    elements.clone(),
                    coefficients.clone(),
                )))
            }
        }
    }
}

/// Exactly one of `coefficient` (shared) and `per_element`.
fn coefficients_of(
    coefficient: &Option<String>,
    per_element: &Option<String>,
) -> Result<Coefficients> {
    match (coefficient, per_element) {
        (Some(name), None) => Ok(Coefficients::Shared(name.clone())),
        (None, Some(prefix)) => Ok(Coefficients::PerElement(prefix.clone())),
        (shared, _) => {
            let given = if shared.is_some() {
                "both `coefficient` and `per_element`"
            } else {
                "neither `coefficient` nor `per_element`"
            };
            Err(Error::choice(
                "coefficient",
                given,
                "give exactly one of `coefficient` (shared) or `per_element` (one per element)",
            ))
        }
    }
}

/// The recipe of a history term: its kind's shape parameters from `parameters` (every
/// name known, every required one given), the estimated ones appended to `estimated`.
fn history_recipe(
    name: &str,
    spec: &HistorySpec,
    n: usize,
    estimated: &mut Vec<NonlinearParameter>,
) -> Result<TermRecipe> {
    // cannot fail: the model-file schema only names built-in kinds here.
    let kind = history::kind(name).expect("a built-in history kind");
    let coefficients = coefficients_of(&spec.coefficient, &spec.per_element)?;
    let owner = spec
        .coefficient
        .as_ref()
        .or(spec.per_element.as_ref())
        .cloned()
        .unwrap_or_default();
    let known = || {
        kind.parameters
            .iter()
            .map(|(p, _)| *p)
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(unknown) = spec
        .parameters
        .keys()
        .find(|k| !kind.parameters.iter().any(|(p, _)| p == k))
    {
        return Err(Error::UnknownName {
            what: format!("{name} parameter"),
            name: unknown.clone(),
            known: known(),
        });
    }
    let mut fixed = Vec::with_capacity(kind.parameters.len());
    let mut indices = Vec::new();
    let mut initial = Vec::with_capacity(kind.parameters.len());
    for (p, (parameter, default)) in kind.parameters.iter().enumerate() {
        match (spec.parameters.get(*parameter), default) {
            (Some(ParameterSpec::Value(v)), _) => {
                fixed.push(*v);
                initial.push(*v);
            }
            (Some(ParameterSpec::Estimated(e)), _) => {
                let parameter = estimated_parameter(&owner, parameter, e)?;
                fixed.push(parameter.initial);
                initial.push(parameter.initial);
                indices.push((p, estimated.len()));
                estimated.push(parameter);
            }
            (None, Some(d)) => {
                fixed.push(*d);
                initial.push(*d);
            }
            (None, None) => {
                return Err(Error::missing(
                    format!("{name} parameter '{parameter}'"),
                    &format!(
                        "a {name} term needs its shape parameters ({}) in `parameters`, each a number or {{ estimate = true, initial, lower, upper }}",
                        known()
                    ),
                ));
            }
        }
    }
    // the element must build at its initial values (values it refuses are reported
    // here, at the term's line)
    (kind.build)(&initial)?;
    Ok(TermRecipe::History {
        kind,
        fixed,
        estimated: indices,
        elements: build_elements(&spec.elements, n)?,
        coefficients,
    })
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
            let coefficients = coefficients_of(coefficient, per_element)?;
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
        TermSpec::BoucWen(h) => history_recipe("bouc_wen", h, n, estimated)?,
        TermSpec::Dahl(h) => history_recipe("dahl", h, n, estimated)?,
        TermSpec::Iwan(h) => history_recipe("iwan", h, n, estimated)?,
        TermSpec::Structural(s) => TermRecipe::Fixed(structural_term(s, n)?),
    })
}

/// Structural damping: the elements, one stiffness each (a number for all or a list
/// as long as the elements, each finite and > 0) and the loss factors' sharing.
fn structural_term(spec: &StructuralTermSpec, n: usize) -> Result<Term> {
    let coefficients = coefficients_of(&spec.coefficient, &spec.per_element)?;
    let elements = build_elements(&spec.elements, n)?;
    let stiffness = match &spec.stiffness {
        StiffnessSpec::Each(k) => vec![*k; elements.len()],
        StiffnessSpec::PerElement(list) => list.clone(),
    };
    let term = StructuralDamping::new(elements, stiffness, coefficients);
    term.validate(n)?;
    Ok(Term::Structural(term))
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
