//! The simulator, a leaf that produces records (identification never needs it):
//!
//!   M x'' + Q_d(x, x') + K x + f_c(x) = r(t),
//!
//! with the damping Q_d from the term library and given true coefficients, conservative
//! nonlinear forces f_c (e.g. a cubic spring), and harmonic forcing on chosen DOFs,
//! r_i(t) = a cos(ωt + φ). Integrated from rest by classic RK4 with `substeps` steps per
//! recorded sample; `transient_steps` samples are dropped, then `recorded_steps`
//! samples of x, x' and the force channels are recorded. [`string`] simulates a
//! uniform string on its linear modes (a continuous system, apart from [`System`]).

mod matrices;
mod rk4;
pub mod string;

pub use matrices::chain_stiffness;

/// Mass matrices with a larger condition number are treated as singular.
const MAX_MASS_CONDITION: f64 = 1e12;

use std::fmt;
use std::sync::Arc;

use faer::Mat;
use faer::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, check_finite};
use crate::model::DampingModel;
use crate::record::{Forcing, Record, RecordParts};
use crate::terms::Term;
pub(crate) use rk4::Rk4;

/// `f(x, out)`: adds a conservative force f_c(x) to `out`.
pub type ConservativeFn = dyn Fn(&[f64], &mut [f64]) + Send + Sync;

/// A conservative force f_c(x) on the left-hand side of the equations of motion.
#[derive(Clone)]
pub enum ConservativeForce {
    /// A grounded cubic spring, f_c,dof = k x_dof³.
    Cubic {
        /// The DOF (0-based).
        dof: usize,
        /// Coefficient k.
        coefficient: f64,
    },
    /// Any conservative force: `f(x, out)` adds f_c(x) to `out`. It must be the
    /// gradient of a potential for the energy balance to hold.
    Custom(Arc<ConservativeFn>),
}

impl fmt::Debug for ConservativeForce {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConservativeForce::Cubic { dof, coefficient } => {
                write!(f, "Cubic {{ dof: {dof}, coefficient: {coefficient} }}")
            }
            ConservativeForce::Custom(_) => write!(f, "Custom(..)"),
        }
    }
}

/// A harmonic force a cos(ωt + φ) on one DOF.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HarmonicForce {
    /// The DOF (0-based).
    pub dof: usize,
    /// Amplitude a.
    pub amplitude: f64,
    /// Angular frequency ω (rad per unit time).
    pub frequency: f64,
    /// Phase φ (rad).
    pub phase: f64,
}

/// The system to simulate.
#[derive(Debug, Clone)]
pub struct System {
    /// Mass matrix M (n × n, invertible).
    pub mass: Mat<f64>,
    /// Stiffness matrix K (n × n).
    pub stiffness: Mat<f64>,
    /// The damping model.
    pub damping: DampingModel,
    /// Its true coefficients, in the model's coefficient order.
    pub damping_coefficients: Vec<f64>,
    /// Conservative nonlinear forces.
    pub conservative: Vec<ConservativeForce>,
    /// Harmonic forces, all at one frequency (the record's period is 2π/ω).
    pub forcing: Vec<HarmonicForce>,
}

/// Integration and recording settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimSettings {
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step (≥ 1).
    pub substeps: usize,
    /// Recorded steps dropped as transient.
    pub transient_steps: usize,
    /// Recorded steps kept.
    pub recorded_steps: usize,
}

impl Default for SimSettings {
    /// The paper's settings: h = 0.1, 1000 transient steps, 200 recorded steps.
    fn default() -> Self {
        SimSettings {
            step: 0.1,
            substeps: 1,
            transient_steps: 1000,
            recorded_steps: 200,
        }
    }
}

