//! History terms: damping forces with memory. The force of one element is
//!
//! ```text
//!   F(t) = θ s(t),    s(t) = S[x_e](t),
//! ```
//!
//! a coefficient θ times a functional S of the element's relative displacement x_e
//! along its whole path (Bouc–Wen, Dahl, an Iwan joint), not a function of the present
//! (x, v). This is where [`crate::terms::Law`] ends: a law's force at a sample is
//! f(x_i, v_i), so the kernel sums it block by block in any order; a history force
//! needs the state at the block's first sample, which only the path before it knows.
//!
//! All three built-in kinds are rate-independent: the state moves with dx alone
//! (dz/dx, never dz/dt), so it is advanced exactly or to high order along the record's
//! own displacement samples, the path between two samples taken as a straight line
//! ([`Hysteresis::step`]); no velocity and no time step enter the state.
//!
//! In a window of whole periods the force per unit coefficient is taken on the
//! periodic orbit (`orbit.rs`): the state runs through the window's period again and
//! again until it repeats. The regressor then sums it like a force channel,
//! A_e = Σ_i w_i v_e,i s_i (`crate::regressor`'s periodic rows).
//!
//! Kinds, one file each: Bouc–Wen (`bouc_wen.rs`), Dahl (`dahl.rs`), the
//! four-parameter Iwan joint of Segalman (`iwan.rs`).

pub mod bouc_wen;
pub mod dahl;
pub mod iwan;
pub mod orbit;

use crate::terms::on_elements::{Coefficients, OnElements};
use std::fmt;
use std::sync::Arc;

pub use bouc_wen::BoucWen;
pub use dahl::Dahl;
pub use iwan::Iwan;

use crate::error::{Error, Result};
use crate::terms::element::Element;

/// A hysteretic element: a state advanced along the displacement and the force per
/// unit coefficient it gives.
pub trait Hysteresis: Send + Sync + fmt::Debug {
    /// The kind as model files name it ("bouc_wen", "dahl", "iwan").
    fn kind(&self) -> &'static str;

    /// A readable name with the shape parameters.
    fn name(&self) -> String;

    /// Number of state variables.
    fn state_len(&self) -> usize;

    /// The virgin state at displacement `x` (the element unloaded there).
    fn start(&self, x: f64, state: &mut [f64]);

    /// Advances `state` along the straight path from displacement `x0` to `x1`.
    fn step(&self, state: &mut [f64], x0: f64, x1: f64);

    /// The force per unit coefficient in `state` at displacement `x`.
    fn force(&self, state: &[f64], x: f64) -> f64;

    /// The size of the state for a displacement amplitude `amplitude` (the scale of
    /// the periodic-orbit tolerance): a displacement for Bouc–Wen and Iwan, 1 for Dahl.
    fn state_scale(&self, amplitude: f64) -> f64;
}

/// A hysteretic element kind on elements (a DOF to ground or a pair of DOFs, acting on
/// their relative displacement), one shared coefficient or one per element.
#[derive(Debug, Clone)]
pub struct HistoryTerm {
    hysteresis: Arc<dyn Hysteresis>,
    elements: Vec<Element>,
    coefficients: Coefficients,
    max_passes: usize,
}

impl HistoryTerm {
    /// `hysteresis` on `elements`, sharing coefficients as `coefficients` says.
    pub fn new(
        hysteresis: Arc<dyn Hysteresis>,
        elements: Vec<Element>,
        coefficients: Coefficients,
    ) -> Self {
        HistoryTerm {
            hysteresis,
            elements,
            coefficients,
            max_passes: orbit::MAX_PASSES,
        }
    }

    /// At most `passes` passes through a window's period to reach the periodic orbit
    /// (default [`orbit::MAX_PASSES`]); more is an [`Error::NoPeriodicOrbit`].
    pub fn with_max_passes(mut self, passes: usize) -> Self {
        self.max_passes = passes;
        self
    }

    /// The cap on passes through a window's period.
    pub fn max_passes(&self) -> usize {
        self.max_passes
    }

    /// The hysteretic element.
    pub fn hysteresis(&self) -> &dyn Hysteresis {
        self.hysteresis.as_ref()
    }

    pub(crate) fn validate(&self, dofs: usize) -> Result<()> {
        let what = format!("{} term", self.hysteresis.kind());
        self.validate_elements(dofs, &what)?;
        if self.max_passes == 0 {
            return Err(Error::invalid(
                &format!("max_passes of the {what}"),
                0.0,
                "the state needs at least one pass through the window's period",
            ));
        }
        Ok(())
    }
}

impl OnElements for HistoryTerm {
    fn elements(&self) -> &[Element] {
        &self.elements
    }

    fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }
}

/// A shape parameter that must be finite and within `(lower, upper)` (open ends when
/// `open`), as an [`Error::InvalidParameter`] naming the kind, the parameter and why.
pub(crate) fn require(kind: &str, name: &str, value: f64, ok: bool, expected: &str) -> Result<()> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(Error::invalid(
            &format!("{kind} parameter '{name}'"),
            value,
            expected,
        ))
    }
}

/// One history kind as model files name it: its shape parameters (name and default,
/// `None` when required), a description and a constructor from their values in that
/// order. [`KINDS`] lists the built-in ones.
#[derive(Debug, Clone, Copy)]
pub struct HistoryKind {
    /// `kind = "…"` in a model file.
    pub name: &'static str,
    /// Shape parameters in constructor order, each with its default.
    pub parameters: &'static [(&'static str, Option<f64>)],
    /// The linear coefficient the term's column multiplies.
    pub coefficient: &'static str,
    /// One line: the force and its state equation.
    pub description: &'static str,
    /// The element at these parameter values.
    pub build: fn(&[f64]) -> Result<Arc<dyn Hysteresis>>,
}

/// The built-in history kinds, one per file of this folder.
pub const KINDS: &[HistoryKind] = &[
    HistoryKind {
        name: "bouc_wen",
        parameters: &[("beta", None), ("gamma", None), ("n", Some(1.0))],
        coefficient: "α (force per unit z, a stiffness)",
        description: "f = α z, ż = v − β|v||z|^{n−1}z − γ v|z|^n (A = 1: z in displacement units)",
        build: |p| Ok(Arc::new(BoucWen::new(p[0], p[1], p[2])?)),
    },
    HistoryKind {
        name: "dahl",
        parameters: &[("x_c", None), ("exponent", Some(1.0))],
        coefficient: "F_c (the Coulomb force)",
        description: "f = F_c ẑ, dẑ/dx = (1 − ẑ sgn ẋ)^i / x_c, x_c = F_c/σ",
        build: |p| Ok(Arc::new(Dahl::new(p[0], p[1])?)),
    },
    HistoryKind {
        name: "iwan",
        parameters: &[("phi_max", None), ("chi", None), ("beta", None)],
        coefficient: "K_T (the joint's stiffness)",
        description: "Segalman's four-parameter Iwan joint: density R φ^χ on [0, φ_max] + S δ(φ − φ_max), β = S/(R φ_max^{χ+1}/(χ+1))",
        build: |p| Ok(Arc::new(Iwan::new(p[0], p[1], p[2])?)),
    },
];

/// The built-in kind named `name`.
pub fn kind(name: &str) -> Option<&'static HistoryKind> {
    KINDS.iter().find(|k| k.name == name)
}
