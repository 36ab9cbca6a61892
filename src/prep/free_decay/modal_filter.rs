//! Several sensors of one mode: a modal filter projects the record's s channels
//! y(t) ∈ ℝˢ onto one modal coordinate q(t), which then goes through the single-sensor
//! pipeline ([`super::isolate_with`]: band-pass, integration, cycles).
//!
//! With the mode's shape φ at the sensors given (`mode_shape`), the coordinate is the
//! least-squares fit of y ≈ φ q,
//!
//! ```text
//!   q(t) = φᵀ y(t) / (φᵀ φ),
//! ```
//!
//! in the normalisation of φ (the modal mass m = φᵀ M φ in the same one; `mass = 1`
//! makes the coefficients per unit modal mass and ζ exact). With the record's own POD
//! (`modal_filter = "pod"`), the proper orthogonal modes u_k of the channels over the
//! decay ([`crate::prep::pod`], R = Yᵀ Y / N = U Λ Uᵀ) replace φ (unit length), and the
//! mode is the u_k whose coordinate u_kᵀ y has the largest displacement-spectrum peak
//! in the band (or in `peak_in`, or anywhere with neither).
//!
//! **What it assumes.** Another mode r leaks into q by φᵀφ_r / φᵀφ of its coordinate:
//! nothing when the shapes are orthogonal at the sensors (POD modes are orthogonal, and
//! they are the normal modes when the mass matrix is proportional to the identity and
//! the modes are lightly damped), else the band-pass that follows must remove it (a
//! mode outside [f/2, 2f] goes; one inside the band stays). So: at least as many
//! sensors as modes that carry energy in the band, and the shapes of those modes
//! distinct at the sensors. All channels must measure the same quantity (all
//! accelerations, all velocities or all displacements), so that one combination of
//! them is a signal of one kind.

use faer::Mat;
use serde::{Deserialize, Serialize};

use super::band::{Band, DisplacementSpectrum};
use crate::error::{Error, Result};
use crate::prep::pod::{Pod, PodSettings, Retain};
use crate::record::{Record, Sensor};

/// How a record of several sensors is reduced to one mode's coordinate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModalFilter {
    /// The mode's shape at the sensors, one value per channel in the record's order.
    Shape(Vec<f64>),
    /// The record's own proper orthogonal modes; the one whose coordinate peaks highest
    /// in the band.
    Pod,
}

impl ModalFilter {
    /// Checks a shape: finite, not all zero.
    pub fn validate(&self) -> Result<()> {
        if let ModalFilter::Shape(shape) = self {
            if let Some(bad) = shape.iter().find(|v| !v.is_finite()) {
                return Err(Error::invalid(
                    "mode_shape",
                    *bad,
                    "every entry of a mode shape must be finite",
                ));
            }
            if shape.iter().all(|v| *v == 0.0) {
                return Err(Error::invalid(
                    "mode_shape",
                    0.0,
                    "the mode shape is zero at every sensor: no sensor sees the mode, so nothing can be projected onto it",
                ));
            }
        }
        Ok(())
    }
}

/// The channels of `record` (N × s) and their one sensor kind.
fn channels(record: &Record) -> Result<(Mat<f64>, Sensor)> {
    let (signals, sensors) = match record.measured_motion() {
        Some(m) => (m.signals.clone(), m.sensors.clone()),
        None => (
            record.displacements().to_owned(),
            vec![Sensor::Displacement; record.dofs()],
        ),
    };
    let first = sensors[0];
    if let Some(other) = sensors.iter().find(|s| **s != first) {
        return Err(Error::choice(
            "modal filter",
            format!(
                "record '{}' mixes {} and {} sensors",
                record.label(),
                first.name(),
                other.name()
            ),
            "a modal filter adds the channels of one mode: give sensors that all measure the same quantity (all accelerations, all velocities or all displacements)",
        ));
    }
    Ok((signals, first))
}

/// The modal coordinate of `record` under `filter`, a signal of the record's sensor kind
/// (module doc); `range` is the band or `peak_in` that chooses a POD mode, and `start`
/// the decay's first sample (the POD reads the decay only).
pub fn project(
    record: &Record,
    filter: &ModalFilter,
    range: Option<Band>,
    start: usize,
) -> Result<(Vec<f64>, Sensor)> {
    filter.validate()?;
    let (signals, sensor) = channels(record)?;
    let s = signals.ncols();
    let weights: Vec<f64> = match filter {
        ModalFilter::Shape(shape) => {
            if shape.len() != s {
                return Err(Error::mismatch(
                    format!(
                        "mode_shape entries vs motion channels of record '{}'",
                        record.label()
                    ),
                    s,
                    shape.len(),
                ));
            }
            let norm: f64 = shape.iter().map(|v| v * v).sum();
            shape.iter().map(|v| v / norm).collect()
        }
        ModalFilter::Pod => {
            let n = signals.nrows();
            let from = start.min(n.saturating_sub(1));
            let decay = signals.as_ref().subrows(from, n - from);
            let settings = PodSettings {
                retain: Retain::Count(s),
                ..PodSettings::default()
            };
            let pod = Pod::from_displacements(decay, &settings)?;
            let mut best: Option<(f64, Vec<f64>)> = None;
            for k in 0..s {
                if pod.values()[k] <= 1e-12 * pod.values()[0] {
                    continue;
                }
                // cannot fail: k < s, the POD's number of modes.
                let u = pod.mode(k).expect("k is a mode of the POD").to_vec();
                let q: Vec<f64> = (from..n)
                    .map(|i| (0..s).map(|j| u[j] * signals[(i, j)]).sum())
                    .collect();
                let peak = largest_peak(&q, sensor, record.step(), range);
                if best.as_ref().is_none_or(|(b, _)| peak > *b) {
                    best = Some((peak, u));
                }
            }
            best.map(|(_, u)| u).ok_or_else(|| {
                Error::invalid(
                    "modal_filter",
                    0.0,
                    &format!(
                        "record '{}' has no motion after the decay's start: its POD has no mode",
                        record.label()
                    ),
                )
            })?
        }
    };
    let q = (0..signals.nrows())
        .map(|i| (0..s).map(|j| weights[j] * signals[(i, j)]).sum())
        .collect();
    Ok((q, sensor))
}

/// The largest displacement-spectrum magnitude |S_q| / ω_q^r of `signal` within
/// `range` (everywhere above 4/(N h) without one), Hann-windowed
/// ([`DisplacementSpectrum`]); 0 for fewer than 8 samples or a failed transform.
fn largest_peak(signal: &[f64], sensor: Sensor, step: f64, range: Option<Band>) -> f64 {
    if signal.len() < 8 {
        return 0.0;
    }
    let Ok(spectrum) = DisplacementSpectrum::new(signal, sensor, step, range) else {
        return 0.0;
    };
    let df = spectrum.df;
    let first = ((spectrum.low / df).ceil() as usize).max(1);
    let last = ((spectrum.high / df).floor() as usize).min(spectrum.magnitudes.len() - 1);
    (first..=last)
        .map(|q| spectrum.magnitudes[q])
        .fold(0.0, f64::max)
}
