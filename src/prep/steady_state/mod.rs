//! How far each window is from periodic motion, before it becomes an equation, judged
//! on denoised signals against what the noise allows.
//!
//! The energy balance holds over a window [t₀, t₀ + kT] only when the stored energy at
//! its end equals that at its start. Raw samples cannot show it under measurement noise
//! (a central-difference velocity multiplies displacement noise by about 1/(h√2)), so
//! the states are taken from harmonic projections ([`projection`]): every displacement
//! channel is projected on the harmonics of ω that stand above the noise of its record
//! (selected once per record, `prep/fourier/record_noise.rs`), separately over single
//! periods, and each
//! projection gives x̂(t) = bᵀ(t) c_x, v̂(t) = bᵀ(t) c_v with the covariance of
//! (c_x, c_v) from the record's noise σ̂_j estimated out of band,
//! `σ̂_j² [I; J](RᵀR)⁻¹[I; J]ᵀ`.
//!
//! **Which periods.** A window of k ≥ 2 periods compares the projection of its first
//! period at t₀ with that of its last period at t₀ + kT (k' = k). A window of one period
//! compares itself with the next period and with the previous one, where the record
//! holds them (k' = 2 over the two; the next one may be cut short by the record's end
//! down to ¾ of a period), and the better of the two comparisons decides: a period is
//! steady when it matches a neighbour, so a steady window next to a transient one is
//! not blamed for it. A record of a single period cannot be judged, and its window is
//! accepted with that said. A window that closes periodically
//! ([`crate::prep::window::Window::closed`]) is treated the same: its periods are all in
//! the record, so the closure is never used (it would make the comparison exact by
//! construction). A projection over one period sees a drift across its seam as half a
//! jump at each end, so for a drift linear in time the difference between the first
//! and last projected periods is the drift over k' − 1 periods; it is scaled by
//! s = k/(k' − 1) to the window:
//!
//! ```text
//!   δx_j = s (x̂_j^last(t₀ + k'T) − x̂_j^first(t₀)),   Var δx_j = s² (bᵀ Cov^last b + bᵀ Cov^first b),
//!   δv_j likewise with c_v;   relative: δx = max_j |δx_j| / A_x,   A_x = max_j ½ range of x̂_j,
//! ```
//!
//! and, when mass and stiffness are known (and grounded cubic springs k x_d³),
//!
//! ```text
//!   ΔE = s (E(x̂^last, v̂^last) − E(x̂^first, v̂^first)),   E = ½ vᵀMv + ½ xᵀKx + ¼ Σ k_d x_d⁴,
//!   Var ΔE = s² Σ_j (g_jᵀ Cov_j g_j)^first + (…)^last,   g_j = (∂E/∂x_j b, ∂E/∂v_j b),
//!   ε_E = |ΔE| / |W|,   W = ∫ vᵀ r dt,
//! ```
//!
//! W by the trapezoid rule over [t₀, t₀ + kT] (the window's own weights when the record
//! ends first or the window closes periodically) with measured or central-difference
//! velocities: W only normalises, and its noise averages over the window.
//!
//! **Verdict.** With z = [`SteadyStateSettings::noise_sigmas`] (default 4):
//!
//! - M and K known: steady when ε_E ≤ max(ε_max, z σ(ΔE)/|W|), ε_max =
//!   [`SteadyStateSettings::max_energy_mismatch`];
//! - else: steady when every |δx_j| ≤ max(δ_max A_x, z σ(δx_j)) and every |δv_j| ≤
//!   max(δ_max A_v, z σ(δv_j)), δ_max = [`SteadyStateSettings::max_state_mismatch`];
//! - and in both cases the motion holds no significant content between the harmonics
//!   of ω: per channel, the whole compared span fitted on the kept harmonics leaves a
//!   residual RSS_j over m − p degrees of freedom; the non-harmonic RMS
//!   r_j = √max(0, RSS_j/(m − p) − σ̂_j²) must stay below δ_max A_x unless the residual
//!   is within its noise, RSS_j/((m − p) σ̂_j²) ≤ 1 + z √(2/(m − p)) + 0.75 (the margin
//!   covers the error of σ̂ from a median of a few dozen bins). This second symptom sees
//!   a transient that the end states happen to hide.
//!
//! A mismatch within the noise of the projected end states is steady, and so is one
//! within the fixed tolerance whatever the noise: noise-free records are judged as
//! before, on the tolerance alone. The report gives each window's noise-relative
//! mismatch |δ|/σ(δ) ("3.1 σ") and says in words why it is or is not steady.
//!
//! Files: `projection.rs` (the projection of periods, the one place that turns samples
//! into coefficients and covariances), `table.rs` (a span's basis held once, and the
//! passes over a channel's samples against it), `range_grid.rs` (a period's ½ ranges
//! bounded from every eighth sample), `few.rs` (products of a channel's few
//! coefficients, unrolled), `judge.rs` (one window), `energy.rs`
//! (stored energy and its gradient), `spans.rs` (every compared span of a check, each
//! span and each period fitted once). [`check`] estimates each record's harmonics and
//! noise once, projects each compared span once per record, however many windows
//! compare it, and fits each period once for the spans it takes part in.