impl SimSettings {
    /// Checks the settings themselves.
    pub fn validate(&self) -> Result<()> {
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(Error::invalid(
                "step",
                self.step,
                "must be finite and positive",
            ));
        }
        if self.substeps == 0 {
            return Err(Error::invalid("substeps", 0.0, "must be at least 1"));
        }
        if self
            .transient_steps
            .checked_add(self.recorded_steps)
            .is_none()
        {
            return Err(Error::invalid(
                "transient_steps",
                self.transient_steps as f64,
                "transient plus recorded steps overflow",
            ));
        }
        if self.recorded_steps < 3 {
            return Err(Error::invalid(
                "recorded_steps",
                self.recorded_steps as f64,
                "must be at least 3",
            ));
        }
        Ok(())
    }
}

impl System {
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    fn validate(&self) -> Result<()> {
        let n = self.dofs();
        if n == 0 {
            return Err(Error::Empty {
                what: "mass matrix".into(),
            });
        }
        for (what, m) in [("mass", &self.mass), ("stiffness", &self.stiffness)] {
            if m.nrows() != n || m.ncols() != n {
                let found = if m.nrows() != n { m.nrows() } else { m.ncols() };
                return Err(Error::mismatch(
                    format!("{what} matrix size vs DOFs"),
                    n,
                    found,
                ));
            }
            check_finite(what, m.as_ref())?;
        }
        self.damping.validate(n)?;
        if let Some(Term::History(h)) = self
            .damping
            .terms()
            .iter()
            .find(|t| matches!(t, Term::History(_)))
        {
            return Err(Error::choice(
                "damping term",
                format!("{} (a force with memory)", h.hysteresis().kind()),
                "not simulated: the RK4 simulator evaluates damping forces f(x, v) of the present state; simulate hysteresis with an integrator that carries its state (tests/hysteresis.rs has one for an SDOF)",
            ));
        }
        if self
            .damping
            .terms()
            .iter()
            .any(|t| matches!(t, Term::Structural(_)))
        {
            return Err(Error::choice(
                "damping term",
                "structural (a loss factor)",
                "not simulated: a hysteretic-damping force −ηk H[x](t) is non-causal in the time domain (the Hilbert transform at t reads the motion after t), so no time-stepping integrator produces it; its steady state is closed form per harmonic, X_n = F_n/(k − m(nω)² + iηk) (tests/structural.rs)",
            ));
        }
        if self.damping_coefficients.len() != self.damping.coefficient_count() {
            return Err(Error::mismatch(
                "true damping coefficients vs model coefficients",
                self.damping.coefficient_count(),
                self.damping_coefficients.len(),
            ));
        }
        for (k, c) in self.damping_coefficients.iter().enumerate() {
            if !c.is_finite() {
                return Err(Error::invalid(
                    &format!("damping coefficient {k}"),
                    *c,
                    "must be finite",
                ));
            }
        }
        for c in &self.conservative {
            if let ConservativeForce::Cubic { dof, coefficient } = c {
                if *dof >= n {
                    return Err(Error::dof_index("cubic spring", *dof, n));
                }
                if !coefficient.is_finite() {
                    return Err(Error::invalid(
                        "cubic spring coefficient",
                        *coefficient,
                        "must be finite",
                    ));
                }
            }
        }
        let Some(first) = self.forcing.first() else {
            return Err(Error::Empty {
                what: "forcing".into(),
            });
        };
        for f in &self.forcing {
            if f.dof >= n {
                return Err(Error::dof_index("harmonic force", f.dof, n));
            }
            if !(f.frequency.is_finite() && f.frequency > 0.0) {
                return Err(Error::invalid(
                    "forcing frequency",
                    f.frequency,
                    "must be finite and positive",
                ));
            }
            if f.frequency != first.frequency {
                return Err(Error::invalid(
                    "forcing frequency",
                    f.frequency,
                    &format!(
                        "all forces must share one frequency (the first is {})",
                        first.frequency
                    ),
                ));
            }
            if !f.amplitude.is_finite() {
                return Err(Error::invalid(
                    "forcing amplitude",
                    f.amplitude,
                    "must be finite",
                ));
            }
            if !f.phase.is_finite() {
                return Err(Error::invalid("forcing phase", f.phase, "must be finite"));
            }
        }
        Ok(())
    }

