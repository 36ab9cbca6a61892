//! Motion sensors that never move. A displacement, velocity or acceleration channel
//! that reads a constant over a whole record (a column of zeros, an unplugged or dead
//! sensor, a frozen camera track) while other channels of the record move says that
//! its DOF stands still. Every term on that DOF then sees the wrong relative motion,
//! and the fit returns confident wrong numbers (a chain's end dashpot 0.016 for 0.10
//! with one displacement column of zeros in one record of six). So
//! [`crate::regressor::Regressor::build`] refuses such a record with
//! [`Error::DeadMotionSensor`] naming the record and the DOF (from 1), as
//! [`crate::regressor::input_work`] refuses a dead force channel.
//!
//! A channel j of record R, with samples s_ij, *never moves* when its range is nothing
//! beside its own level and beside the channels of its kind:
//!
//! ```text
//!   max_i s_ij − min_i s_ij ≤ ρ · max( max_i |s_ij|,  max_{k of the same sensor kind} range_k ),   ρ = 10⁻¹²,
//! ```
//!
//! and some channel of the record moves (range > 0). ρ is far below any sensor's
//! resolution (a 24-bit converter resolves 6·10⁻⁸ of its range) and far above round-off,
//! so a constant column or a constant offset is caught whatever its units, and a DOF that
//! moves a millionth of the others (far from the drive) is not. The channels tested are
//! the ones measured: the sensors' signals of a record of velocity or acceleration
//! sensors ([`crate::record::Record::measured_motion`]), otherwise the displacements, and
//! the measured velocities beside them.
//!
//! A DOF that is held still in the experiment (clamped, grounded through a rigid
//! support) is declared with [`crate::record::Record::with_fixed_dofs`] (`fixed_dofs =
//! [2]` in a model file's record, DOFs from 1), and its channels are not tested.
//!
//! Not caught: a dead sensor that reads noise (its range is the noise's). Its DOF then
//! looks like a DOF that barely moves, which the noise model of the default pipeline
//! carries into wide standard errors.

use crate::error::{Error, Result};
use crate::record::{Record, Sensor};

/// ρ: a channel whose range is at most this share of its level and of its kind's
/// largest range never moves.
pub const STILL_RANGE: f64 = 1e-12;

/// [`Error::DeadMotionSensor`] for the first record of `records` with a motion channel
/// that never moves while another channel does (module doc).
pub(crate) fn require_motion(records: &[Record]) -> Result<()> {
    for record in records {
        // (DOF, sensor) of each channel, in the order of `Record::motion_ranges`.
        let channels: Vec<(usize, Sensor)> = match record.measured_motion() {
            Some(measured) => measured.sensors.iter().copied().enumerate().collect(),
            None => {
                let kinds = if record.velocities().is_some() {
                    &[Sensor::Displacement, Sensor::Velocity][..]
                } else {
                    &[Sensor::Displacement][..]
                };
                kinds
                    .iter()
                    .flat_map(|&s| (0..record.dofs()).map(move |j| (j, s)))
                    .collect()
            }
        };
        let ranges = record.motion_ranges();
        if !ranges.iter().any(|(r, _)| *r > 0.0) {
            continue;
        }
        // The largest range of each sensor kind.
        let mut kinds: Vec<(Sensor, f64)> = Vec::new();
        for (&(_, sensor), &(own, _)) in channels.iter().zip(ranges) {
            match kinds.iter_mut().find(|(s, _)| *s == sensor) {
                Some((_, largest)) => *largest = largest.max(own),
                None => kinds.push((sensor, own)),
            }
        }
        for (&(dof, sensor), &(own, level)) in channels.iter().zip(ranges) {
            if record.fixed_dofs().contains(&dof) {
                continue;
            }
            let kind = kinds
                .iter()
                .find(|(s, _)| *s == sensor)
                .map_or(0.0, |(_, largest)| *largest);
            if own <= STILL_RANGE * level.max(kind) {
                let reason = if own == 0.0 {
                    format!("it reads {} in every sample", level_text(level))
                } else {
                    format!(
                        "its range {own:.3e} is at most {STILL_RANGE:e} of its level {level:.3e} or of the largest range of the record's {} channels, {kind:.3e}",
                        sensor.name()
                    )
                };
                return Err(Error::DeadMotionSensor {
                    record: record.label().to_string(),
                    dof: dof + 1,
                    sensor: sensor.name().to_string(),
                    reason: format!("{reason}, while other channels of the record move"),
                });
            }
        }
    }
    Ok(())
}

fn level_text(level: f64) -> String {
    if level == 0.0 {
        "zero".into()
    } else {
        format!("the constant {}", crate::format::number(level))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Forcing, RecordParts};
    use faer::Mat;

    /// Two DOFs, DOF 2 given by `second`.
    fn record(second: impl Fn(usize) -> f64) -> Record {
        Record::new(RecordParts {
            label: "r".into(),
            step: 0.1,
            start_time: 0.0,
            displacements: Mat::from_fn(20, 2, |i, j| {
                if j == 0 {
                    (0.3 * i as f64).sin()
                } else {
                    second(i)
                }
            }),
            velocities: None,
            forcing: Forcing::on_dofs(Mat::from_fn(20, 1, |i, _| (0.3 * i as f64).cos()), vec![0]),
            period: 2.0,
        })
        .unwrap()
    }

    #[test]
    fn a_column_of_zeros_or_a_constant_is_named_from_one() {
        for value in [0.0, 3.5] {
            let e = require_motion(&[record(|_| value)]).unwrap_err();
            match &e {
                Error::DeadMotionSensor { dof, sensor, .. } => {
                    assert_eq!((*dof, sensor.as_str()), (2, "displacement"), "{e}");
                }
                other => panic!("{other}"),
            }
        }
    }

    /// A DOF moving a millionth of the other, or declared fixed, passes.
    #[test]
    fn small_motion_and_fixed_dofs_pass() {
        assert!(require_motion(&[record(|i| 1e-6 * (0.3 * i as f64).sin())]).is_ok());
        let fixed = record(|_| 0.0).with_fixed_dofs(vec![1]).unwrap();
        assert!(require_motion(&[fixed]).is_ok());
        assert!(record(|_| 0.0).with_fixed_dofs(vec![2]).is_err());
    }
}
