//! One experiment: uniformly sampled displacements x (N × n), applied forces, optional
//! measured velocities, and the driving period T.
//!
//! Applied forces are stored as force channels s(t) (N × c) with the generalized force
//! they produce, r(t) = D s(t), where column k of D (n × c) is the load distribution of
//! channel k. A force on one DOF is a unit column; a full generalized force record is
//! D = I. The input power is then v^T r = Σ_k s_k(t) (d_k · v(t)).
//!
//! Motion may come from any sensor: per DOF a displacement, a velocity or an
//! acceleration ([`Sensor`]). A record whose sensors are not all displacements is built
//! by [`crate::prep::motion::record_from_sensors`]: its [`Record::displacements`] and
//! [`Record::velocities`] are then reconstructed from the measured signals (frequency-
//! domain integration over whole periods, mean removed), and the signals themselves stay
//! with the record ([`Record::measured_motion`]) for the noise-robust pipeline, which
//! projects them and integrates per harmonic. No consumer ever reads an acceleration or
//! a velocity as a displacement.

use faer::{Mat, MatRef};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, check_finite};
use crate::terms::simd::{self, Kernel};

/// How the force channels map onto the generalized forces r(t) = D s(t).
#[derive(Debug, Clone, PartialEq)]
pub enum LoadDistribution {
    /// Channel k acts on DOF `dofs[k]` alone (D has unit columns).
    Dofs(Vec<usize>),
    /// A dense n × c distribution matrix (spatial load shapes, weights included).
    Matrix(Mat<f64>),
}

/// Applied force channels and where they act.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing {
    /// N × c force signals, one column per channel.
    pub signals: Mat<f64>,
    /// Where each channel acts.
    pub distribution: LoadDistribution,
}

impl Forcing {
    /// A full generalized-force record (N × n): channel i acts on DOF i.
    pub fn generalized(forces: Mat<f64>) -> Self {
        let dofs = (0..forces.ncols()).collect();
        Forcing {
            signals: forces,
            distribution: LoadDistribution::Dofs(dofs),
        }
    }

    /// Force channels (N × c), channel k acting on DOF `dofs[k]` (0-based).
    pub fn on_dofs(signals: Mat<f64>, dofs: Vec<usize>) -> Self {
        Forcing {
            signals,
            distribution: LoadDistribution::Dofs(dofs),
        }
    }

    /// Force channels (N × c) with a dense load-distribution matrix (n × c).
    pub fn distributed(signals: Mat<f64>, distribution: Mat<f64>) -> Self {
        Forcing {
            signals,
            distribution: LoadDistribution::Matrix(distribution),
        }
    }

    fn validate(&self, samples: usize, dofs: usize) -> Result<()> {
        if self.signals.nrows() != samples {
            return Err(Error::mismatch(
                "rows (samples) of force signals vs displacements",
                samples,
                self.signals.nrows(),
            ));
        }
        check_finite("force signals", self.signals.as_ref())?;
        let channels = self.signals.ncols();
        match &self.distribution {
            LoadDistribution::Dofs(list) => {
                if list.len() != channels {
                    return Err(Error::mismatch(
                        "force DOF list length vs force channels",
                        channels,
                        list.len(),
                    ));
                }
                for (k, &dof) in list.iter().enumerate() {
                    if dof >= dofs {
                        return Err(Error::dof_index(
                            format!("force channel {}", k + 1),
                            dof,
                            dofs,
                        ));
                    }
                }
            }
            LoadDistribution::Matrix(d) => {
                if d.nrows() != dofs {
                    return Err(Error::mismatch(
                        "rows of load distribution vs DOFs",
                        dofs,
                        d.nrows(),
                    ));
                }
                if d.ncols() != channels {
                    return Err(Error::mismatch(
                        "columns of load distribution vs force channels",
                        channels,
                        d.ncols(),
                    ));
                }
                check_finite("load distribution", d.as_ref())?;
            }
        }
        Ok(())
    }
}

/// What a motion channel measures.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sensor {
    /// Displacement x (a position sensor, a strain gauge, a camera).
    #[default]
    Displacement,
    /// Velocity ẋ (a laser vibrometer, a velocity pickup).
    Velocity,
    /// Acceleration ẍ (an accelerometer).
    Acceleration,
}

