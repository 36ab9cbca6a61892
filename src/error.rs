//! Typed errors. Every variant carries the data that explains it: the field, the
//! offending value, and what was expected. The library never panics on bad input and
//! never returns a number it could not compute honestly.

use thiserror::Error;

use crate::format::{integer, number};

/// Result alias used throughout dampid.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong between records and a fit report. New variants may be
/// added (`#[non_exhaustive]`); [`Error::kind`] names each one, and [`KINDS`] lists
/// them all.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A value that must be finite is NaN or infinite.
    #[error("{what} has a non-finite value {} at row {row}, column {column}", number(*.value))]
    NonFinite {
        /// Which array or field.
        what: String,
        /// Row (sample) index, 0-based.
        row: usize,
        /// Column (DOF or channel) index, 0-based.
        column: usize,
        /// The offending value.
        value: f64,
    },

    /// Two sizes that must agree do not.
    #[error("{what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// What was being compared (e.g. "rows of velocities vs displacements").
        what: String,
        /// The size required.
        expected: usize,
        /// The size given.
        found: usize,
    },

    /// A scalar parameter is outside its valid range.
    #[error("invalid {name} = {}: {reason}", number(*.value))]
    InvalidParameter {
        /// The parameter's name (e.g. "step", "period", "exponent").
        name: String,
        /// The value given.
        value: f64,
        /// Why it is rejected.
        reason: String,
    },

    /// A setting that is a choice (a rule, a source, one key or another) was given a
    /// value that does not fit: `given` says what was given, in words.
    #[error("invalid {name} = {given}: {reason}")]
    InvalidChoice {
        /// The setting's name (e.g. "quadrature", "velocity", "step").
        name: String,
        /// What was given ("spectral", "both `time` and `step`", "neither").
        given: String,
        /// Why it is rejected, and what would fit.
        reason: String,
    },

    /// A required setting or value is missing.
    #[error("missing {name}: {reason}")]
    Missing {
        /// What is missing (e.g. "exponent", "simulation coefficient 'c'").
        name: String,
        /// What needs it, and how to give it.
        reason: String,
    },

    /// A record holds fewer samples than the requested windows need.
    #[error(
        "record '{record}' is too short: the windows need {} samples, it has {}", integer(*.needed as u64), integer(*.available as u64)
    )]
    RecordTooShort {
        /// The record's label.
        record: String,
        /// Samples needed.
        needed: usize,
        /// Samples present.
        available: usize,
    },

    /// Fewer equations (windows) than free coefficients.
    #[error(
        "too few equations: {equations} windows for {coefficients} free coefficients; add records (amplitudes, frequencies, forcing points) or windows"
    )]
    TooFewEquations {
        /// Rows of the regressor.
        equations: usize,
        /// Free (not fixed) coefficients.
        coefficients: usize,
    },

    /// A DOF number is out of range for the record or system. DOFs are numbered from 1
    /// in every message, as in model files (the API's 0-based index i is DOF i + 1).
    #[error("{what} refers to DOF {dof}, but DOFs are numbered 1..{dofs}")]
    DofOutOfRange {
        /// Which element, force or term.
        what: String,
        /// The offending DOF, numbered from 1.
        dof: usize,
        /// Number of DOFs available.
        dofs: usize,
    },

    /// The model has no terms, or no records were given.
    #[error("nothing to identify: {what} is empty")]
    Empty {
        /// What is empty ("model", "records").
        what: String,
    },

    /// A DOF of a record has no motion column, or more than one kind of motion column
    /// (displacement, velocity, acceleration).
    #[error(
        "record '{record}', DOF {dof}: {found}; give exactly one of a displacement, velocity or acceleration column per DOF (or displacements and velocities for every DOF: measured velocities)"
    )]
    MotionSensors {
        /// The record's label.
        record: String,
        /// The DOF, numbered from 1.
        dof: usize,
        /// What was found for it, in words.
        found: String,
    },

    /// Two coefficients share a name.
    #[error("coefficient name '{name}' is used twice")]
    DuplicateCoefficient {
        /// The repeated name.
        name: String,
    },

    /// A constraint names a coefficient the model does not have.
    #[error("unknown coefficient '{name}'; the model has: {known}")]
    UnknownCoefficient {
        /// The name given.
        name: String,
        /// Comma-separated list of valid names.
        known: String,
    },

    /// A lower bound exceeds an upper bound, or a fixed value violates its bounds.
    #[error("infeasible bounds for '{name}': lower {} > upper {}", number(*.lower), number(*.upper))]
    InfeasibleBounds {
        /// The coefficient.
        name: String,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },

    /// Velocities were requested from the record but it has none.
    #[error("record '{record}' has no measured velocities; choose an estimated velocity source")]
    MissingVelocities {
        /// The record's label.
        record: String,
    },

    /// A damping-law expression does not parse or uses an unknown identifier.
    #[error("bad expression '{expression}': {message}")]
    Expression {
        /// The expression text.
        expression: String,
        /// What is wrong.
        message: String,
    },

    /// A model file is malformed: bad TOML, an unknown key, a wrong type or value.
    #[error("{}: {message}", position_text(.file, *.line, *.column))]
    ModelFile {
        /// The file.
        file: String,
        /// 1-based line (0 when the problem has no position).
        line: usize,
        /// 1-based column (0 when the problem has no position).
        column: usize,
        /// What is wrong.
        message: String,
        /// The typed error behind `message`, when the library raised one (a bad value
        /// in a section, a DOF out of range); `None` for TOML syntax and schema errors.
        /// Kept as data for matching, not as [`std::error::Error::source`], because
        /// `message` already says it.
        cause: Option<Box<Error>>,
    },

    /// A name in a model file does not refer to anything known.
    #[error("unknown {what} '{name}'; known: {}", known_text(.known))]
    UnknownName {
        /// What kind of name ("law", "matrix", "column").
        what: String,
        /// The name given.
        name: String,
        /// The names that would be accepted.
        known: String,
    },

    /// A data file cannot be read or holds a bad value.
    #[error("{}: {message}", data_position_text(.file, *.row, .column))]
    Data {
        /// The file.
        file: String,
        /// 1-based data row (0 for the header or the file as a whole).
        row: usize,
        /// The column (or variable) name.
        column: String,
        /// What is wrong.
        message: String,
    },

    /// A time column is not uniform: its steps depart from their mean by more than the
    /// jitter accepted ([`crate::io::table::MAX_TIME_JITTER`]).
    #[error(
        "{file}, column '{column}': the time steps depart from their mean {} by up to {jitter:.2e} of it (worst at row {row}), more than the {tolerance:e} accepted; resample the record, or give `step = {}` instead of the time column if the samples are uniform", number(*.step), number(*.step)
    )]
    TimeJitter {
        /// The file.
        file: String,
        /// The time column.
        column: String,
        /// 1-based data row of the worst step's end.
        row: usize,
        /// max |Δt − h| / h.
        jitter: f64,
        /// The largest jitter accepted.
        tolerance: f64,
        /// The mean step h.
        step: f64,
    },

    /// A numerical step failed (a singular mass matrix, a failed decomposition).
    #[error("numerical failure in {stage}: {detail}")]
    Numerical {
        /// Which stage failed.
        stage: String,
        /// What happened.
        detail: String,
    },

    /// No driving period can be detected from a record's force signals.
    #[error(
        "record '{record}': no driving period can be detected from the force: {reason}; give the record's `period` or `frequency`"
    )]
    NoPeriod {
        /// The record's label.
        record: String,
        /// Share of the force's variance the best single sinusoid explains (0 when the
        /// force is constant).
        explained: f64,
        /// Why the force shows no period.
        reason: String,
    },

    /// A window is not in steady state: the motion at its end differs from its start.
    #[error(
        "record '{record}', window {window} (starting at t = {}): not in steady state: {measure} {mismatch:.3e} exceeds {threshold:.3e}; skip more of the transient, or accept it", number(*.start_time)
    )]
    NotSteady {
        /// The record's label.
        record: String,
        /// The window's index within its record (0-based).
        window: usize,
        /// Time of the window's first sample.
        start_time: f64,
        /// What was measured ("stored-energy mismatch / input work", "state mismatch").
        measure: String,
        /// The mismatch found.
        mismatch: f64,
        /// The largest mismatch accepted.
        threshold: f64,
    },

    /// A record gives no input work: no force channel acts on it, or the work its force
    /// channels do cannot be told from zero ([`crate::regressor::input_work`]). Every
    /// equation of it would say "damping work = 0", a confident wrong answer.
    #[error("record '{record}'{}, {channels}: no input work: {reason}", window_text(.window))]
    NoInputWork {
        /// The record's label.
        record: String,
        /// The window concerned (0-based, as in the steady-state table of `dampid
        /// check`); `None` when the whole record is.
        window: Option<usize>,
        /// The force channels, numbered from 1, with their column names where a model
        /// file gave them (`force channel 1 ('f1', on DOF 3)`), or `no force channel`.
        channels: String,
        /// What was found, and what would fix it.
        reason: String,
    },

    /// A history term's state (Bouc–Wen, Dahl, Iwan) did not repeat within the passes
    /// through a window's period that `crate::terms::history::orbit` allows: the window
    /// gives the element no periodic orbit to take its force on.
    #[error(
        "record '{record}', window {window}: the {term} element's state did not repeat after {passes} passes through the window's period (change {} per pass, tolerance {}); give a longer record of steady periodic motion, or shape parameters whose hysteresis settles", number(*.change), number(*.tolerance)
    )]
    NoPeriodicOrbit {
        /// The record's label.
        record: String,
        /// The window, numbered from 1.
        window: usize,
        /// The term kind and element (`bouc_wen [1-2]`).
        term: String,
        /// Passes made.
        passes: usize,
        /// Largest change of the state over the last pass.
        change: f64,
        /// The change accepted.
        tolerance: f64,
    },

    /// Every column of the regressor is zero: no coefficient changes the fit, so
    /// none can be estimated.
    #[error("these data carry no information on {coefficients}: {reason}")]
    NoInformation {
        /// The coefficients, by name (`c[1], c[2] and d`).
        coefficients: String,
        /// Why, and what would fix it.
        reason: String,
    },

    /// Linear constraints that, with the bounds, no set of coefficients can meet.
    #[error(
        "the constraints admit no coefficients: {constraints} (with the bounds); remove or relax one"
    )]
    InfeasibleConstraints {
        /// The linear constraints, as written.
        constraints: String,
    },

    /// An input asks for more memory than the limit (the available memory, or
    /// `--max-memory`), checked before allocating it, or for more time than the time
    /// limit (a day unless lifted), estimated from a measured rate.
    #[error("{what} needs {needed}, beyond the limit of {limit}: {reduce}")]
    TooLarge {
        /// What would be allocated or run.
        what: String,
        /// How much, readable (`8.0 GB`, `3.2 years`).
        needed: String,
        /// The limit, readable.
        limit: String,
        /// What to reduce.
        reduce: String,
    },

    /// An output file is already there, and the caller did not ask to replace it.
    #[error("will not write '{path}': {reason}")]
    OutputExists {
        /// The file.
        path: String,
        /// What is there, and how to replace it.
        reason: String,
    },

    /// Long work stopped at a check between steps because cancellation was requested
    /// (Ctrl-C in the command line; [`crate::cancel::request`]). No result, and no
    /// output file, is produced.
    #[error("cancelled: {what} stopped before it finished; nothing was written")]
    Cancelled {
        /// The work that stopped (`the simulation`, `the bootstrap`).
        what: String,
    },

    /// Writing an output file failed (its temporary file is removed, the target is
    /// left as it was).
    #[error("could not write '{path}': {message}")]
    Output {
        /// The file.
        path: String,
        /// The system's message.
        message: String,
    },

    /// The input work is negative beyond its noise in some records or sweeps, or over
    /// all of them ([`crate::regressor::passive`]): a passive structure cannot give out
    /// energy over whole periods, so a sign, a DOF or a phase convention is wrong, and
    /// a fit would return a confident wrong answer (every coefficient zero at its
    /// bound, or a term compensating the error).
    #[error(
        "input work negative beyond its noise in {} of {total} {unit}s{}: {} of the input work |b| is negative; {reason}",
        .groups.len(), groups_text(.groups), percent(*.share)
    )]
    NegativeInputWork {
        /// `record` or `sweep`.
        unit: String,
        /// Each record or sweep whose net input work is negative beyond its noise, with
        /// its net work as a share of its gross work (`'a=0.5' (net −0.99 of gross)`).
        groups: Vec<String>,
        /// How many records or sweeps there are.
        total: usize,
        /// Σ_{b<0} |b| / Σ |b| over every equation.
        share: f64,
        /// The rule that fired, the likely causes and how to proceed anyway.
        reason: String,
    },

    /// A motion channel never moves in a record while other DOFs do
    /// ([`crate::regressor::dead_motion`]): a dead or unplugged sensor, or a column of
    /// zeros, read as a DOF that stands still, biases every term on that DOF.
    #[error(
        "record '{record}', {sensor} channel of DOF {dof}: never moves ({reason}); check the sensor and its column in the model file, or declare the DOF held still with `fixed_dofs = [{dof}]` in the record"
    )]
    DeadMotionSensor {
        /// The record's label.
        record: String,
        /// The DOF, numbered from 1.
        dof: usize,
        /// `displacement`, `velocity` or `acceleration`.
        sensor: String,
        /// What was found (its range against the other channels').
        reason: String,
    },

    /// A record's signal is too large or too small for double precision to carry its
    /// products through the energy balance ([`crate::prep::data_scale`]).
    #[error(
        "record '{record}': the largest {signal} is {}, {reason}; give the data in other units: multiply the `scale` of its {signal} channels in the model file by about 1e{factor_exponent} (every coefficient then scales with them)", number(*.magnitude)
    )]
    DataScale {
        /// The record's label.
        record: String,
        /// `displacement`, `velocity` or `force`.
        signal: String,
        /// Its largest magnitude, in the record's units.
        magnitude: f64,
        /// Which product leaves double precision.
        reason: String,
        /// The power of ten that brings that product to order one.
        factor_exponent: i32,
    },

    /// Jobs whose backbones cannot be put side by side ([`crate::analysis::backbones`]):
    /// not one mode, or amplitudes or frequencies in different units.
    #[error("cannot compare the backbones of {files}: {what}: {reason}")]
    Incomparable {
        /// The model files concerned (one, or two joined by "and").
        files: String,
        /// What does not fit, with its value in each file (e.g. "`[units]` length 'm'
        /// and 'mm'").
        what: String,
        /// Why they cannot be compared, and what would fit.
        reason: String,
    },
}

