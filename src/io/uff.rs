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
//! kind are [`Error::Data`] naming the file line and record field.
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

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::table::Table;

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

fn data_error(file: &str, line: usize, field: &str, message: impl std::fmt::Display) -> Error {
    Error::Data {
        file: file.to_string(),
        row: line,
        column: field.to_string(),
        message: format!("line {line}: {message}"),
    }
}

/// Lines and raw bytes of a file, with the current line number (1-based).
struct Cursor<'a> {
    file: &'a str,
    bytes: &'a [u8],
    at: usize,
    line: usize,
}

impl<'a> Cursor<'a> {
    fn next_line(&mut self) -> Option<Result<&'a str>> {
        if self.at >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.at..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.at += (end + 1).min(rest.len());
        self.line += 1;
        let raw = rest[..end].strip_suffix(b"\r").unwrap_or(&rest[..end]);
        Some(
            std::str::from_utf8(raw)
                .map_err(|_| data_error(self.file, self.line, "", "not text (UTF-8)")),
        )
    }

    /// The next line, or an error naming what was expected.
    fn expect(&mut self, what: &str) -> Result<&'a str> {
        match self.next_line() {
            Some(line) => line,
            None => Err(data_error(
                self.file,
                self.line,
                what,
                format!("the file ends where {what} should be (truncated dataset)"),
            )),
        }
    }

    fn take(&mut self, count: usize) -> Option<&'a [u8]> {
        let slice = self.bytes.get(self.at..self.at.checked_add(count)?)?;
        self.line += slice.iter().filter(|&&b| b == b'\n').count();
        self.at += count;
        Some(slice)
    }
}

/// Splits `line` into fixed-width fields (the last ones may be missing when the line is
/// short), falling back to whitespace separation when the fixed fields are not numbers.
fn fields<'a>(line: &'a str, widths: &[usize]) -> Vec<&'a str> {
    let mut out = Vec::new();
    let mut at = 0;
    for &w in widths {
        if at >= line.len() {
            break;
        }
        let end = (at + w).min(line.len());
        match line.get(at..end) {
            Some(field) => out.push(field.trim()),
            None => return line.split_whitespace().collect(),
        }
        at = end;
    }
    out
}

fn number(text: &str) -> Option<f64> {
    let value: f64 = text.replace(['D', 'd'], "E").parse().ok()?;
    value.is_finite().then_some(value)
}

fn integer(text: &str) -> Option<i64> {
    text.parse().ok()
}

/// Parses integer fields `widths` of `line` (record `record`), all required.
fn integers(cursor: &Cursor, line: &str, record: usize, widths: &[usize]) -> Result<Vec<i64>> {
    let parse = |fs: &[&str]| fs.iter().map(|f| integer(f)).collect::<Option<Vec<_>>>();
    let fixed = fields(line, widths);
    if let Some(values) = parse(&fixed).filter(|v| v.len() == widths.len()) {
        return Ok(values);
    }
    let free: Vec<&str> = line.split_whitespace().take(widths.len()).collect();
    if let Some(values) = parse(&free).filter(|v| v.len() == widths.len()) {
        return Ok(values);
    }
    let bad = fixed.iter().position(|f| integer(f).is_none());
    let (field, text) = bad.map_or((fixed.len(), "(missing)"), |k| (k, fixed[k]));
    Err(data_error(
        cursor.file,
        cursor.line,
        &format!("record {record} field {}", field + 1),
        format!("expected an integer, found {text:?}"),
    ))
}

fn characteristics(cursor: &mut Cursor, record: usize) -> Result<Characteristics> {
    let line = cursor.expect(&format!("record {record}"))?;
    let n = integers(cursor, line, record, &[10, 5, 5, 5])?;
    let text = |a: usize, b: usize| line.get(a..b.min(line.len())).unwrap_or("").trim();
    Ok(Characteristics {
        data_type: n[0],
        length_exponent: n[1],
        force_exponent: n[2],
        temperature_exponent: n[3],
        label: text(26, 46).to_string(),
        units: text(47, 67).to_string(),
    })
}

