//! `dampid init [FILES] --out MODEL`: a first, annotated model file for data files (or a
//! template that runs as is), written without replacing an existing one unless asked
//! ([`crate::model_file::init`]).

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::Outcome;
use crate::error::{Error, Result};
use crate::io::output::{Overwrite, refuse_existing, write_file};
use crate::model_file::init::{InitModel, InitRecord, init, path_in_model};

/// The model file `dampid init` wrote.
#[derive(Debug, Clone, Serialize)]
pub struct Initialized {
    /// Where.
    pub file: PathBuf,
    /// What it holds.
    #[serde(skip)]
    pub model: InitModel,
    /// Temporary files of an interrupted run that the write removed.
    pub stale: Vec<PathBuf>,
}

/// Guesses a model file for the data `files` (none: the template) and writes it to
/// `out`.
pub fn run(files: &[PathBuf], out: &Path, overwrite: Overwrite) -> Result<Initialized> {
    // Refuse an existing model file before reading any data, and again at the rename.
    if overwrite == Overwrite::Refuse {
        refuse_existing(out)?;
    }
    let records = files
        .iter()
        .map(|file| {
            // Every column the file gives (as `identify` reads it by name); a MAT file's
            // variables and struct fields are listed in the model file's comments.
            let data = crate::io::data_file::DataFile::open(file)?;
            let contents = data.contents().map(<[_]>::to_vec);
            let (table, left_out) = data.usable()?;
            let mut record = InitRecord::guess(&path_in_model(file, out), &table);
            record.left_out = left_out;
            record.contents = contents.unwrap_or_default();
            Ok(record)
        })
        .collect::<Result<Vec<_>>>()?;
    let model = init(records);
    let stale = write_file(out, overwrite, |sink| {
        sink.write_all(model.text.as_bytes())
            .map_err(|e| Error::Output {
                path: out.display().to_string(),
                message: e.to_string(),
            })
    })?;
    Ok(Initialized {
        file: out.to_path_buf(),
        model,
        stale,
    })
}

impl fmt::Display for Initialized {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "wrote {}: {}next: dampid check {0}",
            self.file.display(),
            self.model
        )
    }
}

impl Outcome for Initialized {
    fn notices(&self) -> Vec<String> {
        self.stale.iter().map(|p| super::stale_notice(p)).collect()
    }
}