/// ` ('a' (…), 'b' (…))`, at most eight named, for [`Error::NegativeInputWork`].
fn groups_text(groups: &[String]) -> String {
    const SHOWN: usize = 8;
    if groups.is_empty() {
        return String::new();
    }
    let mut text = groups
        .iter()
        .take(SHOWN)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if groups.len() > SHOWN {
        text.push_str(&format!(" and {} more", groups.len() - SHOWN));
    }
    format!(" ({text})")
}

/// `12.5%`.
fn percent(share: f64) -> String {
    format!("{:.1}%", 100.0 * share)
}

/// `, window k` for an error about one window.
/// `file:line:column`, or `file` alone when the problem has no position (line 0), never
/// `file:0:0`.
fn position_text(file: &str, line: usize, column: usize) -> String {
    match (line, column) {
        (0, _) => file.to_string(),
        (line, 0) => format!("{file}:{line}"),
        (line, column) => format!("{file}:{line}:{column}"),
    }
}

/// `file, row R, column 'C'`, leaving out the row of a problem with the header or the
/// file as a whole (row 0) and an empty column.
fn data_position_text(file: &str, row: usize, column: &str) -> String {
    let mut text = file.to_string();
    if row > 0 {
        text.push_str(&format!(", row {row}"));
    }
    if !column.is_empty() {
        text.push_str(&format!(", column '{column}'"));
    }
    text
}

