//! What the outer loop minimises and where it ends: the projected residual r(η) of one
//! trial, whose squared norm φ(η) = ‖r(η)‖² is the cost, and the minimum reached
//! (shared by Brent in `outer.rs` and Levenberg–Marquardt in `levenberg_marquardt.rs`).

use crate::error::Result;

/// The cost φ(η) of one trial.
pub(super) type Cost<'a> = &'a dyn Fn(&[f64]) -> Result<f64>;

/// The projected residual r(η) of one trial (its squared norm is the cost).
pub(super) type Residuals<'a> = &'a dyn Fn(&[f64]) -> Result<Vec<f64>>;

/// The Jacobian's column of η_j at η (η, j, and h the step of a difference) where the
/// problem knows ∂A/∂η_j (`None`: difference whole trials).
pub(super) type Shifted<'a> = &'a dyn Fn(&[f64], usize, f64) -> Result<Option<Column>>;

/// A column of the projected residual's Jacobian (`projected_jacobian.rs`).
pub(super) enum Column {
    /// ∂r/∂η_j, exact.
    Derivative(Vec<f64>),
    /// The projected residual at η + h e_j, from the fit of A(η) + h ∂A/∂η_j (a
    /// forward difference).
    Shifted(Vec<f64>),
}

/// Where the outer loop ended.
pub(super) struct Minimum {
    pub values: Vec<f64>,
    pub converged: bool,
    pub iterations: u64,
    pub method: &'static str,
    pub reason: String,
}
