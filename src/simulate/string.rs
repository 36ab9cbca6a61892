//! The modal simulator of a uniform string fixed at both ends, driven by a point load
//! and sensed at equally spaced points (the paper's section 3.2.1; its case settings and
//! identification are in `crate::reference::string`):
//!
//! ```text
//!   ρ z̈ − T z'' + c ż + d ż|ż| = δ(x − L_a) a cos ωt,   z(0, t) = z(L, t) = 0.
//! ```
//!
//! **Simulation.** On the first `modes` mass-normalized modes φ_j(x) = √(2/ρL) sin(jπx/L),
//! z = Σ_j q_j φ_j, ω_j = jπ√(T/ρ)/L:
//!
//! ```text
//!   q̈_j + (c/ρ) q̇_j + ω_j² q_j + d Σ_k φ_j(x_k) f(ż(x_k)) Δx_k = a φ_j(L_a) cos ωt,
//! ```
//!
//! f(ż) = ż|ż|, with the damping integral taken by the rectangular rule on P equally
//! spaced points, x_k = kL/P, k = 1..P, Δx_k = L/P (the right-endpoint rule; x_P = L is a
//! wall where ż = 0, so the interior points carry it). With the paper's P = 18 this grid
//! contains every sensor (x_i = i/9 = 2i/18) and the load point (5/9 = 10/18), and the
//! rule keeps the modes discretely orthogonal, Σ_k φ_j(x_k) φ_l(x_k) Δx = δ_jl for
//! j, l < 18.
//!
//! **Step.** Classic RK4 on an undamped oscillator is stable for hω ≤ 2√2 ≈ 2.83. The
//! paper's h = 0.1 gives hω_10 = π ≈ 3.14 for the tenth mode: unstable (the RK4 growth
//! factor there is about 2 per step), and hω_9 = 2.827 is at the limit. The simulator
//! integrates with `substeps` RK4 sub-steps per recorded sample (the paper's case uses
//! ten: h = 0.01, hω_10 = 0.31) and refuses any sub-step with hω_max > 2√2.
//!
//! **Record.** The sensors at x_i = iL/(sensors + 1) record z(x_i, t) and ż(x_i, t);
//! the one force channel a cos ωt acts on the sensor at L_a (which must be a sensor
//! position).

use std::f64::consts::{PI, SQRT_2};

use faer::Mat;
use serde::{Deserialize, Serialize};

use super::SimSettings;
use super::rk4::Rk4;
use crate::error::{Error, Result};
use crate::record::{Forcing, Record, RecordParts};

/// Stability limit of classic RK4 on the imaginary axis: hω ≤ 2√2.
pub const RK4_STABILITY_LIMIT: f64 = 2.0 * SQRT_2;

/// A uniform string fixed at both ends, driven by a point load, sensed at equally
/// spaced points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StringSystem {
    /// Tension T.
    pub tension: f64,
    /// Mass per unit length ρ.
    pub density: f64,
    /// Length L.
    pub length: f64,
    /// Linear damping coefficient c.
    pub linear_damping: f64,
    /// Quadratic damping coefficient d.
    pub quadratic_damping: f64,
    /// Load position L_a; must be a sensor position.
    pub force_position: f64,
    /// Load amplitude a.
    pub amplitude: f64,
    /// Driving frequency ω.
    pub frequency: f64,
    /// Linear modes simulated.
    pub modes: usize,
    /// Points of the rectangular rule for the simulated damping integral.
    pub damping_points: usize,
    /// Sensors at x_i = iL/(sensors + 1).
    pub sensors: usize,
}

