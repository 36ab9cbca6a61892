//! Typed errors. Every variant carries the data that explains it: the field, the
//! offending value, and what was expected. The library never panics on bad input and
//! never returns a number it could not compute honestly.

use thiserror::Error;

/// Result alias used throughout dampid.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong between records and a fit report.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A value that must be finite is NaN or infinite.
    #[error("{what} has a non-finite value {value} at row {row}, column {column}")]
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
    #[error("invalid {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name (e.g. "step", "period", "exponent").
        name: String,
        /// The value given.
        value: f64,
        /// Why it is rejected.
        reason: String,
    },

    /// A record holds fewer samples than the requested windows need.
    #[error(
        "record '{record}' is too short: the windows need {needed} samples, it has {available}"
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

    /// A DOF index is out of range for the record or system.
    #[error("{what} refers to DOF {dof} (0-based), but there are only {dofs} DOFs")]
    DofOutOfRange {
        /// Which element, force or term.
        what: String,
        /// The offending index.
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
    #[error("infeasible bounds for '{name}': lower {lower} > upper {upper}")]
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
    #[error("{file}:{line}:{column}: {message}")]
    ModelFile {
        /// The file.
        file: String,
        /// 1-based line (0 when the problem has no position).
        line: usize,
        /// 1-based column (0 when the problem has no position).
        column: usize,
        /// What is wrong.
        message: String,
    },

    /// A name in a model file does not refer to anything known.
    #[error("unknown {what} '{name}'; known: {known}")]
    UnknownName {
        /// What kind of name ("law", "matrix", "column").
        what: String,
        /// The name given.
        name: String,
        /// The names that would be accepted.
        known: String,
    },

    /// A data file cannot be read or holds a bad value.
    #[error("{file}, row {row}, column '{column}': {message}")]
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

    /// A numerical step failed (a singular mass matrix, a failed decomposition).
    #[error("numerical failure in {stage}: {detail}")]
    Numerical {
        /// Which stage failed.
        stage: String,
        /// What happened.
        detail: String,
    },

    /// No driving period can be detected from a record's force signals.
    #[error("record '{record}': no driving period can be detected from the force: {reason}")]
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
        "record '{record}', window {window} (starting at t = {start_time}): not in steady state: {measure} {mismatch:.3e} exceeds {threshold:.3e}; skip more of the transient, or accept it"
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
}

impl Error {
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