mod energy;
mod few;
mod judge;
pub mod projection;
mod range_grid;
mod spans;
mod table;

use std::fmt;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::fourier::RecordNoises;
use crate::prep::quadrature::Quadrature;
use crate::prep::window::WindowSpec;
use crate::record::Record;

pub use energy::StoredEnergy;

/// Default largest |ΔE| / |W| of a steady window (1% of the input work).
pub const DEFAULT_MAX_ENERGY_MISMATCH: f64 = 0.01;
/// Default largest max(δx, δv) of a steady window when M and K are unknown (2%).
pub const DEFAULT_MAX_STATE_MISMATCH: f64 = 0.02;
/// Default z: a mismatch within z standard deviations of its noise is steady.
pub const DEFAULT_NOISE_SIGMAS: f64 = 4.0;
/// Fewest samples per period a harmonic projection can judge (a mean and the
/// fundamental below the Nyquist frequency).
const MIN_SAMPLES_PER_PERIOD: f64 = 3.0;
/// Least share of the next period a one-period window is compared with, when the
/// record ends within it.
const MIN_NEIGHBOUR: f64 = 0.75;
/// Allowance in the non-harmonic residual ratio for the error of the noise estimate.
const NON_HARMONIC_MARGIN: f64 = 0.75;

/// Thresholds, and whether windows that are not steady are accepted anyway.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SteadyStateSettings {
    /// Largest stored-energy mismatch |ΔE| / |W| whatever the noise (M and K known).
    pub max_energy_mismatch: f64,
    /// Largest state mismatch max(δx, δv) whatever the noise (M and K unknown), and
    /// largest non-harmonic RMS relative to the amplitude.
    pub max_state_mismatch: f64,
    /// z: a mismatch within z standard deviations of its estimated noise is steady.
    #[serde(default = "default_noise_sigmas")]
    pub noise_sigmas: f64,
    /// Accept windows that are not steady (report them, do not reject them).
    pub accept_transient: bool,
}

fn default_noise_sigmas() -> f64 {
    DEFAULT_NOISE_SIGMAS
}

impl Default for SteadyStateSettings {
    fn default() -> Self {
        SteadyStateSettings {
            max_energy_mismatch: DEFAULT_MAX_ENERGY_MISMATCH,
            max_state_mismatch: DEFAULT_MAX_STATE_MISMATCH,
            noise_sigmas: DEFAULT_NOISE_SIGMAS,
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
            ("noise_sigmas", self.noise_sigmas),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(name, value, "must be finite and positive"));
            }
        }
        Ok(())
    }
}

/// Which periods a window's check compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComparedPeriods {
    /// The window's first period with its last (k ≥ 2).
    FirstAndLastPeriod,
    /// The window's one period with the next one in the record.
    NextPeriod,
    /// The window's one period with the previous one in the record.
    PreviousPeriod,
    /// Nothing: the window cannot be judged (a record of one period, or periods of
    /// too few samples); it is accepted.
    NotJudged,
}