impl StringSystem {
    /// Checks every field; the load must sit on a sensor.
    pub fn validate(&self) -> Result<()> {
        for (name, value) in [
            ("tension", self.tension),
            ("density", self.density),
            ("length", self.length),
            ("frequency", self.frequency),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(name, value, "must be finite and positive"));
            }
        }
        for (name, value) in [
            ("linear_damping", self.linear_damping),
            ("quadratic_damping", self.quadratic_damping),
            ("amplitude", self.amplitude),
        ] {
            if !value.is_finite() {
                return Err(Error::invalid(name, value, "must be finite"));
            }
        }
        for (name, value) in [
            ("modes", self.modes),
            ("damping_points", self.damping_points),
            ("sensors", self.sensors),
        ] {
            if value == 0 {
                return Err(Error::invalid(name, 0.0, "must be at least 1"));
            }
        }
        self.force_sensor().map(|_| ())
    }

    /// ω_j = jπ√(T/ρ)/L for mode j = 1, 2, ….
    pub fn modal_frequency(&self, j: usize) -> f64 {
        j as f64 * PI * (self.tension / self.density).sqrt() / self.length
    }

    /// φ_j(x) = √(2/ρL) sin(jπx/L) for mode j = 1, 2, ….
    pub fn mode_shape(&self, j: usize, x: f64) -> f64 {
        (2.0 / (self.density * self.length)).sqrt() * (j as f64 * PI * x / self.length).sin()
    }

    /// Sensor spacing Δx = L/(sensors + 1).
    pub fn sensor_spacing(&self) -> f64 {
        self.length / (self.sensors + 1) as f64
    }

    /// Sensor positions x_i = iΔx, i = 1..=sensors.
    pub fn sensor_positions(&self) -> Vec<f64> {
        let dx = self.sensor_spacing();
        (1..=self.sensors).map(|i| i as f64 * dx).collect()
    }

    /// Points of the simulator's damping rule, x_k = kL/P, k = 1..=P.
    pub fn damping_positions(&self) -> Vec<f64> {
        let dx = self.damping_spacing();
        (1..=self.damping_points).map(|k| k as f64 * dx).collect()
    }

    /// Spacing of the simulator's damping rule, L/P.
    pub fn damping_spacing(&self) -> f64 {
        self.length / self.damping_points as f64
    }

    /// The index (0-based) of the sensor at the load position.
    pub fn force_sensor(&self) -> Result<usize> {
        let dx = self.sensor_spacing();
        let position = self.force_position / dx;
        let nearest = position.round();
        if !(self.force_position > 0.0 && self.force_position < self.length)
            || (position - nearest).abs() > 1e-9 * position.max(1.0)
            || nearest < 1.0
            || nearest > self.sensors as f64
        {
            return Err(Error::invalid(
                "force_position",
                self.force_position,
                &format!(
                    "must be one of the sensor positions iL/{} inside the string",
                    self.sensors + 1
                ),
            ));
        }
        Ok(nearest as usize - 1)
    }

    /// The RK4 stability figure of `settings` for the highest simulated mode.
    pub fn step_check(&self, settings: &SimSettings) -> StepCheck {
        let omega = self.modal_frequency(self.modes);
        let substep = settings.step / settings.substeps.max(1) as f64;
        StepCheck {
            highest_frequency: omega,
            recording_step: settings.step,
            recording_product: settings.step * omega,
            substeps: settings.substeps,
            substep,
            substep_product: substep * omega,
            limit: RK4_STABILITY_LIMIT,
        }
    }
}

/// RK4 stability of a step for the highest simulated mode: stable when hω ≤ 2√2.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepCheck {
    /// ω of the highest simulated mode.
    pub highest_frequency: f64,
    /// The recording step h.
    pub recording_step: f64,
    /// h ω_max: RK4 with one step per sample would need this ≤ 2√2.
    pub recording_product: f64,
    /// RK4 sub-steps per recorded step.
    pub substeps: usize,
    /// The integration step h/substeps.
    pub substep: f64,
    /// (h/substeps) ω_max.
    pub substep_product: f64,
    /// 2√2.
    pub limit: f64,
}

impl StepCheck {
    /// Whether the recording step alone (one RK4 step per sample) would be stable.
    pub fn recording_step_stable(&self) -> bool {
        self.recording_product <= self.limit
    }
    /// Whether the integration step is stable.
    pub fn stable(&self) -> bool {
        self.substep_product <= self.limit
    }
}

