//! A measured record from a data file (`[[data.records]]`): its time base, its motion
//! columns (per DOF one displacement, velocity or acceleration sensor, or displacements
//! and measured velocities of every DOF), its force columns, and the gain of each
//! column: physical value = scale × column + offset (`time_scale` × the time column).
//! DOFs are 1-based; the period is given or detected from the force.

use std::fmt;
use std::mem::MaybeUninit;
use std::path::Path;

use serde::Serialize;
use toml::Spanned;

use super::context::Context;
use super::spec::{ColumnSpec, RecordSpec, Scale};
use crate::error::{Error, Result};
use crate::format::number;
use crate::io::Table;
use crate::io::data_file::DataFiles;
use crate::io::fresh::Fresh;
use crate::io::scatter::put;
use crate::prep::motion::{Integration, SensorParts, record_from_sensors};
use crate::prep::period::{PeriodEstimate, detect_period};
use crate::record::{Forcing, Record, RecordParts, Sensor};

/// How the columns of one data record were read: the gains that are not the identity,
/// and what each DOF's sensor measures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordInputs {
    /// The record's label.
    pub record: String,
    /// Time = `time_scale` × the time column (1 when not given).
    pub time_scale: f64,
    /// The columns read with a gain other than scale 1, offset 0.
    pub gains: Vec<ChannelGain>,
    /// What each DOF's motion channel measures.
    pub sensors: Vec<Sensor>,
    /// The high-pass cut-off that treated the drift of integrated channels in the
    /// non-periodic mode (`None`: integrated over whole periods, or nothing integrated).
    pub high_pass: Option<f64>,
}

/// One column's gain: value = scale × column + offset.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelGain {
    /// The data-file column.
    pub column: String,
    /// What it gives ("force on DOF 1", "acceleration of DOF 2").
    pub quantity: String,
    /// The scale.
    pub scale: f64,
    /// The offset.
    pub offset: f64,
}

impl RecordInputs {
    /// Whether anything is worth saying: a gain, a time scale or a sensor that is not a
    /// displacement.
    pub fn is_plain(&self) -> bool {
        self.gains.is_empty()
            && self.time_scale == 1.0
            && self.sensors.iter().all(|s| *s == Sensor::Displacement)
    }
}

impl fmt::Display for RecordInputs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "record '{}':", self.record)?;
        if self.time_scale != 1.0 {
            writeln!(f, "  time = {} × time column", number(self.time_scale))?;
        }
        for g in &self.gains {
            write!(f, "  {} = {} × '{}'", g.quantity, number(g.scale), g.column)?;
            if g.offset != 0.0 {
                write!(f, " + {}", number(g.offset))?;
            }
            writeln!(f)?;
        }
        for kind in [Sensor::Velocity, Sensor::Acceleration] {
            let dofs: Vec<String> = (0..self.sensors.len())
                .filter(|&j| self.sensors[j] == kind)
                .map(|j| (j + 1).to_string())
                .collect();
            if dofs.is_empty() {
                continue;
            }
            match self.high_pass {
                None => writeln!(
                    f,
                    "  {} sensors on DOF {}: integrated over whole periods per harmonic; the mean of x and v over each window is set to zero (the k = 0 component is removed)",
                    kind.name(),
                    dofs.join(", ")
                )?,
                Some(cutoff) => writeln!(
                    f,
                    "  {} sensors on DOF {}: integrated over the record with a zero-phase high-pass at {cutoff} cycles per time unit against drift (content below it is removed)",
                    kind.name(),
                    dofs.join(", ")
                )?,
            }
        }
        Ok(())
    }
}

/// A record read from its data file, the period detected from its force (when none was
/// given), and how its columns were read.
pub(super) struct ReadRecord {
    pub(super) record: Record,
    pub(super) detected: Option<PeriodEstimate>,
    /// The jitter of its time column, when it has one.
    pub(super) jitter: Option<f64>,
    pub(super) inputs: RecordInputs,
}

/// The gain (scale, offset) of a column, checked: a scale of 0 or a non-finite scale
/// or offset is an error at the column's line.
fn gain<T>(
    ctx: &Context,
    at: &Spanned<T>,
    column: &str,
    scale: Option<f64>,
    offset: Option<f64>,
) -> Result<(f64, f64)> {
    let scale = scale.unwrap_or(1.0);
    let offset = offset.unwrap_or(0.0);
    if !scale.is_finite() || scale == 0.0 {
        let e = Error::invalid(
            &format!("scale of column '{column}'"),
            scale,
            "must be finite and not zero (value = scale × column + offset)",
        );
        return Err(ctx.typed_error_at(at, e));
    }
    if !offset.is_finite() {
        let e = Error::invalid(
            &format!("offset of column '{column}'"),
            offset,
            "must be finite (value = scale × column + offset)",
        );
        return Err(ctx.typed_error_at(at, e));
    }
    Ok((scale, offset))
}

