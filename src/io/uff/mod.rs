//! Universal File Format dataset 58 (function at nodal DOF): the time histories that
//! modal-test software exports (Simcenter Testlab, m+p, ME'scope, pyuff). ASCII `58` and
//! binary `58b` datasets are read in one pass; other datasets (151, 164, 2411, …) are
//! skipped when ASCII and refused when binary.
//!
//! A dataset is `-1`, its number (`58`, or `58b` followed by byte order 1 = little /
//! 2 = big endian, float format 2 = IEEE 754, 11 ASCII lines and the byte count), records
//! 1–5 (ID lines), 6 (function type, response entity, node, direction, reference…),
//! 7 (ordinate type 2 = real single / 4 = real double, number of values N, abscissa
//! spacing 1 = even / 0 = uneven, abscissa minimum and increment in E13.5), 8–11 (abscissa,
//! ordinate, denominator and z-axis characteristics), then N values (even: 6E13.5 or
//! 4E20.12; uneven: x,y pairs) in fixed-width fields or raw bytes, and `-1`.
//!
//! Only time responses (function type 1, or 0 = general) with real ordinates are read;
//! complex ordinates, other function types (spectra, FRFs) and a time axis of another
//! kind are [`Error::Data`](crate::error::Error::Data) naming the file line and record field.
//!
//! **Columns.** Each record gives the column named by its response node and direction,
//! `{node}{±axis}`: `3+Z`, `12-X`, `7+RY` (rotations RX, RY, RZ; direction 0, a scalar,
//! gives just `7`), and the column named by its ID line 1, trimmed, unless blank or
//! `NONE`. A name shared by two records names neither (it would be ambiguous); a record
//! left without any name is an error. The time column `t` is t_i = t_0 + i·h.
//!
//! **The time step.** Every record must share N, t_0 and h (to the six digits written).
//! The ASCII header stores h with six significant digits, 1/2048 s as 4.88281e-04: a
//! relative error up to 5e-6, a drift of a sample over 2·10⁵ samples. The reader assumes
//! the sample rate is a whole number of hertz (every acquisition system's 1024, 2560,
//! 51200 Hz…): if exactly one integer rate f has 1/f within half a unit of the sixth
//! digit, h = 1/f; otherwise the written step is kept. Uneven abscissas must be uniform
//! to the precision written (else an error at the offending value's line) and are
//! treated the same way, with h = (x_{N−1} − x_0)/(N − 1).
//!
//! The whole record set is also available with its units ([`read_records`]): record 9's
//! specific data type ([`Characteristics::quantity`]: displacement, velocity, …).

mod fields;
mod record;

use std::path::Path;

use crate::error::Result;
use crate::io::table::Table;
use fields::{Cursor, data_error};
pub use record::exact_step;
use record::{Abscissa, binary_header, function_record, half_unit};

/// A data characteristics record (8–11): what an axis measures and in which units.
#[derive(Debug, Clone, PartialEq)]
pub struct Characteristics {
    /// Specific data type (8 displacement, 11 velocity, 12 acceleration, 13 excitation
    /// force, 17 time…).
    pub data_type: i64,
    /// Length units exponent.
    pub length_exponent: i64,
    /// Force units exponent.
    pub force_exponent: i64,
    /// Temperature units exponent.
    pub temperature_exponent: i64,
    /// Axis label.
    pub label: String,
    /// Axis units label.
    pub units: String,
}

impl Characteristics {
    /// The quantity named by the specific data type.
    pub fn quantity(&self) -> &'static str {
        match self.data_type {
            8 => "displacement",
            9 => "reaction force",
            11 => "velocity",
            12 => "acceleration",
            13 => "excitation force",
            15 => "pressure",
            17 => "time",
            18 => "frequency",
            1 => "general",
            _ => "unknown",
        }
    }
}

/// One dataset 58 function record.
#[derive(Debug, Clone, PartialEq)]
pub struct FunctionRecord {
    /// The line of the record's `58` header.
    pub line: usize,
    /// ID line 1, trimmed.
    pub id: String,
    /// Function type (1 = time response).
    pub function_type: i64,
    /// Response node.
    pub node: i64,
    /// Response direction (±1..±6 for ±X, ±Y, ±Z, ±RX, ±RY, ±RZ; 0 scalar).
    pub direction: i64,
    /// The ordinate's characteristics (record 9).
    pub ordinate: Characteristics,
    /// The ordinate values.
    pub values: Vec<f64>,
}

impl FunctionRecord {
    /// The node-direction name, e.g. `3+Z` (module doc).
    pub fn node_name(&self) -> String {
        let axis = ["X", "Y", "Z", "RX", "RY", "RZ"];
        match self.direction {
            0 => self.node.to_string(),
            d if (1..=6).contains(&d.abs()) => {
                let sign = if d > 0 { '+' } else { '-' };
                format!("{}{sign}{}", self.node, axis[d.unsigned_abs() as usize - 1])
            }
            d => format!("{}:{d}", self.node),
        }
    }
}

/// The dataset 58 records of a file with their shared time axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Uff58 {
    /// The file (for error messages).
    pub file: String,
    /// The records in file order.
    pub records: Vec<FunctionRecord>,
    /// The abscissa start t_0.
    pub start: f64,
    /// The step h (module doc).
    pub step: f64,
}

