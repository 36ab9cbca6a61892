//! CSV files with a header row: every column numeric (or, asked for by name, text
//! labels such as a sweep's `FC1`: [`read_with_labels`]). Errors name the file, the 1-based
//! data row and the column. Plain numeric files are parsed by `io/csv_fast.rs`
//! (in parallel for files of [`PARALLEL_BLOCK`] bytes and more); anything it does not
//! take (quoted fields, a bad cell) is read by the csv crate, which also words every
//! error.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::io::output::{self, Overwrite};
use crate::io::table::Table;

/// The bytes per block of lines parsed on one thread: files of two blocks or more are
/// parsed in parallel.
pub const PARALLEL_BLOCK: usize = 1 << 20;

/// The buffer a CSV file is streamed through by the fast path.
const READ_BUFFER: usize = 16 << 20;

/// Reads a CSV file with a header row.
pub fn read(path: &Path) -> Result<Table> {
    let file = path.display().to_string();
    let error = |e: std::io::Error| Error::Data {
        file: file.clone(),
        row: 0,
        column: String::new(),
        message: e.to_string(),
    };
    super::require_data_file(path)?;
    let fast = super::csv_fast::read_file(path, READ_BUFFER, PARALLEL_BLOCK).map_err(error)?;
    if let Some((headers, columns)) = fast {
        return Ok(Table {
            file,
            headers,
            columns,
        });
    }
    let bytes = std::fs::read(path).map_err(error)?;
    general(&bytes, file)
}

/// Reads CSV text with a header row (`file` names it in errors).
pub fn parse(text: &str, file: &str) -> Result<Table> {
    from_bytes(text.as_bytes(), file.to_string())
}

fn from_bytes(bytes: &[u8], file: String) -> Result<Table> {
    if let Some((headers, columns)) = super::csv_fast::read(bytes, PARALLEL_BLOCK) {
        return Ok(Table {
            file,
            headers,
            columns,
        });
    }
    general(bytes, file)
}

/// Reads CSV text with the csv crate: quoted fields, and the words of every error.
pub(crate) fn general(bytes: &[u8], file: String) -> Result<Table> {
    from_reader(reader_of(bytes), file, &[]).map(|(table, _)| table)
}

/// A CSV file whose columns `labels` hold text (a sweep named `FC1`, `RC3`): the
/// numeric columns as a [`Table`] (the label columns left out), and each label
/// column's fields in row order. A label column the file lacks is an error naming the
/// known columns.
pub fn read_with_labels(path: &Path, labels: &[&str]) -> Result<(Table, Vec<Vec<String>>)> {
    let file = path.display().to_string();
    super::require_data_file(path)?;
    let bytes = std::fs::read(path).map_err(|e| Error::Data {
        file: file.clone(),
        row: 0,
        column: String::new(),
        message: e.to_string(),
    })?;
    from_reader(reader_of(&bytes), file, labels)
}

fn reader_of(bytes: &[u8]) -> ::csv::Reader<&[u8]> {
    ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(bytes)
}