/// The scales of a record's columns given by name (`scale = "gtau"`): each named scalar
/// variable of the record's data file, read once ([`DataFiles::scalar`]); an error at the
/// entry that names a missing or non-scalar one.
fn named_scales(
    ctx: &Context,
    spec: &RecordSpec,
    path: &Path,
    files: &mut DataFiles,
) -> Result<std::collections::HashMap<String, f64>> {
    let mut values = std::collections::HashMap::new();
    let motion = [&spec.displacements, &spec.velocities, &spec.accelerations]
        .into_iter()
        .flatten()
        .map(|c| (c.span(), c.get_ref().scale.as_ref()));
    let forces = spec
        .forces
        .iter()
        .map(|f| (f.span(), f.get_ref().scale.as_ref()));
    for (span, scale) in motion.chain(forces) {
        if let Some(Scale::Variable(name)) = scale
            && !values.contains_key(name)
        {
            let value = files
                .scalar(path, name)
                .map_err(|e| ctx.typed_error_at(&Spanned::new(span.clone(), ()), e))?;
            values.insert(name.clone(), value);
        }
    }
    Ok(values)
}

/// A column's scale as a number: given, or the named scalar read by [`named_scales`].
fn scale_value(
    scale: Option<&Scale>,
    named: &std::collections::HashMap<String, f64>,
) -> Option<f64> {
    match scale? {
        Scale::Value(v) => Some(*v),
        // Every named scale was read before (named_scales): NaN only if not, refused by `gain`.
        Scale::Variable(name) => Some(named.get(name).copied().unwrap_or(f64::NAN)),
    }
}

/// The columns of a record's table, each moved into the matrix that uses it.
struct Columns {
    table: Table,
    /// How many channels still read each column (by its index in the table).
    uses: Vec<usize>,
    rows: usize,
}

impl Columns {
    fn new<'a>(table: Table, names: impl Iterator<Item = &'a str>, rows: usize) -> Self {
        let mut uses = vec![0; table.headers.len()];
        for name in names {
            if let Some(k) = table.headers.iter().position(|h| h == name) {
                uses[k] += 1;
            }
        }
        Self { table, uses, rows }
    }

    /// Writes scale × `column` + offset into every sample of `into`, and frees the
    /// column when no other channel names it. A column of another length than `into`
    /// is an error (the table's columns all have the record's samples, and each is
    /// freed only after its last reader: counted in `new`).
    fn move_into(
        &mut self,
        into: &mut [MaybeUninit<f64>],
        column: &str,
        gain: (f64, f64),
    ) -> Result<()> {
        let values = self.table.column(column)?;
        if values.len() != into.len() || values.len() != self.rows {
            return Err(Error::Numerical {
                stage: "reading a record's columns".into(),
                detail: format!(
                    "the column '{column}' has {} samples, its destination {}",
                    values.len(),
                    into.len()
                ),
            });
        }
        put(into, values.iter(), gain);
        if let Some(k) = self.table.headers.iter().position(|h| h == column) {
            self.uses[k] = self.uses[k].saturating_sub(1);
            if self.uses[k] == 0 {
                self.table.columns[k] = Vec::new();
            }
        }
        Ok(())
    }
}

/// One motion channel of a DOF: the column, its gain and its line.
struct MotionColumn<'a> {
    spec: &'a Spanned<ColumnSpec>,
    sensor: Sensor,
    gain: (f64, f64),
}