/// Parses the dataset 58 records of a UFF file's bytes.
pub fn parse(file: &str, bytes: &[u8]) -> Result<Uff58> {
    let mut cursor = Cursor {
        file,
        bytes,
        at: 0,
        line: 0,
    };
    let mut records: Vec<FunctionRecord> = Vec::new();
    let mut axis: Option<Abscissa> = None;
    while let Some(line) = cursor.next_line() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        if line.trim() != "-1" {
            return Err(data_error(
                file,
                cursor.line,
                "delimiter",
                format!("expected -1 before a dataset, found {:?}", line.trim()),
            ));
        }
        let header = cursor.expect("the dataset number")?;
        let header_line = cursor.line;
        let h = header.trim_start();
        let digits = h.find(|c: char| !c.is_ascii_digit()).unwrap_or(h.len());
        let (number, rest) = h.split_at(digits);
        let binary = rest.starts_with(['b', 'B']);
        match (number, binary) {
            ("58", _) => {
                let binary = if binary {
                    Some(binary_header(&cursor, &rest[1..])?)
                } else {
                    None
                };
                let (record, abscissa) = function_record(&mut cursor, header_line, binary)?;
                if let Some(first) = &axis {
                    check_same_axis(file, first, &abscissa, &records[0], &record)?;
                } else {
                    axis = Some(abscissa);
                }
                records.push(record);
            }
            ("", _) => {
                return Err(data_error(
                    file,
                    header_line,
                    "dataset number",
                    format!("expected a dataset number, found {:?}", header.trim()),
                ));
            }
            (n, true) => {
                return Err(data_error(
                    file,
                    header_line,
                    "dataset number",
                    format!("binary dataset {n}b cannot be skipped: only 58 and 58b are read"),
                ));
            }
            (_, false) => loop {
                let l = cursor.expect("the closing -1 of a skipped dataset")?;
                if l.trim() == "-1" {
                    break;
                }
            },
        }
    }
    let Some(axis) = axis else {
        return Err(data_error(
            file,
            cursor.line,
            "",
            "no dataset 58 (function at nodal DOF) in the file",
        ));
    };
    Ok(Uff58 {
        file: file.to_string(),
        records,
        start: axis.start,
        step: exact_step(axis.step, axis.tolerance),
    })
}

fn check_same_axis(
    file: &str,
    a: &Abscissa,
    b: &Abscissa,
    ra: &FunctionRecord,
    rb: &FunctionRecord,
) -> Result<()> {
    let mismatch = |what: &str, x: String, y: String| {
        Err(data_error(
            file,
            b.line,
            "record 7",
            format!(
                "the record at line {} has {what} {y}, the one at line {} has {x}: all records of a file must share the time axis",
                rb.line, ra.line
            ),
        ))
    };
    if ra.values.len() != rb.values.len() {
        return mismatch(
            "length",
            ra.values.len().to_string(),
            rb.values.len().to_string(),
        );
    }
    if (a.step - b.step).abs() > a.tolerance + b.tolerance {
        return mismatch("step", a.step.to_string(), b.step.to_string());
    }
    let start = half_unit(a.start) + half_unit(b.start) + 1e-9 * a.step;
    if (a.start - b.start).abs() > start {
        return mismatch("abscissa start", a.start.to_string(), b.start.to_string());
    }
    if ra.function_type != rb.function_type {
        return mismatch(
            "function type",
            ra.function_type.to_string(),
            rb.function_type.to_string(),
        );
    }
    Ok(())
}

impl Uff58 {
    /// The table: `t`, then each record's names (module doc).
    pub fn table(self) -> Result<Table> {
        let names: Vec<Vec<String>> = self
            .records
            .iter()
            .map(|r| {
                let mut n = vec![r.node_name()];
                if !r.id.is_empty() && r.id != "NONE" && r.id != n[0] {
                    n.push(r.id.clone());
                }
                n
            })
            .collect();
        let count = |name: &str| names.iter().flatten().filter(|n| *n == name).count();
        let rows = self.records[0].values.len();
        let mut headers = vec!["t".to_string()];
        let mut columns = vec![
            (0..rows)
                .map(|i| self.start + i as f64 * self.step)
                .collect::<Vec<_>>(),
        ];
        for (record, names) in self.records.into_iter().zip(&names) {
            let unique: Vec<&String> = names
                .iter()
                .filter(|n| count(n) == 1 && *n != "t")
                .collect();
            if unique.is_empty() {
                return Err(data_error(
                    &self.file,
                    record.line,
                    "record 1 and 6",
                    format!(
                        "the record's names {names:?} are shared with another record: give each record a distinct ID line 1"
                    ),
                ));
            }
            for name in unique {
                headers.push(name.clone());
                columns.push(record.values.clone());
            }
        }
        Ok(Table {
            file: self.file,
            headers,
            columns,
        })
    }
}

/// Reads the dataset 58 records of a UFF file with their units.
pub fn read_records(path: &Path) -> Result<Uff58> {
    let file = path.display().to_string();
    crate::io::require_data_file(path)?;
    let bytes = std::fs::read(path).map_err(|e| data_error(&file, 0, "", e))?;
    parse(&file, &bytes)
}

/// Reads a UFF file (`.uff`, `.unv`) as a table (module doc).
pub fn read(path: &Path) -> Result<Table> {
    read_records(path)?.table()
}