impl Sensor {
    /// How many times the signal is differentiated from the displacement (0, 1, 2).
    pub fn order(self) -> u32 {
        match self {
            Sensor::Displacement => 0,
            Sensor::Velocity => 1,
            Sensor::Acceleration => 2,
        }
    }

    /// "displacement", "velocity" or "acceleration".
    pub fn name(self) -> &'static str {
        match self {
            Sensor::Displacement => "displacement",
            Sensor::Velocity => "velocity",
            Sensor::Acceleration => "acceleration",
        }
    }
}

/// The signals a record's sensors measured (N × n, column j in the units of
/// `sensors[j]`), kept beside the displacements reconstructed from them.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredMotion {
    /// What each DOF's channel measures.
    pub sensors: Vec<Sensor>,
    /// N × n measured signals.
    pub signals: Mat<f64>,
}

/// The parts of a record, by name. Pass to [`Record::new`], which validates them.
#[derive(Debug, Clone)]
pub struct RecordParts {
    /// A label for reports and errors (e.g. "a=0.25").
    pub label: String,
    /// Sampling step h > 0.
    pub step: f64,
    /// Time of the first sample (used only for labels and plots).
    pub start_time: f64,
    /// N × n displacements (for a record of other sensors, see
    /// [`crate::prep::motion::record_from_sensors`]).
    pub displacements: Mat<f64>,
    /// Optional N × n measured velocities.
    pub velocities: Option<Mat<f64>>,
    /// Applied force channels.
    pub forcing: Forcing,
    /// Driving period T > 0 (2π/ω).
    pub period: f64,
}

/// A validated experiment record. Construct with [`Record::new`].
#[derive(Debug, Clone)]
pub struct Record {
    parts: RecordParts,
    /// Force channels that are not zero everywhere (found once, when validating).
    active_channels: Vec<usize>,
    /// The force channels' names (their data-file columns), one per channel; empty
    /// when the record was built without them.
    channel_names: Vec<String>,
    /// The signals of sensors that are not all displacements, from which the
    /// displacements and velocities were reconstructed; `None` for displacement records.
    measured: Option<MeasuredMotion>,
    /// DOFs (0-based) declared held still in this record: their motion channels may
    /// read a constant ([`crate::regressor::dead_motion`]).
    fixed_dofs: Vec<usize>,
    /// (max − min, max |s|) of each motion channel the dead-sensor check tests, found
    /// once here so that a build does not read the whole record again
    /// ([`Record::motion_ranges`]).
    motion_ranges: Vec<(f64, f64)>,
    /// The largest |value| of the displacements, the measured velocities and the
    /// forces, found once here ([`Record::magnitudes`]).
    magnitudes: Magnitudes,
}

/// The largest magnitude of each kind of signal a record holds, in its own units: what
/// [`crate::prep::data_scale`] compares with the range of double precision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Magnitudes {
    /// max |x| over every displacement channel and sample.
    pub displacement: f64,
    /// max |v| over the measured velocities, if the record holds them.
    pub velocity: Option<f64>,
    /// max |f| over every force channel (0 for a record without force).
    pub force: f64,
}

