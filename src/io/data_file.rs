//! A data file opened once, and the columns a record names read from it.
//!
//! [`DataFile::open`] reads what a file's columns are: a CSV or UFF file is parsed
//! whole (its columns are one table), a `.npz` archive only its directory and each
//! array's header, a `.mat` file its variables. [`DataFile::table`] gives the table of
//! the columns asked for: from a `.npz` or `.mat` file only the arrays holding them are
//! read, so the file may hold others that cannot be columns (a 0-d text description,
//! a 3-D array, a scalar gain of another length), and only the arrays asked for must
//! be valid and of one length. [`DataFile::whole`] is the whole-file read of
//! [`super::read_table`]: every array (complex and N-D MAT variables are skipped, as
//! before).
//!
//! The arrays of one table are read in parallel (rayon), each in one pass.
//!
//! [`DataFiles`] opens each file a job names once, however many records name it
//! (files are told apart by their canonical path), and lets go of it after its last
//! record.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io::arrays::{self, NamedArray, table_from_arrays, without_scalars};
use crate::io::in_place::InPlace;
use crate::io::mat;
use crate::io::npy::{Header, data_error};
use crate::io::npz::Npz;
use crate::io::table::Table;

/// Where an array's data come from.
enum Source {
    /// Member `k` of the archive.
    Npz(usize),
    /// Column-major values, r × c.
    Mat(usize, usize, Vec<f64>),
}

/// One array: the columns it offers, or why it cannot be columns.
struct Slot {
    name: String,
    columns: std::result::Result<(Vec<String>, Source), String>,
    /// Whether the whole-file read refuses the file for this slot's problem (NPZ) or
    /// skips it (MAT, as the MAT reader always did).
    strict: bool,
}

enum Content {
    /// Read whole (CSV, UFF, NPY).
    Table(Table),
    /// Arrays read on demand (NPZ, MAT).
    Arrays { slots: Vec<Slot>, npz: Option<Npz> },
}

/// Reads the real numeric variables of a `.mat` file (`io/mat.rs`); every one must have
/// the same number of samples.
pub fn read_mat(path: &Path) -> Result<Table> {
    DataFile::open(path)?.whole()
}

/// Reads every array of a `.npz` archive (`io/npz.rs`); each must be usable.
pub fn read_npz(path: &Path) -> Result<Table> {
    DataFile::open(path)?.whole()
}

/// A data file opened once (module doc).
pub struct DataFile {
    file: String,
    content: Content,
    /// What a MAT file holds (named in the error for a column that is not there, or
    /// for a file with no numeric arrays).
    contents: Option<Vec<mat::Entry>>,
}

impl DataFile {
    /// Opens the data file at `path` by its extension (see [`super::read_table`]).
    pub fn open(path: &Path) -> Result<DataFile> {
        super::require_data_file(path)?;
        let file = path.display().to_string();
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let mut contents = None;
        let content = match extension.as_deref() {
            Some("npz") => {
                let npz = Npz::open(path)?;
                let slots = npz
                    .members
                    .iter()
                    .enumerate()
                    .map(|(k, m)| Slot {
                        name: m.name.clone(),
                        columns: m
                            .header
                            .as_ref()
                            .map(|h: &Header| (h.layout.headers(&m.name), Source::Npz(k)))
                            .map_err(Clone::clone),
                        strict: true,
                    })
                    .collect();
                Content::Arrays {
                    slots,
                    npz: Some(npz),
                }
            }
            Some("mat") => {
                let read = mat::variables(path)?;
                contents = Some(read.contents);
                let slots = read
                    .variables
                    .into_iter()
                    .map(|v| {
                        let columns = v.values.and_then(|(r, c, values)| {
                            let layout = arrays::Layout::new(r, c, false)
                                .filter(|l| l.elements() == values.len())
                                .ok_or_else(|| format!("{r} × {c} with {} values", values.len()))?;
                            Ok((layout.headers(&v.name), Source::Mat(r, c, values)))
                        });
                        Slot {
                            name: v.name,
                            columns,
                            strict: false,
                        }
                    })
                    .collect();
                Content::Arrays { slots, npz: None }
            }
            _ => Content::Table(super::read_whole(path)?),
        };
        Ok(DataFile {
            file,
            content,
            contents,
        })
    }

