//! The specs of the damping model in a model file: its terms (matrix terms, laws on
//! elements, forces with memory, structural damping), where they act, and their
//! parameters (fixed or estimated).

use std::collections::BTreeMap;

use serde::Deserialize;

/// A matrix: a name from `[matrices]`, a built-in (`identity`, `chain`), or inline rows.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum MatrixRef {
    /// `"identity"`, `"chain"` (tridiag(−1, 2, −1), fixed at both ends) or a name.
    Name(String),
    /// Inline rows.
    Rows(Vec<Vec<f64>>),
}

/// One damping term.
#[derive(Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TermSpec {
    /// C = θ C₀ with a given C₀.
    Viscous {
        /// Coefficient name.
        coefficient: String,
        /// C₀.
        matrix: MatrixRef,
    },
    /// C = θ K.
    StiffnessProportional {
        /// Coefficient name.
        coefficient: String,
        /// K.
        matrix: MatrixRef,
    },
    /// C = θ M.
    MassProportional {
        /// Coefficient name.
        coefficient: String,
        /// M.
        matrix: MatrixRef,
    },
    /// A law on elements.
    Law {
        /// A name from the law registry (`dampid::terms::laws::Registry`): built in,
        /// `linear`, `quadratic`, `coulomb`, `power` or `expression`.
        law: String,
        /// The law's numeric parameters by name, `parameters = { exponent = 1.5 }`, each
        /// a number or estimated, `{ estimate = true, initial = …, lower = …, upper = … }`.
        #[serde(default)]
        parameters: BTreeMap<String, ParameterSpec>,
        /// `exponent = p`, shorthand for `parameters = { exponent = p }` (a power law's).
        exponent: Option<ParameterSpec>,
        /// f(x, v) of a law that takes an expression.
        expression: Option<String>,
        /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
        elements: ElementsSpec,
        /// One shared coefficient with this name …
        coefficient: Option<String>,
        /// … or one per element, named `prefix[label]`.
        per_element: Option<String>,
        /// Element weights (sensor spacing or area).
        weights: Option<Vec<f64>>,
    },
    /// A Bouc–Wen element on elements (`dampid::terms::history`).
    BoucWen(HistorySpec),
    /// A Dahl element on elements.
    Dahl(HistorySpec),
    /// A four-parameter Iwan joint on elements.
    Iwan(HistorySpec),
    /// Structural damping: a loss factor on elements of given stiffness
    /// (`dampid::terms::structural`), periodic windows only.
    Structural(StructuralTermSpec),
}

/// Structural damping on elements: `kind = "structural"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructuralTermSpec {
    /// Each element's stiffness k: one number for every element or a list, one per
    /// element.
    pub stiffness: StiffnessSpec,
    /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
    pub elements: ElementsSpec,
    /// One shared loss factor with this name …
    pub coefficient: Option<String>,
    /// … or one per element, named `prefix[label]`.
    pub per_element: Option<String>,
}

/// The stiffness of structural damping's elements.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum StiffnessSpec {
    /// The same stiffness for every element.
    Each(f64),
    /// One per element, in element order.
    PerElement(Vec<f64>),
}

/// A force with memory on elements: `kind = "bouc_wen"`, `"dahl"` or `"iwan"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistorySpec {
    /// The kind's shape parameters by name (`beta`, `gamma`, `n`; `x_c`, `exponent`;
    /// `phi_max`, `chi`, `beta`), each a number or `{ estimate = true, initial, lower,
    /// upper }`.
    #[serde(default)]
    pub parameters: BTreeMap<String, ParameterSpec>,
    /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
    pub elements: ElementsSpec,
    /// One shared coefficient with this name …
    pub coefficient: Option<String>,
    /// … or one per element, named `prefix[label]`.
    pub per_element: Option<String>,
}

/// A law parameter: a number, or estimated with the coefficients (variable projection,
/// `dampid::varpro`).
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum ParameterSpec {
    /// A fixed value.
    Value(f64),
    /// `{ estimate = true, initial = 1.5, lower = 0.5, upper = 4.0 }`.
    Estimated(EstimatedSpec),
}

/// An estimated law parameter; `initial`, `lower` and `upper` are all required (checked
/// when the term is built, so the error carries the term's line).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatedSpec {
    /// Must be true (a fixed parameter is written as a number).
    pub estimate: bool,
    /// Initial value, within the bounds.
    pub initial: Option<f64>,
    /// Lower bound.
    pub lower: Option<f64>,
    /// Upper bound.
    pub upper: Option<f64>,
}

/// Where a law acts.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum ElementsSpec {
    /// `"each_dof"` or `"chain"`.
    Named(String),
    /// DOF pairs, 1-based, 0 = ground.
    Pairs(Vec<[usize; 2]>),
}
