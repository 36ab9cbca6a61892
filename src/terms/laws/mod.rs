//! The built-in damping laws, one per file.

mod coulomb;
mod custom;
mod expression;
mod linear;
mod power;
mod quadratic;

pub use coulomb::Coulomb;
pub use custom::Custom;
pub use expression::Expression;
pub use linear::Linear;
pub use power::PowerLaw;
pub use quadratic::Quadratic;
