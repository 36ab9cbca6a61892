//! Reading and writing files. Every measurement format becomes a [`Table`] of named
//! numeric columns, which model files refer to by name.
//!
//! | extension | reader | columns |
//! |---|---|---|
//! | `.csv` | [`csv::read`] | header names |
//! | `.npy` | [`npy::read_npy`] | the file stem (`x`, or `x[1]`…`x[k]` for N × k) |
//! | `.npz` | [`read_npz`] (`io/npz.rs`) | each array's name, as above |
//! | `.mat` | [`read_mat`] | each real numeric variable's name, as above; struct fields by MATLAB path (`s.a`, `s(2).b`) |
//! | `.uff`, `.unv` | [`uff::read`] | `t`, then per dataset 58 record `3+Z` (node, direction) and its ID line 1 |
//!
//! [`read_table`] reads a whole file; a model file's records go through
//! [`data_file::DataFiles`] instead, which opens each file once for all the records that
//! name it and reads from a `.npz` or `.mat` file only the arrays a record names.
//!
//! Other files: [`records`] writes records as CSV and [`run`] a simulation run's folder
//! with its manifest (`dampid simulate`), [`stepped_sine`]
//! reads and writes stepped-sine tables, [`pod_files`] runs the POD of record files
//! (`dampid pod`). Every file is written through [`output`]: complete or absent, and
//! never replacing an existing file unless asked to.

mod arrays;
pub mod csv;
mod csv_fast;
pub mod data_file;
pub(crate) mod fresh;
pub mod in_place;
pub mod mat;
pub mod npy;
mod npz;
pub mod output;
mod parts;
pub mod pod_files;
pub mod records;
pub mod run;
pub(crate) mod scatter;
pub mod stepped_sine;
pub mod table;
pub mod uff;

use std::path::Path;

use crate::error::{Error, Result};
pub use data_file::{read_mat, read_npz};
pub use table::Table;

/// Checks a data file before it is opened: it must be a regular file (symbolic links
/// followed), since opening a FIFO waits for a writer and a device such as `/dev/zero`
/// never ends, and its size must fit the memory budget
/// ([`crate::budget::require`]: readers hold at least the file's bytes or its values).
/// Returns the size in bytes; [`Error::Data`] naming the file, or [`Error::TooLarge`].
pub(crate) fn require_data_file(path: &Path) -> Result<u64> {
    let file = path.display().to_string();
    regular_file(path, "data file", "data are read only from files").map_err(|message| {
        Error::Data {
            file: file.clone(),
            row: 0,
            column: String::new(),
            message,
        }
    })?
}

/// The size of the regular file at `path` within the memory budget (the checks of
/// [`require_data_file`] for a file that is a `what`): `Err` is why it cannot be read,
/// in words; `Ok(Err)` is [`Error::TooLarge`].
pub(crate) fn regular_file(
    path: &Path,
    what: &str,
    why: &str,
) -> std::result::Result<Result<u64>, String> {
    let metadata = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !metadata.is_file() {
        let kind = if metadata.is_dir() {
            "a folder"
        } else {
            "a device, FIFO or socket"
        };
        return Err(format!("is {kind}, not a regular file: {why}"));
    }
    let bytes = metadata.len();
    Ok(crate::budget::require(
        &format!("reading the {what} {}", path.display()),
        u128::from(bytes),
        &format!("read a smaller {what}, or raise --max-memory"),
    )
    .map(|()| bytes))
}

/// Reads a data file by its extension: every column of it (every array of a `.npz`,
/// every real numeric variable of a `.mat`).
pub fn read_table(path: &Path) -> Result<Table> {
    data_file::DataFile::open(path)?.whole()
}

/// The formats read whole, and the error for an unknown extension; `.npz` and `.mat`
/// files are opened by [`data_file::DataFile::open`].
fn read_whole(path: &Path) -> Result<Table> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("csv") | Some("txt") => csv::read(path),
        Some("npy") => npy::read_npy(path),
        Some("uff") | Some("unv") => uff::read(path),
        other => Err(Error::Data {
            file: path.display().to_string(),
            row: 0,
            column: String::new(),
            message: format!(
                "unknown data format {other:?}: use .csv, .npy, .npz, .mat, .uff or .unv"
            ),
        }),
    }
}