/// The binary `58b` header: byte order (true = little endian) and the byte count.
fn binary_header(cursor: &Cursor, rest: &str) -> Result<(bool, usize)> {
    let tokens: Vec<&str> = rest.split_whitespace().collect();
    let field = |k: usize, name: &str| {
        tokens.get(k).and_then(|t| integer(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                cursor.line,
                &format!("58b header field {} ({name})", k + 2),
                format!("expected an integer, found {:?}", tokens.get(k)),
            )
        })
    };
    let order = field(0, "byte order")?;
    let format = field(1, "floating-point format")?;
    let lines = field(2, "number of ASCII lines")?;
    let bytes = field(3, "number of bytes")?;
    let bad = |k: usize, message: String| {
        Err(data_error(
            cursor.file,
            cursor.line,
            &format!("58b header field {k}"),
            message,
        ))
    };
    if order != 1 && order != 2 {
        return bad(
            2,
            format!("byte order {order}: expected 1 (little) or 2 (big endian)"),
        );
    }
    if format != 2 {
        return bad(
            3,
            format!("floating-point format {format}: only 2 (IEEE 754) is read"),
        );
    }
    if lines != 11 {
        return bad(4, format!("{lines} ASCII lines: dataset 58b has 11"));
    }
    match usize::try_from(bytes) {
        Ok(bytes) => Ok((order == 1, bytes)),
        Err(_) => bad(5, format!("byte count {bytes}")),
    }
}

/// The abscissa of one record: start, step, the precision they were written to, and
/// the line of record 7.
struct Abscissa {
    start: f64,
    step: f64,
    tolerance: f64,
    line: usize,
}

/// Half a unit of the sixth significant digit of `value` (E13.5 rounding).
fn half_unit(value: f64) -> f64 {
    if value == 0.0 {
        return 0.0;
    }
    0.5 * 10f64.powi(value.abs().log10().floor() as i32 - 5) * (1.0 + 1e-9)
}

/// The exact step 1/f for the one whole sample rate f within `tolerance` of `step`.
pub fn exact_step(step: f64, tolerance: f64) -> f64 {
    let rate = (1.0 / step).round();
    let fits = |f: f64| f >= 1.0 && (1.0 / f - step).abs() <= tolerance;
    if fits(rate) && !fits(rate - 1.0) && !fits(rate + 1.0) {
        1.0 / rate
    } else {
        step
    }
}

