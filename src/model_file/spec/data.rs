//! The specs of measured data in a model file: `[data]` records (their files, time base
//! and motion and force columns with gains) and the `[stepped_sine]` table.

use serde::Deserialize;
use toml::Spanned;

use super::modes::PhaseName;

/// `[data]`: measured records.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DataSpec {
    /// One entry per record file.
    pub records: Vec<Spanned<RecordSpec>>,
}

/// One measured record in a data file with a header row.
///
/// Motion: per DOF exactly one of a displacement, velocity or acceleration column
/// (`displacements`, `velocities`, `accelerations`; an entry without `dof` is the DOF of
/// its position in the list). Displacements *and* velocities for every DOF keep their
/// older meaning: measured velocities beside the displacements (`velocity = "measured"`).
/// Every column may carry a gain: physical value = `scale` × column + `offset`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordSpec {
    /// Path, relative to the model file.
    pub file: String,
    /// A label (default: the file name).
    pub label: Option<String>,
    /// The time column (uniform step required) …
    pub time: Option<String>,
    /// … or the step h.
    pub step: Option<f64>,
    /// Time = `time_scale` × the time column (default 1), e.g. 1e-3 for milliseconds.
    pub time_scale: Option<Spanned<f64>>,
    /// Displacement columns.
    #[serde(default)]
    pub displacements: Vec<Spanned<ColumnSpec>>,
    /// Velocity columns (velocity sensors, or measured velocities beside displacements
    /// of every DOF).
    #[serde(default)]
    pub velocities: Vec<Spanned<ColumnSpec>>,
    /// Acceleration columns.
    #[serde(default)]
    pub accelerations: Vec<Spanned<ColumnSpec>>,
    /// Force columns and the DOF each acts on (none for a free decay).
    #[serde(default)]
    pub forces: Vec<Spanned<ForceColumn>>,
    /// Driving period T …
    pub period: Option<f64>,
    /// … or driving frequency ω (rad per unit time); with neither, the period is
    /// detected from the force columns (`dampid::prep::period`).
    pub frequency: Option<f64>,
    /// DOFs (from 1) held still in this experiment: their motion columns may read a
    /// constant ([`crate::regressor::dead_motion`]).
    #[serde(default)]
    pub fixed_dofs: Option<Spanned<Vec<usize>>>,
}

/// A motion column: its name (`"x1"`), or `{ column = "qm", dof = 2, scale = 1e-3,
/// offset = 0.0 }` (all but `column` optional).
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSpec {
    /// Column name.
    pub column: String,
    /// DOF, 1-based (default: the entry's position in its list).
    pub dof: Option<usize>,
    /// Gain: physical value = scale × column + offset (default 1); a number or the
    /// name of a scalar variable of the data file.
    pub scale: Option<Scale>,
    /// Offset in physical units (default 0).
    pub offset: Option<f64>,
}

/// The table form of [`ColumnSpec`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ColumnTable {
    column: String,
    dof: Option<usize>,
    scale: Option<Scale>,
    offset: Option<f64>,
}

impl<'de> Deserialize<'de> for ColumnSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = ColumnSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a column name or a table { column, dof, scale, offset }")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<ColumnSpec, E> {
                Ok(ColumnSpec {
                    column: name.to_string(),
                    dof: None,
                    scale: None,
                    offset: None,
                })
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<ColumnSpec, A::Error> {
                let t =
                    ColumnTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(ColumnSpec {
                    column: t.column,
                    dof: t.dof,
                    scale: t.scale,
                    offset: t.offset,
                })
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// A force column, the DOF (1-based) it acts on, and its gain.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceColumn {
    /// Column name.
    pub column: String,
    /// DOF, 1-based.
    pub dof: usize,
    /// Gain: force = scale × column + offset (default 1), e.g. 35.15 N/V, or the name
    /// of a scalar variable of the data file.
    pub scale: Option<Scale>,
    /// Offset in force units (default 0).
    pub offset: Option<f64>,
}

