//! Model files: one TOML file describes the damping model (terms on elements or
//! matrices, shared or per-element coefficients, custom laws as expressions), how to
//! identify (windows, quadrature, velocity source, constraints), and where the records
//! come from: a `[simulation]` section that generates them (so a model file runs on a
//! fresh machine) or a `[data]` section that reads measured CSV files.
//!
//! A law term names its law, `law = "power"`, in a law registry
//! ([`crate::terms::laws::Registry`]): the built-in laws for [`load`] and [`parse`],
//! or a registry extended with a program's own laws for [`parse_with_laws`].
//!
//! Errors carry the file and the line and column of the offending table or key.

mod context;
mod job;
mod measured;
mod provenance;
mod records;
mod reduction;
mod settings;
pub use settings::PERIODIC_ONLY;
mod spec;
mod string;
mod summary;
mod terms;

use std::path::Path;

pub use job::Job;
pub use measured::{ChannelGain, RecordInputs};
pub use spec::*;
pub use summary::{CheckReport, DetectedPeriod, JitteredTime, NOTED_JITTER, Periods, Preamble};

use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::terms::laws::Registry;
use context::Context;

/// Reads and builds the model file at `path` (data paths are relative to its folder).
pub fn load(path: &Path) -> Result<Job> {
    load_with_progress(path, &crate::progress::silent)
}

/// [`load`], reporting the progress of simulating or reading the records.
pub fn load_with_progress(path: &Path, progress: Progress<'_>) -> Result<Job> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::ModelFile {
        file: path.display().to_string(),
        line: 0,
        column: 0,
        message: e.to_string(),
        cause: None,
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse_with_progress(&text, &path.display().to_string(), base, progress)
}

/// Parses model-file `text` (named `file` in errors) and builds the job.
pub fn parse(text: &str, file: &str, base: &Path) -> Result<Job> {
    parse_with_progress(text, file, base, &crate::progress::silent)
}

/// [`parse`] with the laws of `laws` instead of the built-in ones, so that
/// `law = "..."` may name a law the program registered
/// (`Registry::builtin().with(MY_LAW)`).
pub fn parse_with_laws(text: &str, file: &str, base: &Path, laws: &Registry) -> Result<Job> {
    parse_with(text, file, base, laws, &crate::progress::silent)
}

/// [`parse`], reporting the progress of simulating or reading the records.
pub fn parse_with_progress(
    text: &str,
    file: &str,
    base: &Path,
    progress: Progress<'_>,
) -> Result<Job> {
    parse_with(text, file, base, &Registry::builtin(), progress)
}

fn parse_with(
    text: &str,
    file: &str,
    base: &Path,
    laws: &Registry,
    progress: Progress<'_>,
) -> Result<Job> {
    let context = Context { file, text };
    let spec: ModelFileSpec = toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map_or((0, 0), |s| context.position(s.start));
        Error::ModelFile {
            file: file.to_string(),
            line,
            column,
            message: e.message().to_string(),
            cause: None,
        }
    })?;
    context.build(&spec, base, laws, progress)
}
