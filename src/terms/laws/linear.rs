//! Linear viscous law: f = v, power v². Over a cycle of x = X cos ωt,
//! ∫ v² dt = π ω X².

use crate::terms::lanes;
use crate::terms::law::{ElementMotion, Law, Weights};

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
        lanes::sum(Weights::PerSample(w), v, |v| v * v)
    }
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        lanes::velocity_power(motion, weights, |v| v * v)
    }
}
