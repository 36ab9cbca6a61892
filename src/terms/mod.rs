//! The term library. A term is one damping mechanism with one or more unknown
//! coefficients θ_k; its only job is the window integral of the power per coefficient,
//! ∫ vᵀ f_k(x, v) dt, which becomes one regressor column. The same term also gives the
//! damping force Σ θ_k f_k(x, v), which the simulator uses.
//!
//! Three kinds: a matrix (θ C₀), a memoryless [`Law`] on elements (f(x, v)), and a
//! force with memory on elements ([`history`]: Bouc–Wen, Dahl, Iwan), whose force per
//! unit coefficient is a functional of the path, computed per window on its periodic
//! orbit; and structural damping ([`structural`]: a loss factor on elements of given
//! stiffness, its force per unit loss factor −k H\[x_e\] a functional of the window's
//! periodic motion).

pub mod element;
pub mod element_term;
pub mod harmonic_work;
pub mod history;
pub mod lanes;
pub mod law;
pub mod laws;
pub mod matrix_term;
pub mod on_elements;
pub mod simd;
pub mod structural;

use std::sync::Arc;

use faer::Mat;

pub use element::Element;
pub use element_term::ElementTerm;
pub use history::{HistoryTerm, Hysteresis};
pub use law::{ElementMotion, Law, PowerForm, Weights};
pub use matrix_term::{MatrixKind, MatrixTerm};
pub use on_elements::{Coefficients, OnElements};
pub use structural::StructuralDamping;

use crate::error::Result;

/// One damping mechanism.
#[derive(Debug, Clone)]
pub enum Term {
    /// A damping matrix with one coefficient.
    Matrix(MatrixTerm),
    /// A law on elements.
    Elements(ElementTerm),
    /// A force with memory (Bouc–Wen, Dahl, Iwan) on elements: computed along each
    /// window's period on its periodic orbit ([`history`]), periodic windows only.
    History(HistoryTerm),
    /// Structural damping: a loss factor on elements of given stiffness, its force per
    /// unit loss factor −k H\[x_e\] in each window of whole periods ([`structural`]),
    /// periodic windows only.
    Structural(StructuralDamping),
}

impl Term {
    /// Viscous damping C = θ C₀ with a given C₀; coefficient `name`.
    pub fn viscous(name: impl Into<String>, c0: Mat<f64>) -> Self {
        Term::Matrix(MatrixTerm::new(name, MatrixKind::Viscous, c0))
    }

    /// Stiffness-proportional damping C = θ K; coefficient `name`.
    pub fn stiffness_proportional(name: impl Into<String>, stiffness: Mat<f64>) -> Self {
        Term::Matrix(MatrixTerm::new(
            name,
            MatrixKind::StiffnessProportional,
            stiffness,
        ))
    }

    /// Mass-proportional damping C = θ M; coefficient `name`.
    pub fn mass_proportional(name: impl Into<String>, mass: Mat<f64>) -> Self {
        Term::Matrix(MatrixTerm::new(name, MatrixKind::MassProportional, mass))
    }

    /// `law` on `elements` (dashpots on a connectivity, or DOFs to ground).
    pub fn on_elements(
        law: impl Law + 'static,
        elements: Vec<Element>,
        coefficients: Coefficients,
    ) -> Self {
        Term::Elements(ElementTerm::new(Arc::new(law), elements, coefficients))
    }

    /// `law` on `elements` with element weights (sensor spacing or area, for a
    /// distributed law sampled at sensors).
    pub fn weighted(
        law: impl Law + 'static,
        elements: Vec<Element>,
        weights: Vec<f64>,
        coefficients: Coefficients,
    ) -> Self {
        Term::Elements(
            ElementTerm::new(Arc::new(law), elements, coefficients).with_weights(weights),
        )
    }

    /// The hysteretic element `hysteresis` on `elements`.
    pub fn history(
        hysteresis: impl Hysteresis + 'static,
        elements: Vec<Element>,
        coefficients: Coefficients,
    ) -> Self {
        Term::History(HistoryTerm::new(
            Arc::new(hysteresis),
            elements,
            coefficients,
        ))
    }

    /// Structural damping: a loss factor on each of `elements`, element i of stiffness
    /// `stiffness[i]` ([`structural`]).
    pub fn structural(
        elements: Vec<Element>,
        stiffness: Vec<f64>,
        coefficients: Coefficients,
    ) -> Self {
        Term::Structural(StructuralDamping::new(elements, stiffness, coefficients))
    }

    /// `law` from each of DOFs 0..n to ground.
    pub fn per_dof(law: impl Law + 'static, dofs: usize, coefficients: Coefficients) -> Self {
        Self::on_elements(law, Element::each_dof(dofs), coefficients)
    }

    /// Names of this term's coefficients, in column order.
    pub fn coefficient_names(&self) -> Vec<String> {
        match self {
            Term::Matrix(t) => t.coefficient_names(),
            Term::Elements(t) => t.coefficient_names(),
            Term::History(t) => t.coefficient_names(),
            Term::Structural(t) => t.coefficient_names(),
        }
    }

    /// Number of coefficients (without formatting their names: the simulator asks for
    /// it at every force evaluation).
    pub fn coefficient_count(&self) -> usize {
        match self {
            Term::Matrix(_) => 1,
            Term::Elements(t) => t.coefficient_count(),
            Term::History(t) => t.coefficient_count(),
            Term::Structural(t) => t.coefficient_count(),
        }
    }

    pub(crate) fn validate(&self, dofs: usize) -> Result<()> {
        match self {
            Term::Matrix(t) => t.validate(dofs),
            Term::Elements(t) => t.validate(dofs),
            Term::History(t) => t.validate(dofs),
            Term::Structural(t) => t.validate(dofs),
        }
    }

    /// Adds the damping force Σ_k θ_k f_k(x, v) to `out` (length n). A history
    /// or structural term has no force at (x, v) alone and adds nothing: the simulator
    /// refuses models that hold one (`System::validate`).
    pub(crate) fn add_force(&self, coefficients: &[f64], x: &[f64], v: &[f64], out: &mut [f64]) {
        match self {
            Term::Matrix(t) => t.add_force(coefficients, v, out),
            Term::Elements(t) => t.add_force(coefficients, x, v, out),
            Term::History(_) | Term::Structural(_) => {}
        }
    }
}
