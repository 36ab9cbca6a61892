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

    /// The power p(x, v) = v f(x, v) of one sample.
    fn power(&self, x: f64, v: f64) -> f64 {
        v * self.force(x, v)
    }

    /// Expected change of the power when x and v carry independent zero-mean noise of
    /// variances `var_x` and `var_v`: E[p(x + δx, v + δv)] − p(x, v), to second order.
    /// The default is the three-point Gauss–Hermite rule in each variable,
    /// (p(v + √3σ) − 2 p(v) + p(v − √3σ))/6 (and likewise in x), exact for a power that
    /// is a polynomial of degree ≤ 5 over ±√3σ (v² gives σ², |v|³ gives 3|v|σ² away
    /// from v = 0) and finite across a kink.
    fn noise_bias(&self, x: f64, v: f64, var_x: f64, var_v: f64) -> f64 {
        let p0 = self.power(x, v);
        let mut bias = 0.0;
        if var_v > 0.0 {
            let s = (3.0 * var_v).sqrt();
            bias += (self.power(x, v + s) - 2.0 * p0 + self.power(x, v - s)) / 6.0;
        }
        if var_x > 0.0 && self.uses_displacement() {
            let s = (3.0 * var_x).sqrt();
            bias += (self.power(x + s, v) - 2.0 * p0 + self.power(x - s, v)) / 6.0;
        }
        bias
    }

    /// The slopes (∂p/∂x, ∂p/∂v) of the power, for first-order noise propagation. The
    /// default takes central differences over ±`dx` and ±`dv`, the noise scales, so
    /// that across a kink it averages as the noise does.
    fn power_slope(&self, x: f64, v: f64, dx: f64, dv: f64) -> (f64, f64) {
        let dv = if dv > 0.0 {
            dv
        } else {
            1e-8 * v.abs().max(1e-300)
        };
        let slope_v = (self.power(x, v + dv) - self.power(x, v - dv)) / (2.0 * dv);
        let slope_x = if self.uses_displacement() {
            let dx = if dx > 0.0 {
                dx
            } else {
                1e-8 * x.abs().max(1e-300)
            };
            (self.power(x + dx, v) - self.power(x - dx, v)) / (2.0 * dx)
        } else {
            0.0
        };
        (slope_x, slope_v)
    }

    /// True when the power is |v| (Coulomb friction): its window integral is then the
    /// total variation of the displacement, a form that needs no velocity.
    fn is_total_variation(&self) -> bool {
        false
    }
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