impl ComparedPeriods {
    fn short(&self) -> &'static str {
        match self {
            ComparedPeriods::FirstAndLastPeriod => "first/last",
            ComparedPeriods::NextPeriod => "next",
            ComparedPeriods::PreviousPeriod => "previous",
            ComparedPeriods::NotJudged => "-",
        }
    }
}

/// The comparison that decided a window's verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Decisive {
    /// What was measured ("stored-energy mismatch |ΔE|/|W|", "state mismatch (velocity
    /// of DOF 2)").
    pub measure: String,
    /// The mismatch, relative (to |W|, or to the amplitude).
    pub mismatch: f64,
    /// The largest mismatch accepted for this window: max(tolerance, z σ) (relative).
    pub threshold: f64,
    /// The mismatch in standard deviations of its noise, |δ| / σ(δ).
    pub sigmas: f64,
    /// The fixed tolerance.
    pub tolerance: f64,
    /// The quantity, in words.
    #[serde(skip)]
    what: String,
    /// What the relative mismatch is relative to, in words.
    #[serde(skip)]
    of: &'static str,
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
    /// Which periods were compared.
    pub compared: ComparedPeriods,
    /// The harmonic orders the projections kept (empty when not judged).
    pub harmonics: Vec<usize>,
    /// δx: displacement change over the window relative to its amplitude.
    pub displacement_mismatch: f64,
    /// δv: velocity change over the window relative to its amplitude.
    pub velocity_mismatch: f64,
    /// The largest significant non-harmonic RMS relative to the displacement amplitude
    /// (0 when within the noise).
    pub non_harmonic: f64,
    /// Input work W over the window (trapezoid rule).
    pub input_work: f64,
    /// ΔE, the stored-energy change over the window, when M and K are known.
    pub energy_change: Option<f64>,
    /// |ΔE| / |W|, when M and K are known.
    pub energy_mismatch: Option<f64>,
    /// The comparison that decided (`None`: not judged).
    pub decisive: Option<Decisive>,
    /// Whether the window is accepted as steady (also when it cannot be judged).
    pub steady: bool,
    /// The verdict in words, with the reason.
    pub reason: String,
}

impl WindowCheck {
    /// max(δx, δv).
    pub fn state_mismatch(&self) -> f64 {
        self.displacement_mismatch.max(self.velocity_mismatch)
    }

