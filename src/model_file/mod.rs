//! Model files: one TOML file describes the damping model (terms on elements or
//! matrices, shared or per-element coefficients, custom laws as expressions), how to
//! identify (windows, quadrature, velocity source, constraints), and where the records
//! come from: a `[simulation]` section that generates them (so a model file runs on a
//! fresh machine) or a `[data]` section that reads measured CSV files.
//!
//! A law term names its law, `law = "power"`, in a law registry
//! ([`crate::terms::laws::Registry`]): the built-in laws, or a registry extended with a
//! program's own laws ([`Options::laws`] of [`load`] and [`parse`]).
//!
//! Errors carry the file and the line and column of the offending table or key: the
//! settings are checked against the model before any record is simulated or read
//! (`preflight.rs`), and an error without a position gets the one of the key it
//! concerns (`locate.rs`).
//!
//! [`candidate_model`] builds the candidate models of `dampid compare --laws`.
//!
//! [`init`] writes a first, annotated model file from data files or from nothing
//! (`dampid init`); docs/model-file.md is the reference of every key.

mod candidates;
mod compared;
pub use compared::ComparedModel;
mod context;
mod free_decay;
pub use free_decay::free_decay_identification;
pub mod init;
mod job;
mod keep;
mod locate;
mod measured;
mod preflight;
mod provenance;
mod records;
mod reduction;
mod settings;
pub use settings::{
    IDENTIFICATION_KEYS, PERIODIC_ONLY, identification, non_periodic_identification,
};
mod spec;
mod stepped_sine;
mod string;
pub(crate) mod summary;
mod terms;

use std::path::Path;

pub use candidates::{ESTIMATED_EXPONENT, candidate, candidate_model};
pub use job::Job;
pub use measured::{ChannelGain, RecordInputs};
pub use provenance::settings_in_effect;
pub use spec::*;
pub use summary::{
    DetectedPeriod, JitteredTime, NOTED_JITTER, Periods, Preamble, SteppedSineSummary,
};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::regressor::ParametricModel;
use crate::terms::laws::Registry;
use context::Context;

/// How a model file is read: with the built-in laws or a program's own registry, and a
/// progress callback over simulating or reading its records.
#[derive(Clone, Copy)]
pub struct Options<'a> {
    /// The laws `law = "..."` may name (`None`: the built-in ones,
    /// [`Registry::builtin`]); a program adds its own with
    /// `Registry::builtin().with(MY_LAW)`.
    pub laws: Option<&'a Registry>,
    /// `progress(done, total)` in records simulated or read.
    pub progress: Progress<'a>,
}

impl Default for Options<'_> {
    fn default() -> Self {
        Options {
            laws: None,
            progress: &crate::progress::silent,
        }
    }
}

impl std::fmt::Debug for Options<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Options")
            .field("laws", &self.laws.map(|_| "custom"))
            .finish_non_exhaustive()
    }
}

/// Reads and builds the model file at `path` (data paths are relative to its folder).
pub fn load(path: &Path, options: Options<'_>) -> Result<Job> {
    let text = read(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse(&text, &path.display().to_string(), base, options)
}

/// Parses model-file `text` (named `file` in errors, data paths relative to `base`) and
/// builds the job.
pub fn parse(text: &str, file: &str, base: &Path, options: Options<'_>) -> Result<Job> {
    let context = Context { file, text };
    let spec = parse_spec(text, file)?;
    let builtin;
    let laws = match options.laws {
        Some(laws) => laws,
        None => {
            builtin = Registry::builtin();
            &builtin
        }
    };
    preflight::model(&context, &spec)?;
    preflight::settings(&context, &spec, laws)?;
    context
        .build(&spec, base, laws, options.progress)
        .map_err(|e| context.located(e, None))
}

/// The damping model of the model file at `path` alone (`dofs`, `[matrices]` and
/// `[[terms]]`): its records, if it has any, are neither simulated nor read, so a file
/// of terms only is enough (`dampid compare`'s second model).
pub fn load_model(path: &Path) -> Result<DampingModel> {
    let text = read(path)?;
    parse_model(&text, &path.display().to_string())
}

/// [`load_model`] of model-file `text` (named `file` in errors).
pub fn parse_model(text: &str, file: &str) -> Result<DampingModel> {
    // Estimated parameters stand at their initial values in a terms-only model.
    parse_parametric_model(text, file).map(|(model, _)| model)
}

/// [`load_model`] with the file's estimated law parameters, if it has any: the model
/// at their initial values and the [`ParametricModel`] that builds it at others
/// (`dampid compare` estimates them on the first file's records).
pub fn load_parametric_model(path: &Path) -> Result<(DampingModel, ParametricModel)> {
    let text = read(path)?;
    parse_parametric_model(&text, &path.display().to_string())
}

/// [`load_parametric_model`] of model-file `text` (named `file` in errors).
pub fn parse_parametric_model(text: &str, file: &str) -> Result<(DampingModel, ParametricModel)> {
    let context = Context { file, text };
    let spec = parse_spec(text, file)?;
    preflight::model(&context, &spec)?;
    context
        .damping_model(&spec, &Registry::builtin())
        .map_err(|e| context.located(e, None))
}

/// The text of the model file at `path`: a regular file (not a FIFO, which would wait
/// for a writer, nor a device such as `/dev/zero`, which never ends) within the memory
/// budget, as data files are checked ([`crate::io::require_data_file`]), and UTF-8.
fn read(path: &Path) -> Result<String> {
    let file = path.display().to_string();
    let error = |message: String| Error::ModelFile {
        file: file.clone(),
        line: 0,
        column: 0,
        message,
        cause: None,
    };
    crate::io::regular_file(
        path,
        "model file",
        "a model file is read from a file (TOML text)",
    )
    .map_err(error)??;
    let bytes = std::fs::read(path).map_err(|e| error(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let text = String::from_utf8_lossy(&e.as_bytes()[..at]);
        let line = text.matches('\n').count() + 1;
        let column = text.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Error::ModelFile {
            file: file.clone(),
            line,
            column,
            message: format!(
                "byte {at} is not UTF-8 text (byte 0x{:02x}): save the model file as UTF-8 (a Latin-1 or Windows-1252 file shows this at its first accented letter)",
                e.as_bytes().get(at).copied().unwrap_or_default()
            ),
            cause: None,
        }
    })
}

/// The serde form of `text`; a TOML or schema error carries its line and column. The
/// title and the records' labels, which reports print, have their control characters
/// (an ANSI escape, a bell, a carriage return) escaped ([`crate::format::printable`]).
fn parse_spec(text: &str, file: &str) -> Result<ModelFileSpec> {
    let mut spec = read_spec(text, file)?;
    let printable = |s: &mut String| *s = crate::format::printable(s).into_owned();
    if let Some(title) = spec.title.as_mut() {
        printable(title);
    }
    for data in spec.data.iter_mut() {
        for record in data.get_mut().records.iter_mut() {
            if let Some(label) = record.get_mut().label.as_mut() {
                printable(label);
            }
        }
    }
    Ok(spec)
}

fn read_spec(text: &str, file: &str) -> Result<ModelFileSpec> {
    let context = Context { file, text };
    toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map_or((0, 0), |s| context.position(s.start));
        Error::ModelFile {
            file: file.to_string(),
            line,
            column,
            message: e.message().to_string(),
            cause: None,
        }
    })
}
