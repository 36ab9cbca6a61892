//! Windows: the stretches of a record that become equations.
//!
//! - Whole driving periods ([`WindowSpec`]): window j of a record starts at sample
//!   s_j = skip + round(j · kT/h) and spans kT in time; the quadrature rule decides
//!   which samples inside it are read and with which weights.
//! - Periodic closure ([`periodic_closure`], [`Window::closed`]): synchronous
//!   acquisition and FFT analysers save records of exactly k periods, N = kT/h samples,
//!   the last one step before kT. A window of k whole periods whose L = kT/h is a whole
//!   number (to 10⁻⁹ relative) and whose last sample t₀ + (L − 1)h is the record's last
//!   closes periodically: the sample at t₀ + kT, which the record does not hold, is the
//!   sample at t₀,
//!
//!   ```text
//!     y(t₀ + kT + i h) = y(t₀ + i h),   i.e. sample s + L + i is sample s + i,
//!   ```
//!
//!   so the window reads exactly its L samples ([`Window::samples`]). This is the one
//!   place that decides it; the quadrature weights ([`Window::weights`]), the velocity
//!   sources ([`crate::prep::velocity::VelocitySource::velocities_of`]), the
//!   derivative-free path, the noise-robust rows and the steady-state check read
//!   [`Window::closed`], and the stepped-sine fundamentals [`periodic_closure`]. A window
//!   whose closing sample is in the record never closes: it reads the sample at kT as
//!   before.
//! - Fixed spans of a record that is not periodic ([`span_windows`]): window j spans
//!   L = round(length/h) steps from s_j = skip + j L, so consecutive windows share
//!   their end samples.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::quadrature::{Quadrature, WindowWeights};
use crate::record::Record;

/// How to cut records into windows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowSpec {
    /// Samples to skip at the start of each record (transient).
    pub skip: usize,
    /// Whole driving periods per window (k ≥ 1).
    pub cycles: usize,
    /// How many windows per record: `None` takes as many as fit, `Some(j)` requires j.
    pub count: Option<usize>,
}

impl Default for WindowSpec {
    /// One window of one period per record, starting at the first sample.
    fn default() -> Self {
        WindowSpec::cycles(1).first(1)
    }
}

/// One window: the source of one equation of the regressor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// Index of the record in the list given to the regressor.
    pub record: usize,
    /// Index of the window within its record.
    pub index: usize,
    /// First sample.
    pub start: usize,
    /// Time span kT.
    pub span: f64,
    /// Whole periods k.
    pub cycles: usize,
    /// Whether the window closes periodically ([`periodic_closure`]): its L = kT/h
    /// samples end with the record, and the sample at t₀ + kT is the one at t₀.
    pub closed: bool,
}

impl Window {
    /// How many samples from `start` the window reads under `quadrature`: L = kT/h when
    /// it closes periodically, else the rule's own count ([`Quadrature::samples`]).
    pub fn samples(&self, quadrature: Quadrature, step: f64) -> usize {
        self.closed_length(step)
            .unwrap_or_else(|| quadrature.samples(self.span, step))
    }

    /// L = kT/h when the window closes periodically, else `None`.
    pub fn closed_length(&self, step: f64) -> Option<usize> {
        self.closed.then(|| Quadrature::length(self.span, step).0)
    }

    /// The quadrature weights w_i over the window's samples: the rule's own
    /// ([`Quadrature::weights`]), or w_i = h for its L samples when the window closes
    /// periodically, which every rule reduces to (see [`crate::prep::quadrature`]).
    pub fn weights(&self, quadrature: Quadrature, step: f64, period: f64) -> Result<Vec<f64>> {
        Ok(self.window_weights(quadrature, step, period)?.to_vec())
    }

    /// The same weights held compactly.
    pub(crate) fn window_weights(
        &self,
        quadrature: Quadrature,
        step: f64,
        period: f64,
    ) -> Result<WindowWeights> {
        if self.closed {
            Quadrature::closed_weights(self.span, step)
        } else {
            quadrature.window_weights(self.span, step, period)
        }
    }
}

/// Whether a window of `span` = kT from sample `start` of `record` closes periodically:
/// L = kT/h is a whole number (to 10⁻⁹ relative, as [`Quadrature`] snaps it) and the
/// record's last sample is `start + L − 1`, one step before t₀ + kT. The record then
/// holds exactly the window's whole periods and not the sample at t₀ + kT, which
/// periodic closure takes to be the sample at t₀.
pub fn periodic_closure(record: &Record, start: usize, span: f64) -> bool {
    let (whole, frac) = Quadrature::length(span, record.step());
    frac == 0.0 && whole > 0 && start.checked_add(whole) == Some(record.samples())
}

