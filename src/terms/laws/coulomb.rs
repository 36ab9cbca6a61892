//! Coulomb (dry) friction: f = sign(v), power |v|. Over a cycle of x = X cos ωt,
//! ∫ |v| dt = 4X (the total distance travelled).

use std::sync::Arc;

use super::LawRegistration;
use crate::terms::lanes;
use crate::terms::law::{ElementMotion, Law, PowerForm, Weights, sign};

/// `law = "coulomb"` in model files.
pub(super) const REGISTRATION: LawRegistration =
    LawRegistration::new("coulomb", "f = sign(v) (dry friction)", |_| Ok(Arc::new(Coulomb)));

/// Coulomb friction, f(v) = sign(v) with sign(0) = 0.
#[derive(Debug, Clone, Copy, Default)]
pub struct Coulomb;

impl Law for Coulomb {
    fn name(&self) -> String {
        "coulomb".into()
    }
    fn force(&self, _x: f64, v: f64) -> f64 {
        sign(v)
    }
    fn weighted_power(&self, _x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        lanes::sum(Weights::PerSample(w), v, |v| PowerForm::Abs.power(v))
    }
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        lanes::velocity_power(motion, weights, |v| PowerForm::Abs.power(v))
    }
    /// None: Coulomb work is read as the total variation of the (denoised)
    /// displacement, which zero-mean noise leaves unbiased to first order.
    fn noise_bias(&self, _x: f64, _v: f64, _var_x: f64, _var_v: f64) -> f64 {
        0.0
    }
    fn power_form(&self) -> Option<PowerForm> {
        Some(PowerForm::Abs)
    }
    fn power_slope(&self, _x: f64, v: f64, _dx: f64, _dv: f64) -> (f64, f64) {
        (0.0, sign(v))
    }
    fn is_total_variation(&self) -> bool {
        true
    }
}