/// `[stepped_sine]`: a measured stepped-sine table, one point per row: frequency, force
/// amplitude, and per DOF a response amplitude and phase. Every column may carry a gain
/// (value = `scale` × column + `offset`), e.g. `scale = 6.283185307179586` for a
/// frequency in Hz, `scale = 0.017453292519943295` for a phase in degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteppedSineSpec {
    /// The table file (CSV, NPY/NPZ, MAT), relative to the model file.
    pub file: String,
    /// Driving frequency ω (rad per unit time after the gain).
    pub frequency: ColumnSpec,
    /// Force amplitude a (the phase reference).
    pub force: ColumnSpec,
    /// The DOF the force acts on, 1-based (default 1).
    pub force_dof: Option<usize>,
    /// What the amplitude and phase columns measure: `"displacement"` (default),
    /// `"velocity"` or `"acceleration"`.
    #[serde(default)]
    pub response: crate::record::Sensor,
    /// Response amplitude per DOF (an entry without `dof` is the DOF of its position).
    pub amplitudes: Vec<Spanned<ColumnSpec>>,
    /// Response phase per DOF, in the order of `amplitudes`.
    pub phases: Vec<Spanned<ColumnSpec>>,
    /// `"lag"` (default): the response is X cos(ωt − φ); `"lead"`: X cos(ωt + φ), the
    /// phase of a frequency response function (−π/2 at resonance).
    #[serde(default)]
    pub phase_convention: PhaseConvention,
    /// A column whose distinct values group the points in sweeps (one force or
    /// response level each); without it all points are one sweep.
    pub sweep: Option<String>,
    /// Instead of `sweep`, for a MAT file: the struct arrays whose elements are the
    /// sweeps (`"FRdata.ResponseControl"`, a list of them, or a struct holding them:
    /// `"FRdata"`), each element one sweep labelled by its path, the columns its fields
    /// (`crate::io::mat` sweeps).
    pub sweeps: Option<Spanned<Paths>>,
    /// σ of the force amplitude per point (a column, same gain as `force`) …
    pub force_std: Option<String>,
    /// … σ of each amplitude (columns, the gains of `amplitudes`) …
    pub amplitude_std: Option<Vec<String>>,
    /// … and σ of each phase (columns, the gains of `phases`); all three or none. Without
    /// them the noise is estimated from the scatter along each sweep.
    pub phase_std: Option<Vec<String>>,
    /// How the DOFs' common phase is read (as in `[harmonic_approximation]`).
    #[serde(default)]
    pub phase_reading: PhaseName,
    /// The DOF (1-based) whose lag is used with `phase_reading = "dof"`.
    pub phase_dof: Option<usize>,
    /// Structural damping terms: a loss factor on an element of given stiffness.
    #[serde(default)]
    pub structural: Vec<Spanned<StructuralSpec>>,
    /// The residual receptance of the out-of-band modes estimated per sweep with the
    /// damping: `"none"` (default), `"stiffness"` (r_k) or `"mass_and_stiffness"`
    /// (R = r_k − r_m/ω²); one-DOF tables with a `sweep` column.
    #[serde(default)]
    pub residual: crate::prep::harmonic::residual::ResidualKind,
    /// Bounds [lower, upper] of every sweep's r_k (default ± the sweep's smallest
    /// measured receptance X/a).
    pub residual_stiffness: Option<Spanned<[f64; 2]>>,
    /// Bounds [lower, upper] of every sweep's r_m (default ± that bound × the sweep's
    /// lowest ω²).
    pub residual_mass: Option<Spanned<[f64; 2]>>,
    /// The points to keep (all by default): a frequency band, a band of the
    /// displacement's lag, some sweeps ([`KeepSpec`]).
    pub keep: Option<Spanned<KeepSpec>>,
}

/// `keep = { frequency_hz = [48.5, 51.5], lag = [0.97, 2.17], sweeps = ["FC1", "RC2"] }`:
/// the points of a `[stepped_sine]` table to identify from, every condition given
/// holding (bounds inclusive).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeepSpec {
    /// [lower, upper] of ω/2π in Hz (ω after the frequency column's gain).
    pub frequency_hz: Option<[f64; 2]>,
    /// [lower, upper] of the displacement's lag φ behind the force at the force's DOF,
    /// in rad after the phase convention and `response` (π/2 at resonance; near
    /// resonance: `[1.5708 - 0.6, 1.5708 + 0.6]`).
    pub lag: Option<[f64; 2]>,
    /// The sweeps, by the names dampid gives them (`FC1`, or `level = 2` for a
    /// numeric sweep column).
    pub sweeps: Option<Vec<String>>,
}

/// One path or a list of them (`sweeps = "FRdata.ResponseControl"` or
/// `sweeps = ["FRdata.ForceControl", "FRdata.ResponseControl"]`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Paths {
    /// One path.
    One(String),
    /// Several.
    Many(Vec<String>),
}

impl Paths {
    /// The paths, as a list.
    pub fn list(&self) -> Vec<String> {
        match self {
            Paths::One(p) => vec![p.clone()],
            Paths::Many(p) => p.clone(),
        }
    }
}

/// A column's scale: a number, or the name of a scalar variable of the same data file
/// (`scale = "gtau"`: a gain stored beside the signals in a `.mat` or `.npz` file).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Scale {
    /// The factor.
    Value(f64),
    /// A scalar variable of the data file.
    Variable(String),
}

/// Which way a stepped-sine phase is counted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseConvention {
    /// x = X cos(ωt − φ): φ is the lag behind the force.
    #[default]
    Lag,
    /// x = X cos(ωt + φ): φ is the phase of the response (an FRF's phase).
    Lead,
}

/// `{ coefficient = "eta", stiffness = 2.0e5, element = [1, 0] }`: a loss factor η on
/// an element of stiffness k (DOFs 1-based, 0 = ground), dissipating π η k X² per cycle.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructuralSpec {
    /// The loss factor's name.
    pub coefficient: String,
    /// k.
    pub stiffness: f64,
    /// [a, b], 1-based, 0 = ground (default [1, 0]).
    pub element: Option<[usize; 2]>,
}