impl WindowSpec {
    /// Windows of `k` whole periods from the first sample, as many per record as fit.
    pub fn cycles(k: usize) -> Self {
        WindowSpec {
            skip: 0,
            cycles: k,
            count: None,
        }
    }

    /// These windows after the first `samples` samples of each record (a transient).
    pub fn skipping(mut self, samples: usize) -> Self {
        self.skip = samples;
        self
    }

    /// These windows, exactly `count` per record (a record too short for them is an
    /// error).
    pub fn first(mut self, count: usize) -> Self {
        self.count = Some(count);
        self
    }

    /// Checks the settings themselves.
    pub fn validate(&self) -> Result<()> {
        if self.cycles == 0 {
            return Err(Error::invalid(
                "cycles",
                0.0,
                "a window needs at least one whole period",
            ));
        }
        if self.count == Some(0) {
            return Err(Error::invalid("count", 0.0, "ask for at least one window"));
        }
        Ok(())
    }

    /// The windows of `record` (its index in the list is `record_index`).
    pub fn windows(
        &self,
        record: &Record,
        record_index: usize,
        quadrature: Quadrature,
    ) -> Result<Vec<Window>> {
        self.validate()?;
        let span = self.cycles as f64 * record.period();
        let length = span / record.step();
        // A window shorter than one step would not advance from one window to the
        // next: with `count: None` the loop below would never end. The quadrature rules
        // reject such a window anyway; say so before cutting any.
        if length.is_nan() || length < 1.0 {
            return Err(Error::invalid(
                "window span",
                span,
                &format!(
                    "is shorter than one sample step h = {}; record with a smaller step",
                    record.step()
                ),
            ));
        }
        let needed_by_rule = quadrature.samples(span, record.step());
        // Saturating arithmetic: absurd skips, counts or spans must end in
        // RecordTooShort, never in an overflow.
        let start_of = |j: usize| {
            self.skip
                .saturating_add((j as f64 * length).round() as usize)
        };
        let closes = |j: usize| periodic_closure(record, start_of(j), span);
        // A window fits when the record holds every sample its rule reads, or when it
        // closes periodically (the rule's sample at t₀ + kT is then the one at t₀).
        let fits =
            |j: usize| start_of(j).saturating_add(needed_by_rule) <= record.samples() || closes(j);
        let wanted = self.count.unwrap_or(usize::MAX);
        let mut windows = Vec::new();
        while windows.len() < wanted && fits(windows.len()) {
            let index = windows.len();
            windows.push(Window {
                record: record_index,
                index,
                start: start_of(index),
                span,
                cycles: self.cycles,
                closed: closes(index),
            });
        }
        let required = self.count.unwrap_or(1);
        if windows.len() < required {
            return Err(Error::RecordTooShort {
                record: record.label().to_string(),
                needed: start_of(required - 1).saturating_add(needed_by_rule),
                available: record.samples(),
            });
        }
        Ok(windows)
    }
}

/// The windows of `length` time units over a record that is not periodic: consecutive,
/// L = round(length/h) steps each, sharing their end samples, as many as fit after
/// `skip` (the span is L h).
pub fn span_windows(
    record: &Record,
    record_index: usize,
    length: f64,
    skip: usize,
) -> Result<Vec<Window>> {
    let steps = (length / record.step()).round();
    if steps < 1.0 {
        return Err(Error::invalid(
            "window",
            length,
            &format!(
                "is shorter than one sample step h = {} of record '{}'",
                record.step(),
                record.label()
            ),
        ));
    }
    let steps = steps as usize;
    let span = steps as f64 * record.step();
    let last = record.samples() - 1;
    let count = last.saturating_sub(skip) / steps;
    if count == 0 || skip >= last {
        return Err(Error::RecordTooShort {
            record: record.label().to_string(),
            needed: skip.saturating_add(steps).saturating_add(1),
            available: record.samples(),
        });
    }
    Ok((0..count)
        .map(|index| Window {
            record: record_index,
            index,
            start: skip + index * steps,
            span,
            cycles: 0,
            closed: false,
        })
        .collect())
}