/// The motion columns of `spec` per DOF, and the measured velocities when displacements
/// and velocities are given for every DOF (their older meaning).
#[allow(clippy::type_complexity)]
fn motion_columns<'a>(
    ctx: &Context,
    spec: &'a RecordSpec,
    n: usize,
    label: &str,
    named: &std::collections::HashMap<String, f64>,
) -> Result<(Vec<MotionColumn<'a>>, Option<Vec<MotionColumn<'a>>>)> {
    let lists = [
        (Sensor::Displacement, &spec.displacements),
        (Sensor::Velocity, &spec.velocities),
        (Sensor::Acceleration, &spec.accelerations),
    ];
    let mut per_kind: Vec<Vec<Option<MotionColumn<'a>>>> = Vec::new();
    for (sensor, list) in lists {
        let mut slots: Vec<Option<MotionColumn<'a>>> = (0..n).map(|_| None).collect();
        for (position, entry) in list.iter().enumerate() {
            let c = entry.get_ref();
            let dof = c.dof.unwrap_or(position + 1);
            let index = dof.checked_sub(1).filter(|d| *d < n).ok_or_else(|| {
                let e = Error::DofOutOfRange {
                    what: format!("{} column '{}'", sensor.name(), c.column),
                    dof,
                    dofs: n,
                };
                ctx.typed_error_at(entry, e)
            })?;
            if let Some(other) = &slots[index] {
                let e = Error::MotionSensors {
                    record: label.to_string(),
                    dof,
                    found: format!(
                        "two {} columns ('{}' and '{}')",
                        sensor.name(),
                        other.spec.get_ref().column,
                        c.column
                    ),
                };
                return Err(ctx.typed_error_at(entry, e));
            }
            let scale = scale_value(c.scale.as_ref(), named);
            let gain = gain(ctx, entry, &c.column, scale, c.offset)?;
            slots[index] = Some(MotionColumn {
                spec: entry,
                sensor,
                gain,
            });
        }
        per_kind.push(slots);
    }
    let full = |slots: &Vec<Option<MotionColumn>>| slots.iter().all(Option::is_some);
    let mut accelerations = per_kind.pop().unwrap_or_default();
    let mut velocities = per_kind.pop().unwrap_or_default();
    let mut displacements = per_kind.pop().unwrap_or_default();
    if full(&displacements) && full(&velocities) && accelerations.iter().all(Option::is_none) {
        let x = displacements.into_iter().flatten().collect();
        return Ok((x, Some(velocities.into_iter().flatten().collect())));
    }
    let mut motion = Vec::with_capacity(n);
    for dof in 0..n {
        let found: Vec<MotionColumn> = [
            displacements[dof].take(),
            velocities[dof].take(),
            accelerations[dof].take(),
        ]
        .into_iter()
        .flatten()
        .collect();
        if found.len() != 1 {
            let text = if found.is_empty() {
                "no motion column".to_string()
            } else {
                let names: Vec<String> = found
                    .iter()
                    .map(|m| format!("{} '{}'", m.sensor.name(), m.spec.get_ref().column))
                    .collect();
                format!(
                    "{} kinds of motion column ({})",
                    found.len(),
                    names.join(", ")
                )
            };
            return Err(Error::MotionSensors {
                record: label.to_string(),
                dof: dof + 1,
                found: text,
            });
        }
        motion.extend(found);
    }
    Ok((motion, None))
}

/// The records' mode: periodic, or `[non_periodic]` with its high-pass cut-off (at its
/// line) for integrating velocity and acceleration columns.
pub(super) enum Mode<'a> {
    Periodic,
    NonPeriodic(Option<&'a Spanned<f64>>),
    /// A ringdown: the isolation of its mode integrates its signals again
    /// ([`crate::prep::free_decay`]); here a high-pass at two cycles per record length
    /// only gives the record its provisional x and v.
    FreeDecay,
}

/// The columns a record names: its time column, its motion columns, its forces.
fn named_columns(spec: &RecordSpec) -> Vec<&str> {
    let motion = [&spec.displacements, &spec.velocities, &spec.accelerations]
        .into_iter()
        .flatten()
        .map(|c| c.get_ref().column.as_str());
    let forces = spec.forces.iter().map(|f| f.get_ref().column.as_str());
    spec.time
        .as_deref()
        .into_iter()
        .chain(motion)
        .chain(forces)
        .collect()
}

/// The motion columns a record names that are not also its time or force columns: those
/// read from the file straight into the record's matrices where the file allows
/// (`io::in_place`).
fn in_place_columns(spec: &RecordSpec) -> Vec<&str> {
    let other: Vec<&str> = spec
        .time
        .as_deref()
        .into_iter()
        .chain(spec.forces.iter().map(|f| f.get_ref().column.as_str()))
        .collect();
    [&spec.displacements, &spec.velocities, &spec.accelerations]
        .into_iter()
        .flatten()
        .map(|c| c.get_ref().column.as_str())
        .filter(|c| !other.contains(c))
        .collect()
}

