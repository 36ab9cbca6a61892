//! The backbone of a free decay: per window of whole cycles, the amplitude X, the
//! frequency ω, the damping ratio the decay itself shows, and the one the fitted law
//! gives at that amplitude and frequency.
//!
//! Measured: the energy decrement over the [`SPAN`] windows either side of the window
//! and itself (fewer at a record's ends), from the first one's start a to the last
//! one's end b, at their mean frequency ω̄ (the frequency of the point, at which the
//! fitted ζ_eq is evaluated too),
//!
//! ```text
//!   ζ = ln(E_a / E_b) / (2 ω̄ (t_b − t_a)),   f = ω̄ / 2π,
//! ```
//!
//! the one-window decrement of [`crate::prep::free_decay::cycles`] averaged over
//! 2·SPAN + 1 windows: the error of E at each end enters once per span instead of once
//! per cycle. Fitted: the law's dissipated energy per cycle of harmonic
//! motion x = X cos ωt, E_d(X, ω) = g(X, ω)ᵀθ (g the columns of the model per unit
//! coefficient, [`crate::regressor::stepped_sine::columns_of`]), equals that of a
//! viscous damper c_eq with π c_eq ω X² = E_d, so with the modal mass m
//!
//! ```text
//!   ζ_eq(X, ω) = c_eq / (2 m ω) = E_d(X, ω) / (2π m ω² X²).
//! ```
//!
//! For one mode the ratio needs no mass at all when m = 1 was assumed: a unit modal
//! mass scales E_d and the stored energy alike.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::model::DampingModel;
use crate::prep::free_decay::{DecaySettings, of_record};
use crate::prep::harmonic::{HarmonicApproximation, SteppedSinePoint};
use crate::record::Record;
use crate::regressor::stepped_sine::columns_of;

/// Windows either side that the measured decrement and frequency span.
pub const SPAN: usize = 4;

/// One window of a decay on the backbone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BackbonePoint {
    /// The record's label.
    pub record: String,
    /// The window's index in its record (from 0).
    pub window: usize,
    /// Time of the window's first sample.
    pub time: f64,
    /// Amplitude X (displacement).
    pub amplitude: f64,
    /// Frequency f = ω/2π (cycles per time unit).
    pub frequency: f64,
    /// The energy decrement's damping ratio over the windows around (module doc).
    pub measured: f64,
    /// The fitted law's ζ_eq(X, ω̄) at the window's amplitude and the point's frequency.
    pub fitted: f64,
}

/// The backbone of every window of a free-decay job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Backbone {
    /// The modal mass the coefficients are per.
    pub mass: f64,
    /// One point per window, record after record.
    pub points: Vec<BackbonePoint>,
}

/// The backbone of the modes' `records` (as isolated) under `model` with damping
/// coefficients `theta` (module doc).
pub fn backbone(
    model: &DampingModel,
    theta: &[f64],
    records: &[Record],
    decay: &DecaySettings,
) -> Result<Backbone> {
    let approximation = HarmonicApproximation::default();
    let mut points = Vec::new();
    for record in records {
        let cycles = of_record(record, decay);
        // The windows around each (module doc) and their mean frequency.
        let around = |j: usize| &cycles[j.saturating_sub(SPAN)..(j + SPAN + 1).min(cycles.len())];
        let means: Vec<f64> = (0..cycles.len())
            .map(|j| around(j).iter().map(|c| c.frequency).sum::<f64>() / around(j).len() as f64)
            .collect();
        let synthetic: Vec<SteppedSinePoint> = cycles
            .iter()
            .zip(&means)
            .map(|(c, &omega)| SteppedSinePoint {
                label: format!("{} X={}", record.label(), c.amplitude),
                frequency: omega,
                force_dof: 0,
                // Any force: the columns are the damping terms' alone.
                force_amplitude: 1.0,
                amplitudes: vec![c.amplitude],
                // At resonance: the force does work (the build checks that it does).
                phases: vec![std::f64::consts::FRAC_PI_2],
            })
            .collect();
        let columns = columns_of(model, &[], &approximation, &synthetic)?;
        for (j, (cycle, g)) in cycles.iter().zip(columns).enumerate() {
            let dissipated: f64 = g.iter().zip(theta).map(|(g, t)| g * t).sum();
            let omega = means[j];
            let span = around(j);
            let (first, last) = (span[0], span[span.len() - 1]);
            let duration = (last.end - first.start) as f64 * record.step();
            points.push(BackbonePoint {
                record: record.label().to_string(),
                window: j,
                time: record.start_time() + cycle.start as f64 * record.step(),
                amplitude: cycle.amplitude,
                frequency: omega / (2.0 * std::f64::consts::PI),
                measured: (first.energy_start / last.energy_end).ln() / (2.0 * omega * duration),
                fitted: dissipated
                    / (2.0
                        * std::f64::consts::PI
                        * decay.mass
                        * omega
                        * omega
                        * cycle.amplitude.powi(2)),
            });
        }
    }
    Ok(Backbone {
        mass: decay.mass,
        points,
    })
}

impl Backbone {
    /// The smallest and largest amplitude.
    pub fn amplitude_range(&self) -> Option<(f64, f64)> {
        let mut amplitudes = self.points.iter().map(|p| p.amplitude);
        let first = amplitudes.next()?;
        Some(amplitudes.fold((first, first), |(lo, hi), a| (lo.min(a), hi.max(a))))
    }

    /// About `count` points spread evenly in log amplitude (for the text).
    fn sampled(&self, count: usize) -> Vec<&BackbonePoint> {
        let Some((lo, hi)) = self.amplitude_range() else {
            return Vec::new();
        };
        let mut sorted: Vec<&BackbonePoint> = self.points.iter().collect();
        sorted.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
        if sorted.len() <= count || hi <= lo {
            return sorted;
        }
        let mut chosen: Vec<&BackbonePoint> = Vec::with_capacity(count);
        for k in 0..count {
            let target = (hi.ln() - (hi / lo).ln() * k as f64 / (count - 1) as f64).exp();
            if let Some(p) = sorted
                .iter()
                .min_by(|a, b| {
                    (a.amplitude / target)
                        .ln()
                        .abs()
                        .total_cmp(&(b.amplitude / target).ln().abs())
                })
                .filter(|p| !chosen.iter().any(|c| std::ptr::eq(*c, **p)))
            {
                chosen.push(p);
            }
        }
        chosen
    }
}

impl fmt::Display for Backbone {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some((lo, hi)) = self.amplitude_range() else {
            return Ok(());
        };
        writeln!(
            f,
            "backbone of the free decay: {} windows, amplitude {} to {} ({:.1}×), modal mass {}",
            self.points.len(),
            crate::format::label(lo),
            crate::format::label(hi),
            hi / lo,
            self.mass
        )?;
        writeln!(
            f,
            "  {:>12} {:>12} {:>12} {:>12} {:>8}",
            "amplitude", "frequency", "ζ measured", "ζ fitted", "ratio"
        )?;
        for p in self.sampled(12) {
            writeln!(
                f,
                "  {:>12} {:>12.6} {:>12.4e} {:>12.4e} {:>8.4}",
                crate::format::label(p.amplitude),
                p.frequency,
                p.measured,
                p.fitted,
                p.measured / p.fitted
            )?;
        }
        writeln!(
            f,
            "  (every window in the JSON's `backbone`; ζ measured is the energy decrement over the {} windows around each, ζ fitted the law's equivalent ratio at its amplitude and frequency)",
            2 * SPAN + 1
        )
    }
}
