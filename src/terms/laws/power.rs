//! Power law: f = |v|^p sign(v), power |v|^{p+1}. p = 0 is Coulomb, p = 1 linear,
//! p = 2 quadratic. Over a cycle of x = X cos ωt,
//! ∫ |v|^{p+1} dt = (ωX)^{p+1} · (4/ω) · ∫_0^{π/2} sin^{p+1} θ dθ.

use std::sync::Arc;

use super::LawRegistration;
use crate::error::{Error, Result};
use crate::terms::lanes;
use crate::terms::law::{ElementMotion, Law, PowerForm, Weights, sign};

/// `law = "power"` with `parameters = { exponent = p }` in model files.
pub(super) const REGISTRATION: LawRegistration =
    LawRegistration::new("power", "f = |v|^p sign(v), p = exponent ≥ 0", |parameters| {
        Ok(Arc::new(PowerLaw::new(parameters.number("exponent")?)?))
    })
    .with_parameters(&["exponent"]);

/// Power-law damping, f(v) = |v|^p sign(v), p ≥ 0.
#[derive(Debug, Clone, Copy)]
pub struct PowerLaw {
    exponent: f64,
}

impl PowerLaw {
    /// A power law with exponent p; p must be finite and nonnegative.
    pub fn new(exponent: f64) -> Result<Self> {
        if !(exponent.is_finite() && exponent >= 0.0) {
            return Err(Error::invalid(
                "exponent",
                exponent,
                "a power law needs a finite exponent p ≥ 0",
            ));
        }
        Ok(PowerLaw { exponent })
    }

    /// The exponent p.
    pub fn exponent(&self) -> f64 {
        self.exponent
    }
}

impl Law for PowerLaw {
    fn name(&self) -> String {
        format!("power({})", self.exponent)
    }
    fn force(&self, _x: f64, v: f64) -> f64 {
        v.abs().powf(self.exponent) * sign(v)
    }
    fn weighted_power(&self, _x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        let q = self.exponent + 1.0;
        lanes::sum(Weights::PerSample(w), v, |v| PowerForm::AbsPow(q).power(v))
    }
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        let q = self.exponent + 1.0;
        lanes::velocity_power(motion, weights, |v| PowerForm::AbsPow(q).power(v))
    }
    fn noise_bias(&self, x: f64, v: f64, _var_x: f64, var_v: f64) -> f64 {
        if self.exponent == 0.0 {
            0.0 // Coulomb: read as total variation
        } else {
            // the trait's three-point Gauss–Hermite rule in v
            let s = (3.0 * var_v).sqrt();
            (self.power(x, v + s) - 2.0 * self.power(x, v) + self.power(x, v - s)) / 6.0
        }
    }
    fn power_form(&self) -> Option<PowerForm> {
        Some(PowerForm::AbsPow(self.exponent + 1.0))
    }
    fn power_slope(&self, _x: f64, v: f64, _dx: f64, _dv: f64) -> (f64, f64) {
        // d/dv |v|^{p+1} = (p + 1)|v|^p sign(v)
        (
            0.0,
            (self.exponent + 1.0) * v.abs().powf(self.exponent) * sign(v),
        )
    }
    fn is_total_variation(&self) -> bool {
        self.exponent == 0.0
    }
}
