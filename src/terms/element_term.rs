//! A law acting on a set of elements, with one shared coefficient or one per element.
//!
//! Column of element e: ∫ v_e f(x_e, v_e) dt ≈ Σ_i w_i v_e(t_i) f(x_e(t_i), v_e(t_i)),
//! where x_e, v_e are the element's relative displacement and velocity, times the
//! element's weight ω_e (1 by default; a sensor's spacing or area for a continuum,
//! turning Σ_e into a spatial quadrature of the distributed law). A shared
//! coefficient's column is the weighted sum over elements.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::terms::element::Element;
use crate::terms::law::Law;
use crate::terms::on_elements::{Coefficients, OnElements};

/// A damping law on elements.
#[derive(Debug, Clone)]
pub struct ElementTerm {
    law: Arc<dyn Law>,
    elements: Vec<Element>,
    coefficients: Coefficients,
    weights: Option<Vec<f64>>,
}

impl ElementTerm {
    /// The law `law` on `elements`, sharing coefficients as `coefficients` says.
    pub fn new(law: Arc<dyn Law>, elements: Vec<Element>, coefficients: Coefficients) -> Self {
        ElementTerm {
            law,
            elements,
            coefficients,
            weights: None,
        }
    }

    /// Gives element e the weight `weights[e]` (spacing or area of a sensor); the law's
    /// force and power on that element are multiplied by it.
    pub fn with_weights(mut self, weights: Vec<f64>) -> Self {
        self.weights = Some(weights);
        self
    }

    /// The element weights, if any.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }

    fn weight(&self, e: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[e])
    }

    /// The law.
    pub fn law(&self) -> &dyn Law {
        self.law.as_ref()
    }

    pub(crate) fn validate(&self, dofs: usize) -> Result<()> {
        let what = format!("{} term", self.law.name());
        self.validate_elements(dofs, &what)?;
        if let Some(weights) = &self.weights {
            let what = format!("element weights of the {what}");
            if weights.len() != self.elements.len() {
                return Err(Error::mismatch(
                    format!("{what} vs elements"),
                    self.elements.len(),
                    weights.len(),
                ));
            }
            if let Some((row, &value)) = weights.iter().enumerate().find(|(_, w)| !w.is_finite()) {
                return Err(Error::NonFinite {
                    what,
                    row,
                    column: 0,
                    value,
                });
            }
            if let Some((k, &value)) = weights.iter().enumerate().find(|(_, w)| **w < 0.0) {
                return Err(Error::invalid(
                    &format!("weight of element {} in the {what}", k + 1),
                    value,
                    "an element weight scales a dissipative law and must be zero or positive: a negative weight would make the element supply energy",
                ));
            }
        }
        Ok(())
    }

    pub(crate) fn add_force(&self, coefficients: &[f64], x: &[f64], v: &[f64], out: &mut [f64]) {
        for (k, e) in self.elements.iter().enumerate() {
            let theta = match self.coefficients {
                Coefficients::Shared(_) => coefficients[0],
                Coefficients::PerElement(_) => coefficients[k],
            };
            let (xr, vr) = match e.b {
                None => (x[e.a], v[e.a]),
                Some(b) => (x[e.a] - x[b], v[e.a] - v[b]),
            };
            let f = theta * self.weight(k) * self.law.force(xr, vr);
            out[e.a] += f;
            if let Some(b) = e.b {
                out[b] -= f;
            }
        }
    }
}

impl OnElements for ElementTerm {
    fn elements(&self) -> &[Element] {
        &self.elements
    }

    fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }
}