impl Record {
    /// Validates shapes, finiteness, the step and the period.
    pub fn new(parts: RecordParts) -> Result<Self> {
        if !(parts.step.is_finite() && parts.step > 0.0) {
            return Err(Error::invalid(
                "step",
                parts.step,
                "must be finite and positive",
            ));
        }
        if !(parts.period.is_finite() && parts.period > 0.0) {
            return Err(Error::invalid(
                "period",
                parts.period,
                "must be finite and positive",
            ));
        }
        if !parts.start_time.is_finite() {
            return Err(Error::invalid(
                "start_time",
                parts.start_time,
                "must be finite",
            ));
        }
        let (samples, dofs) = parts.displacements.shape();
        if dofs == 0 {
            return Err(Error::Empty {
                what: "displacement DOFs".into(),
            });
        }
        if samples < 3 {
            return Err(Error::RecordTooShort {
                record: parts.label.clone(),
                needed: 3,
                available: samples,
            });
        }
        let mut motion_ranges = finite_ranges("displacements", parts.displacements.as_ref())?;
        let mut velocity_ranges = None;
        if let Some(v) = &parts.velocities {
            if v.shape() != (samples, dofs) {
                let (what, expected, found) = if v.nrows() != samples {
                    ("rows of velocities vs displacements", samples, v.nrows())
                } else {
                    ("columns of velocities vs displacements", dofs, v.ncols())
                };
                return Err(Error::mismatch(what, expected, found));
            }
            velocity_ranges = Some(finite_ranges("velocities", v.as_ref())?);
        }
        parts.forcing.validate(samples, dofs)?;
        let force_ranges = channel_ranges(parts.forcing.signals.as_ref()).0;
        let active_channels = (0..force_ranges.len())
            .filter(|&k| force_ranges[k].1 > 0.0)
            .collect();
        let largest = |ranges: &[(f64, f64)]| ranges.iter().fold(0.0, |m: f64, r| m.max(r.1));
        let mut magnitudes = Magnitudes {
            displacement: largest(&motion_ranges),
            velocity: None,
            force: largest(&force_ranges),
        };
        if let Some(ranges) = velocity_ranges {
            magnitudes.velocity = Some(largest(&ranges));
            motion_ranges.extend(ranges);
        }
        Ok(Record {
            parts,
            active_channels,
            channel_names: Vec::new(),
            measured: None,
            fixed_dofs: Vec::new(),
            motion_ranges,
            magnitudes,
        })
    }

    /// This record with the signals `motion` its sensors measured, its displacements and
    /// velocities having been reconstructed from them ([`crate::prep::motion`], the only
    /// caller, which keeps the two consistent).
    pub(crate) fn with_measured_motion(mut self, motion: MeasuredMotion) -> Result<Self> {
        let shape = (self.samples(), self.dofs());
        if motion.sensors.len() != shape.1 {
            return Err(Error::mismatch(
                "sensors vs DOFs",
                shape.1,
                motion.sensors.len(),
            ));
        }
        if motion.signals.shape() != shape {
            let (what, expected, found) = if motion.signals.nrows() != shape.0 {
                (
                    "rows of measured motion vs samples",
                    shape.0,
                    motion.signals.nrows(),
                )
            } else {
                (
                    "columns of measured motion vs DOFs",
                    shape.1,
                    motion.signals.ncols(),
                )
            };
            return Err(Error::mismatch(what, expected, found));
        }
        check_finite("measured motion", motion.signals.as_ref())?;
        self.measured = motion
            .sensors
            .iter()
            .any(|s| *s != Sensor::Displacement)
            .then_some(motion);
        if let Some(measured) = &self.measured {
            self.motion_ranges = channel_ranges(measured.signals.as_ref()).0;
        }
        Ok(self)
    }

    /// The signals the sensors measured, when they are not all displacements (the
    /// displacements and velocities of this record were then reconstructed from them).
    pub fn measured_motion(&self) -> Option<&MeasuredMotion> {
        self.measured.as_ref()
    }

    /// What each DOF's sensor measures (all displacements unless the record was built
    /// from other sensors).
    pub fn sensors(&self) -> Vec<Sensor> {
        self.measured.as_ref().map_or_else(
            || vec![Sensor::Displacement; self.dofs()],
            |m| m.sensors.clone(),
        )
    }

    /// This record with a name for each force channel (the data-file columns they came
    /// from), for messages about a channel; an empty list leaves them unnamed.
    pub fn with_channel_names(mut self, names: Vec<String>) -> Result<Self> {
        let channels = self.parts.forcing.signals.ncols();
        if !names.is_empty() && names.len() != channels {
            return Err(Error::mismatch(
                "force channel names vs force channels",
                channels,
                names.len(),
            ));
        }
        self.channel_names = names;
        Ok(self)
    }

    /// This record with `dofs` (0-based) declared held still (grounded or clamped in
    /// this experiment): a motion channel of theirs that never moves is then what the
    /// experiment did, not a dead sensor ([`crate::regressor::dead_motion`]).
    pub fn with_fixed_dofs(mut self, dofs: Vec<usize>) -> Result<Self> {
        if let Some(&dof) = dofs.iter().find(|&&d| d >= self.dofs()) {
            return Err(Error::dof_index(
                format!("fixed DOF of record '{}'", self.label()),
                dof,
                self.dofs(),
            ));
        }
        self.fixed_dofs = dofs;
        Ok(self)
    }

