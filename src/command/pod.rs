//! `dampid pod FILES`: the proper orthogonal modes of the columns of record files, with
//! their energy shares ([`crate::io::pod_files`]).

use std::fmt;
use std::path::PathBuf;

use serde::Serialize;

use super::Outcome;
use crate::error::Result;
use crate::io::pod_files::{Columns, FilePod, PodTables, pod_of_files};
use crate::prep::pod::PodSettings;

/// The decomposition of each file (or of all stacked).
#[derive(Debug, Clone, Serialize)]
pub struct Decompositions {
    /// One per file, or one for all with a shared basis.
    pub decompositions: Vec<FilePod>,
}

/// The POD of the `columns` of `files` with `settings`.
pub fn run(files: &[PathBuf], columns: &Columns, settings: &PodSettings) -> Result<Decompositions> {
    Ok(Decompositions {
        decompositions: pod_of_files(files, columns, settings)?,
    })
}

impl fmt::Display for Decompositions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", PodTables(&self.decompositions))
    }
}

impl Outcome for Decompositions {}
