//! Linear viscous law: f = v, power v². Over a cycle of x = X cos ωt,
//! ∫ v² dt = π ω X².

use std::sync::Arc;

use super::LawRegistration;
use crate::terms::lanes;
use crate::terms::law::{ElementMotion, Law, PowerForm, Weights};

/// `law = "linear"` in model files.
pub(super) const REGISTRATION: LawRegistration =
    LawRegistration::new("linear", "f = v (viscous)", |_| Ok(Arc::new(Linear)));

/// Viscous damping, f(v) = v.
#[derive(Debug, Clone, Copy, Default)]
pub struct Linear;

impl Law for Linear {
    fn name(&self) -> String {
        "linear".into()
    }
    fn force(&self, _x: f64, v: f64) -> f64 {
        v
    }
    fn weighted_power(&self, _x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        lanes::sum(Weights::PerSample(w), v, |v| PowerForm::Square.power(v))
    }
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        lanes::velocity_power(motion, weights, |v| PowerForm::Square.power(v))
    }
    /// E[(v + δv)²] − v² = σ_v², exactly.
    fn noise_bias(&self, _x: f64, _v: f64, _var_x: f64, var_v: f64) -> f64 {
        var_v
    }
    fn power_form(&self) -> Option<PowerForm> {
        Some(PowerForm::Square)
    }
    fn power_slope(&self, _x: f64, v: f64, _dx: f64, _dv: f64) -> (f64, f64) {
        (0.0, 2.0 * v)
    }
}