/// The names a list of known names holds, for a message: `(none)` for an empty list,
/// the first [`KNOWN_SHOWN`] and how many more for a long one (a CSV header of 300,000
/// columns is not a message).
fn known_text(known: &str) -> String {
    if known.trim().is_empty() {
        return "(none)".into();
    }
    let names: Vec<&str> = known.split(", ").collect();
    if names.len() <= KNOWN_SHOWN {
        return known.to_string();
    }
    format!(
        "{}, … and {} more",
        names[..KNOWN_SHOWN].join(", "),
        integer(names.len() as u128 - KNOWN_SHOWN as u128)
    )
}

/// Known names shown in an [`Error::UnknownName`] message at most.
const KNOWN_SHOWN: usize = 40;

fn window_text(window: &Option<usize>) -> String {
    window.map_or_else(String::new, |w| format!(", window {w}"))
}

/// The name of every [`enum@Error`] variant, as [`Error::kind`] gives it.
pub const KINDS: &[&str] = &[
    "non_finite",
    "dimension_mismatch",
    "invalid_parameter",
    "invalid_choice",
    "missing",
    "record_too_short",
    "too_few_equations",
    "dof_out_of_range",
    "empty",
    "motion_sensors",
    "duplicate_coefficient",
    "unknown_coefficient",
    "infeasible_bounds",
    "missing_velocities",
    "expression",
    "model_file",
    "unknown_name",
    "data",
    "time_jitter",
    "numerical",
    "no_period",
    "not_steady",
    "no_input_work",
    "no_information",
    "no_periodic_orbit",
    "infeasible_constraints",
    "too_large",
    "output_exists",
    "cancelled",
    "output",
    "negative_input_work",
    "dead_motion_sensor",
    "data_scale",
    "incomparable",
];

