//! Uniform string with linear and quadratic damping (section 3.2.1):
//!
//! ```text
//!   ρ z̈ − T z'' + c ż + d ż|ż| = δ(x − L_a) a cos ωt,   z(0, t) = z(L, t) = 0,
//! ```
//!
//! with T = ρ = L = 1, c = 0.4, d = 0.5, L_a = 5/9, ω = π (the first natural frequency)
//! and a ∈ {4, 8, 16, 32}.
//!
//! **Simulation** (`crate::simulate::string`, which states the modal equations): the
//! first ten mass-normalized modes, with the damping integral taken by the rectangular
//! rule on eighteen equally spaced points. Our choice of points: x_k = kL/18,
//! k = 1..18, Δx_k = L/18 (the right-endpoint rule; x_18 = L is a wall where ż = 0, so
//! the seventeen interior points carry it). This grid contains every sensor
//! (x_i = i/9 = 2i/18) and the load point (5/9 = 10/18), and the rule keeps the modes
//! discretely orthogonal, Σ_k φ_j(x_k) φ_l(x_k) Δx = δ_jl for j, l < 18.
//!
//! **Step.** Classic RK4 on an undamped oscillator is stable for hω ≤ 2√2 ≈ 2.83. The
//! paper's h = 0.1 gives hω_10 = π ≈ 3.14 for the tenth mode: unstable (the RK4 growth
//! factor there is about 2 per step), and hω_9 = 2.827 is at the limit. We integrate
//! with [`STRING_SUBSTEPS`] = 10 RK4 sub-steps per sample (h = 0.01, hω_10 = 0.31) and
//! record at h = 0.1: 1000 transient samples, then 200 (ten periods of T = 2, twenty
//! samples each). [`simulate_string`] refuses any sub-step with hω_max > 2√2.
//!
//! **Record.** Eight sensors at x_i = iL/9, i = 1..8 (spacing Δx = L/9), record
//! z(x_i, t) and ż(x_i, t); the one force channel a cos ωt acts on the sensor at L_a
//! (sensor 5, DOF index 4).
//!
//! **Model** (section 3.2, eqs. 12–14): rectangular rule over the sensors,
//! c ∫ ż² dx ≈ c Σ_i Δx ż_i² and d ∫ |ż|³ dx ≈ d Σ_i Δx |ż_i|³, i.e.
//! `Term::viscous("c", Δx·I)` and `Term::weighted(Quadratic, sensors, Δx, "d")`. The
//! point load's work is ∮ ż(L_a) a cos ωt dt, with no Δx (∫ δ(x − L_a) ż dx = ż(L_a)).
//! The walls (x = 0, L) add nothing since ż = 0 there.
//!
//! **What the discretizations do.** The choice of the simulator's eighteen points hardly
//! matters: the midpoint rule ((k − ½)L/18), the interior points kL/19 and
//! linspace(0, L, 18) move the two-mode estimates by less than 1e-4. The sensors' rule
//! matters more: with eight sensors (Δx = 1/9) the sum Σ_i Δx |ż_i|³ differs slightly
//! from the simulator's eighteen-point sum, which alone moves even the full-order fit
//! to c ≈ 0.408 (+2%), d ≈ 0.498. With seventeen sensors on the simulator's own grid the
//! full-order fit returns c and d to 0.05%.

use std::f64::consts::PI;

use faer::Mat;

use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::model::DampingModel;
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::record::{Record, RecordParts};
use crate::regressor::RegressorSettings;
use crate::simulate::SimSettings;
use crate::simulate::string::{StringSystem, simulate_string};
use crate::terms::laws::Quadratic;
use crate::terms::{Coefficients, Element, Term};

/// True linear damping coefficient c.
pub const STRING_C: f64 = 0.4;
/// True quadratic damping coefficient d.
pub const STRING_D: f64 = 0.5;
/// Driving frequency ω = π (first mode).
pub const STRING_OMEGA: f64 = PI;
/// Load position L_a = 5/9.
pub const STRING_FORCE_POSITION: f64 = 5.0 / 9.0;
/// Forcing amplitudes a.
pub const STRING_AMPLITUDES: [f64; 4] = [4.0, 8.0, 16.0, 32.0];
/// Linear modes simulated.
pub const STRING_MODES: usize = 10;
/// Points of the rectangular rule for the damping integral in the simulator.
pub const STRING_DAMPING_POINTS: usize = 18;
/// Displacement sensors.
pub const STRING_SENSORS: usize = 8;
/// RK4 sub-steps per recorded step of 0.1 (h = 0.01).
pub const STRING_SUBSTEPS: usize = 10;

