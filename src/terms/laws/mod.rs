//! The built-in damping laws, one per file, and the registry that finds a law by the
//! name a model file gives it (`law = "power"`, registry.rs).
//!
//! A built-in memoryless law is one file here holding the law, its `impl Law` and its
//! registration, `pub(super) const REGISTRATION: LawRegistration`, plus one line
//! `module => Type,` in the `builtin_laws!` list below. That line declares the module,
//! re-exports the type and enters the registration in [`BUILTIN`], so the law is known
//! to [`NAMES`], [`by_name`], [`Registry::builtin`], model files and the fuzz target.
//! A program adds laws of its own at run time with [`Registry::with`].
//!
//! [`Custom`] (a closure) has no registration: a model file cannot write a closure,
//! and writes an `expression` instead.

mod custom;
mod registry;

pub use custom::Custom;
pub use registry::{LawConstructor, LawParameters, LawRegistration, Registry, by_name};

/// Declares each law's module, re-exports its type, and lists its registration in
/// [`BUILTIN`] and its name in [`NAMES`].
macro_rules! builtin_laws {
    ($($module:ident => $law:ident,)*) => {
        $(mod $module;)*
        $(pub use $module::$law;)*

        /// Every built-in law's registration, in the order model-file errors list them.
        pub const BUILTIN: &[LawRegistration] = &[$($module::REGISTRATION),*];

        /// The names model files give the built-in laws (`law = "..."`), in [`BUILTIN`]
        /// order.
        pub const NAMES: &[&str] = &[$($module::REGISTRATION.name()),*];
    };
}

pub use expression::MAX_EXPRESSION_BYTES;

builtin_laws! {
    linear => Linear,
    quadratic => Quadratic,
    coulomb => Coulomb,
    power => PowerLaw,
    expression => Expression,
}
