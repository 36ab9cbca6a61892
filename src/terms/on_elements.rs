//! What every term on elements shares (a law's [`super::ElementTerm`], a force with
//! memory's [`super::HistoryTerm`], structural damping's [`super::StructuralDamping`]):
//! its elements (a DOF to ground or a pair of DOFs) and how they share coefficients,
//! one shared or one per element ([`Coefficients`]). Column k of the term belongs to
//! element e when `column_of(e) = k`: 0 for a shared coefficient, e for one per element.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::terms::element::Element;

/// How the elements of a term share coefficients.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Coefficients {
    /// One coefficient with this name for every element.
    Shared(String),
    /// One coefficient per element, named `prefix[label]`.
    PerElement(String),
}

impl Coefficients {
    /// The coefficients' names for `elements`: the shared name once, or `prefix[label]`
    /// per element.
    pub(crate) fn names(&self, elements: &[Element]) -> Vec<String> {
        match self {
            Coefficients::Shared(name) => vec![name.clone()],
            Coefficients::PerElement(prefix) => elements
                .iter()
                .map(|e| {
                    // "prefix[label]" without the format machinery: thousands of
                    // columns name themselves on every build.
                    let mut name = String::with_capacity(prefix.len() + e.label.len() + 2);
                    name.push_str(prefix);
                    name.push('[');
                    name.push_str(&e.label);
                    name.push(']');
                    name
                })
                .collect(),
        }
    }

    /// How many coefficients on `elements`: one shared, or one per element.
    pub(crate) fn count(&self, elements: usize) -> usize {
        match self {
            Coefficients::Shared(_) => 1,
            Coefficients::PerElement(_) => elements,
        }
    }

    /// The column of element `index` within the term's columns.
    pub(crate) fn column_of(&self, index: usize) -> usize {
        match self {
            Coefficients::Shared(_) => 0,
            Coefficients::PerElement(_) => index,
        }
    }
}

/// A term on elements.
pub trait OnElements {
    /// The elements.
    fn elements(&self) -> &[Element];

    /// The sharing of coefficients.
    fn coefficients(&self) -> &Coefficients;

    /// The coefficients' names: the shared name, or `prefix[label]` per element.
    fn coefficient_names(&self) -> Vec<String> {
        self.coefficients().names(self.elements())
    }

    /// How many coefficients: one shared, or one per element.
    fn coefficient_count(&self) -> usize {
        self.coefficients().count(self.elements().len())
    }

    /// The column of element `index` (an offset within the term's columns).
    fn column_of(&self, index: usize) -> usize {
        self.coefficients().column_of(index)
    }

    /// At least one element, each on DOFs of a model of `dofs` (`what` names the term
    /// in errors).
    fn validate_elements(&self, dofs: usize, what: &str) -> Result<()> {
        if self.elements().is_empty() {
            return Err(Error::Empty {
                what: format!("element list of the {what}"),
            });
        }
        self.elements()
            .iter()
            .try_for_each(|e| e.validate(dofs, what))
    }
}