/// Simulates the string on its modes from rest and records the sensors' steady state.
pub fn simulate_string(system: &StringSystem, settings: &SimSettings) -> Result<Record> {
    system.validate()?;
    settings.validate()?;
    let check = system.step_check(settings);
    if !check.stable() {
        return Err(Error::invalid(
            "substeps",
            settings.substeps as f64,
            &format!(
                "RK4 is unstable for mode {} (ω = {:.4}): h ω = {:.4} exceeds 2√2 ≈ 2.828; use at least {} sub-steps",
                system.modes,
                check.highest_frequency,
                check.substep_product,
                (settings.step * check.highest_frequency / RK4_STABILITY_LIMIT).ceil()
            ),
        ));
    }
    let modes = system.modes;
    // Φ on the damping points (points × modes), the velocity there and the positions,
    // then the recorded sensors' displacement and velocity and the force.
    let values = (system.damping_points as u128)
        .saturating_mul(modes as u128 + 2)
        .saturating_add(
            (settings.recorded_steps as u128).saturating_mul(2 * system.sensors as u128 + 1),
        );
    crate::budget::require(
        &format!(
            "the string simulation ({} damping points × {modes} modes, {} recorded steps × {} sensors)",
            crate::format::integer(system.damping_points as u128),
            crate::format::integer(settings.recorded_steps as u128),
            system.sensors
        ),
        crate::budget::f64s(values),
        "reduce `damping_points`, `modes` or `recorded_steps`",
    )?;
    let points = system.damping_positions();
    let point_weight = system.damping_spacing();
    // Φ_kj = φ_j(x_k) on the damping points, and φ_j at the load.
    let phi = Mat::from_fn(points.len(), modes, |k, j| {
        system.mode_shape(j + 1, points[k])
    });
    let load: Vec<f64> = (1..=modes)
        .map(|j| system.mode_shape(j, system.force_position))
        .collect();
    let omega2: Vec<f64> = (1..=modes)
        .map(|j| system.modal_frequency(j).powi(2))
        .collect();
    let c_over_rho = system.linear_damping / system.density;
    let mut velocity_at = vec![0.0; points.len()];
    let mut derivative = |t: f64, y: &[f64], out: &mut [f64]| {
        let (q, qd) = y.split_at(modes);
        for (k, vk) in velocity_at.iter_mut().enumerate() {
            *vk = (0..modes).map(|j| phi[(k, j)] * qd[j]).sum();
        }
        let drive = system.amplitude * (system.frequency * t).cos();
        for j in 0..modes {
            let quadratic: f64 = velocity_at
                .iter()
                .enumerate()
                .map(|(k, v)| phi[(k, j)] * v * v.abs())
                .sum::<f64>()
                * point_weight;
            out[j] = qd[j];
            out[modes + j] = drive * load[j]
                - c_over_rho * qd[j]
                - omega2[j] * q[j]
                - system.quadratic_damping * quadratic;
        }
    };
    let mut rk = Rk4::new(2 * modes);
    let sensors = system.sensor_positions();
    let at_sensors = Mat::from_fn(sensors.len(), modes, |i, j| {
        system.mode_shape(j + 1, sensors[i])
    });
    let recorded = settings.recorded_steps;
    let mut z = Mat::<f64>::zeros(recorded, sensors.len());
    let mut zd = Mat::<f64>::zeros(recorded, sensors.len());
    let mut signal = Mat::<f64>::zeros(recorded, 1);
    let mut state = vec![0.0; 2 * modes];
    let h = settings.step / settings.substeps as f64;
    let total = settings.transient_steps + recorded;
    let mut stopwatch = crate::budget::Stopwatch::start();
    // RK4 steps done and to do; checked about every 2^16 multiply-adds of the modal
    // equations (modes × damping points per evaluation).
    let mut integrated: u64 = 0;
    let work = (total as u64).saturating_mul(settings.substeps as u64);
    let check_every = (65_536
        / (modes as u64)
            .saturating_mul(system.damping_points as u64)
            .max(1))
    .clamp(1, 64);
    for step in 0..total {
        let t_sample = step as f64 * settings.step;
        if step >= settings.transient_steps {
            let row = step - settings.transient_steps;
            for i in 0..sensors.len() {
                z[(row, i)] = (0..modes).map(|j| at_sensors[(i, j)] * state[j]).sum();
                zd[(row, i)] = (0..modes)
                    .map(|j| at_sensors[(i, j)] * state[modes + j])
                    .sum();
            }
            signal[(row, 0)] = system.amplitude * (system.frequency * t_sample).cos();
        }
        for sub in 0..settings.substeps {
            rk.step(t_sample + sub as f64 * h, h, &mut state, &mut derivative);
            integrated += 1;
            if integrated.is_multiple_of(check_every) {
                crate::cancel::check("the string simulation")?;
                stopwatch.check(
                    integrated,
                    work,
                    &format!(
                        "a string simulation of {} steps × {} substeps on {modes} modes and {} damping points",
                        crate::format::integer(total as u128),
                        crate::format::integer(settings.substeps as u128),
                        crate::format::integer(system.damping_points as u128)
                    ),
                    "reduce `transient_steps`, `recorded_steps`, `substeps`, `modes` or `damping_points`",
                )?;
            }
        }
        if state.iter().any(|s| !s.is_finite()) {
            return Err(Error::Numerical {
                stage: "string simulation".into(),
                detail: format!(
                    "the modal state diverged at t = {}; add sub-steps",
                    t_sample + settings.step
                ),
            });
        }
    }
    Record::new(RecordParts {
        label: format!("a={}", system.amplitude),
        step: settings.step,
        start_time: settings.transient_steps as f64 * settings.step,
        displacements: z,
        velocities: Some(zd),
        forcing: Forcing::on_dofs(signal, vec![system.force_sensor()?]),
        period: 2.0 * PI / system.frequency,
    })
}
