//! Analyses of a regressor and its fit: diagnostics (residuals, conditioning, standard
//! errors), identifiability (near-null directions and determined combinations by
//! name), the window bootstrap, model comparison, experiment design, and the noise
//! bias of the velocity estimator (velocity_noise); [`digest`] is how their long lists
//! read in text; [`solved`] is the one
//! solve-and-diagnose path `identify` and `dampid check` share. They read a
//! [`crate::regressor::Regressor`] and a [`crate::fit::Fit`]; nothing in the chain
//! before them imports them.

pub mod backbone;
pub mod backbones;
pub mod bootstrap;
pub mod bound_set;
pub mod check;
pub mod compare;
pub mod design;
pub mod diagnostics;
pub mod digest;
pub mod equivalent;
pub mod identifiability;
pub mod lack_of_fit;
pub mod measured_levels;
pub mod replicates;
pub mod solved;
pub(crate) mod stats;
pub mod velocity_noise;
