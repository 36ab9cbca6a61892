//! How far each window is from periodic motion, before it becomes an equation.
//!
//! The energy balance holds over a window [t₀, t₀ + kT] only when the stored energy at
//! its end equals that at its start. For every window this module compares the state at
//! the end, interpolated at the fractional sample t₀ + kT by four-point (cubic) Lagrange
//! interpolation, with the state at the start:
//!
//! ```text
//!   δx = max_j |x_j(t₀ + kT) − x_j(t₀)| / A_x,   A_x = max_j ½ (max_t x_j − min_t x_j),
//!   δv = max_j |v_j(t₀ + kT) − v_j(t₀)| / A_v    (the same with velocities),
//! ```
//!
//! amplitudes taken over the window. When mass and stiffness are known (and any
//! grounded cubic springs k x_d³), the stored-energy mismatch this implies is compared
//! with the window's input work:
//!
//! ```text
//!   ΔE = ½ Δ(vᵀ M v) + ½ Δ(xᵀ K x) + ¼ Σ_d k_d Δ(x_d⁴),   W = ∫ vᵀ r dt,   ε_E = |ΔE| / |W|,
//! ```
//!
//! W by the trapezoid rule over exactly [t₀, t₀ + kT] (the window's own rule when the
//! record ends before the trapezoid's last sample). ΔE is exactly the error the
//! window's equation carries, as a share of its right-hand side.
//!
//! When t₀ + kT lies past the record's last sample (a window that ends with the record),
//! the comparison is over the k' < k whole periods that fit, scaled by k/k'.
//!
//! A window that closes periodically ([`Window::closed`]: its L = kT/h samples end with
//! the record, one step before t₀ + kT) is such a window. Its equation takes the sample
//! at t₀ + kT to be the one at t₀, which would make the comparison trivially exact, so
//! the check does not use the closure: with k ≥ 2 it compares the state k − 1 periods
//! on with the start (scaled by k/(k − 1)), a drift period by period; with k = 1 it
//! extrapolates the state at t₀ + kT one step past the record's last sample from its
//! last four samples, which tests the seam the closure assumes (a record that does not
//! end where it started shows a jump there). Its input work W uses the window's own
//! weights, w_i = h over the L samples.
//!
//! A window is steady when ε_E ≤ [`SteadyStateSettings::max_energy_mismatch`] (M and K
//! known), else when max(δx, δv) ≤ [`SteadyStateSettings::max_state_mismatch`].
//!
//! Velocities: the record's measured velocities when it has them; otherwise central
//! differences. The spectral and harmonic-projection estimators fit a series periodic
//! over the window, which would make any window look periodic, so they are not used here.

use std::fmt;

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::{Window, WindowSpec};
use crate::record::{LoadDistribution, Record};

/// Default largest |ΔE| / |W| of a steady window (1% of the input work).
pub const DEFAULT_MAX_ENERGY_MISMATCH: f64 = 0.01;
/// Default largest max(δx, δv) of a steady window when M and K are unknown (2%).
pub const DEFAULT_MAX_STATE_MISMATCH: f64 = 0.02;

/// Thresholds, and whether windows that are not steady are accepted anyway.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SteadyStateSettings {
    /// Largest stored-energy mismatch |ΔE| / |W| (used when M and K are known).
    pub max_energy_mismatch: f64,
    /// Largest state mismatch max(δx, δv) (used when M and K are unknown).
    pub max_state_mismatch: f64,
    /// Accept windows that are not steady (report them, do not reject them).
    pub accept_transient: bool,
}

impl Default for SteadyStateSettings {
    fn default() -> Self {
        SteadyStateSettings {
            max_energy_mismatch: DEFAULT_MAX_ENERGY_MISMATCH,
            max_state_mismatch: DEFAULT_MAX_STATE_MISMATCH,
            accept_transient: false,
        }
    }
}

impl SteadyStateSettings {
    /// Checks the thresholds.
    pub fn validate(&self) -> Result<()> {
        for (name, value) in [
            ("max_energy_mismatch", self.max_energy_mismatch),
            ("max_state_mismatch", self.max_state_mismatch),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(name, value, "must be finite and positive"));
            }
        }
        Ok(())
    }
}

/// What stores energy: M, K and grounded cubic springs, on the records' DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredEnergy {
    /// Mass matrix M (n × n).
    pub mass: Mat<f64>,
    /// Stiffness matrix K (n × n).
    pub stiffness: Mat<f64>,
    /// Grounded cubic springs (DOF, 0-based; k), potential ¼ k x⁴.
    pub cubic_springs: Vec<(usize, f64)>,
}