    /// The mismatch in standard deviations of its noise (`None`: not judged).
    pub fn noise_sigmas(&self) -> Option<f64> {
        self.decisive.as_ref().map(|c| c.sigmas)
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
    /// The windows `indices` (repeats allowed), as [`crate::regressor::Regressor::select_rows`]
    /// selects the rows they are behind.
    pub fn select(&self, indices: &[usize]) -> Self {
        SteadyStateReport {
            settings: self.settings,
            energy_known: self.energy_known,
            windows: indices.iter().map(|&i| self.windows[i].clone()).collect(),
        }
    }

    /// The windows that are not steady.
    pub fn rejected(&self) -> impl Iterator<Item = &WindowCheck> {
        self.windows.iter().filter(|w| !w.steady)
    }

    /// The windows that could not be judged (accepted).
    pub fn not_judged(&self) -> impl Iterator<Item = &WindowCheck> {
        self.windows
            .iter()
            .filter(|w| w.compared == ComparedPeriods::NotJudged)
    }

    /// `Ok` when every window is steady or the settings accept transients; otherwise
    /// [`Error::NotSteady`] for the window furthest beyond its threshold.
    pub fn enforce(&self) -> Result<()> {
        if self.settings.accept_transient {
            return Ok(());
        }
        let excess = |w: &WindowCheck| judge::excess(w, &self.settings);
        let worst = self
            .rejected()
            .max_by(|a, b| excess(a).total_cmp(&excess(b)));
        let Some(w) = worst else {
            return Ok(());
        };
        let (measure, mismatch, threshold) = match &w.decisive {
            Some(c) if c.mismatch > c.threshold => (c.measure.clone(), c.mismatch, c.threshold),
            _ => (
                "non-harmonic RMS / amplitude".to_string(),
                w.non_harmonic,
                self.settings.max_state_mismatch,
            ),
        };
        Err(Error::NotSteady {
            record: w.record.clone(),
            window: w.window,
            start_time: w.start_time,
            measure,
            mismatch,
            threshold,
        })
    }
}

impl fmt::Display for SteadyStateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.settings;
        let criterion = if self.energy_known {
            format!(
                "|ΔE|/|W| within max({}%, {} σ of its noise)",
                100.0 * s.max_energy_mismatch,
                s.noise_sigmas
            )
        } else {
            format!(
                "end state within max({}% of the amplitude, {} σ of its noise)",
                100.0 * s.max_state_mismatch,
                s.noise_sigmas
            )
        };
        writeln!(
            f,
            "steady state per window, from harmonic projections of single periods ({criterion}{}):",
            if s.accept_transient {
                ", transients accepted"
            } else {
                ""
            }
        )?;
        writeln!(
            f,
            "  {:<32} {:>6} {:>12} {:>10} {:>9} {:>9} {:>10} {:>9} {:>12}  verdict",
            "record",
            "window",
            "start time",
            "compared",
            "δx",
            "δv",
            "|ΔE|/|W|",
            "mismatch",
            "input work"
        )?;
        let shown = self.shown_windows();
        for w in shown.iter().map(|&k| &self.windows[k]) {
            let energy = w
                .energy_mismatch
                .map_or_else(|| "-".to_string(), |e| format!("{:.3}%", 100.0 * e));
            let sigmas = match w.noise_sigmas() {
                None => "-".to_string(),
                Some(z) if z < 1e4 => format!("{z:.1} σ"),
                Some(_) => "≫ σ".to_string(),
            };
            let verdict = match (w.steady, w.compared, s.accept_transient) {
                (true, ComparedPeriods::NotJudged, _) => "not judged",
                (true, _, _) => "steady",
                (false, _, true) => "NOT STEADY (accepted)",
                (false, _, false) => "NOT STEADY",
            };
            writeln!(
                f,
                "  {:<32} {:>6} {:>12.6} {:>10} {:>8.3}% {:>8.3}% {:>10} {:>9} {:>12.4e}  {verdict}",
                w.record,
                w.window,
                w.start_time,
                w.compared.short(),
                100.0 * w.displacement_mismatch,
                100.0 * w.velocity_mismatch,
                energy,
                sigmas,
                w.input_work,
            )?;
        }
        if shown.len() < self.windows.len() {
            writeln!(
                f,
                "  … {} more steady windows (of {}; the not-steady ones and the {CLOSEST_WINDOWS} closest to the limit are shown, every window is in the JSON)",
                self.windows.len() - shown.len(),
                self.windows.len()
            )?;
        }
        let unsteady: Vec<&WindowCheck> = self.windows.iter().filter(|w| !w.steady).collect();
        for w in unsteady.iter().take(LISTED_WINDOWS) {
            writeln!(
                f,
                "  record '{}', window {}: {}",
                w.record, w.window, w.reason
            )?;
        }
        if unsteady.len() > LISTED_WINDOWS {
            writeln!(
                f,
                "  + {} more windows not in steady state (in the JSON)",
                unsteady.len() - LISTED_WINDOWS
            )?;
        }
        let unjudged: Vec<&WindowCheck> = self.not_judged().collect();
        if let Some(w) = unjudged.first() {
            writeln!(
                f,
                "  {} window(s) accepted without a judgement, e.g. record '{}', window {}: {}",
                unjudged.len(),
                w.record,
                w.window,
                w.reason
            )?;
        }
        Ok(())
    }
}

/// Windows beyond this many are summarised in the text table.
const LISTED_WINDOWS: usize = 40;
/// Of a summarised table, the steady windows closest to the limit that are shown.
const CLOSEST_WINDOWS: usize = 10;