    /// The file, as error messages name it.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The table of the columns `names` (module doc): the arrays that hold them, all of
    /// one length. A name that no column has is [`Error::UnknownName`]; a name of an
    /// array that cannot be columns is [`Error::Data`] naming it and why.
    pub fn table(&self, names: &[&str]) -> Result<Table> {
        match &self.content {
            Content::Table(table) => {
                let mut headers: Vec<String> = Vec::new();
                let mut columns = Vec::new();
                for name in names {
                    if headers.iter().any(|h| h == name) {
                        continue;
                    }
                    columns.push(table.column(name)?.to_vec());
                    headers.push(name.to_string());
                }
                Ok(Table {
                    file: table.file.clone(),
                    headers,
                    columns,
                })
            }
            Content::Arrays { slots, npz } => {
                let mut chosen: Vec<usize> = Vec::new();
                for name in names {
                    let k = self.slot_of(slots, name)?;
                    if !chosen.contains(&k) {
                        chosen.push(k);
                    }
                }
                let arrays = chosen
                    .into_par_iter()
                    .map(|k| self.read(&slots[k], npz.as_ref()))
                    .collect::<Vec<_>>() // the first error in order, whichever thread saw it first
                    .into_iter()
                    .collect::<Result<Vec<_>>>()?;
                table_from_arrays(&self.file, arrays)
            }
        }
    }