impl StoredEnergy {
    /// ½ vᵀ M v + ½ xᵀ K x + ¼ Σ k x_d⁴.
    pub fn energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let quadratic = |m: &Mat<f64>, y: &[f64]| {
            let mut sum = 0.0;
            for (i, yi) in y.iter().enumerate() {
                for (j, yj) in y.iter().enumerate() {
                    sum += yi * m[(i, j)] * yj;
                }
            }
            sum
        };
        let springs: f64 = self
            .cubic_springs
            .iter()
            .map(|&(dof, k)| 0.25 * k * x[dof].powi(4))
            .sum();
        0.5 * quadratic(&self.mass, v) + 0.5 * quadratic(&self.stiffness, x) + springs
    }

    fn validate(&self, dofs: usize) -> Result<()> {
        for (what, m) in [("mass", &self.mass), ("stiffness", &self.stiffness)] {
            if m.nrows() != dofs || m.ncols() != dofs {
                let found = if m.nrows() != dofs {
                    m.nrows()
                } else {
                    m.ncols()
                };
                return Err(Error::mismatch(
                    format!("{what} matrix size vs record DOFs (steady-state check)"),
                    dofs,
                    found,
                ));
            }
        }
        for &(dof, _) in &self.cubic_springs {
            if dof >= dofs {
                return Err(Error::dof_index(
                    "cubic spring (steady-state check)",
                    dof,
                    dofs,
                ));
            }
        }
        Ok(())
    }
}

/// The check of one window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowCheck {
    /// The record's label.
    pub record: String,
    /// The record's index in the list.
    pub record_index: usize,
    /// The window's index within its record.
    pub window: usize,
    /// Time of the window's first sample.
    pub start_time: f64,
    /// δx: displacement change over the window relative to its amplitude.
    pub displacement_mismatch: f64,
    /// δv: velocity change over the window relative to its amplitude.
    pub velocity_mismatch: f64,
    /// Input work W over the window (trapezoid rule).
    pub input_work: f64,
    /// ΔE, the stored-energy change over the window, when M and K are known.
    pub energy_change: Option<f64>,
    /// |ΔE| / |W|, when M and K are known.
    pub energy_mismatch: Option<f64>,
    /// Whether the window passes its threshold.
    pub steady: bool,
}

impl WindowCheck {
    /// max(δx, δv).
    pub fn state_mismatch(&self) -> f64 {
        self.displacement_mismatch.max(self.velocity_mismatch)
    }
}

/// The check of every window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyStateReport {
    /// The settings checked against.
    pub settings: SteadyStateSettings,
    /// Whether M and K were known (the energy criterion) or not (the state criterion).
    pub energy_known: bool,
    /// One entry per window, in regressor row order.
    pub windows: Vec<WindowCheck>,
}

impl SteadyStateReport {
    /// The windows that are not steady.
    pub fn rejected(&self) -> impl Iterator<Item = &WindowCheck> {
        self.windows.iter().filter(|w| !w.steady)
    }

    /// `Ok` when every window is steady or the settings accept transients; otherwise
    /// [`Error::NotSteady`] for the window furthest from steady.
    pub fn enforce(&self) -> Result<()> {
        if self.settings.accept_transient {
            return Ok(());
        }
        let (measure, threshold) = self.criterion();
        let worst = self
            .rejected()
            .max_by(|a, b| self.measured(a).total_cmp(&self.measured(b)));
        match worst {
            None => Ok(()),
            Some(w) => Err(Error::NotSteady {
                record: w.record.clone(),
                window: w.window,
                start_time: w.start_time,
                measure: measure.into(),
                mismatch: self.measured(w),
                threshold,
            }),
        }
    }

    fn criterion(&self) -> (&'static str, f64) {
        if self.energy_known {
            (
                "stored-energy mismatch |ΔE|/|W|",
                self.settings.max_energy_mismatch,
            )
        } else {
            (
                "state mismatch max(δx, δv)",
                self.settings.max_state_mismatch,
            )
        }
    }

    fn measured(&self, w: &WindowCheck) -> f64 {
        match (self.energy_known, w.energy_mismatch) {
            (true, Some(e)) => e,
            _ => w.state_mismatch(),
        }
    }
}

