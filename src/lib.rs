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
//! ## Start here
//!
//! - [`identify()`] runs the whole chain for every kind of problem: a damping model
//!   (perhaps with estimated law parameters) on records, a stepped-sine table or rows
//!   built already ([`regressor::ParametricRegressor`]) in, an
//!   [`identify::Identification`] out, whose [`report::FitReport`]'s `Display` is the
//!   text report and serde gives the JSON; [`prelude`] has the names most programs need.
//! - [`record`]: a [`record::Record`] is one experiment, built from your own arrays
//!   (example below) or read from files.
//! - [`terms`] and [`model`]: the damping laws (linear, quadratic, Coulomb, power,
//!   expressions, your own) on DOFs, dashpots or matrices, composed into a
//!   [`model::DampingModel`].
//! - [`report`]: the report, its warnings and the HTML page.
//!
//! ## Model files
//!
//! - [`model_file`]: a TOML file (docs/model-file.md lists every key) turned into a job;
//!   [`model_file::init`] writes a first one (`dampid init`).
//! - [`io`]: CSV, NPY/NPZ, MAT and UFF files become tables of named columns; every output
//!   file is written whole or not at all, never replacing one unless asked.
//! - [`simulate`]: records of a system simulated by RK4, with optional noise.
//! - [`mod@reference`]: the paper's systems and studies.
//!
//! ## Internals
//!
//! Data flow one way, one folder per stage: [`prep`] cuts records into windows with
//! quadrature weights and velocities (and checks steady state, detects periods, reduces
//! by POD); [`regressor`] builds `A θ = b` (whole periods, the noise-robust rows, or fixed
//! spans of non-periodic records with stored-energy unknowns); [`fit`] solves it;
//! [`analysis`] diagnoses it (conditioning, identifiability, bootstrap, comparison,
//! experiment design); [`identify::identify`] runs them in order for every problem;
//! [`command`] holds the commands the `dampid` binary (feature `cli`) and the Python
//! package print. Cross-cutting: [`error`] (the typed [`Error`]), [`format`](mod@format)
//! (numbers in messages), [`progress`] (callbacks), [`budget`] (memory and time limits),
//! [`interop`].
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
//! ## A record from your own arrays
//!
//! One DOF, m ẍ + c ẋ + k x = r(t), in steady state x = X cos ωt, so that the force is
//! r = (k − mω²) X cos ωt − cXω sin ωt. Over a whole period the spring and mass forces
//! do no work and ∮ ẋ r dt = c ∮ ẋ² dt = c π X² ω: the energy balance gives c back, whatever
//! m and k (here m = 1, k = 4, c = 0.2, X = 0.5, ω = 1.5, 64 samples per period, the
//! measured velocities used as they are; the trapezoid rule over whole periods of a
//! trigonometric polynomial is exact, so c is recovered to round-off).
//!
//! ```
//! use dampid::prelude::*;
//! use faer::Mat;
//!
//! let (m, k, c, amplitude, omega) = (1.0, 4.0, 0.2, 0.5, 1.5);
//! let period = 2.0 * std::f64::consts::PI / omega;
//! let (per_period, periods) = (64, 4);
//! let step = period / per_period as f64;
//! let t: Vec<f64> = (0..per_period * periods).map(|i| i as f64 * step).collect();
//! // Your arrays: one column per DOF (displacements, velocities) or force channel.
//! let x = Mat::from_fn(t.len(), 1, |i, _| amplitude * (omega * t[i]).cos());
//! let v = Mat::from_fn(t.len(), 1, |i, _| -amplitude * omega * (omega * t[i]).sin());
//! let force = Mat::from_fn(t.len(), 1, |i, _| {
//!     (k - m * omega * omega) * x[(i, 0)] + c * v[(i, 0)]
//! });
//! let record = Record::new(RecordParts {
//!     label: "my test".into(),
//!     step,
//!     start_time: 0.0,
//!     displacements: x,
//!     velocities: Some(v),
//!     forcing: Forcing::on_dofs(force, vec![0]), // channel 1 acts on DOF 1 (0-based here)
//!     period,
//! })?;
//! let model = DampingModel::new().with(Term::per_dof(Linear, 1, Coefficients::Shared("c".into())));
//! let mut settings = IdentifySettings::default();
//! settings.regressor.velocity = VelocitySource::Measured;
//! let records = [record];
//! let problem = ParametricRegressor::linear(&model, &records);
//! let report = identify(&problem, &settings, &silent)?.report;
//! let estimate = report.coefficient("c").unwrap();
//! assert!((estimate - c).abs() < 1e-9 * c, "{estimate}");
//! # Ok::<(), dampid::Error>(())
//! ```
//!
//! The paper's four-mass chain, simulated:
//!
//! ```
//! use dampid::prelude::*;
//! use dampid::reference::{four_mass_model, four_mass_records};
//!
//! let records = four_mass_records(false, 1)?;           // simulate the paper's chain
//! let settings = IdentifySettings::default();            // trapezoid, noise-robust projection
//! let problem = ParametricRegressor::linear(&four_mass_model(), &records);
//! let c = identify(&problem, &settings, &silent)?.coefficient("c").unwrap();
//! assert!((c - 0.15).abs() < 0.15 * 0.005);
//! # Ok::<(), dampid::Error>(())
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod budget;
pub mod campaign;
pub mod cancel;
pub mod command;
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
    pub use crate::identify::{Identification, IdentifySettings, identify};
    pub use crate::model::DampingModel;
    pub use crate::prep::harmonic::{
        HarmonicApproximation, PhaseReading, SteppedSinePoint, SteppedSineTable,
    };
    pub use crate::prep::motion::{SensorParts, record_from_sensors};
    pub use crate::prep::pod::{Pod, PodBasis, PodSettings, Retain, reduce};
    pub use crate::prep::quadrature::Quadrature;
    pub use crate::prep::velocity::VelocitySource;
    pub use crate::prep::window::WindowSpec;
    pub use crate::progress::silent;
    pub use crate::record::{Forcing, MeasuredMotion, Record, RecordParts, Sensor};
    pub use crate::regressor::{
        NonlinearParameter, ParametricModel, ParametricRegressor, Regressor, RegressorSettings,
        Source, SteppedSineSource,
    };
    pub use crate::report::FitReport;
    pub use crate::terms::laws::{
        Coulomb, Custom, LawParameters, LawRegistration, Linear, PowerLaw, Quadratic, Registry,
    };
    pub use crate::terms::{Coefficients, Element, Law, Term};
}