    /// [`DataFile::table`] of the columns `names`, less the arrays left in the file to
    /// be read into place ([`super::in_place`]): each stored `.npz` member whose every
    /// column among `names` is one of `in_place`. Every name is looked up first (the
    /// errors of `table`, in the order of `names`), the other arrays are read, and then
    /// every array asked for must have the same samples (the error of
    /// `table_from_arrays`). Other formats give the whole table and nothing in place.
    pub fn columns(&self, names: &[&str], in_place: &[&str]) -> Result<(Table, InPlace)> {
        let (slots, npz) = match &self.content {
            Content::Arrays {
                slots,
                npz: Some(npz),
            } if !in_place.is_empty() => (slots, npz),
            _ => return Ok((self.table(names)?, InPlace::default())),
        };
        let mut of_name = Vec::with_capacity(names.len());
        let mut chosen: Vec<usize> = Vec::new();
        for name in names {
            let k = self.slot_of(slots, name)?;
            of_name.push(k);
            if !chosen.contains(&k) {
                chosen.push(k);
            }
        }
        // The member of each chosen slot that is read into place.
        let placed = |k: usize| match &slots[k].columns {
            Ok((_, Source::Npz(m)))
                if Npz::can_read_into(&npz.members[*m])
                    && names
                        .iter()
                        .zip(&of_name)
                        .all(|(name, &of)| of != k || in_place.contains(name)) =>
            {
                Some(*m)
            }
            _ => None,
        };
        let arrays = chosen
            .iter()
            .filter(|&&k| placed(k).is_none())
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|&k| self.read(&slots[k], Some(npz)))
            .collect::<Vec<_>>() // the first error in order, whichever thread saw it first
            .into_iter()
            .collect::<Result<Vec<_>>>()?;
        // Every column asked for, in the order of `chosen`, with its samples: of one
        // length, as `table_from_arrays` requires of a table.
        let mut read = arrays.iter();
        let mut lengths: Vec<(String, usize)> = Vec::new();
        let mut members = Vec::new();
        for &k in &chosen {
            match (placed(k), &slots[k].columns) {
                (Some(m), Ok((headers, _))) => {
                    let samples = npz.members[m]
                        .header
                        .as_ref()
                        .map_or(0, |h| h.layout.samples);
                    lengths.extend(headers.iter().map(|h| (h.clone(), samples)));
                    members.push((m, headers.clone()));
                }
                _ => {
                    if let Some(array) = read.next() {
                        let k = array.columns.len();
                        lengths.extend(array.columns.iter().enumerate().map(|(j, c)| {
                            let header = match k {
                                1 => array.name.clone(),
                                _ => format!("{}[{}]", array.name, j + 1),
                            };
                            (header, c.len())
                        }));
                    }
                }
            }
        }
        let Some((first, rows)) = lengths.first().cloned() else {
            // No columns: the error of an empty table.
            return Ok((table_from_arrays(&self.file, arrays)?, InPlace::default()));
        };
        if let Some((column, n)) = lengths.iter().find(|(_, n)| *n != rows) {
            return Err(Error::Data {
                file: self.file.clone(),
                row: 0,
                column: column.clone(),
                message: format!("{n} samples, but '{first}' has {rows}"),
            });
        }
        let table = if arrays.is_empty() {
            Table {
                file: self.file.clone(),
                headers: Vec::new(),
                columns: Vec::new(),
            }
        } else {
            table_from_arrays(&self.file, arrays)?
        };
        Ok((table, InPlace::new(npz, members, rows)))
    }

    /// Every column of the file: the whole-file read ([`super::read_table`]).
    pub fn whole(self) -> Result<Table> {
        match self.content {
            Content::Table(table) => Ok(table),
            Content::Arrays { slots, npz } => {
                if let Some(slot) = slots.iter().find(|s| s.strict && s.columns.is_err())
                    && let Err(problem) = &slot.columns
                {
                    return Err(data_error(&self.file, &slot.name, problem));
                }
                let arrays = slots
                    .par_iter()
                    .filter(|s| s.columns.is_ok())
                    .map(|slot| read_slot(&self.file, slot, npz.as_ref()))
                    .collect::<Vec<_>>() // the first error in order, whichever thread saw it first
                    .into_iter()
                    .collect::<Result<Vec<_>>>()?;
                if let (true, Some(contents)) = (arrays.is_empty(), &self.contents) {
                    return Err(Error::Data {
                        file: self.file.clone(),
                        row: 0,
                        column: String::new(),
                        message: format!(
                            "no numeric arrays to read: the file holds {}; {}",
                            mat::holds(contents),
                            mat::SUPPORTED
                        ),
                    });
                }
                // Scalars beside the signals (gains) are not columns of the whole table.
                table_from_arrays(&self.file, without_scalars(arrays))
            }
        }
    }

    /// What a MAT file holds (every variable, struct and field by path); `None` for
    /// other formats.
    pub fn contents(&self) -> Option<&[mat::Entry]> {
        self.contents.as_deref()
    }

    /// Every column the file can give, for `dampid init` and `dampid pod`, which read
    /// files whole: what [`DataFile::whole`] reads, except that arrays that cannot be
    /// columns are skipped in every format, as are arrays that do not read (a
    /// non-finite value), scalars beside signals, and, when the rest differ in length,
    /// those shorter than the longest (a file that holds several tables, such as a MAT
    /// file of structs). So every file whose columns `identify` reads by name is read
    /// here. Returns the table and what was left out, each with why.
    pub fn usable(self) -> Result<(Table, Vec<String>)> {
        let (slots, npz) = match self.content {
            Content::Table(table) => return Ok((table, Vec::new())),
            Content::Arrays { slots, npz } => (slots, npz),
        };
        let mut left_out = Vec::new();
        let mut arrays = Vec::new();
        for (slot, read) in slots.iter().zip(
            slots
                .par_iter()
                .map(|slot| read_slot(&self.file, slot, npz.as_ref()))
                .collect::<Vec<_>>(),
        ) {
            match (&slot.columns, read) {
                (Err(why), _) => left_out.push(format!("{} ({why})", slot.name)),
                (Ok(_), Err(e)) => left_out.push(format!("{} ({e})", slot.name)),
                (Ok(_), Ok(array)) => arrays.push(array),
            }
        }
        // The longest arrays are the table (scalars beside signals are the shortest).
        let length = |a: &NamedArray| a.columns.first().map_or(0, Vec::len);
        let longest = arrays.iter().map(length).max().unwrap_or(0);
        let (kept, shorter): (Vec<NamedArray>, Vec<NamedArray>) =
            arrays.into_iter().partition(|a| length(a) == longest);
        for a in &shorter {
            left_out.push(match length(a) {
                1 => format!("{} (a scalar)", a.name),
                n => format!(
                    "{} ({n} samples; the longest arrays have {longest})",
                    a.name
                ),
            });
        }
        if let (true, Some(contents)) = (kept.is_empty(), &self.contents) {
            return Err(Error::Data {
                file: self.file.clone(),
                row: 0,
                column: String::new(),
                message: format!(
                    "no numeric arrays to read: the file holds {}; {}",
                    mat::holds(contents),
                    mat::SUPPORTED
                ),
            });
        }
        Ok((table_from_arrays(&self.file, kept)?, left_out))
    }

    /// The slot that holds the column `name`: an exact column name, or an unusable
    /// array's name (`x`, `x[2]`).
    fn slot_of(&self, slots: &[Slot], name: &str) -> Result<usize> {
        if let Some(k) = slots.iter().position(
            |s| matches!(&s.columns, Ok((headers, _)) if headers.iter().any(|h| h == name)),
        ) {
            return Ok(k);
        }
        let array = name.split_once('[').map_or(name, |(array, _)| array);
        if let Some(slot) = slots.iter().find(|s| s.name == array && s.columns.is_err())
            && let Err(problem) = &slot.columns
        {
            return Err(data_error(&self.file, &slot.name, problem));
        }
        let known: Vec<&str> = slots
            .iter()
            .filter_map(|s| s.columns.as_ref().ok())
            .flat_map(|(headers, _)| headers.iter().map(String::as_str))
            .collect();
        let others: Vec<mat::Entry> = self
            .contents
            .iter()
            .flatten()
            .filter(|e| !e.columns && !e.description.ends_with(" struct"))
            .cloned()
            .collect();
        let what = if others.is_empty() {
            format!("column in {}", self.file)
        } else {
            format!(
                "column in {} (which also holds {}, not read as columns: {})",
                self.file,
                mat::holds(&others),
                mat::SUPPORTED
            )
        };
        Err(Error::UnknownName {
            what,
            name: name.to_string(),
            known: known.join(", "),
        })
    }

    /// The value of the scalar variable `name` (one value: a gain stored beside the
    /// signals), for `scale = "name"`. A variable that is not there, or holds more than
    /// one value, is [`Error::Data`] naming the file and the variable; CSV and UFF files
    /// hold no scalars.
    pub fn scalar(&self, name: &str) -> Result<f64> {
        let error = |message: String| Error::Data {
            file: self.file.clone(),
            row: 0,
            column: name.to_string(),
            message,
        };
        let Content::Arrays { slots, npz } = &self.content else {
            return Err(error(format!(
                "scale = \"{name}\" names a scalar variable of the data file, and only .mat and .npz files hold named scalars: give the number"
            )));
        };
        let Some(slot) = slots.iter().find(|s| s.name == name) else {
            let scalars: Vec<&str> = slots
                .iter()
                .filter(|s| matches!(&s.columns, Ok((_, Source::Mat(r, c, _))) if r * c == 1))
                .map(|s| s.name.as_str())
                .collect();
            return Err(error(format!(
                "scale = \"{name}\": the file has no variable '{name}' (its scalars: {})",
                if scalars.is_empty() {
                    "none".to_string()
                } else {
                    scalars.join(", ")
                }
            )));
        };
        let array = self.read(slot, npz.as_ref())?;
        match array.columns.as_slice() {
            [column] if column.len() == 1 => Ok(column[0]),
            columns => Err(error(format!(
                "scale = \"{name}\" names a variable of {} × {} values, not a scalar (one value)",
                columns.first().map_or(0, Vec::len),
                columns.len()
            ))),
        }
    }

    fn read(&self, slot: &Slot, npz: Option<&Npz>) -> Result<NamedArray> {
        read_slot(&self.file, slot, npz)
    }

    /// [`DataFile::table`] for the file's last use: a table read whole gives up its
    /// columns instead of copying them.
    pub fn into_table(self, names: &[&str]) -> Result<Table> {
        let Content::Table(mut table) = self.content else {
            return self.table(names);
        };
        for name in names {
            table.column(name)?;
        }
        let mut headers: Vec<String> = Vec::new();
        let mut columns = Vec::new();
        for name in names {
            if headers.iter().any(|h| h == name) {
                continue;
            }
            let k = table.headers.iter().position(|h| h == name).unwrap_or(0);
            columns.push(std::mem::take(&mut table.columns[k]));
            headers.push(name.to_string());
        }
        Ok(Table {
            file: table.file,
            headers,
            columns,
        })
    }
}

