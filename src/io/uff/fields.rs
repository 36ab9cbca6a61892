//! The text layer of a UFF file: lines and raw bytes with their line numbers, fixed-width
//! Fortran fields (with a whitespace fallback for free-format writers; `D` exponents are
//! read as `E`), and the data characteristics records 8–11.

use crate::error::{Error, Result};

use super::Characteristics;

pub(super) fn data_error(
    file: &str,
    line: usize,
    field: &str,
    message: impl std::fmt::Display,
) -> Error {
    Error::Data {
        file: file.to_string(),
        row: line,
        column: field.to_string(),
        message: format!("line {line}: {message}"),
    }
}

/// Lines and raw bytes of a file, with the current line number (1-based).
pub(super) struct Cursor<'a> {
    pub(super) file: &'a str,
    pub(super) bytes: &'a [u8],
    pub(super) at: usize,
    pub(super) line: usize,
}

impl<'a> Cursor<'a> {
    pub(super) fn next_line(&mut self) -> Option<Result<&'a str>> {
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
    pub(super) fn expect(&mut self, what: &str) -> Result<&'a str> {
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

    pub(super) fn take(&mut self, count: usize) -> Option<&'a [u8]> {
        let slice = self.bytes.get(self.at..self.at.checked_add(count)?)?;
        self.line += slice.iter().filter(|&&b| b == b'\n').count();
        self.at += count;
        Some(slice)
    }
}

/// Splits `line` into fixed-width fields (the last ones may be missing when the line is
/// short), falling back to whitespace separation when the fixed fields are not numbers.
pub(super) fn fields<'a>(line: &'a str, widths: &[usize]) -> Vec<&'a str> {
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

pub(super) fn number(text: &str) -> Option<f64> {
    let value: f64 = text.replace(['D', 'd'], "E").parse().ok()?;
    value.is_finite().then_some(value)
}

pub(super) fn integer(text: &str) -> Option<i64> {
    text.parse().ok()
}

/// Parses integer fields `widths` of `line` (record `record`), all required.
pub(super) fn integers(
    cursor: &Cursor,
    line: &str,
    record: usize,
    widths: &[usize],
) -> Result<Vec<i64>> {
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

pub(super) fn characteristics(cursor: &mut Cursor, record: usize) -> Result<Characteristics> {
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
