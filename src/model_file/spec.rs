//! The TOML schema of a model file, as serde types. Unknown keys are rejected
//! (`deny_unknown_fields`); DOFs are numbered from 1 as engineers do, 0 meaning ground.
//! See `models/` and README.md for annotated examples.
//!
//! The tables of a model file live by concept: `spec/data.rs` (`[data]`,
//! `[stepped_sine]`), `spec/terms.rs` (the damping model), `spec/simulation.rs`
//! (`[simulation]`, `[string_simulation]`, `[system]`), `spec/modes.rs` (`[non_periodic]`,
//! `[pod]`, `[harmonic_approximation]`); this file holds the whole file's spec and
//! `[identification]` and `[design]`, and re-exports the rest.

mod data;
mod modes;
mod simulation;
mod terms;

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use crate::analysis::design::Criterion;
use crate::fit::Relation;
use crate::prep::quadrature::Quadrature;

pub use data::{
    ColumnSpec, DataSpec, ForceColumn, KeepSpec, Paths, PhaseConvention, RecordSpec, Scale,
    SteppedSineSpec, StructuralSpec,
};
pub use modes::{
    FreeDecaySpec, HarmonicApproximationSpec, NonPeriodicSpec, OffsetsSpec, PhaseName, PodSpec,
    StartSpec, StorageSpec,
};
pub use simulation::{CubicSpec, ExperimentSpec, SimulationSpec, StringSimulationSpec, SystemSpec};
pub use terms::{
    ElementsSpec, EstimatedSpec, HistorySpec, MatrixRef, ParameterSpec, StiffnessSpec,
    StructuralTermSpec, TermSpec,
};

/// A whole model file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFileSpec {
    /// A title for reports.
    pub title: Option<String>,
    /// Number of DOFs (sensors) n.
    pub dofs: usize,
    /// Named matrices, n × n rows, for matrix terms and the simulation.
    #[serde(default)]
    pub matrices: BTreeMap<String, Spanned<Vec<Vec<f64>>>>,
    /// The damping model.
    pub terms: Vec<Spanned<TermSpec>>,
    /// How to identify.
    #[serde(default)]
    pub identification: IdentificationSpec,
    /// Generate the records by simulation.
    pub simulation: Option<Spanned<SimulationSpec>>,
    /// Read the records from files.
    pub data: Option<Spanned<DataSpec>>,
    /// Experiment design over the `[simulation]` experiments (`dampid design`).
    pub design: Option<Spanned<DesignSpec>>,
    /// Generate the records with the paper's string simulator (section 3.2.1).
    pub string_simulation: Option<Spanned<StringSimulationSpec>>,
    /// Mass and stiffness of measured data, for the steady-state energy check.
    pub system: Option<Spanned<SystemSpec>>,
    /// Reduce the records to their proper orthogonal modes before identifying.
    pub pod: Option<Spanned<PodSpec>>,
    /// Identify by the synchronous harmonic approximation (paper eq. 4).
    pub harmonic_approximation: Option<Spanned<HarmonicApproximationSpec>>,
    /// Identify from records that are not periodic, with stored energy and constant
    /// forces as extra unknowns (`dampid::regressor::nonperiodic`).
    pub non_periodic: Option<Spanned<NonPeriodicSpec>>,
    /// Each record is a free decay (ringdown) of one mode (`dampid::prep::free_decay`).
    pub free_decay: Option<Spanned<FreeDecaySpec>>,
    /// Read a measured stepped-sine table (`dampid::prep::harmonic::sweeps`) instead of
    /// records.
    pub stepped_sine: Option<Spanned<SteppedSineSpec>>,
    /// The units the numbers are in, for reports (`length = "m"`, `force = "N"`,
    /// `time = "s"`, `angle`, `mass`; [`crate::report::units`]).
    #[serde(default)]
    pub units: BTreeMap<String, Spanned<String>>,
}

