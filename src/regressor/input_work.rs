//! Input work that is really there. The right-hand side of every equation is the input
//! work of a window, b_r = ∫ vᵀ r dt (or ∫ rᵀ dx). A dead force sensor (an unplugged
//! load cell, a force column of zeros, `forces = []`) gives b_r = 0, and the fit then
//! reports θ = 0 as if the data said the structure does not dissipate. Such records
//! are refused before any fit, with [`Error::NoInputWork`] naming the record and its
//! force channels (numbered from 1, with their data-file columns when known):
//!
//! 1. **No force acts** (windows of whole periods). The record has no force channel, or
//!    each channel reads zero in every sample or acts through a zero load column: then
//!    b_r = 0 exactly in every window.
//! 2. **The net work is nothing beside the gross work** (whole periods, every window).
//!    For window r over samples a … a + L (L = round(kT/h)) and each acting channel k
//!    with signal s_k and load column d_k,
//!
//!    ```text
//!      W_r = Σ_k Σ_{i=a}^{a+L−1} ½(|s_k,i| + |s_k,i+1|) · |d_kᵀ(x_{i+1} − x_i)|  ≈ ∫ |vᵀ r| dt,
//!    ```
//!
//!    the gross work (the energy that flows in and back out), from the raw samples
//!    whatever the velocity source. The window is refused when |b_r| ≤ η W_r with
//!    η = [`NET_WORK_FLOOR`] = 1e-9. W_r = 0 covers a channel that reads zero in the
//!    window, DOFs it acts on that do not move, and products that underflow; the
//!    message says which. Why η cannot fire on a real steady-state record with
//!    damping: over whole periods b_r is the damping work, and b_r/W_r is the share
//!    of the input power that is net, at least the drive's power factor cos φ. For a
//!    resonance of damping ratio ζ driven at frequency ratio ρ,
//!    cos φ = 2ζρ/√((1 − ρ²)² + (2ζρ)²), so firing needs 2ζρ/|1 − ρ²| < 1e-9: a
//!    quality factor above 10⁸ a decade away from resonance (structures have 10 to
//!    10⁴; quartz and silicon resonators in vacuum reach 10⁶ to 10⁷), or quadrature
//!    and velocity errors that cancel the damping work to nine digits. Round-off in
//!    b_r stays below N·ε·W_r ≈ 2e-10 W_r for windows of up to 10⁶ samples, so a force
//!    that truly does no net work (a spring force, in phase with x, read in place of
//!    the drive) is caught.
//! 3. **Fixed spans** (the non-periodic mode). There b_r = ∫ vᵀ r dt − Δ(known stored
//!    energy), and a window may take no work in (the drive stops), so windows are not
//!    tested alone. A record is refused when b_r = 0 exactly in each of its windows:
//!    no force acts and no known stored energy moves to the right-hand side, so its
//!    equations are homogeneous, the same as those of a dead sensor. A free decay is
//!    identified by giving its stored energy as known (mass and stiffness matrices).
//!
//! Not caught: a dead channel that reads only noise (its net work is a random share of
//! its gross work, like that of a lightly damped drive off resonance), a dead channel
//! whose constant offset does work over fixed spans (the offset unknowns absorb it),
//! and a dead channel among others that work (nothing in the data says that it should
//! read a force). The propagated noise of b_r in the noise-robust rows
//! ([`crate::regressor::robust`]) is not used as a threshold: on short windows its
//! noise estimate is not reliable (a noise-free record sampled 2.4 times per period
//! gives |b| = 3.2 against σ = 4.1), so it would refuse good records. A dead noisy
//! channel still shows in the report: the model explains none of b (relative residual
//! near 1), and the noise level of the equations leaves the coefficients not
//! determined (the measured chain with its force column replaced by noise: relative
//! residual 0.99, practical rank 2 of 5).

use crate::error::{Error, Result};
use crate::prep::window::Window;
use crate::record::{LoadDistribution, Record, col};
use crate::regressor::Regressor;
use crate::regressor::passive::WorkScale;

/// η: a window of whole periods whose |net input work| is at most this share of its
/// gross work ∫|vᵀr| dt takes no work in.
pub const NET_WORK_FLOOR: f64 = 1e-9;

/// Rule 1: every record has a force channel that acts (windows of whole periods).
pub(crate) fn require_force(records: &[Record]) -> Result<()> {
    for record in records {
        if acting(record).is_empty() {
            let all: Vec<usize> = (0..record.forcing().signals.ncols()).collect();
            let reason = if all.is_empty() {
                "the record lists no force, so no work goes in and every equation would \
                 say that nothing dissipates; list the drive's force column under `forces` \
                 of its record in the model file"
            } else if record.active_channels().is_empty() {
                "every sample reads zero (an unplugged or dead load cell); check the force \
                 sensor and its column in the model file"
            } else {
                "each channel reads zero in every sample or acts through a zero load \
                 column; check the force sensor, its column in the model file and the load \
                 distribution"
            };
            return Err(no_input_work(record, None, &all, reason.to_string()));
        }
    }
    Ok(())
}

