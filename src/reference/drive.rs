//! A closed-loop linear drive: the reference case of the non-periodic mode
//! ([`crate::regressor::nonperiodic`]). A carriage of mass m on a guide with viscous friction c,
//! Coulomb friction F_c and a constant force f₀ (the weight on an inclined axis),
//!
//! ```text
//!   m ẍ + c ẋ + F_c sign(ẋ) + f₀ = r,   r = k_p (x_ref − x) + k_d (ẋ_ref − ẋ) + f₀,
//! ```
//!
//! is moved by a PD position controller (with gravity feed-forward) through random
//! point-to-point moves, x_ref going from one target to the next along a minimum-jerk
//! profile, 10 s³ − 15 s⁴ + 6 s⁵ in normalized time s, with dwells between moves. The
//! motion is neither periodic nor steady: the drive stops, reverses and starts again.
//! The record holds what a drive measures: the encoder position x and the motor force
//! r, optionally with white noise on each.
//!
//! Integrated by RK4 with `substeps` steps per recorded sample, sign(0) = 0. While the
//! carriage sticks the integrator chatters about ẋ = 0 with a velocity of order
//! F_c h/m, which is far below the moves' velocities.

use faer::Mat;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::record::{Forcing, Record, RecordParts};
use crate::simulate::Rk4;
use crate::terms::laws::{Coulomb, Linear};
use crate::terms::{Coefficients, Element, Term};

/// The drive, its controller, the moves and the recording.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveSettings {
    /// Moving mass m.
    pub mass: f64,
    /// Viscous friction c.
    pub viscous: f64,
    /// Coulomb friction F_c.
    pub coulomb: f64,
    /// Constant force f₀ (on the left-hand side).
    pub offset: f64,
    /// A spring to ground k x (0: none), to check that a conservative force only adds
    /// a stiffness estimate.
    pub spring: f64,
    /// Position gain k_p.
    pub position_gain: f64,
    /// Velocity gain k_d.
    pub velocity_gain: f64,
    /// Largest distance of a target from 0.
    pub travel: f64,
    /// Shortest and longest move durations.
    pub move_time: (f64, f64),
    /// Longest dwell between moves (uniform from 0).
    pub dwell_time: f64,
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step.
    pub substeps: usize,
    /// Recorded samples.
    pub samples: usize,
    /// Standard deviation of white noise on the recorded position.
    pub position_noise: f64,
    /// Standard deviation of white noise on the recorded force.
    pub force_noise: f64,
    /// Seed of the moves and the noise.
    pub seed: u64,
}

impl Default for DriveSettings {
    /// m = 2 kg, c = 8 N s/m, F_c = 3 N, f₀ = 4.9 N (a 14° incline), k_p = 2000 N/m,
    /// k_d = 60 N s/m; moves within ±0.2 m of 0.3–1 s with dwells up to 0.4 s; 20 s
    /// at h = 1 ms, 10 RK4 steps per sample; no noise.
    fn default() -> Self {
        DriveSettings {
            mass: 2.0,
            viscous: 8.0,
            coulomb: 3.0,
            offset: 4.9,
            spring: 0.0,
            position_gain: 2000.0,
            velocity_gain: 60.0,
            travel: 0.2,
            move_time: (0.3, 1.0),
            dwell_time: 0.4,
            step: 1e-3,
            substeps: 10,
            samples: 20_001,
            position_noise: 0.0,
            force_noise: 0.0,
            seed: 7,
        }
    }
}

/// One point-to-point move of the reference.
struct Move {
    start_time: f64,
    duration: f64,
    from: f64,
    to: f64,
}

impl Move {
    /// x_ref and ẋ_ref at time t (constant before and after the move).
    fn reference(&self, t: f64) -> (f64, f64) {
        let s = ((t - self.start_time) / self.duration).clamp(0.0, 1.0);
        let shape = s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
        let slope = 30.0 * s * s * (1.0 - s) * (1.0 - s) / self.duration;
        let span = self.to - self.from;
        (self.from + span * shape, span * slope)
    }
}

/// The reference trajectory: moves, each followed by a dwell, covering `duration`.
fn moves(settings: &DriveSettings, duration: f64, rng: &mut StdRng) -> Vec<Move> {
    let mut list = Vec::new();
    let (mut t, mut at) = (0.0, 0.0);
    let (shortest, longest) = settings.move_time;
    while t <= duration {
        let to = rng.random_range(-settings.travel..=settings.travel);
        let move_duration = rng.random_range(shortest..=longest);
        list.push(Move {
            start_time: t,
            duration: move_duration,
            from: at,
            to,
        });
        t += move_duration + rng.random_range(0.0..=settings.dwell_time);
        at = to;
    }
    list
}

