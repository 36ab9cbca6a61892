//! A custom law given as a closure f(x, v) of relative displacement and velocity;
//! power v · f(x, v). Model files will build these from textual expressions.

use std::fmt;
use std::sync::Arc;

use crate::terms::law::Law;

type LawFn = dyn Fn(f64, f64) -> f64 + Send + Sync;

/// A user-supplied damping law f(x, v).
#[derive(Clone)]
pub struct Custom {
    name: String,
    f: Arc<LawFn>,
}

impl Custom {
    /// A law named `name` with force `f(x, v)`.
    pub fn new(
        name: impl Into<String>,
        f: impl Fn(f64, f64) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Custom {
            name: name.into(),
            f: Arc::new(f),
        }
    }
}

impl fmt::Debug for Custom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Custom").field("name", &self.name).finish()
    }
}

impl Law for Custom {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn force(&self, x: f64, v: f64) -> f64 {
        (self.f)(x, v)
    }
    fn uses_displacement(&self) -> bool {
        true
    }
    fn weighted_power(&self, x: &[f64], v: &[f64], w: &[f64]) -> f64 {
        w.iter()
            .zip(x.iter().zip(v))
            .map(|(w, (&x, &v))| w * v * (self.f)(x, v))
            .sum()
    }
}
