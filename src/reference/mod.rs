//! Reference systems from the paper (Feeny, JVA 131(4) 041005, 2009), shared by the
//! examples, tests, benches and the command line. Each builds the system, simulates it
//! with the paper's settings and identifies it; none contains an expected answer other
//! than the paper's printed values, which are only compared against.

pub mod check;
pub mod dashpot_chain;
pub mod drive;
pub mod four_mass;
pub mod four_mass_pod;
pub mod noisy_chain;
mod pods;
pub mod string;
pub mod string_study;

pub use check::{Check, Measure};
pub use dashpot_chain::{chain_dashpots, dashpot_chain_model};
pub use four_mass::*;
pub use four_mass_pod::FourMassPodStudy;
pub use noisy_chain::*;
pub use string_study::StringStudy;
