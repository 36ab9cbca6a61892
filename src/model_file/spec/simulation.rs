//! The specs of the systems a model file simulates or describes: `[simulation]` (M, K,
//! cubic springs, the experiments), `[string_simulation]` and `[system]` (the mass and
//! stiffness of measured data).

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use super::terms::MatrixRef;

/// `[simulation]`: M x'' + Q_d + K x + cubic springs = harmonic forces.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// M.
    pub mass: MatrixRef,
    /// K.
    pub stiffness: MatrixRef,
    /// True damping coefficients, by name (every coefficient of the model).
    pub coefficients: BTreeMap<String, f64>,
    /// True values of estimated law parameters, by their reported name
    /// (`"d.exponent" = 1.7`); one not given is simulated at its initial value.
    #[serde(default)]
    pub parameters: BTreeMap<String, f64>,
    /// Grounded cubic springs k x³.
    #[serde(default)]
    pub cubic_springs: Vec<CubicSpec>,
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step.
    #[serde(default = "one")]
    pub substeps: usize,
    /// Dropped steps.
    pub transient_steps: usize,
    /// Recorded steps.
    pub recorded_steps: usize,
    /// One simulated record per experiment.
    pub experiments: Vec<Spanned<ExperimentSpec>>,
    /// Gaussian noise added to every recorded channel (displacements, velocities,
    /// forces), its standard deviation this fraction of the channel's RMS (default: none).
    pub noise: Option<f64>,
    /// Seed of the noise (default 0): the same seed gives the same records.
    #[serde(default)]
    pub noise_seed: u64,
}

fn one() -> usize {
    1
}

/// A grounded cubic spring.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CubicSpec {
    /// DOF, 1-based.
    pub dof: usize,
    /// k in k x³.
    pub coefficient: f64,
}

/// One simulated experiment: a cos(ωt + φ) on one DOF.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    /// DOF, 1-based.
    pub force_dof: usize,
    /// a.
    pub amplitude: f64,
    /// ω (rad per unit time).
    pub frequency: f64,
    /// φ (rad).
    #[serde(default)]
    pub phase: f64,
}

/// `[string_simulation]`: a uniform string on its linear modes, sensed at equally spaced
/// points, driven by a point load at each amplitude (`dampid::reference::string`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StringSimulationSpec {
    /// Tension T (default 1).
    #[serde(default = "unit")]
    pub tension: f64,
    /// Mass per unit length ρ (default 1).
    #[serde(default = "unit")]
    pub density: f64,
    /// Length L (default 1).
    #[serde(default = "unit")]
    pub length: f64,
    /// Load position L_a (a sensor position).
    pub force_position: f64,
    /// Driving frequency ω.
    pub frequency: f64,
    /// Load amplitudes a, one record each.
    pub amplitudes: Vec<f64>,
    /// Linear modes simulated.
    pub modes: usize,
    /// Points of the rectangular rule for the simulated damping integral.
    pub damping_points: usize,
    /// True coefficients by model name.
    pub coefficients: BTreeMap<String, f64>,
    /// The model coefficient that is the string's linear damping c ż.
    pub linear: String,
    /// The model coefficient that is the string's quadratic damping d ż|ż|.
    pub quadratic: String,
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step.
    #[serde(default = "one")]
    pub substeps: usize,
    /// Dropped steps.
    pub transient_steps: usize,
    /// Recorded steps.
    pub recorded_steps: usize,
}

fn unit() -> f64 {
    1.0
}

/// `[system]`: what stores energy in measured data (never used by the fit).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SystemSpec {
    /// M.
    pub mass: MatrixRef,
    /// K.
    pub stiffness: MatrixRef,
    /// Grounded cubic springs k x³.
    #[serde(default)]
    pub cubic_springs: Vec<CubicSpec>,
}