/// `[identification]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentificationSpec {
    /// Quadrature rule.
    pub quadrature: Quadrature,
    /// Velocity source (default: harmonic projection; central difference for
    /// `[non_periodic]`).
    pub velocity: Option<VelocityName>,
    /// K for spectral or harmonic-projection velocities.
    pub harmonics: Option<usize>,
    /// Noise correction: `"auto"` (with harmonic projection), `"ignore"`, `"correct"`.
    pub noise: crate::regressor::NoiseTreatment,
    /// Equation weights: `"auto"`, `"ordinary"`, `"propagated"`.
    pub weighting: crate::fit::Weighting,
    /// Input and Coulomb work: `"velocity"` or `"derivative_free"`.
    pub work_form: crate::regressor::WorkForm,
    /// Whole periods per window.
    pub cycles: usize,
    /// Windows per record (absent: as many as fit).
    pub windows: Option<usize>,
    /// Samples to skip at the start of each record.
    pub skip: usize,
    /// All coefficients ≥ 0.
    pub nonnegative: bool,
    /// Per-coefficient bounds.
    pub bounds: BTreeMap<String, BoundSpec>,
    /// Per-coefficient fixed values.
    pub fixed: BTreeMap<String, f64>,
    /// Linear relations between coefficients.
    pub constraints: Vec<LinearConstraintSpec>,
    /// Largest stored-energy mismatch |ΔE|/|W| of a steady window (M and K known).
    pub max_energy_mismatch: f64,
    /// Largest state mismatch of a steady window (M and K unknown).
    pub max_state_mismatch: f64,
    /// Identify from windows that are not steady (they are reported, not rejected).
    pub accept_transient: bool,
    /// Fit rows whose input work is negative beyond its noise
    /// ([`crate::regressor::passive`]).
    pub accept_negative_work: bool,
}

impl Default for IdentificationSpec {
    fn default() -> Self {
        IdentificationSpec {
            quadrature: Quadrature::default(),
            velocity: None,
            harmonics: None,
            noise: crate::regressor::NoiseTreatment::default(),
            weighting: crate::fit::Weighting::default(),
            work_form: crate::regressor::WorkForm::default(),
            cycles: 1,
            windows: None,
            skip: 0,
            nonnegative: false,
            bounds: BTreeMap::new(),
            fixed: BTreeMap::new(),
            constraints: Vec::new(),
            max_energy_mismatch: crate::prep::steady_state::DEFAULT_MAX_ENERGY_MISMATCH,
            max_state_mismatch: crate::prep::steady_state::DEFAULT_MAX_STATE_MISMATCH,
            accept_transient: false,
            accept_negative_work: false,
        }
    }
}

/// Velocity source names.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocityName {
    /// Measured (or simulated) velocities.
    Measured,
    /// Central differences of the displacements.
    CentralDifference,
    /// Fourier series in harmonics of the drive (`harmonics` sets K).
    Spectral,
    /// Projection of whole periods on the harmonics above the noise floor (`harmonics`
    /// sets 1..K instead); with `noise = "auto"` the noise-robust pipeline.
    #[default]
    HarmonicProjection,
}

/// Bounds on one coefficient.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundSpec {
    /// Lower bound.
    pub lower: Option<f64>,
    /// Upper bound.
    pub upper: Option<f64>,
}

/// `{ terms = { "dashpot[0-1]" = 1, "dashpot[4-5]" = -1 }, relation = "=", value = 0 }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearConstraintSpec {
    /// Coefficient name → multiplier.
    pub terms: BTreeMap<String, f64>,
    /// `"="`, `"<="` or `">="`.
    pub relation: Relation,
    /// Right-hand side (default 0).
    #[serde(default)]
    pub value: f64,
}

/// `[design]`: how `dampid design` chooses among the `[simulation]` experiments.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignSpec {
    /// `"d_optimal"` (default) or `"condition"`.
    #[serde(default)]
    pub criterion: Criterion,
    /// Most experiments to add (default 3).
    pub picks: Option<usize>,
    /// Experiments always included, 1-based in the order of `[[simulation.experiments]]`.
    #[serde(default)]
    pub start: Vec<usize>,
    /// Stop once the column-scaled condition number falls below this.
    pub target_condition: Option<f64>,
}
