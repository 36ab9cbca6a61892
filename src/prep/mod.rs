//! Preparation: from records to what the regressor reads. Windows of whole periods (or
//! fixed spans), the quadrature weights over each window, velocities, the steady-state
//! check, the driving period, and the record-to-record transforms: proper orthogonal
//! decomposition, the synchronous harmonic approximation, and motion from velocity or
//! acceleration sensors.
//!
//! Everything here reads records and settings and returns records, windows, weights or
//! velocities; nothing here builds a regressor or fits.

pub mod data_scale;
pub(crate) mod fourier;
pub mod free_decay;
pub mod harmonic;
pub mod motion;
pub mod period;
pub mod pod;
pub mod quadrature;
pub mod steady_state;
pub mod velocity;
pub mod window;