    /// The applied force r(t) (length n).
    fn applied(&self, t: f64, out: &mut [f64]) {
        out.fill(0.0);
        for f in &self.forcing {
            out[f.dof] += f.amplitude * (f.frequency * t + f.phase).cos();
        }
    }
}

/// A state of the simulation: t, x and v.
type State = (f64, Vec<f64>, Vec<f64>);

/// The error for a damping force that is not finite at a finite state (t, x, v): the
/// term whose law is undefined there, its DOF and the state, 1-based.
fn undefined_damping(system: &System, t: f64, x: &[f64], v: &[f64]) -> Error {
    let n = x.len();
    let mut culprit = None;
    for (term, range) in system.damping.term_columns() {
        let mut out = vec![0.0; n];
        term.add_force(&system.damping_coefficients[range], x, v, &mut out);
        if let Some(dof) = out.iter().position(|f| !f.is_finite()) {
            culprit = Some((term.coefficient_names().join(", "), dof, out[dof]));
            break;
        }
    }
    let list = |values: &[f64]| {
        values
            .iter()
            .map(|value| format!("{value:.4e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (term, dof, value) = culprit.unwrap_or_default();
    Error::Numerical {
        stage: "simulation".into(),
        detail: format!(
            "the damping force of the term with coefficient(s) {term} on DOF {} is {value} at t = {}, x = [{}], v = [{}]: its law is not defined there (an expression such as sqrt(v) or ln(v) at a velocity ≤ 0, or a division by zero); make the law defined for every x and v (e.g. sqrt(abs(v))). This is not a step-size problem",
            dof + 1,
            crate::format::number(t),
            list(x),
            list(v)
        ),
    }
}

/// Reports at most this many times per simulation.
const PROGRESS_REPORTS: usize = 100;

/// Simulates `system` and records its steady state, calling `progress(done, total)` in
/// integration steps (recorded steps, transient included) about every 1% of the run and
/// once at its end ([`crate::progress::silent`] for none).
pub fn simulate(
    system: &System,
    settings: &SimSettings,
    progress: crate::progress::Progress<'_>,
) -> Result<Record> {
    settings.validate()?;
    system.validate()?;
    // The record holds x and v (N × n) and the force channels (N × c).
    let values = (settings.recorded_steps as u128)
        .saturating_mul(2 * system.dofs() as u128 + system.forcing.len() as u128);
    crate::budget::require(
        &format!(
            "a simulated record of {} recorded steps × {} DOFs",
            settings.recorded_steps,
            system.dofs()
        ),
        crate::budget::f64s(values),
        "reduce `recorded_steps` (or the DOFs)",
    )?;
    let n = system.dofs();
    // A mass matrix is invertible in floating point only if it is well conditioned: an
    // LU pivot of round-off size is not a pivot.
    let singular_values = system
        .mass
        .singular_values()
        .map_err(|e| Error::Numerical {
            stage: "simulation".into(),
            detail: format!("SVD of the mass matrix failed: {e:?}"),
        })?;
    let condition = singular_values[0] / singular_values[n - 1];
    if !(condition.is_finite() && condition < MAX_MASS_CONDITION) {
        return Err(Error::Numerical {
            stage: "simulation".into(),
            detail: format!("the mass matrix is singular (condition number {condition:e})"),
        });
    }
    let mass_inverse = system
        .mass
        .partial_piv_lu()
        .solve(Mat::<f64>::identity(n, n));
    let h = settings.step / settings.substeps as f64;
    let mut rk = Rk4::new(2 * n);
    let mut state = vec![0.0; 2 * n];
    let mut force = vec![0.0; n];
    let mut net = vec![0.0; n];
    let mut damping = vec![0.0; n];
    let mut conservative = vec![0.0; n];
    // The first state at which the damping force was not finite while the state was:
    // a law undefined there (an expression's sqrt of a negative velocity), reported as
    // such rather than as a divergence of the integration.
    let undefined: std::cell::RefCell<Option<State>> = Default::default();
    let mut derivative = |t: f64, y: &[f64], out: &mut [f64]| {
        let (x, v) = y.split_at(n);
        system.applied(t, &mut force);
        // net = r − Q_d − K x − f_c
        damping.fill(0.0);
        system
            .damping
            .add_damping_force(&system.damping_coefficients, x, v, &mut damping);
        if !damping.iter().all(|d| d.is_finite())
            && y.iter().all(|s| s.is_finite())
            && undefined.borrow().is_none()
        {
            *undefined.borrow_mut() = Some((t, x.to_vec(), v.to_vec()));
        }
        conservative.fill(0.0);
        for c in &system.conservative {
            match c {
                ConservativeForce::Cubic { dof, coefficient } => {
                    conservative[*dof] += coefficient * x[*dof].powi(3)
                }
                ConservativeForce::Custom(f) => f(x, &mut conservative),
            }
        }
        for i in 0..n {
            let kx: f64 = (0..n).map(|j| system.stiffness[(i, j)] * x[j]).sum();
            net[i] = force[i] - damping[i] - kx - conservative[i];
        }
        out[..n].copy_from_slice(v);
        for i in 0..n {
            out[n + i] = (0..n).map(|j| mass_inverse[(i, j)] * net[j]).sum();
        }
    };
    let total = settings.transient_steps + settings.recorded_steps;
    let report_every = (total / PROGRESS_REPORTS).max(1);
    let recorded = settings.recorded_steps;
    let mut x = Mat::<f64>::zeros(recorded, n);
    let mut v = Mat::<f64>::zeros(recorded, n);
    let mut signals = Mat::<f64>::zeros(recorded, system.forcing.len());
    let mut t = 0.0;
    let mut stopwatch = crate::budget::Stopwatch::start();
    // RK4 steps done and to do (each evaluates the damping forces four times).
    let mut integrated: u64 = 0;
    let work = (total as u64).saturating_mul(settings.substeps as u64);
    // Checked about every 2^16 multiply-adds of the equations of motion (n² per step).
    let check_every = (65_536 / (n as u64).saturating_mul(n as u64).max(1)).clamp(1, 64);
    for step in 0..total {
        if step >= settings.transient_steps {
            let row = step - settings.transient_steps;
            for i in 0..n {
                x[(row, i)] = state[i];
                v[(row, i)] = state[n + i];
            }
            let t_sample = step as f64 * settings.step;
            for (k, f) in system.forcing.iter().enumerate() {
                signals[(row, k)] = f.amplitude * (f.frequency * t_sample + f.phase).cos();
            }
        }
        for sub in 0..settings.substeps {
            t = step as f64 * settings.step + sub as f64 * h;
            rk.step(t, h, &mut state, &mut derivative);
            integrated += 1;
            if integrated.is_multiple_of(check_every) {
                // Every RK4 step counts, so that `substeps` is in the estimate too.
                crate::cancel::check("the simulation")?;
                stopwatch.check(
                    integrated,
                    work,
                    &format!(
                        "a simulation of {} steps × {} substeps of {n} DOFs",
                        crate::format::integer(total as u128),
                        crate::format::integer(settings.substeps as u128)
                    ),
                    "reduce `transient_steps`, `recorded_steps` or `substeps`",
                )?;
            }
        }
        if state.iter().any(|s| !s.is_finite()) {
            if let Some((at, x, v)) = undefined.borrow().as_ref() {
                return Err(undefined_damping(system, *at, x, v));
            }
            return Err(Error::Numerical {
                stage: "simulation".into(),
                detail: format!(
                    "the state diverged at t = {}; reduce the step or add substeps",
                    crate::format::number(t)
                ),
            });
        }
        if (step + 1) % report_every == 0 || step + 1 == total {
            progress((step + 1) as u64, total as u64);
        }
    }
    let frequency = system.forcing[0].frequency;
    Record::new(RecordParts {
        label: format!("sim ω={frequency}"),
        step: settings.step,
        start_time: settings.transient_steps as f64 * settings.step,
        displacements: x,
        velocities: Some(v),
        forcing: Forcing::on_dofs(signals, system.forcing.iter().map(|f| f.dof).collect()),
        period: 2.0 * std::f64::consts::PI / frequency,
    })
}
