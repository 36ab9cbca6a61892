//! Model files: one TOML file describes the damping model (terms on elements or
//! matrices, shared or per-element coefficients, custom laws as expressions), how to
//! identify (windows, quadrature, velocity source, constraints), and where the records
//! come from: a `[simulation]` section that generates them (so a model file runs on a
//! fresh machine) or a `[data]` section that reads measured CSV files.
//!
//! Errors carry the file and the line and column of the offending table or key.

mod context;
mod job;
mod records;
mod reduction;
mod settings;
mod spec;
mod string;
mod terms;

use std::path::Path;

pub use job::Job;
pub use spec::*;

use crate::error::{Error, Result};
use crate::progress::Progress;
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
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse_with_progress(&text, &path.display().to_string(), base, progress)
}

/// Parses model-file `text` (named `file` in errors) and builds the job.
pub fn parse(text: &str, file: &str, base: &Path) -> Result<Job> {
    parse_with_progress(text, file, base, &crate::progress::silent)
}

/// [`parse`], reporting the progress of simulating or reading the records.
pub fn parse_with_progress(
    text: &str,
    file: &str,
    base: &Path,
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
        }
    })?;
    context.build(&spec, base, progress)
}