/// Reads the data of a slot (an error naming it when it cannot be columns).
fn read_slot(file: &str, slot: &Slot, npz: Option<&Npz>) -> Result<NamedArray> {
    let problem = |problem: &str| data_error(file, &slot.name, problem);
    match &slot.columns {
        Err(p) => Err(problem(p)),
        Ok((_, Source::Mat(r, c, values))) => {
            arrays::column_major(file, &slot.name, *r, *c, values)
        }
        Ok((_, Source::Npz(k))) => {
            let member = npz.and_then(|npz| npz.members.get(*k).map(|m| (npz, m)));
            match member {
                Some((npz, member)) => match &member.header {
                    Ok(header) => npz.read(member, header),
                    Err(p) => Err(problem(p)),
                },
                None => Err(problem("not in the archive")),
            }
        }
    }
}

/// The data files of a job, each opened once (module doc).
#[derive(Default)]
pub struct DataFiles {
    /// Per canonical path: the open file and how many records will still ask for it.
    files: HashMap<PathBuf, (Option<DataFile>, usize)>,
    opened: usize,
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

impl DataFiles {
    /// The files named by `paths`, one entry per record that will ask for one (a file
    /// named twice is opened once and kept until its second record has read it).
    pub fn new<'a>(paths: impl IntoIterator<Item = &'a Path>) -> DataFiles {
        let mut files: HashMap<PathBuf, (Option<DataFile>, usize)> = HashMap::new();
        for path in paths {
            files.entry(canonical(path)).or_insert((None, 0)).1 += 1;
        }
        DataFiles { files, opened: 0 }
    }