/// The paper's printed POM energy shares (dominant, second) for a = 4 and a = 32,
/// noise-free (the text gives the two extremes of the four amplitudes).
pub const PAPER_SHARES: [(f64, f64, f64); 2] = [(4.0, 0.991, 0.009), (32.0, 0.953, 0.046)];
/// The paper's one-mode estimate (c₁, d₁), noise-free.
pub const PAPER_ONE_MODE: (f64, f64) = (0.3032, 0.5354);
/// The paper's two-mode estimate (c₂, d₂), noise-free.
pub const PAPER_TWO_MODES: (f64, f64) = (0.4024, 0.4987);
/// The paper's one-mode estimate with sensor noise 2⁻³.
pub const PAPER_NOISY_ONE_MODE: (f64, f64) = (0.1964, 0.5479);
/// The paper's two-mode estimate with sensor noise 2⁻³.
pub const PAPER_NOISY_TWO_MODES: (f64, f64) = (0.3935, 0.5007);
/// The paper's sensor-noise amplitude: U(−1, 1) · 2⁻³.
pub const STRING_NOISE_AMPLITUDE: f64 = 0.125;

// The paper's case, beside its constants (the simulator itself is in `simulate::string`).
impl StringSystem {
    /// The paper's string driven at amplitude `amplitude`.
    pub fn paper(amplitude: f64) -> Self {
        StringSystem {
            tension: 1.0,
            density: 1.0,
            length: 1.0,
            linear_damping: STRING_C,
            quadratic_damping: STRING_D,
            force_position: STRING_FORCE_POSITION,
            amplitude,
            frequency: STRING_OMEGA,
            modes: STRING_MODES,
            damping_points: STRING_DAMPING_POINTS,
            sensors: STRING_SENSORS,
        }
    }
}

/// The paper's recording (h = 0.1, 1000 transient and 200 recorded samples) with
/// [`STRING_SUBSTEPS`] RK4 sub-steps per sample for stability.
pub fn string_sim_settings() -> SimSettings {
    SimSettings {
        substeps: STRING_SUBSTEPS,
        ..SimSettings::default()
    }
}

/// The identification model on the sensors (eqs. 12 and 14 with L_c = 1):
/// C₀ = Δx I for `c`, and d ż|ż| on every sensor with weight Δx for `d`.
pub fn string_model(system: &StringSystem) -> DampingModel {
    let n = system.sensors;
    let dx = system.sensor_spacing();
    let mut c0 = Mat::<f64>::identity(n, n);
    c0 *= faer::Scale(dx);
    DampingModel::new()
        .with(Term::viscous("c", c0))
        .with(Term::weighted(
            Quadratic,
            Element::each_dof(n),
            vec![dx; n],
            Coefficients::Shared("d".into()),
        ))
}

/// Simulated sensor records of the paper's string for every amplitude.
pub fn string_records(settings: &SimSettings) -> Result<Vec<Record>> {
    STRING_AMPLITUDES
        .iter()
        .map(|&a| simulate_string(&StringSystem::paper(a), settings))
        .collect()
}

/// The record with `noise` (samples × sensors) added to its displacements and its
/// velocities dropped: what noisy displacement sensors give. Forces are unchanged.
pub fn with_displacement_noise(record: &Record, noise: &Mat<f64>) -> Result<Record> {
    if noise.shape() != (record.samples(), record.dofs()) {
        let (what, expected, found) = if noise.nrows() != record.samples() {
            ("rows of noise vs samples", record.samples(), noise.nrows())
        } else {
            ("columns of noise vs DOFs", record.dofs(), noise.ncols())
        };
        return Err(Error::mismatch(what, expected, found));
    }
    let parts = record.parts();
    Record::new(RecordParts {
        label: format!("{} (noisy)", parts.label),
        displacements: &parts.displacements + noise,
        velocities: None,
        ..parts.clone()
    })
}

/// Our reading of the string fits: one equation per amplitude from one window of all
/// ten recorded periods, rectangular rule (exact here: T/h = 20), velocities from
/// `velocity`.
pub fn string_identify_settings(velocity: VelocitySource) -> IdentifySettings {
    IdentifySettings {
        regressor: RegressorSettings {
            windows: WindowSpec::cycles(10).first(1).into(),
            quadrature: Quadrature::Rectangular,
            velocity,
            ..RegressorSettings::default()
        },
        ..IdentifySettings::default()
    }
}
