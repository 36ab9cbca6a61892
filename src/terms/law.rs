//! A damping law: the force f(x, v) of one element as a function of its relative
//! displacement x and relative velocity v, and the power it dissipates, v · f(x, v).
//!
//! A new law is one file in `laws/` implementing [`Law`]; nothing else changes.

use std::fmt;

/// A scalar damping law on one element. Coefficients multiply the force; a law has none.
pub trait Law: Send + Sync + fmt::Debug {
    /// A short readable name ("linear", "quadratic", "power(1.5)").
    fn name(&self) -> String;

    /// The damping force per unit coefficient, f(x, v).
    fn force(&self, x: f64, v: f64) -> f64;

    /// Whether f depends on x. When false, [`Law::weighted_power`] receives an empty `x`.
    fn uses_displacement(&self) -> bool {
        false
    }

    /// Σ_i w_i v_i f(x_i, v_i): the window integral of the power per unit coefficient.
    fn weighted_power(&self, x: &[f64], v: &[f64], w: &[f64]) -> f64;
}

/// sign(v) with sign(0) = 0 (unlike `f64::signum`), so that Coulomb friction at rest
/// exerts no force in the simulator and dissipates nothing.
pub fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}