impl fmt::Display for SteadyStateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (measure, threshold) = self.criterion();
        writeln!(
            f,
            "steady state per window ({measure} at most {:.2}%{}):",
            100.0 * threshold,
            if self.settings.accept_transient {
                ", transients accepted"
            } else {
                ""
            }
        )?;
        writeln!(
            f,
            "  {:<32} {:>6} {:>12} {:>10} {:>10} {:>12} {:>10}  verdict",
            "record", "window", "start time", "δx", "δv", "input work", "|ΔE|/|W|"
        )?;
        for w in &self.windows {
            let energy = w
                .energy_mismatch
                .map_or_else(|| "-".to_string(), |e| format!("{:.3}%", 100.0 * e));
            let verdict = match (w.steady, self.settings.accept_transient) {
                (true, _) => "steady",
                (false, true) => "NOT STEADY (accepted)",
                (false, false) => "NOT STEADY",
            };
            writeln!(
                f,
                "  {:<32} {:>6} {:>12.6} {:>9.3}% {:>9.3}% {:>12.4e} {:>10}  {verdict}",
                w.record,
                w.window,
                w.start_time,
                100.0 * w.displacement_mismatch,
                100.0 * w.velocity_mismatch,
                w.input_work,
                energy
            )?;
        }
        Ok(())
    }
}

/// Checks every window that `windows` cuts from `records` for the rule `quadrature`;
/// `energy` gives M and K when known.
pub fn check(
    records: &[Record],
    windows: &WindowSpec,
    quadrature: Quadrature,
    energy: Option<&StoredEnergy>,
    settings: &SteadyStateSettings,
) -> Result<SteadyStateReport> {
    settings.validate()?;
    let spec = windows;
    let mut windows = Vec::new();
    for (index, record) in records.iter().enumerate() {
        if let Some(e) = energy {
            e.validate(record.dofs())?;
        }
        for window in spec.windows(record, index, quadrature)? {
            let mut checked = check_window(record, &window, quadrature, energy)?;
            checked.steady = match checked.energy_mismatch {
                Some(e) => e <= settings.max_energy_mismatch,
                None => checked.state_mismatch() <= settings.max_state_mismatch,
            };
            windows.push(checked);
        }
    }
    Ok(SteadyStateReport {
        settings: *settings,
        energy_known: energy.is_some(),
        windows,
    })
}

/// The check of `window` of `record`.
fn check_window(
    record: &Record,
    window: &Window,
    quadrature: Quadrature,
    energy: Option<&StoredEnergy>,
) -> Result<WindowCheck> {
    let (start, span) = (window.start, window.span);
    let samples = record.samples();
    let h = record.step();
    let (compared, scale) = compared_span(record, start, span, window.cycles);
    let end = start as f64 + compared / h;
    let stencil = Stencil::at(end, samples);
    // Velocities for the stencil and for every sample the work's weights read.
    let work_samples = Quadrature::Trapezoid
        .samples(span, h)
        .max(quadrature.samples(span, h));
    let last = stencil
        .last()
        .max(start.saturating_add(work_samples).saturating_sub(1))
        .max(start + 1)
        .min(samples - 1);
    // The stencil may reach before the window's start in a short record's last window.
    let origin = start.min(stencil.first);
    let source = if record.velocities().is_some() {
        VelocitySource::Measured
    } else {
        VelocitySource::CentralDifference
    };
    let velocities = source.window_velocities(record, origin, last + 1 - origin)?;
    let v = velocities
        .as_ref()
        .subrows(start - origin, last + 1 - start);
    let count = last + 1 - start;
    let x = record.displacements().subrows(start, count);
    let n = record.dofs();
    let x_start: Vec<f64> = (0..n).map(|j| x[(0, j)]).collect();
    let v_start: Vec<f64> = (0..n).map(|j| v[(0, j)]).collect();
    let x_end: Vec<f64> = (0..n)
        .map(|j| stencil.value(|i| record.displacements()[(i, j)]))
        .collect();
    let all_v = velocities.as_ref();
    let v_end: Vec<f64> = (0..n)
        .map(|j| stencil.value(|i| all_v[(i - origin, j)]))
        .collect();
    // Amplitudes over the samples inside the window.
    let inside = ((start as f64 + span / h).floor() as usize).min(last) + 1 - start;
    let amplitude = |m: faer::MatRef<'_, f64>| {
        (0..n)
            .map(|j| {
                let column = m.col(j);
                let (lo, hi) = column
                    .iter()
                    .take(inside)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &a| {
                        (lo.min(a), hi.max(a))
                    });
                0.5 * (hi - lo)
            })
            .fold(0.0, f64::max)
    };
    let relative = |a: &[f64], b: &[f64], scale: f64| {
        let change = a
            .iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if change == 0.0 {
            0.0
        } else if scale == 0.0 {
            f64::INFINITY
        } else {
            change / scale
        }
    };
    let displacement_mismatch = scale * relative(&x_end, &x_start, amplitude(x));
    let velocity_mismatch = scale * relative(&v_end, &v_start, amplitude(v));
    let input_work = input_work(record, window, count, v, quadrature)?;
    let energy_change =
        energy.map(|e| scale * (e.energy(&x_end, &v_end) - e.energy(&x_start, &v_start)));
    let energy_mismatch = energy_change.map(|de| {
        if de == 0.0 {
            0.0
        } else if input_work == 0.0 {
            f64::INFINITY
        } else {
            (de / input_work).abs()
        }
    });
    Ok(WindowCheck {
        record: record.label().to_string(),
        record_index: window.record,
        window: window.index,
        start_time: record.start_time() + start as f64 * h,
        displacement_mismatch,
        velocity_mismatch,
        input_work,
        energy_change,
        energy_mismatch,
        steady: true,
    })
}

