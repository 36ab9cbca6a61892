//! Quadratic (velocity-squared) law: f = v|v|, power |v|³. Over a cycle of
//! x = X cos ωt, ∫ |v|³ dt = (8/3) ω² X³.

use std::sync::Arc;

use super::LawRegistration;
use crate::terms::lanes;
use crate::terms::law::{ElementMotion, Law, PowerForm, Weights};

/// `law = "quadratic"` in model files.
pub(super) const REGISTRATION: LawRegistration =
    LawRegistration::new("quadratic", "f = v|v| (velocity squared)", |_| Ok(Arc::new(Quadratic)));

/// Quadratic damping, f(v) = v|v|.
#[derive(Debug, Clone, Copy, Default)]
pub struct Quadratic;

impl Law for Quadratic {
    fn name(&self) -> String {
        "quadratic".into()
    }
    fn force(&self, _x: f64, v: f64) -> f64 {
        v * v.abs()
    }
    fn weighted_power(&self, _x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        lanes::sum(Weights::PerSample(w), v, |v| PowerForm::AbsCube.power(v))
    }
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        lanes::velocity_power(motion, weights, |v| PowerForm::AbsCube.power(v))
    }
    fn power_form(&self) -> Option<PowerForm> {
        Some(PowerForm::AbsCube)
    }
    fn power_slope(&self, _x: f64, v: f64, _dx: f64, _dv: f64) -> (f64, f64) {
        (0.0, 3.0 * v * v.abs())
    }
}
