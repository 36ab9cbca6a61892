//! Columns read straight from a data file into their destination (a column of a
//! record's matrix), instead of into a table's column first and then copied: the
//! destination's memory is the only memory the data touch, once.
//!
//! [`super::data_file::DataFile::columns`] leaves in the file every stored (not
//! deflated) `.npz` member whose columns a record reads only as motion channels, and
//! [`InPlace::read`] reads each such member in one pass, block by block, writing column p
//! of its (oriented) array at sample s as
//!
//! ```text
//!   into[s] = scale × value(s, p) + offset
//! ```
//!
//! which is what the table path computes (`Columns::move_into` of
//! `model_file/measured.rs`), so the values are the same bit for bit. The members are read
//! in parallel (rayon), a large one in parts of whole rows or columns (`io/parts.rs`),
//! each with the checks of the table path: its data inside the member, every value finite
//! (an error at its sample and column), its CRC-32. Every other format, and deflated
//! members, go through the table.

use std::mem::MaybeUninit;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io::npz::Npz;
use crate::io::scatter::Target;

/// One column left in the file: its name, its member and its column in the member's
/// array.
#[derive(Debug, Clone)]
struct Placed {
    name: String,
    member: usize,
    column: usize,
}

/// The columns of a record left in the file to be read into place (module doc).
#[derive(Debug, Default)]
pub struct InPlace {
    npz: Option<Npz>,
    columns: Vec<Placed>,
    /// The samples of every column, when some are left in the file.
    rows: Option<usize>,
}

/// A destination of [`InPlace::read`]: a column's name, where it goes (its samples, which
/// need not hold values yet: each is written once the read succeeds) and its gain
/// (scale, offset).
pub type Destination<'a> = (&'a str, &'a mut [MaybeUninit<f64>], (f64, f64));

impl InPlace {
    /// The columns `names` of the `npz` members `members` (per member its index and its
    /// column names), `rows` samples each.
    pub(crate) fn new(npz: &Npz, members: Vec<(usize, Vec<String>)>, rows: usize) -> InPlace {
        if members.is_empty() {
            return InPlace::default();
        }
        let columns = members
            .into_iter()
            .flat_map(|(member, names)| {
                names
                    .into_iter()
                    .enumerate()
                    .map(move |(column, name)| Placed {
                        name,
                        member,
                        column,
                    })
            })
            .collect();
        InPlace {
            npz: Some(npz.clone()),
            columns,
            rows: Some(rows),
        }
    }

    /// Whether the column `name` is left in the file.
    pub fn holds(&self, name: &str) -> bool {
        self.columns.iter().any(|c| c.name == name)
    }

    /// The samples of each column left in the file (`None` when there are none).
    pub fn rows(&self) -> Option<usize> {
        self.rows
    }

    /// Reads every member holding a column of `destinations` once, each column into its
    /// destinations (module doc); the members in parallel, the first error in the order
    /// of the members. A destination whose column is not left in the file, or whose
    /// length is not the columns' samples, is an error. When it returns `Ok`, every
    /// sample of every destination has been written (each member's every flat index is
    /// scattered by `Npz::read_into`).
    pub fn read(&self, destinations: Vec<Destination<'_>>) -> Result<()> {
        let mut members: Vec<(usize, Vec<Target<'_>>)> = Vec::new();
        for (name, into, gain) in destinations {
            let placed = self.columns.iter().find(|c| c.name == name);
            let (Some(placed), Some(rows)) = (placed, self.rows) else {
                return Err(Error::Numerical {
                    stage: "reading a column in place".into(),
                    detail: format!("the column '{name}' is not left in the file"),
                });
            };
            if into.len() != rows {
                return Err(Error::Numerical {
                    stage: "reading a column in place".into(),
                    detail: format!(
                        "the column '{name}' has {rows} samples, its destination {}",
                        into.len()
                    ),
                });
            }
            let target = Target {
                column: placed.column,
                into,
                gain,
            };
            match members.iter_mut().find(|(m, _)| *m == placed.member) {
                Some((_, targets)) => targets.push(target),
                None => members.push((placed.member, vec![target])),
            }
        }
        let Some(npz) = &self.npz else {
            return Ok(());
        };
        members.sort_by_key(|(m, _)| *m);
        // Each member's share of the threads, by its bytes: one large member is read by
        // all of them in parts, two of equal size by one each (more parts than threads
        // only interleave the same work).
        let bytes = |m: usize| match &npz.members[m].header {
            Ok(header) => header.data_bytes().unwrap_or(u64::MAX) as f64,
            Err(_) => 0.0,
        };
        let total: f64 = members.iter().map(|(m, _)| bytes(*m)).sum();
        let threads = rayon::current_num_threads() as f64;
        members
            .into_par_iter()
            .map(|(m, mut targets)| {
                let member = &npz.members[m];
                let share = (threads * bytes(m) / total.max(1.0)).round().max(1.0) as usize;
                match &member.header {
                    Ok(header) => npz.read_into(member, header, &mut targets, share),
                    Err(problem) => Err(crate::io::npy::data_error(
                        npz.file(),
                        &member.name,
                        problem,
                    )),
                }
            })
            .collect::<Vec<_>>() // the first error in order, whichever thread saw it first
            .into_iter()
            .collect()
    }
}