/// The span over which the end state is compared with the start, and the factor that
/// scales its mismatch to the window: kT when t₀ + kT lies within the record's samples;
/// otherwise the k' < k whole periods that do, scaled by k/k' (a drift accumulates
/// period by period); kT extrapolated (by less than a sample, or one sample for a
/// window that closes periodically) when not even one does.
fn compared_span(record: &Record, start: usize, span: f64, cycles: usize) -> (f64, f64) {
    let last = (record.samples() - 1 - start) as f64 * record.step();
    if span <= last || cycles <= 1 {
        return (span, 1.0);
    }
    let fitting = (last / record.period()).floor() as usize;
    match fitting.min(cycles) {
        // Periods shorter than a sample step cannot be compared on their own.
        k if k == 0 || k as f64 * record.period() < record.step() => (span, 1.0),
        k => (k as f64 * record.period(), cycles as f64 / k as f64),
    }
}

/// W = Σ_i w_i v_iᵀ r_i with trapezoid weights over [t₀, t₀ + span]; the window's own
/// weights when the trapezoid would read past the velocities available (`count`
/// samples), as in a window that closes periodically.
fn input_work(
    record: &Record,
    window: &Window,
    count: usize,
    v: faer::MatRef<'_, f64>,
    rule: Quadrature,
) -> Result<f64> {
    let (start, span, h) = (window.start, window.span, record.step());
    let trapezoid = Quadrature::Trapezoid.weights(span, h, record.period())?;
    let weights = if trapezoid.len() <= count {
        trapezoid
    } else {
        window.weights(rule, h, record.period())?
    };
    let forcing = record.forcing();
    let signals = &forcing.signals;
    let mut work = 0.0;
    for (k, w) in weights.iter().enumerate().take(count) {
        let i = start + k;
        let power: f64 = match &forcing.distribution {
            LoadDistribution::Dofs(dofs) => dofs
                .iter()
                .enumerate()
                .map(|(c, &dof)| signals[(i, c)] * v[(k, dof)])
                .sum(),
            LoadDistribution::Matrix(d) => (0..d.ncols())
                .map(|c| {
                    let load: f64 = (0..d.nrows()).map(|j| d[(j, c)] * v[(k, j)]).sum();
                    signals[(i, c)] * load
                })
                .sum(),
        };
        work += w * power;
    }
    Ok(work)
}

/// Four-point Lagrange interpolation at a fractional sample position.
struct Stencil {
    first: usize,
    weights: Vec<f64>,
}

impl Stencil {
    /// The stencil for position `at` in a record of `samples` samples: the four samples
    /// around it (fewer in a record of fewer samples), shifted inside the record.
    fn at(at: f64, samples: usize) -> Self {
        let points = samples.min(4);
        let below = at.floor().max(0.0) as usize;
        let first = below.saturating_sub((points - 1) / 2).min(samples - points);
        let weights = (0..points)
            .map(|a| {
                let xa = (first + a) as f64;
                (0..points)
                    .filter(|&b| b != a)
                    .map(|b| {
                        let xb = (first + b) as f64;
                        (at - xb) / (xa - xb)
                    })
                    .product()
            })
            .collect();
        Stencil { first, weights }
    }

    fn last(&self) -> usize {
        self.first + self.weights.len() - 1
    }

    fn value(&self, sample: impl Fn(usize) -> f64) -> f64 {
        self.weights
            .iter()
            .enumerate()
            .map(|(a, w)| w * sample(self.first + a))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_stencil_is_exact_for_cubics() {
        let f = |i: usize| {
            let t = i as f64;
            1.0 + 2.0 * t - 0.5 * t * t + 0.1 * t * t * t
        };
        let at = 7.37;
        let exact = 1.0 + 2.0 * at - 0.5 * at * at + 0.1 * at * at * at;
        let stencil = Stencil::at(at, 12);
        assert!((stencil.value(f) - exact).abs() < 1e-10);
        // Near the end of the record the stencil shifts inside it.
        let end = Stencil::at(10.6, 11);
        assert_eq!(end.last(), 10);
        assert!(
            (end.value(f) - (1.0 + 21.2 - 0.5 * 10.6f64.powi(2) + 0.1 * 10.6f64.powi(3))).abs()
                < 1e-9
        );
    }
}