impl DriveSettings {
    fn validate(&self) -> Result<()> {
        for (name, value) in [
            ("mass", self.mass),
            ("step", self.step),
            ("move_time.0", self.move_time.0),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(name, value, "must be finite and positive"));
            }
        }
        if self.move_time.1 < self.move_time.0 {
            return Err(Error::invalid(
                "move_time.1",
                self.move_time.1,
                "the longest move must not be shorter than the shortest",
            ));
        }
        if self.substeps == 0 || self.samples < 3 {
            return Err(Error::invalid(
                "samples",
                self.samples as f64,
                "at least 3 samples and 1 substep",
            ));
        }
        Ok(())
    }

    /// The true coefficients under the names a model with a shared `viscous` linear
    /// term, a shared `coulomb` Coulomb term and the non-periodic nuisance columns
    /// `mass[1]`, `offset[1]` (and `stiffness[1]`) gives them.
    pub fn truth(&self) -> Vec<(String, f64)> {
        let mut truth = vec![
            ("viscous".to_string(), self.viscous),
            ("coulomb".to_string(), self.coulomb),
            ("mass[1]".to_string(), self.mass),
        ];
        if self.spring != 0.0 {
            truth.push(("stiffness[1]".to_string(), self.spring));
        }
        truth.push(("offset[1]".to_string(), self.offset));
        truth
    }
}

/// The drive's damping model: a shared `viscous` linear term and a shared `coulomb`
/// Coulomb term on DOF 1 (the names [`DriveSettings::truth`] uses).
pub fn drive_model() -> DampingModel {
    DampingModel::new()
        .with(Term::on_elements(
            Linear,
            Element::each_dof(1),
            Coefficients::Shared("viscous".into()),
        ))
        .with(Term::on_elements(
            Coulomb,
            Element::each_dof(1),
            Coefficients::Shared("coulomb".into()),
        ))
}

/// Simulates the drive and returns its record: position x (with measured velocity,
/// noise-free) and the motor force r on DOF 1. The record's period is its duration
/// (nothing in it is periodic).
pub fn closed_loop_drive(settings: &DriveSettings) -> Result<Record> {
    settings.validate()?;
    let duration = (settings.samples - 1) as f64 * settings.step;
    let mut rng = StdRng::seed_from_u64(settings.seed);
    let reference = moves(settings, duration, &mut rng);
    let at = |t: f64| -> (f64, f64) {
        let k = reference.partition_point(|m| m.start_time <= t).max(1) - 1;
        reference[k].reference(t)
    };
    let s = settings;
    let control = |t: f64, x: f64, v: f64| {
        let (x_ref, v_ref) = at(t);
        s.position_gain * (x_ref - x) + s.velocity_gain * (v_ref - v) + s.offset
    };
    let mut rk = Rk4::new(2);
    let mut state = [0.0, 0.0];
    let h = settings.step / settings.substeps as f64;
    let (mut x, mut v, mut force) = (
        Mat::<f64>::zeros(settings.samples, 1),
        Mat::<f64>::zeros(settings.samples, 1),
        Mat::<f64>::zeros(settings.samples, 1),
    );
    let sign = |v: f64| if v == 0.0 { 0.0 } else { v.signum() };
    for i in 0..settings.samples {
        let t = i as f64 * settings.step;
        x[(i, 0)] = state[0];
        v[(i, 0)] = state[1];
        force[(i, 0)] = control(t, state[0], state[1]);
        if i + 1 == settings.samples {
            break;
        }
        for k in 0..settings.substeps {
            rk.step(t + k as f64 * h, h, &mut state, |t, y, out| {
                let r = control(t, y[0], y[1]);
                out[0] = y[1];
                out[1] =
                    (r - s.viscous * y[1] - s.coulomb * sign(y[1]) - s.offset - s.spring * y[0])
                        / s.mass;
            });
        }
    }
    let mut noise = |sigma: f64, m: &mut Mat<f64>| -> Result<()> {
        let normal = Normal::new(0.0, sigma)
            .map_err(|_| Error::invalid("noise", sigma, "must be finite and nonnegative"))?;
        for i in 0..m.nrows() {
            m[(i, 0)] += normal.sample(&mut rng);
        }
        Ok(())
    };
    noise(settings.position_noise, &mut x)?;
    noise(settings.force_noise, &mut force)?;
    Record::new(RecordParts {
        label: format!("drive seed {}", settings.seed),
        step: settings.step,
        start_time: 0.0,
        displacements: x,
        velocities: Some(v),
        forcing: Forcing::on_dofs(force, vec![0]),
        period: duration,
    })
}