impl Error {
    /// The variant's name in snake case (one of [`KINDS`]), for tests and programs
    /// that sort errors without matching every variant.
    pub fn kind(&self) -> &'static str {
        match self {
            Error::NonFinite { .. } => "non_finite",
            Error::DimensionMismatch { .. } => "dimension_mismatch",
            Error::InvalidParameter { .. } => "invalid_parameter",
            Error::InvalidChoice { .. } => "invalid_choice",
            Error::Missing { .. } => "missing",
            Error::RecordTooShort { .. } => "record_too_short",
            Error::TooFewEquations { .. } => "too_few_equations",
            Error::DofOutOfRange { .. } => "dof_out_of_range",
            Error::Empty { .. } => "empty",
            Error::MotionSensors { .. } => "motion_sensors",
            Error::DuplicateCoefficient { .. } => "duplicate_coefficient",
            Error::UnknownCoefficient { .. } => "unknown_coefficient",
            Error::InfeasibleBounds { .. } => "infeasible_bounds",
            Error::MissingVelocities { .. } => "missing_velocities",
            Error::Expression { .. } => "expression",
            Error::ModelFile { .. } => "model_file",
            Error::UnknownName { .. } => "unknown_name",
            Error::Data { .. } => "data",
            Error::TimeJitter { .. } => "time_jitter",
            Error::Numerical { .. } => "numerical",
            Error::NoPeriod { .. } => "no_period",
            Error::NotSteady { .. } => "not_steady",
            Error::NoInputWork { .. } => "no_input_work",
            Error::NoInformation { .. } => "no_information",
            Error::NoPeriodicOrbit { .. } => "no_periodic_orbit",
            Error::InfeasibleConstraints { .. } => "infeasible_constraints",
            Error::TooLarge { .. } => "too_large",
            Error::OutputExists { .. } => "output_exists",
            Error::Cancelled { .. } => "cancelled",
            Error::Output { .. } => "output",
            Error::NegativeInputWork { .. } => "negative_input_work",
            Error::DeadMotionSensor { .. } => "dead_motion_sensor",
            Error::DataScale { .. } => "data_scale",
            Error::Incomparable { .. } => "incomparable",
        }
    }

    /// For a model-file error, the typed error behind it; else this error itself.
    pub fn innermost(&self) -> &Error {
        match self {
            Error::ModelFile {
                cause: Some(cause), ..
            } => cause.innermost(),
            other => other,
        }
    }

    pub(crate) fn choice(name: &str, given: impl std::fmt::Display, reason: &str) -> Self {
        Error::InvalidChoice {
            name: name.to_string(),
            given: given.to_string(),
            reason: reason.to_string(),
        }
    }

    pub(crate) fn missing(name: impl Into<String>, reason: &str) -> Self {
        Error::Missing {
            name: name.into(),
            reason: reason.to_string(),
        }
    }

    /// A DOF out of range given as a 0-based `index` (reported 1-based) of `dofs`.
    pub(crate) fn dof_index(what: impl Into<String>, index: usize, dofs: usize) -> Self {
        Error::DofOutOfRange {
            what: what.into(),
            dof: index.saturating_add(1),
            dofs,
        }
    }

    pub(crate) fn invalid(name: &str, value: f64, reason: &str) -> Self {
        Error::InvalidParameter {
            name: name.to_string(),
            value,
            reason: reason.to_string(),
        }
    }

    pub(crate) fn mismatch(what: impl Into<String>, expected: usize, found: usize) -> Self {
        Error::DimensionMismatch {
            what: what.into(),
            expected,
            found,
        }
    }
}