/// The table of `reader` and the text of its columns named in `labels`.
fn from_reader<R: std::io::Read>(
    mut reader: ::csv::Reader<R>,
    file: String,
    labels: &[&str],
) -> Result<(Table, Vec<Vec<String>>)> {
    let data_error = |row: usize, column: &str, message: String| Error::Data {
        file: file.clone(),
        row,
        column: column.to_string(),
        message,
    };
    let headers: Vec<String> = reader
        .headers()
        .map_err(|e| data_error(0, "", e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    if headers.is_empty() || headers.iter().all(String::is_empty) {
        return Err(data_error(0, "", "no header row".into()));
    }
    // The first column of each name: one hash map, linear in the header's length.
    let mut first_of: std::collections::HashMap<&str, usize> =
        std::collections::HashMap::with_capacity(headers.len());
    for (k, name) in headers.iter().enumerate() {
        if name.is_empty() {
            return Err(data_error(
                0,
                "",
                format!("column {} of the header has no name", k + 1),
            ));
        }
        if let Some(&first) = first_of.get(name.as_str()) {
            return Err(data_error(
                0,
                name,
                format!(
                    "the header names '{name}' twice (columns {} and {}): rename one, so that the model file's column names are unambiguous",
                    first + 1,
                    k + 1
                ),
            ));
        }
        first_of.insert(name, k);
    }
    // Which label (if any) each column is.
    let label_of: Vec<Option<usize>> = headers
        .iter()
        .map(|h| labels.iter().position(|l| l == h))
        .collect();
    if let Some(missing) = labels.iter().find(|l| !headers.iter().any(|h| h == *l)) {
        return Err(data_error(
            0,
            missing,
            format!("no column '{missing}' (columns: {})", headers.join(", ")),
        ));
    }
    let mut columns = vec![Vec::new(); headers.len()];
    let mut texts = vec![Vec::new(); labels.len()];
    for (index, record) in reader.records().enumerate() {
        let row = index + 1;
        let record = record.map_err(|e| data_error(row, "", e.to_string()))?;
        if record.len() != headers.len() {
            return Err(data_error(
                row,
                "",
                format!("{} fields, the header has {}", record.len(), headers.len()),
            ));
        }
        for (k, field) in record.iter().enumerate() {
            if let Some(l) = label_of[k] {
                texts[l].push(crate::format::printable(field).into_owned());
                continue;
            }
            let value: f64 = field
                .parse()
                .map_err(|_| data_error(row, &headers[k], format!("'{field}' is not a number")))?;
            if !value.is_finite() {
                return Err(data_error(
                    row,
                    &headers[k],
                    format!("non-finite value {value}"),
                ));
            }
            columns[k].push(value);
        }
    }
    if columns.iter().all(Vec::is_empty) && texts.iter().all(Vec::is_empty) {
        return Err(data_error(0, "", "no data rows".into()));
    }
    // The label columns left out of the numeric table.
    let (headers, columns): (Vec<String>, Vec<Vec<f64>>) = headers
        .into_iter()
        .zip(columns)
        .zip(&label_of)
        .filter(|(_, label)| label.is_none())
        .map(|(pair, _)| pair)
        .unzip();
    if headers.is_empty() {
        return Err(data_error(0, "", "no numeric column".into()));
    }
    Ok((
        Table {
            file,
            headers,
            columns,
        },
        texts,
    ))
}

/// Writes `headers` and column-major `columns` as a CSV file at `path`, atomically
/// ([`crate::io::output`]): an existing file is an error under [`Overwrite::Refuse`].
pub fn write(
    path: &Path,
    headers: &[String],
    columns: &[Vec<f64>],
    overwrite: Overwrite,
) -> Result<()> {
    output::write_file(path, overwrite, |sink| {
        write_to(sink, headers, columns).map_err(|e| Error::Output {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    })
    .map(drop)
}

/// Writes `headers` and column-major `columns` as CSV to `sink`.
pub(crate) fn write_to(
    sink: &mut dyn Write,
    headers: &[String],
    columns: &[Vec<f64>],
) -> ::csv::Result<()> {
    let mut writer = ::csv::Writer::from_writer(sink);
    writer.write_record(headers)?;
    let rows = columns.first().map_or(0, Vec::len);
    for i in 0..rows {
        writer.write_record(columns.iter().map(|c| format!("{:.10e}", c[i])))?;
    }
    writer.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_columns_and_names_bad_cells() {
        let table = parse("t, x1, f\n0, 1.0, 2\n0.1, 1.5, -2\n", "mem.csv").unwrap();
        assert_eq!(table.column("x1").unwrap(), [1.0, 1.5]);
        assert_eq!(table.rows(), 2);
        match parse("t,x\n0,1\n0.1,abc\n", "mem.csv") {
            Err(Error::Data {
                file,
                row,
                column,
                message,
            }) => {
                assert_eq!((file.as_str(), row, column.as_str()), ("mem.csv", 2, "x"));
                assert!(message.contains("abc"));
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            parse("t,x\n0,NaN\n", "mem.csv"),
            Err(Error::Data { row: 1, .. })
        ));
        assert!(matches!(table.column("x9"), Err(Error::UnknownName { .. })));
    }

    /// A header that names a column twice, or not at all, is refused: a model file's
    /// column name must pick one column.
    #[test]
    fn duplicate_and_empty_column_names_are_errors() {
        let twice = parse("t,x,f,x\n0,1,2,3\n", "mem.csv").unwrap_err();
        assert!(
            twice.to_string().contains("'x' twice (columns 2 and 4)"),
            "{twice}"
        );
        let unnamed = parse("t,,f\n0,1,2\n", "mem.csv").unwrap_err();
        assert!(unnamed.to_string().contains("column 2"), "{unnamed}");
    }
}
