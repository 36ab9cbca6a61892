//! Linear viscous law: f = v, power v². Over a cycle of x = X cos ωt,
//! ∫ v² dt = π ω X².

use crate::terms::law::Law;

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
        w.iter().zip(v).map(|(w, v)| w * v * v).sum()
    }
}