/// Reads one record; a periodic record without a period or frequency gets one detected
/// from its force, a non-periodic one gets its duration (which nothing uses). Only the
/// columns it names are read from `files` (a `.npz` or `.mat` file may hold other
/// arrays), each file once for all the records that name it.
pub(super) fn read_record(
    ctx: &Context,
    spec: &RecordSpec,
    n: usize,
    files: (&Path, &mut DataFiles),
    mode: Mode,
) -> Result<ReadRecord> {
    let periodic = matches!(mode, Mode::Periodic);
    let (base, files) = files;
    let path = base.join(&spec.file);
    let named = named_scales(ctx, spec, &path, files)?;
    let names = named_columns(spec);
    let (table, in_place) = files.columns(&path, &names, &in_place_columns(spec))?;
    let label = spec
        .label
        .clone()
        .unwrap_or_else(|| crate::format::printable(&spec.file).into_owned());
    let time_scale = match &spec.time_scale {
        None => 1.0,
        Some(s) => {
            let scale = gain(ctx, s, "time", Some(*s.get_ref()), None)?.0;
            if !(scale.is_finite() && scale > 0.0) {
                return Err(ctx.typed_error_at(
                    s,
                    Error::invalid(
                        "time_scale",
                        scale,
                        "time = time_scale × the time column must increase with the column: give a positive factor (1e-3 for a column in milliseconds)",
                    ),
                ));
            }
            scale
        }
    };
    let (step, jitter) = match (&spec.time, spec.step) {
        (Some(time), None) => {
            let time = table.uniform_step(time)?;
            (time_scale * time.step, Some(time.jitter))
        }
        (None, Some(step)) => (step, None),
        (time, _) => {
            let given = if time.is_some() {
                "both `time` and `step`"
            } else {
                "neither `time` nor `step`"
            };
            return Err(Error::choice(
                "step",
                given,
                "give exactly one of `time` (a column) or `step`",
            ));
        }
    };
    let start_time = spec
        .time
        .as_deref()
        .map_or(Ok(0.0), |t| table.column(t).map(|c| time_scale * c[0]))?;
    let (motion, measured_velocities) = motion_columns(ctx, spec, n, &label, &named)?;
    // Each column moves from the table into its matrix and is freed there (cloned only
    // while another channel still names it), or is read from the file straight into its
    // matrix (`io::in_place`), so reading a record holds the data once plus one column,
    // not twice.
    let rows = match in_place.rows() {
        Some(rows) => rows,
        None => table.rows(),
    };
    let mut columns = Columns::new(
        table,
        motion
            .iter()
            .chain(measured_velocities.iter().flatten())
            .map(|m| m.spec.get_ref().column.as_str())
            .chain(spec.forces.iter().map(|f| f.get_ref().column.as_str())),
        rows,
    );
    let mut gains = Vec::new();
    let mut note = |column: &str, gain: (f64, f64), quantity: String| {
        if gain != (1.0, 0.0) {
            gains.push(ChannelGain {
                column: column.to_string(),
                quantity,
                scale: gain.0,
                offset: gain.1,
            });
        }
    };
    // The matrices are not zeroed first (`io::fresh`): every column is written below,
    // from the file or from the table, before the matrix takes its shape.
    let mut fresh_motion = Fresh::new(rows, motion.len());
    let mut fresh_velocities = measured_velocities
        .as_ref()
        .map(|channels| Fresh::new(rows, channels.len()));
    {
        let mut destinations = Vec::new();
        let matrices = std::iter::once((&motion, fresh_motion.columns())).chain(
            measured_velocities
                .iter()
                .zip(fresh_velocities.iter_mut().map(Fresh::columns)),
        );
        for (channels, matrix) in matrices {
            for (j, (c, into)) in channels.iter().zip(matrix).enumerate() {
                let column = c.spec.get_ref().column.as_str();
                note(
                    column,
                    c.gain,
                    format!("{} of DOF {}", c.sensor.name(), j + 1),
                );
                if in_place.holds(column) {
                    destinations.push((column, into, c.gain));
                } else {
                    columns.move_into(into, column, c.gain)?;
                }
            }
        }
        in_place.read(destinations)?;
    }
    // SAFETY: each motion channel (one per column of the two matrices, `zip` above over
    // as many channels as columns) was written in full, by `move_into` (every sample,
    // or an error) or by `in_place.read` (every sample of every destination, or an
    // error), and every error returned before this point.
    let signals_motion = unsafe { fresh_motion.assume_written() };
    // SAFETY: as above.
    let velocities = fresh_velocities.map(|v| unsafe { v.assume_written() });
    let mut force_names = Vec::with_capacity(spec.forces.len());
    let mut dofs = Vec::with_capacity(spec.forces.len());
    let mut fresh_signals = Fresh::new(rows, spec.forces.len());
    for (force, into) in spec.forces.iter().zip(fresh_signals.columns()) {
        let f = force.get_ref();
        let dof = f.dof.checked_sub(1).filter(|d| *d < n).ok_or_else(|| {
            let e = Error::DofOutOfRange {
                what: format!("force column '{}'", f.column),
                dof: f.dof,
                dofs: n,
            };
            ctx.typed_error_at(force, e)
        })?;
        let g = gain(
            ctx,
            force,
            &f.column,
            scale_value(f.scale.as_ref(), &named),
            f.offset,
        )?;
        note(&f.column, g, format!("force on DOF {}", f.dof));
        columns.move_into(into, &f.column, g)?;
        force_names.push(f.column.clone());
        dofs.push(dof);
    }
    // SAFETY: one force per column (`zip` above), each written in full by `move_into`
    // (every sample, or an error that returned).
    let signals = unsafe { fresh_signals.assume_written() };
    let (period, detected) = match (spec.period, spec.frequency) {
        (Some(period), None) => (period, None),
        (None, Some(omega)) if omega.is_finite() && omega > 0.0 => {
            (2.0 * std::f64::consts::PI / omega, None)
        }
        (None, Some(omega)) => {
            return Err(Error::invalid(
                "frequency",
                omega,
                "the driving frequency ω (rad per unit time) must be finite and positive; or give `period`, or neither to detect the period from the force",
            ));
        }
        (None, None) if !periodic => (step * (signals.nrows().max(2) - 1) as f64, None),
        (None, None) => {
            let estimate = detect_period(signals.as_ref(), step, &label)?;
            (estimate.period, Some(estimate))
        }
        (Some(period), Some(_)) => {
            return Err(Error::invalid(
                "period",
                period,
                "give at most one of `period` or `frequency` (rad per unit time); with neither, the period is detected from the force",
            ));
        }
    };
    let sensors: Vec<Sensor> = motion.iter().map(|m| m.sensor).collect();
    let forcing = Forcing::on_dofs(signals, dofs);
    let mut cutoff = None;
    let record = if let Some(velocities) = velocities {
        Record::new(RecordParts {
            label: label.clone(),
            step,
            start_time,
            displacements: signals_motion,
            velocities: Some(velocities),
            forcing,
            period,
        })?
    } else {
        let integration = match mode {
            Mode::Periodic => Integration::WholePeriods,
            _ if sensors.iter().all(|s| *s == Sensor::Displacement) => Integration::WholePeriods,
            Mode::NonPeriodic(Some(cutoff)) => Integration::HighPass {
                cutoff: *cutoff.get_ref(),
            },
            Mode::FreeDecay => Integration::HighPass {
                cutoff: 2.0 / (step * rows.max(2) as f64),
            },
            Mode::NonPeriodic(None) => {
                return Err(Error::missing(
                    "high_pass in [non_periodic]",
                    "velocity or acceleration columns in a record that is not periodic are integrated with a zero-phase high-pass against drift: add `high_pass = f_c` (the cut-off frequency, cycles per time unit, well below the slowest motion of interest, e.g. 0.05 for moves of about a second) to [non_periodic]; content below f_c is removed",
                ));
            }
        };
        cutoff = match integration {
            Integration::HighPass { cutoff } => Some(cutoff),
            Integration::WholePeriods => None,
        };
        let high_pass_line = match mode {
            Mode::NonPeriodic(Some(cutoff)) => Some(cutoff),
            _ => None,
        };
        let built = record_from_sensors(SensorParts {
            label: label.clone(),
            step,
            start_time,
            motion: signals_motion,
            sensors: sensors.clone(),
            forcing,
            period,
            integration,
        });
        match (built, high_pass_line) {
            (Err(e @ Error::InvalidParameter { .. }), Some(at)) => {
                return Err(ctx.typed_error_at(at, e));
            }
            (built, _) => built?,
        }
    }
    .with_channel_names(force_names)?;
    let record = match &spec.fixed_dofs {
        None => record,
        Some(fixed) => {
            let mut dofs = Vec::with_capacity(fixed.get_ref().len());
            for &dof in fixed.get_ref() {
                let index = dof.checked_sub(1).filter(|d| *d < n).ok_or_else(|| {
                    let e = Error::DofOutOfRange {
                        what: format!("fixed DOF of record '{label}'"),
                        dof,
                        dofs: n,
                    };
                    ctx.typed_error_at(fixed, e)
                })?;
                dofs.push(index);
            }
            record.with_fixed_dofs(dofs)?
        }
    };
    Ok(ReadRecord {
        record,
        detected,
        jitter,
        inputs: RecordInputs {
            record: label,
            time_scale,
            gains,
            sensors,
            high_pass: cutoff,
        },
    })
}
