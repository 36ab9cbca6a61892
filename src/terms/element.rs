//! Elements: where a damping law acts. An element joins DOF a to DOF b (a dashpot on
//! relative motion x_a − x_b) or DOF a to ground (motion x_a). The force f acts as +f
//! on a and −f on b, so its power is (v_a − v_b) f: the element's relative velocity
//! times its force.

use crate::error::{Error, Result};

/// One element of a connectivity.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Element {
    /// First DOF (0-based).
    pub a: usize,
    /// Second DOF, or `None` for ground.
    pub b: Option<usize>,
    /// Label used in coefficient names, e.g. "2-3" in `dashpot[2-3]`.
    pub label: String,
}

impl Element {
    /// DOF `dof` to ground; label is the 1-based DOF number.
    pub fn to_ground(dof: usize) -> Self {
        Element {
            a: dof,
            b: None,
            label: format!("{}", dof + 1),
        }
    }

    /// A dashpot between DOFs `a` and `b`; label "a-b" with 1-based numbers.
    pub fn between(a: usize, b: usize) -> Self {
        Element {
            a,
            b: Some(b),
            label: format!("{}-{}", a + 1, b + 1),
        }
    }

    /// Replaces the label.
    pub fn labelled(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    /// Every DOF 0..n to ground (per-DOF laws).
    pub fn each_dof(n: usize) -> Vec<Element> {
        (0..n).map(Element::to_ground).collect()
    }

    /// A chain of n DOFs fixed to walls at both ends: n + 1 dashpots labelled
    /// "0-1", "1-2", …, "n-(n+1)" (walls numbered 0 and n + 1, as in the paper's figures).
    pub fn chain_fixed_both_ends(n: usize) -> Vec<Element> {
        if n == 0 {
            return Vec::new();
        }
        let mut elements = vec![Element::to_ground(0).labelled("0-1")];
        elements.extend((0..n - 1).map(|i| Element::between(i, i + 1)));
        elements.push(Element::to_ground(n - 1).labelled(format!("{}-{}", n, n + 1)));
        elements
    }

    pub(crate) fn validate(&self, dofs: usize, what: &str) -> Result<()> {
        for dof in std::iter::once(self.a).chain(self.b) {
            if dof >= dofs {
                return Err(Error::dof_index(
                    format!("{what} element [{}]", self.label),
                    dof,
                    dofs,
                ));
            }
        }
        if self.b == Some(self.a) {
            return Err(Error::invalid(
                "element",
                self.a as f64,
                &format!(
                    "element [{}] joins DOF {} to itself",
                    self.label,
                    self.a + 1
                ),
            ));
        }
        Ok(())
    }
}