/// One dataset 58 after its header line.
fn function_record(
    cursor: &mut Cursor,
    header_line: usize,
    binary: Option<(bool, usize)>,
) -> Result<(FunctionRecord, Abscissa)> {
    let id = cursor.expect("record 1 (ID line 1)")?.trim().to_string();
    for record in 2..=5 {
        cursor.expect(&format!("record {record} (ID line {record})"))?;
    }
    let r6 = cursor.expect("record 6")?;
    let w6 = [5, 10, 5, 10, 11, 10, 4, 11, 10, 4];
    let t6 = fields(r6, &w6);
    let int6 = |k: usize, name: &str| {
        t6.get(k).and_then(|t| integer(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                cursor.line,
                &format!("record 6 field {} ({name})", k + 1),
                format!("expected an integer, found {:?}", t6.get(k).unwrap_or(&"")),
            )
        })
    };
    let function_type = int6(0, "function type")?;
    let node = int6(5, "response node")?;
    let direction = int6(6, "response direction")?;
    if function_type != 0 && function_type != 1 {
        return Err(data_error(
            cursor.file,
            cursor.line,
            "record 6 field 1 (function type)",
            format!(
                "function type {function_type} is not a time response: dampid reads type 1 (or 0, general)"
            ),
        ));
    }
    let r7 = cursor.expect("record 7")?;
    let line7 = cursor.line;
    let i7 = integers(cursor, r7, 7, &[10, 10, 10])?;
    let t7 = fields(r7, &[10, 10, 10, 13, 13, 13]);
    let real7 = |k: usize, name: &str| {
        t7.get(k).and_then(|t| number(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                line7,
                &format!("record 7 field {} ({name})", k + 1),
                format!("expected a number, found {:?}", t7.get(k).unwrap_or(&"")),
            )
        })
    };
    let (kind, count, spacing) = (i7[0], i7[1], i7[2]);
    let size = match kind {
        2 => 4,
        4 => 8,
        5 | 6 => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 1 (ordinate data type)",
                format!("ordinate type {kind} is complex: dampid reads real time histories (2, 4)"),
            ));
        }
        _ => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 1 (ordinate data type)",
                format!("ordinate type {kind}: expected 2 (real single) or 4 (real double)"),
            ));
        }
    };
    let even = match spacing {
        1 => true,
        0 => false,
        _ => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 3 (abscissa spacing)",
                format!("{spacing}: expected 1 (even) or 0 (uneven)"),
            ));
        }
    };
    let count = usize::try_from(count)
        .ok()
        .filter(|&n| n >= 2)
        .ok_or_else(|| {
            data_error(
                cursor.file,
                line7,
                "record 7 field 2 (number of values)",
                format!("{count}: a time history needs at least two values"),
            )
        })?;
    let (start, increment) = if even {
        (
            real7(3, "abscissa minimum")?,
            real7(4, "abscissa increment")?,
        )
    } else {
        (0.0, 0.0)
    };
    let abscissa = characteristics(cursor, 8)?;
    if abscissa.data_type != 0 && abscissa.data_type != 17 {
        return Err(data_error(
            cursor.file,
            cursor.line,
            "record 8 field 1 (abscissa data type)",
            format!(
                "abscissa type {} ({}): a time history has 17 (time) or 0",
                abscissa.data_type,
                abscissa.quantity()
            ),
        ));
    }
    let ordinate = characteristics(cursor, 9)?;
    characteristics(cursor, 10)?;
    characteristics(cursor, 11)?;
    let per_sample = if even { 1 } else { 2 };
    let total = count.saturating_mul(per_sample);
    let (pairs, data_line) = match binary {
        Some((little, declared)) => {
            let bytes = total.saturating_mul(size);
            // pyuff 2.5 declares N·size bytes for uneven records that hold 2N values.
            if declared != bytes && declared != count.saturating_mul(size) {
                return Err(data_error(
                    cursor.file,
                    header_line,
                    "58b header field 5 (number of bytes)",
                    format!(
                        "{declared} bytes, but record 7 describes {total} values of {size} bytes ({bytes})"
                    ),
                ));
            }
            let line = cursor.line + 1;
            let raw = cursor.take(bytes).ok_or_else(|| {
                data_error(
                    cursor.file,
                    line,
                    "record 12 (data)",
                    format!("the file ends inside the {bytes} data bytes (truncated dataset)"),
                )
            })?;
            let values = raw
                .chunks_exact(size)
                .map(|c| match (size, little) {
                    (4, true) => f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                    (4, false) => f64::from(f32::from_be_bytes([c[0], c[1], c[2], c[3]])),
                    (_, true) => f64::from_le_bytes(c.try_into().unwrap_or([0; 8])),
                    (_, false) => f64::from_be_bytes(c.try_into().unwrap_or([0; 8])),
                })
                .collect::<Vec<_>>();
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(data_error(
                    cursor.file,
                    line,
                    "record 12 (data)",
                    format!("value {} is {}", k + 1, values[k]),
                ));
            }
            (values, line)
        }
        None => ascii_values(cursor, total, size == 8, even)?,
    };
    let line = cursor.line;
    match cursor.next_line() {
        Some(Ok(l)) if l.trim() == "-1" => {}
        // Binary data may be followed by a line end before the delimiter.
        Some(Ok(l)) if binary.is_some() && l.trim().is_empty() => {
            let after = cursor.expect("the delimiter -1")?;
            if after.trim() != "-1" {
                return Err(too_many(cursor, count));
            }
        }
        Some(Ok(_)) => return Err(too_many(cursor, count)),
        Some(Err(e)) => return Err(e),
        None => {
            return Err(data_error(
                cursor.file,
                line,
                "delimiter",
                "the file ends before the dataset's closing -1 (truncated dataset)",
            ));
        }
    }
    let (values, abscissa) = if even {
        let tolerance = half_unit(increment);
        (
            pairs,
            Abscissa {
                start,
                step: increment,
                tolerance,
                line: line7,
            },
        )
    } else {
        uneven(cursor.file, pairs, data_line, binary.is_none(), line7)?
    };
    let record = FunctionRecord {
        line: header_line,
        id,
        function_type,
        node,
        direction,
        ordinate,
        values,
    };
    Ok((record, abscissa))
}