/// Rule 2: the windows of whole periods `windows` of `records` and the rows of
/// `regressor` built from them, one per window. Returns the regressor with the gross
/// work W_r and the sample intervals of each window, by record, for the passivity
/// check ([`crate::regressor::passive`]).
pub(crate) fn require_periodic_work(
    records: &[Record],
    windows: &[Window],
    regressor: Regressor,
) -> Result<Regressor> {
    let rhs = regressor.rhs();
    let mut scale = WorkScale {
        gross: Vec::with_capacity(windows.len()),
        samples: Vec::with_capacity(windows.len()),
        group: Vec::with_capacity(windows.len()),
        names: records.iter().map(|r| r.label().to_string()).collect(),
        unit: "record".into(),
    };
    for (w, &b) in windows.iter().zip(rhs) {
        let record = &records[w.record];
        let gross = Gross::of(record, w);
        if b.abs() <= NET_WORK_FLOOR * gross.work {
            let reason = gross.reason(b, record, w);
            return Err(no_input_work(
                record,
                Some(w.index),
                &acting(record),
                reason,
            ));
        }
        scale.gross.push(gross.work);
        scale.samples.push(gross.intervals);
        scale.group.push(w.record);
    }
    regressor.with_work_scale(scale)
}

/// Rule 3: no record of fixed spans has a right-hand side that is zero in every window.
pub(crate) fn require_span_work(records: &[Record], regressor: &Regressor) -> Result<()> {
    for (index, record) in records.iter().enumerate() {
        let mut rows = regressor
            .rows()
            .iter()
            .zip(regressor.rhs())
            .filter(|(label, _)| label.record_index == index)
            .peekable();
        if rows.peek().is_none() || !rows.all(|(_, b)| *b == 0.0) {
            continue;
        }
        let acting = acting(record);
        let all: Vec<usize> = (0..record.forcing().signals.ncols()).collect();
        let (channels, cause, fix) = if all.is_empty() {
            (
                all,
                "the record lists no force",
                "list the force column under `forces` of its record in the model file",
            )
        } else if acting.is_empty() {
            (
                all,
                "every sample reads zero (an unplugged or dead load cell)",
                "check the force sensor and its column in the model file",
            )
        } else {
            (
                acting,
                "the force does no work in any window",
                "check the force sensor and its column in the model file",
            )
        };
        let reason = format!(
            "{cause}, and no known stored energy enters the balance, so every equation of \
             it says that nothing dissipates; {fix} (a free decay needs its stored energy \
             known: `mass = {{ known = … }}` and `stiffness = {{ known = … }}` in \
             [non_periodic])"
        );
        return Err(no_input_work(record, None, &channels, reason));
    }
    Ok(())
}

/// The gross work of one window of whole periods, and what it saw.
struct Gross {
    /// W_r.
    work: f64,
    /// Some acting channel reads a nonzero force in the window.
    force_read: bool,
    /// Some acting channel's DOFs move in the window.
    moved: bool,
    /// The largest |s| and |d_kᵀΔx| seen, for a message about underflow.
    largest: (f64, f64),
    /// The sample intervals of the window.
    intervals: usize,
}

impl Gross {
    fn of(record: &Record, w: &Window) -> Self {
        let intervals = (w.span / record.step()).round() as usize;
        let end = w
            .start
            .saturating_add(intervals)
            .min(record.samples().saturating_sub(1));
        let x = record.displacements();
        let mut gross = Gross {
            work: 0.0,
            force_read: false,
            moved: false,
            largest: (0.0, 0.0),
            intervals: end.saturating_sub(w.start),
        };
        for k in acting(record) {
            let s = col(record.forcing().signals.as_ref(), k);
            let load: Vec<(&[f64], f64)> = load_column(record, k)
                .into_iter()
                .map(|(j, d)| (col(x, j), d))
                .collect();
            for i in w.start..end {
                let dx: f64 = load.iter().map(|(xj, d)| d * (xj[i + 1] - xj[i])).sum();
                let force = 0.5 * (s[i].abs() + s[i + 1].abs());
                gross.work += force * dx.abs();
                gross.force_read |= force != 0.0;
                gross.moved |= dx != 0.0;
                gross.largest.0 = gross.largest.0.max(force);
                gross.largest.1 = gross.largest.1.max(dx.abs());
            }
        }
        gross
    }