    /// The table of the columns `names` of the file at `path` ([`DataFile::table`]),
    /// opening the file on its first use.
    pub fn table(&mut self, path: &Path, names: &[&str]) -> Result<Table> {
        self.columns(path, names, &[]).map(|(table, _)| table)
    }

    /// The table of the columns `names` of the file at `path` and the columns left in
    /// it to be read into place ([`DataFile::columns`]), opening the file on its first
    /// use; a table read whole gives up its columns on the file's last use.
    pub fn columns(
        &mut self,
        path: &Path,
        names: &[&str],
        in_place: &[&str],
    ) -> Result<(Table, InPlace)> {
        let key = canonical(path);
        let (open, uses) = self.files.remove(&key).unwrap_or((None, 1));
        let file = match open {
            Some(file) => file,
            None => {
                self.opened += 1;
                DataFile::open(path)?
            }
        };
        if uses <= 1 {
            return match file.content {
                Content::Table(_) => Ok((file.into_table(names)?, InPlace::default())),
                _ => file.columns(names, in_place),
            };
        }
        let columns = file.columns(names, in_place);
        self.files.insert(key, (Some(file), uses - 1));
        columns
    }

    /// The scalar variable `name` of the file at `path` ([`DataFile::scalar`]), opening
    /// the file on its first use and keeping it for the records that will read it.
    pub fn scalar(&mut self, path: &Path, name: &str) -> Result<f64> {
        let key = canonical(path);
        let (open, uses) = self.files.remove(&key).unwrap_or((None, 1));
        let file = match open {
            Some(file) => file,
            None => {
                self.opened += 1;
                DataFile::open(path)?
            }
        };
        let value = file.scalar(name);
        self.files.insert(key, (Some(file), uses));
        value
    }

    /// How many files have been opened so far.
    pub fn opened(&self) -> usize {
        self.opened
    }
}
