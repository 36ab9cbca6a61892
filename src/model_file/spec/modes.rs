//! The specs of the identification modes that transform records or windows:
//! `[non_periodic]` (fixed spans with stored energy and offsets), `[pod]` and
//! `[harmonic_approximation]` (eq. 4) with its phase readings.

use serde::Deserialize;
use toml::Spanned;

use super::terms::{ElementsSpec, MatrixRef};

/// `[non_periodic]`: windows of a fixed length, and what stores energy.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonPeriodicSpec {
    /// Window length in time units.
    pub window: f64,
    /// `"each_dof"` (an unknown lumped mass per DOF, the default), `"none"`, or
    /// `{ known = <matrix> }`.
    #[serde(default)]
    pub mass: Option<StorageSpec>,
    /// `"none"` (the default), `"each_dof"`, `"chain"`, DOF pairs (an unknown spring
    /// per element), or `{ known = <matrix> }`.
    #[serde(default)]
    pub stiffness: Option<StorageSpec>,
    /// DOFs (1-based) with an unknown constant force, or `"each_dof"`.
    #[serde(default)]
    pub offsets: Option<OffsetsSpec>,
    /// Cut-off frequency f_c (cycles per time unit) of the zero-phase high-pass that
    /// treats the drift when velocity or acceleration columns are integrated
    /// (`dampid::prep::motion`); required with such columns, unused without.
    pub high_pass: Option<Spanned<f64>>,
}

/// A stored-energy term of `[non_periodic]`.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum StorageSpec {
    /// `"none"`, `"each_dof"`, `"chain"` or DOF pairs (1-based, 0 = ground).
    Elements(ElementsSpec),
    /// A known matrix.
    Known {
        /// The matrix (a name or rows).
        known: MatrixRef,
    },
}

/// The DOFs with a constant force.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum OffsetsSpec {
    /// `"each_dof"` or `"none"`.
    Named(String),
    /// DOFs, 1-based.
    Dofs(Vec<usize>),
}

/// `[pod]`: project every record on its leading proper orthogonal modes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PodSpec {
    /// Retain this many modes …
    pub modes: Option<usize>,
    /// … or the fewest whose cumulative energy share reaches this (default 0.999).
    pub energy: Option<f64>,
    /// One basis per record (default, the paper's) or one shared by all.
    #[serde(default)]
    pub basis: crate::prep::pod::PodBasis,
    /// Remove the column means before the decomposition (the paper does not).
    #[serde(default)]
    pub remove_mean: bool,
}

/// Phase readings of the harmonic approximation.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseName {
    /// Arithmetic mean lag (the paper's reading).
    #[default]
    ArithmeticMean,
    /// Circular mean lag.
    CircularMean,
    /// Amplitude-weighted circular mean lag.
    AmplitudeWeightedMean,
    /// The lag of one DOF (`dof`).
    Dof,
    /// Every DOF its own lag (not synchronous).
    PerDof,
}

/// `[harmonic_approximation]`: fundamentals per window (`[identification]` windows),
/// synchronous motion, eq. 4.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicApproximationSpec {
    /// How the DOFs' common phase is read.
    #[serde(default)]
    pub phase: PhaseName,
    /// The DOF (1-based) whose lag is used with `phase = "dof"`.
    pub dof: Option<usize>,
    /// Samples per synthesized period (default 512).
    pub samples_per_period: Option<usize>,
}

/// `[free_decay]`: each record is a ringdown of one mode (`dampid::prep::free_decay`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreeDecaySpec {
    /// The modal mass m (1.0: a unit modal mass, coefficients per unit mass); required.
    pub mass: Option<Spanned<f64>>,
    /// The mode's band [low, high] in cycles per time unit.
    pub band: Option<Spanned<[f64; 2]>>,
    /// A range [low, high] to find the mode's spectral peak in (band [f_p/2, 2 f_p]).
    pub peak_in: Option<Spanned<[f64; 2]>>,
    /// `"auto"` (after the force has ended; the default) or a time.
    pub start: Option<Spanned<StartSpec>>,
    /// Whole cycles per window (default 1).
    pub cycles: Option<usize>,
    /// Cycles dropped at a record end that cuts through motion (default 4).
    pub edge: Option<usize>,
    /// Keep cycles whose amplitude is at least this many noise amplitudes (default 10).
    pub floor: Option<Spanned<f64>>,
    /// The mode's shape at the record's sensors, one value per motion channel: a modal
    /// filter for a record of several sensors (`dampid::prep::free_decay::modal_filter`).
    pub mode_shape: Option<Spanned<Vec<f64>>>,
    /// `"pod"`: the record's own proper orthogonal modes as the modal filter.
    pub modal_filter: Option<Spanned<String>>,
}

/// `start` of `[free_decay]`: `"auto"` or a time.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum StartSpec {
    /// A time on the record's time axis.
    Time(f64),
    /// `"auto"`.
    Named(String),
}