    /// Why window `w` of `record`, with input work `b`, takes no work in.
    fn reason(&self, b: f64, record: &Record, w: &Window) -> String {
        let start = record.start_time() + w.start as f64 * record.step();
        if !self.force_read {
            format!(
                "it reads zero in every sample of the window (from t = {start}); check the \
                 force sensor and its column in the model file"
            )
        } else if !self.moved {
            format!(
                "the DOFs it acts on do not move in the window (from t = {start}), so no \
                 work goes in; check the displacement columns of those DOFs"
            )
        } else if self.work == 0.0 {
            format!(
                "force times displacement underflows to zero in floating point (force up to \
                 {:.3e}, displacement steps up to {:.3e}); express the data in other units",
                self.largest.0, self.largest.1
            )
        } else {
            format!(
                "over the whole periods from t = {start} the net input work {b:.3e} is at \
                 most {NET_WORK_FLOOR:e} of the gross work ∫|vᵀr| dt = {:.3e}: the force does \
                 no net work, as a force in phase with the displacement (a spring force, not \
                 a drive) would; check the force sensor and its column in the model file",
                self.work
            )
        }
    }
}

/// The force channels of `record` that act: not zero everywhere, and with a nonzero
/// load column.
fn acting(record: &Record) -> Vec<usize> {
    record
        .active_channels()
        .iter()
        .copied()
        .filter(|&k| !load_column(record, k).is_empty())
        .collect()
}

/// The nonzero entries (DOF, weight) of channel `k`'s load column.
fn load_column(record: &Record, k: usize) -> Vec<(usize, f64)> {
    match &record.forcing().distribution {
        LoadDistribution::Dofs(dofs) => vec![(dofs[k], 1.0)],
        LoadDistribution::Matrix(d) => (0..d.nrows())
            .filter(|&j| d[(j, k)] != 0.0)
            .map(|j| (j, d[(j, k)]))
            .collect(),
    }
}

/// `force channel 1 ('f1', on DOF 3)`, `force channels 1 (on DOF 1) and 2 (on DOF 2)`,
/// or `no force channel`.
fn channels_text(record: &Record, channels: &[usize]) -> String {
    let one = |k: usize| {
        let name = record.channel_name(k).map(|n| format!("'{n}'"));
        let dof = match &record.forcing().distribution {
            LoadDistribution::Dofs(dofs) => Some(format!("on DOF {}", dofs[k] + 1)),
            LoadDistribution::Matrix(_) => None,
        };
        let detail: Vec<String> = name.into_iter().chain(dof).collect();
        if detail.is_empty() {
            format!("{}", k + 1)
        } else {
            format!("{} ({})", k + 1, detail.join(", "))
        }
    };
    let listed: Vec<String> = channels.iter().map(|&k| one(k)).collect();
    match listed.as_slice() {
        [] => "no force channel".into(),
        [only] => format!("force channel {only}"),
        [init @ .., last] => format!("force channels {} and {last}", init.join(", ")),
    }
}

fn no_input_work(
    record: &Record,
    window: Option<usize>,
    channels: &[usize],
    reason: String,
) -> Error {
    Error::NoInputWork {
        record: record.label().to_string(),
        window,
        channels: channels_text(record, channels),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Forcing, RecordParts};
    use faer::Mat;

    /// x = sin(2π t) on one DOF, h = 1/8, one period (8 intervals), force s on DOF 1.
    fn record(force: impl Fn(f64) -> f64) -> Record {
        let h = 0.125;
        let t = |i: usize| i as f64 * h;
        Record::new(RecordParts {
            label: "r".into(),
            step: h,
            start_time: 0.0,
            displacements: Mat::from_fn(9, 1, |i, _| (2.0 * std::f64::consts::PI * t(i)).sin()),
            velocities: None,
            forcing: Forcing::on_dofs(Mat::from_fn(9, 1, |i, _| force(t(i))), vec![0]),
            period: 1.0,
        })
        .unwrap()
    }

    fn window() -> Window {
        Window {
            record: 0,
            index: 0,
            start: 0,
            span: 1.0,
            cycles: 1,
            closed: false,
        }
    }

    /// A constant force 2 on x = sin 2πt: the steps |Δx_i| over one period sum to the
    /// total variation of x, 4 (up and down by 1, twice), so W = 2 · 4 = 8 exactly,
    /// while the net work 2·[x] over the period is 0.
    #[test]
    fn gross_work_of_a_constant_force_is_force_times_total_variation() {
        let gross = Gross::of(&record(|_| 2.0), &window());
        assert!((gross.work - 8.0).abs() < 1e-12, "{}", gross.work);
        assert!(gross.force_read && gross.moved);
    }

    /// Channels are numbered from 1, with their names and DOFs (numbered from 1).
    #[test]
    fn channels_are_named_from_one() {
        let r = record(|_| 1.0)
            .with_channel_names(vec!["load".into()])
            .unwrap();
        assert_eq!(
            channels_text(&r, &[0]),
            "force channel 1 ('load', on DOF 1)"
        );
        assert_eq!(channels_text(&r, &[]), "no force channel");
    }
}
