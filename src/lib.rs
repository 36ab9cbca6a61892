//! # dampid: damping identification by balancing energy
//!
//! Over whole cycles of a periodic response the stored (kinetic and potential) energy
//! returns to its start, so the work of the applied forces equals the work of the
//! damping forces, whatever the mass and stiffness (nonlinear springs included):
//!
//! ```text
//!   ∮ ẋᵀ Q_d(x, ẋ) dt = ∮ ẋᵀ r(t) dt            (Feeny 2009, eq. 2)
//! ```
//!
//! With a damping model linear in its coefficients, Q_d = Σ_k θ_k f_k(x, ẋ), each window
//! of whole periods gives one linear equation, and several windows (amplitudes,
//! frequencies, forcing points, cycles) give the regressor
//!
//! ```text
//!   A θ = b,   A_rk = ∮_r ẋᵀ f_k(x, ẋ) dt,   b_r = ∮_r ẋᵀ r dt,
//! ```
//!
//! solved by least squares, min ‖Aθ − b‖₂, or under physical constraints
//! (θ ≥ 0, l ≤ θ ≤ u, fixed θ_i) with clarabel.
//!
//! Data flow one way, one folder per stage: [`record`], [`terms`] and [`model`] say
//! what is fitted; [`prep`] cuts records into windows with quadrature weights and
//! velocities (and checks steady state, detects periods, reduces by POD); [`regressor`]
//! builds `A θ = b` (whole periods, the noise-robust rows, or fixed spans of
//! non-periodic records with stored-energy unknowns); [`fit`] solves it;
//! [`analysis`] diagnoses it (conditioning, identifiability, bootstrap, comparison,
//! experiment design); [`report`] assembles the [`report::FitReport`]. [`identify()`]
//! runs the whole chain, and [`identify::identify_regressor`] the part after the
//! regressor. At the edges: [`io`] reads files, [`simulate`] produces records,
//! [`model_file`] turns a TOML file into a job, [`mod@reference`] holds the paper's
//! systems, and the `dampid` binary (feature `cli`) prints what the library returns.
//!
//! Threads: dampid parallelises over windows, kernel blocks, POD row chunks, bootstrap
//! replicates and design candidates, and combines them in index order, so its own work
//! gives the same bits on any rayon pool. faer's products and decompositions split by the
//! thread count unless told otherwise: for results independent of the thread count (as
//! the `dampid` binary gives, `tests/threads.rs`), call
//! `faer::set_global_parallelism(faer::Par::Seq)` once before identifying.
//!
//! Where to add what (a damping law, a law with memory, a window kind, a file format, a
//! report section, a CLI command): ARCHITECTURE.md.
//!
//! ```
//! use dampid::prelude::*;
//! use dampid::reference::{four_mass_model, four_mass_records};
//!
//! let records = four_mass_records(false, 1)?;           // simulate the paper's chain
//! let settings = IdentifySettings::default();            // trapezoid, noise-robust projection
//! let report = identify(&four_mass_model(), &records, &settings)?;
//! let c = report.coefficient("c").unwrap();
//! assert!((c - 0.15).abs() < 0.15 * 0.005);
//! # Ok::<(), dampid::Error>(())
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod budget;
pub mod cancel;
pub mod error;
pub mod fit;
pub mod format;
pub mod identify;
pub mod interop;
pub mod io;
pub mod model;
pub mod model_file;
pub mod prep;
pub mod progress;
pub mod record;
pub mod reference;
pub mod regressor;
pub mod report;
pub mod simulate;
pub mod terms;
pub mod varpro;

pub use error::{Error, Result};
pub use identify::{IdentifySettings, identify};

/// README.md's Rust snippets, compiled and run by `cargo test` so that they stay true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeSnippets;

/// The names most programs need.
pub mod prelude {
    pub use crate::analysis::bootstrap::BootstrapSettings;
    pub use crate::analysis::compare::{CompareSettings, Comparison, compare};
    pub use crate::analysis::design::{Criterion, DesignReport, DesignSettings, design};
    pub use crate::analysis::identifiability::Identifiability;
    pub use crate::error::{Error, Result};
    pub use crate::fit::{
        Bound, Constraints, Fit, FitSettings, FitStatus, Fixed, LinearConstraint, Relation,
    };
    pub use crate::identify::{
        IdentifySettings, identify, identify_regressor, identify_with_bootstrap,
        identify_with_regressor,
    };
    pub use crate::model::DampingModel;
    pub use crate::prep::harmonic::{
        HarmonicApproximation, PhaseReading, SteppedSinePoint, SteppedSineTable,
    };
    pub use crate::prep::motion::{SensorParts, record_from_sensors};
    pub use crate::prep::pod::{Pod, PodBasis, PodSettings, Retain, reduce};
    pub use crate::prep::quadrature::Quadrature;
    pub use crate::prep::velocity::VelocitySource;
    pub use crate::prep::window::WindowSpec;
    pub use crate::record::{Forcing, MeasuredMotion, Record, RecordParts, Sensor};
    pub use crate::regressor::{Regressor, RegressorSettings};
    pub use crate::report::FitReport;
    pub use crate::terms::laws::{
        Coulomb, Custom, LawParameters, LawRegistration, Linear, PowerLaw, Quadratic, Registry,
    };
    pub use crate::terms::{Coefficients, Element, Law, Term};
}