    /// (max − min, max |s|) of each motion channel the dead-sensor check tests
    /// ([`crate::regressor::dead_motion`]): the columns of the measured signals
    /// ([`Record::measured_motion`]) when there are some, otherwise those of the
    /// displacements followed by those of the measured velocities, if any.
    pub(crate) fn motion_ranges(&self) -> &[(f64, f64)] {
        &self.motion_ranges
    }

    /// The largest magnitude of the displacements, measured velocities and forces.
    pub fn magnitudes(&self) -> Magnitudes {
        self.magnitudes
    }

    /// The DOFs (0-based) declared held still in this record.
    pub fn fixed_dofs(&self) -> &[usize] {
        &self.fixed_dofs
    }

    /// The name of force channel `k` (0-based), when the record has names.
    pub fn channel_name(&self, k: usize) -> Option<&str> {
        self.channel_names.get(k).map(String::as_str)
    }

    /// The force channels' names, one per channel, or empty.
    pub fn channel_names(&self) -> &[String] {
        &self.channel_names
    }

    /// The record's label.
    pub fn label(&self) -> &str {
        &self.parts.label
    }
    /// Sampling step h.
    pub fn step(&self) -> f64 {
        self.parts.step
    }
    /// Time of the first sample.
    pub fn start_time(&self) -> f64 {
        self.parts.start_time
    }
    /// Driving period T.
    pub fn period(&self) -> f64 {
        self.parts.period
    }
    /// Number of samples N.
    pub fn samples(&self) -> usize {
        self.parts.displacements.nrows()
    }
    /// Number of DOFs n.
    pub fn dofs(&self) -> usize {
        self.parts.displacements.ncols()
    }
    /// N × n displacements: measured, or reconstructed from the sensors' signals
    /// ([`Record::measured_motion`]).
    pub fn displacements(&self) -> MatRef<'_, f64> {
        self.parts.displacements.as_ref()
    }
    /// N × n measured velocities, if any (reconstructed for a record of other sensors).
    pub fn velocities(&self) -> Option<MatRef<'_, f64>> {
        self.parts.velocities.as_ref().map(|v| v.as_ref())
    }
    /// Applied force channels.
    pub fn forcing(&self) -> &Forcing {
        &self.parts.forcing
    }
    /// The force channels that are not zero everywhere, in order: the only ones whose
    /// input work can differ from zero.
    pub fn active_channels(&self) -> &[usize] {
        &self.active_channels
    }
    /// The validated parts, for transforms that build a new record from this one (a
    /// record built from them has the displacements and velocities, not the sensors).
    pub fn parts(&self) -> &RecordParts {
        &self.parts
    }
    /// Consumes the record and returns its parts.
    pub fn into_parts(self) -> RecordParts {
        self.parts
    }
}

/// [`channel_ranges`] of `m`, which must be finite: a non-finite value is the error of
/// [`check_finite`] (the first in column-major order), found in the same pass over the
/// data as the ranges, so that a record's signals are read once here, not twice.
fn finite_ranges(what: &str, m: MatRef<'_, f64>) -> Result<Vec<(f64, f64)>> {
    let (ranges, finite) = channel_ranges(m);
    if !finite {
        check_finite(what, m)?;
    }
    Ok(ranges)
}

/// (max − min, max |s|) of each column of `m`, with 8 independent minima and maxima so
/// that the loop runs packed, and whether every value is finite (8 sums of s − s, which
/// are 0 for a finite s and NaN for ±∞ or NaN, in the same pass). The ranges are those
/// of finite data; with a non-finite value they mean nothing.
fn channel_ranges(m: MatRef<'_, f64>) -> (Vec<(f64, f64)>, bool) {
    let range = |j: usize| column_range(col(m, j));
    // Columns in parallel (rayon) once the matrix is large enough to pay for it.
    let ranges: Vec<((f64, f64), bool)> = if m.nrows() * m.ncols() >= PARALLEL_RANGES {
        (0..m.ncols()).into_par_iter().map(range).collect()
    } else {
        (0..m.ncols()).map(range).collect()
    };
    let finite = ranges.iter().all(|r| r.1);
    (ranges.into_iter().map(|r| r.0).collect(), finite)
}

