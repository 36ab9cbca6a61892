//! The harmonic approximation of the energy balance (Feeny 2009, section 2.2, eq. 4)
//! and the stepped-sine amplitude/phase tables it works from.
//!
//! A stepped-sine test point is a force a cos ωt on one DOF (the phase reference) and a
//! response whose fundamental on DOF i is X_i cos(ωt − φ_i). The paper replaces the
//! measured motion by the synchronous motion
//!
//! ```text
//!   x_i(t) = X_i cos(ωt − φ̄),   φ̄ = mean phase lag of the DOFs behind the force,
//! ```
//!
//! whose cycle integrals have closed forms: for a damping matrix C,
//! ∮ ẋᵀCẋ dt = π ω XᵀCX (for C = cK on the four-mass chain, 2πωc A_c); for
//! quadratic damping on every DOF, ∮ Σ|ẋ_i|³ dt = (8/3) ω² Σ X_i³; for Coulomb friction,
//! ∮ Σ|ẋ_i| dt = 4 Σ X_i; and the input work of a cos ωt on DOF f is π a X_f sin φ̄.
//! Balancing them for several amplitudes gives eq. 4,
//!
//! ```text
//!   2πωc A_c + (8/3) ω² d A_d = π a X_4 sin φ̄.
//! ```
//!
//! No term needs code of its own for this: [`HarmonicApproximation`] synthesizes the
//! motion over one period with many samples and exact velocities as an ordinary
//! [`Record`](crate::record::Record), and the ordinary regressor integrates every term
//! over it (spectral quadrature, measured velocities). The closed forms follow to
//! quadrature accuracy, and custom laws work by the same numerical synthesis.
//!
//! - [`fundamentals()`]: amplitude and phase of the fundamental of every DOF and force
//!   channel, by least squares over whole periods of a window of a record.
//! - [`table`]: the stepped-sine table (one test point per row), from records or from
//!   a CSV file.
//! - [`approximation`]: the synchronous motion, the choice of φ̄, and the fit.
//! - [`residual`]: the residual receptance of out-of-band modes, removed per point.

pub mod approximation;
pub mod fundamentals;
pub mod residual;
pub mod sweeps;
pub mod table;

pub use crate::prep::fourier::Phasor;
pub use approximation::{HarmonicApproximation, PhaseReading};
pub use fundamentals::{Fundamentals, fundamentals};
pub use table::{SteppedSinePoint, SteppedSineTable};