/// Checks that every entry of a column-major matrix is finite.
pub(crate) fn check_finite(what: &str, m: faer::MatRef<'_, f64>) -> Result<()> {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let value = m[(i, j)];
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: what.to_string(),
                    row: i,
                    column: j,
                    value,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// KINDS lists every variant once: a new variant that is not added there fails to
    /// compile in `kind` (the match is exhaustive here, inside the crate) or fails
    /// this test.
    #[test]
    fn kinds_name_every_variant_once() {
        let mut kinds = KINDS.to_vec();
        kinds.sort_unstable();
        kinds.dedup();
        assert_eq!(kinds.len(), KINDS.len());
        let examples = [
            Error::invalid("x", 1.0, "r"),
            Error::choice("x", "y", "r"),
            Error::missing("x", "r"),
            Error::dof_index("x", 0, 1),
        ];
        for e in &examples {
            assert!(KINDS.contains(&e.kind()), "{e:?}");
        }
    }

    /// DOFs are reported 1-based: index 0 is DOF 1.
    #[test]
    fn dof_index_is_reported_from_one() {
        let e = Error::dof_index("force", 4, 4);
        assert!(matches!(
            e,
            Error::DofOutOfRange {
                dof: 5,
                dofs: 4,
                ..
            }
        ));
        assert_eq!(
            e.to_string(),
            "force refers to DOF 5, but DOFs are numbered 1..4"
        );
    }
}