fn too_many(cursor: &Cursor, count: usize) -> Error {
    data_error(
        cursor.file,
        cursor.line,
        "record 7 field 2 (number of values)",
        format!("record 7 announces {count} values, but the data go on past them (expected -1)"),
    )
}

/// `total` values in fixed-width fields: 6E13.5 single, 4E20.12 double, and double
/// uneven pairs E13.5,E20.12. Returns them and the first data line.
fn ascii_values(
    cursor: &mut Cursor,
    total: usize,
    double: bool,
    even: bool,
) -> Result<(Vec<f64>, usize)> {
    let widths: &[usize] = match (double, even) {
        (false, _) => &[13; 6],
        (true, true) => &[20; 4],
        (true, false) => &[13, 20, 13, 20],
    };
    // Never reserve more than the file can hold (a field takes at least 2 bytes).
    let mut values = Vec::with_capacity(total.min(cursor.bytes.len() / 2));
    let first = cursor.line + 1;
    while values.len() < total {
        let line = cursor.expect("record 12 (data)")?;
        if line.trim() == "-1" {
            return Err(data_error(
                cursor.file,
                cursor.line,
                "record 7 field 2 (number of values)",
                format!(
                    "record 7 announces {total} values, the data hold {} (truncated dataset)",
                    values.len()
                ),
            ));
        }
        let need = (total - values.len()).min(widths.len());
        let fixed = fields(line, &widths[..need]);
        let parsed: Option<Vec<f64>> = fixed.iter().map(|f| number(f)).collect();
        let parsed = parsed.filter(|p| !p.is_empty()).or_else(|| {
            let free: Option<Vec<f64>> = line.split_whitespace().map(number).collect();
            free.filter(|p| !p.is_empty() && p.len() <= need)
        });
        match parsed {
            Some(p) => values.extend(p),
            None => {
                let k = fixed.iter().position(|f| number(f).is_none()).unwrap_or(0);
                return Err(data_error(
                    cursor.file,
                    cursor.line,
                    &format!("record 12 field {}", k + 1),
                    format!(
                        "expected a finite number, found {:?}",
                        fixed.get(k).unwrap_or(&"")
                    ),
                ));
            }
        }
    }
    Ok((values, first))
}

/// Splits x,y pairs and checks the x are uniform to the precision written.
fn uneven(
    file: &str,
    pairs: Vec<f64>,
    first: usize,
    ascii: bool,
    line7: usize,
) -> Result<(Vec<f64>, Abscissa)> {
    let x: Vec<f64> = pairs.iter().step_by(2).copied().collect();
    let y: Vec<f64> = pairs.iter().skip(1).step_by(2).copied().collect();
    let n = x.len();
    let step = (x[n - 1] - x[0]) / (n - 1) as f64;
    let precision = |v: f64| {
        if ascii {
            half_unit(v)
        } else {
            4.0 * f64::EPSILON * v.abs()
        }
    };
    let values_per_line = if ascii { 2 } else { usize::MAX };
    if step.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(data_error(
            file,
            first,
            "record 12 (abscissa)",
            format!("the abscissa does not increase: mean step {step}"),
        ));
    }
    for (i, &xi) in x.iter().enumerate() {
        let expected = x[0] + i as f64 * step;
        if (xi - expected).abs()
            > precision(xi) + precision(x[0]) + precision(x[n - 1]) + 1e-9 * step
        {
            return Err(data_error(
                file,
                first + i / values_per_line.max(1),
                "record 12 (abscissa)",
                format!(
                    "the abscissa is not uniform: x[{}] = {xi}, a uniform step {step} gives {expected}",
                    i + 1
                ),
            ));
        }
    }
    let tolerance = (precision(x[0]) + precision(x[n - 1])) / (n - 1) as f64;
    Ok((
        y,
        Abscissa {
            start: x[0],
            step,
            tolerance,
            line: line7,
        },
    ))
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
    let bytes = std::fs::read(path).map_err(|e| data_error(&file, 0, "", e))?;
    parse(&file, &bytes)
}

/// Reads a UFF file (`.uff`, `.unv`) as a table (module doc).
pub fn read(path: &Path) -> Result<Table> {
    read_records(path)?.table()
}