/// Values from which [`channel_ranges`] reads a matrix's columns in parallel.
const PARALLEL_RANGES: usize = 1 << 20;

/// (max − min, max |s|) of the values `s` and whether they are all finite
/// ([`channel_ranges`]), compiled for the widest instruction set the CPU has
/// ([`simd::dispatch`]): the eight minima, maxima and sums are lanes, each doing the
/// operations of the plain loop, so every level gives the same bits.
fn column_range(s: &[f64]) -> ((f64, f64), bool) {
    simd::dispatch(ColumnRange(s))
}

/// The pass of [`column_range`] over its values.
struct ColumnRange<'a>(&'a [f64]);

impl Kernel for ColumnRange<'_> {
    type Output = ((f64, f64), bool);
    #[inline(always)]
    fn run(self) -> Self::Output {
        column_range_of(self.0)
    }
}

/// [`column_range`] at the level it is compiled for.
#[inline(always)]
#[allow(clippy::eq_op)] // s − s is the point: 0 for a finite s, NaN otherwise
fn column_range_of(s: &[f64]) -> ((f64, f64), bool) {
    if s.is_empty() {
        return ((0.0, 0.0), true);
    }
    let mut lo = [f64::INFINITY; 8];
    let mut hi = [f64::NEG_INFINITY; 8];
    let mut nan = [0.0; 8];
    let mut chunks = s.chunks_exact(8);
    for chunk in &mut chunks {
        for k in 0..8 {
            lo[k] = if chunk[k] < lo[k] { chunk[k] } else { lo[k] };
            hi[k] = if chunk[k] > hi[k] { chunk[k] } else { hi[k] };
            nan[k] += chunk[k] - chunk[k];
        }
    }
    let rest = chunks.remainder();
    let finite = nan.iter().chain(rest).all(|v| v.is_finite());
    let lo = lo.iter().chain(rest).fold(f64::INFINITY, |a, &b| a.min(b));
    let hi = hi
        .iter()
        .chain(rest)
        .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
    ((hi - lo, lo.abs().max(hi.abs())), finite)
}

/// Column j of a column-major matrix view as a slice.
pub(crate) fn col<'a>(m: MatRef<'a, f64>, j: usize) -> &'a [f64] {
    // cannot fail: faer's Mat (every matrix a record holds) has unit row stride, and so
    // have its column and row-range views, the only views passed here.
    m.col(j)
        .try_as_col_major()
        .expect("dampid stores matrices column-major")
        .as_slice()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed ranges equal the plain max − min and max |s| of each column, serially
    /// and in parallel (a matrix of at least `PARALLEL_RANGES` values), and a NaN or ±∞
    /// anywhere (in the packed body, in the remainder) clears the finite flag, which
    /// `finite_ranges` turns into the error of `check_finite` at the first one.
    #[test]
    fn ranges_and_finiteness_in_one_pass() {
        for (rows, cols) in [(13, 3), (8, 1), (5, 2), ((PARALLEL_RANGES >> 2) + 3, 4)] {
            let m = Mat::from_fn(rows, cols, |i, j| {
                ((i * 7 + j * 3) % 11) as f64 - 4.5 * j as f64
            });
            let (ranges, finite) = channel_ranges(m.as_ref());
            assert!(finite);
            for (j, &(range, magnitude)) in ranges.iter().enumerate() {
                let s = col(m.as_ref(), j);
                let lo = s.iter().fold(f64::INFINITY, |a, &b| a.min(b));
                let hi = s.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b));
                assert_eq!((range, magnitude), (hi - lo, lo.abs().max(hi.abs())));
            }
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for at in [(0, 0), (rows / 2, cols - 1), (rows - 1, cols / 2)] {
                    let mut m = m.clone();
                    m[at] = bad;
                    assert!(!channel_ranges(m.as_ref()).1, "{rows}x{cols} {bad} {at:?}");
                    let e = finite_ranges("velocities", m.as_ref()).unwrap_err();
                    let first = check_finite("velocities", m.as_ref()).unwrap_err();
                    assert_eq!(format!("{e:?}"), format!("{first:?}"));
                }
            }
        }
    }
}
