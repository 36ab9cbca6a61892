//! `[[terms]]` as damping terms: matrices by name or inline, laws on elements (DOF
//! pairs 1-based, 0 = ground), shared or per-element coefficients. A law is looked up
//! by name in a law registry and built from its `parameters` table (or the top-level
//! `exponent` shorthand) and `expression`.

use std::collections::BTreeMap;

use faer::Mat;

use super::spec::{ElementsSpec, MatrixRef, ModelFileSpec, TermSpec};
use crate::error::{Error, Result};
use crate::simulate::chain_stiffness;
use crate::terms::laws::{LawParameters, Registry};
use crate::terms::{Coefficients, Element, ElementTerm, Term};

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

pub(super) fn build_term(
    spec: &TermSpec,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
    laws: &Registry,
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
            parameters,
            exponent,
            expression,
            elements,
            coefficient,
            per_element,
            weights,
        } => {
            let law = laws.build(
                law,
                &law_parameters(parameters, *exponent, expression.as_deref())?,
            )?;
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
            let term = ElementTerm::new(law, build_elements(elements, n)?, coefficients);
            Term::Elements(match weights {
                Some(w) => term.with_weights(w.clone()),
                None => term,
            })
        }
    })
}

/// A law's parameters: the `parameters` table, the top-level `exponent` (shorthand for
/// `parameters = { exponent = p }`, which it may not repeat) and the `expression`.
fn law_parameters(
    table: &BTreeMap<String, f64>,
    exponent: Option<f64>,
    expression: Option<&str>,
) -> Result<LawParameters> {
    let mut parameters = table
        .iter()
        .fold(LawParameters::new(), |p, (name, &value)| {
            p.with(name.clone(), value)
        });
    if let Some(p) = exponent {
        if table.contains_key("exponent") {
            return Err(Error::invalid(
                "exponent",
                p,
                "given twice: as `exponent` and in `parameters`",
            ));
        }
        parameters = parameters.with("exponent", p);
    }
    if let Some(text) = expression {
        parameters = parameters.with_expression(text);
    }
    Ok(parameters)
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
