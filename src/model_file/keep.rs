//! `[stepped_sine] keep`: the points of a table to identify from, as a lab selects them
//! (the points near resonance, a frequency band, some sweeps) without editing the file.
//! A point is kept when every condition given holds, bounds inclusive:
//!
//! ```text
//!   lo ≤ ω/2π ≤ hi        (frequency_hz, in Hz)
//!   lo ≤ φ ≤ hi           (lag: the displacement's lag behind the force at the force's
//!                          DOF, after the phase convention and `response`)
//!   its sweep's name ∈ sweeps
//! ```
//!
//! The selection comes before the noise is estimated from the scatter along each sweep,
//! as if the file held only the kept rows: a sweep left with fewer than three points
//! takes the pooled scatter of the others ([`crate::prep::harmonic::sweeps`]); a sweep
//! left with none is dropped. Nothing kept, an empty band or an unknown sweep is an
//! error naming the key.

use crate::error::{Error, Result};
use crate::model_file::spec::KeepSpec;
use crate::prep::harmonic::SteppedSinePoint;

/// The indices of the points of `points` (of sweeps `sweeps`, named `names`) that `keep`
/// keeps, in table order.
pub(super) fn kept(
    keep: &KeepSpec,
    points: &[SteppedSinePoint],
    sweeps: &[usize],
    names: &[String],
) -> Result<Vec<usize>> {
    let band = |key: &str, [lo, hi]: [f64; 2]| -> Result<[f64; 2]> {
        if lo.is_finite() && hi.is_finite() && lo <= hi {
            Ok([lo, hi])
        } else {
            Err(Error::invalid(
                &format!("keep.{key}"),
                if lo.is_finite() { hi } else { lo },
                "must be [lower, upper] with finite lower ≤ upper",
            ))
        }
    };
    let frequency = keep
        .frequency_hz
        .map(|b| band("frequency_hz", b))
        .transpose()?;
    let lag = keep.lag.map(|b| band("lag", b)).transpose()?;
    let wanted: Option<Vec<usize>> = match &keep.sweeps {
        None => None,
        Some(list) => Some(
            list.iter()
                .map(|name| {
                    names
                        .iter()
                        .position(|n| n == name)
                        .ok_or_else(|| Error::UnknownName {
                            what: "sweep in keep.sweeps".into(),
                            name: name.clone(),
                            known: names.join(", "),
                        })
                })
                .collect::<Result<_>>()?,
        ),
    };
    let within = |[lo, hi]: [f64; 2], x: f64| lo <= x && x <= hi;
    let kept: Vec<usize> = points
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            frequency.is_none_or(|b| within(b, p.frequency / std::f64::consts::TAU))
                && lag.is_none_or(|b| within(b, p.phases[p.force_dof]))
                && wanted.as_ref().is_none_or(|w| w.contains(&sweeps[*i]))
        })
        .map(|(i, _)| i)
        .collect();
    if kept.is_empty() {
        return Err(Error::choice(
            "[stepped_sine] keep",
            format!("a selection of none of the {} points", points.len()),
            "widen frequency_hz or lag, or name other sweeps",
        ));
    }
    Ok(kept)
}

/// `items` at `indices`.
pub(super) fn at<T: Clone>(items: &[T], indices: &[usize]) -> Vec<T> {
    indices.iter().map(|&i| items[i].clone()).collect()
}

/// The sweeps of the points `indices` renumbered over the sweeps that keep a point,
/// with their names.
pub(super) fn sweeps_of(
    sweeps: &[usize],
    names: &[String],
    indices: &[usize],
) -> (Vec<usize>, Vec<String>) {
    let mut map: Vec<Option<usize>> = vec![None; names.len()];
    let mut kept_names = Vec::new();
    let renumbered = indices
        .iter()
        .map(|&i| {
            let s = sweeps[i];
            *map[s].get_or_insert_with(|| {
                kept_names.push(names[s].clone());
                kept_names.len() - 1
            })
        })
        .collect();
    (renumbered, kept_names)
}