impl SteadyStateReport {
    /// The windows the text table shows: all of them up to [`LISTED_WINDOWS`]; beyond,
    /// the first [`LISTED_WINDOWS`] not in steady state and the [`CLOSEST_WINDOWS`] of
    /// largest mismatch (|ΔE|/|W| when judged by energy, else the larger of δx and δv),
    /// in record order.
    fn shown_windows(&self) -> Vec<usize> {
        let n = self.windows.len();
        if n <= LISTED_WINDOWS {
            return (0..n).collect();
        }
        let mismatch = |w: &WindowCheck| {
            w.energy_mismatch
                .unwrap_or_else(|| w.displacement_mismatch.max(w.velocity_mismatch))
        };
        let mut shown: Vec<usize> = (0..n)
            .filter(|&k| !self.windows[k].steady)
            .take(LISTED_WINDOWS)
            .collect();
        let mut order: Vec<usize> = (0..n).filter(|&k| self.windows[k].steady).collect();
        order.sort_by(|&a, &b| mismatch(&self.windows[b]).total_cmp(&mismatch(&self.windows[a])));
        shown.extend(order.into_iter().take(CLOSEST_WINDOWS));
        shown.sort_unstable();
        shown
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
    check_with(records, windows, quadrature, energy, settings, None)
}

/// [`check`] reading the records' harmonics and noise from `noises` where they are of
/// these records (estimated once for the check and the noise-robust rows of a problem,
/// `prep/fourier/record_noise.rs`), else estimating them.
pub(crate) fn check_with(
    records: &[Record],
    windows: &WindowSpec,
    quadrature: Quadrature,
    energy: Option<&StoredEnergy>,
    settings: &SteadyStateSettings,
    noises: Option<&RecordNoises>,
) -> Result<SteadyStateReport> {
    settings.validate()?;
    crate::prep::data_scale::require_representable(records)?;
    let spec = windows;
    let mut cut = Vec::new();
    for (index, record) in records.iter().enumerate() {
        if let Some(e) = energy {
            e.validate(record.dofs())?;
        }
        for window in spec.windows(record, index, quadrature)? {
            cut.push((record, window));
        }
    }
    // The spans each window compares; a span is projected once, however many windows
    // compare it (a one-period window's next period is the next window's previous).
    let plans: Vec<_> = cut
        .iter()
        .map(|(record, window)| judge::compared_spans(record, window))
        .collect();
    let mut spans: Vec<(usize, f64, usize)> = Vec::new();
    let mut known = std::collections::HashMap::new();
    let span_ids: Vec<Vec<usize>> = plans
        .iter()
        .enumerate()
        .map(|(k, plan)| {
            let Ok(plan) = plan else { return Vec::new() };
            let record = cut[k].1.record;
            plan.iter()
                .map(|&(origin, periods, _)| {
                    *known
                        .entry((record, origin.to_bits(), periods))
                        .or_insert_with(|| {
                            spans.push((k, origin, periods));
                            spans.len() - 1
                        })
                })
                .collect()
        })
        .collect();
    let keys: Vec<self::spans::SpanKey<'_>> = spans
        .iter()
        .map(|&(k, origin, periods)| (cut[k].0, cut[k].1.record, origin, periods))
        .collect();
    // the harmonics and noise of each record, estimated once for all its spans
    let noises = RecordNoises::given_or_of(noises, records);
    let projections = self::spans::project_spans(&keys, &noises)?;
    // Each window is judged on its own; rayon's collect keeps window order, so the
    // report is the same at any thread count.
    let windows = cut
        .par_iter()
        .zip(plans.par_iter().zip(span_ids.par_iter()))
        .map(|((record, window), (plan, ids))| {
            crate::cancel::check("the steady-state check")?;
            let projected: Vec<_> = ids.iter().map(|&i| &projections[i]).collect();
            judge::check_window(
                record, window, quadrature, energy, settings, plan, &projected,
            )
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(SteadyStateReport {
        settings: *settings,
        energy_known: energy.is_some(),
        windows,
    })
}
