//! Named arrays from binary files (NumPy, MATLAB) as table columns. A 1-D variable `x`
//! (or an N × 1 one) becomes the column `x`; an N × k variable becomes the columns
//! `x[1]` … `x[k]` (1-based, like DOFs in model files). Rows are samples, so a variable
//! stored k × N with k < N is taken transposed. Every column must have the same length.
//!
//! Where a stored element lies ([`Layout`]): an r × c array stored in C order keeps
//! element (i, j) at flat index i·c + j, in Fortran order at i + j·r. Output column p,
//! sample s is element (s, p), or (p, s) when transposed (r < c), so it lies at
//!
//! | order, transposed | flat index | the column's samples |
//! |---|---|---|
//! | C, no  | s·c + p | interleaved, stride k = c |
//! | C, yes | p·c + s | contiguous, length N = c |
//! | F, no  | p·r + s | contiguous, length N = r |
//! | F, yes | s·r + p | interleaved, stride k = r |
//!
//! so every array is either k contiguous runs of N values (column p is flat
//! p·N .. (p + 1)·N) or N rows of k interleaved values (sample s of column p at s·k + p),
//! and a reader fills the columns in one pass over the flat data in file order.

use crate::error::{Error, Result};
use crate::io::table::Table;

/// Array data as table columns (N samples each, already oriented).
pub(crate) struct NamedArray {
    pub name: String,
    pub columns: Vec<Vec<f64>>,
}

/// How the flat data of a stored array maps to table columns (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Layout {
    /// N, the samples per column.
    pub samples: usize,
    /// k, the number of columns.
    pub columns: usize,
    /// Rows of k interleaved values (true) or k contiguous runs of N (false).
    pub interleaved: bool,
}

impl Layout {
    /// The layout of an r × c array stored in C (row-major) or Fortran order; `None`
    /// when r·c overflows.
    pub fn new(rows: usize, cols: usize, row_major: bool) -> Option<Layout> {
        rows.checked_mul(cols)?;
        let transposed = rows < cols;
        let (samples, columns) = if transposed {
            (cols, rows)
        } else {
            (rows, cols)
        };
        Some(Layout {
            samples,
            columns,
            interleaved: row_major != transposed,
        })
    }

    /// The number of stored elements, N·k.
    pub fn elements(&self) -> usize {
        self.samples * self.columns
    }

    /// The block of elements a reader converts at a time: about `target`, and whole
    /// rows when interleaved.
    pub fn block(&self, target: usize) -> usize {
        if self.interleaved {
            (target / self.columns.max(1)).max(1) * self.columns.max(1)
        } else {
            target.max(1)
        }
    }

    /// The (sample, column) of flat index `f`.
    pub fn position(&self, f: usize) -> (usize, usize) {
        if self.interleaved {
            (f / self.columns, f % self.columns)
        } else {
            (f % self.samples, f / self.samples)
        }
    }

    /// The column names of an array named `name`.
    pub fn headers(&self, name: &str) -> Vec<String> {
        if self.columns == 1 {
            vec![name.to_string()]
        } else {
            (1..=self.columns).map(|j| format!("{name}[{j}]")).collect()
        }
    }

    /// Empty columns with room for N samples each. Call only once the data are known to
    /// be there: N·k is read from a header.
    pub fn allocate(&self) -> Vec<Vec<f64>> {
        (0..self.columns)
            .map(|_| Vec::with_capacity(self.samples))
            .collect()
    }

    /// Appends the flat values `values`, which start at flat index `start`, to their
    /// columns (filled in file order, so each column grows at its end).
    pub fn place(&self, start: usize, values: &[f64], columns: &mut [Vec<f64>]) {
        let k = self.columns;
        if self.interleaved {
            if start.is_multiple_of(k) && values.len().is_multiple_of(k) {
                for (p, column) in columns.iter_mut().enumerate() {
                    column.extend(values[p..].iter().step_by(k));
                }
            } else {
                for (offset, &v) in values.iter().enumerate() {
                    columns[(start + offset) % k].push(v);
                }
            }
        } else {
            let n = self.samples;
            let mut f = start;
            let mut rest = values;
            while !rest.is_empty() {
                let run = (n - f % n).min(rest.len());
                columns[f / n].extend_from_slice(&rest[..run]);
                rest = &rest[run..];
                f += run;
            }
        }
    }
}

/// An r × c array given column-major (MATLAB's order) as table columns; a non-finite
/// value is an error at its sample and column in `file`.
pub(crate) fn column_major(
    file: &str,
    name: &str,
    rows: usize,
    cols: usize,
    data: &[f64],
) -> Result<NamedArray> {
    let layout = Layout::new(rows, cols, false).filter(|l| l.elements() == data.len());
    let Some(layout) = layout else {
        return Err(Error::Data {
            file: file.to_string(),
            row: 0,
            column: name.to_string(),
            message: format!("{rows} × {cols} with {} values", data.len()),
        });
    };
    if let Some(f) = data.iter().position(|v| !v.is_finite()) {
        let (s, p) = layout.position(f);
        return Err(Error::Data {
            file: file.to_string(),
            row: s + 1,
            column: layout.headers(name)[p].clone(),
            message: format!("non-finite value {}", data[f]),
        });
    }
    let mut columns = layout.allocate();
    layout.place(0, data, &mut columns);
    Ok(NamedArray {
        name: name.to_string(),
        columns,
    })
}

/// `arrays` less the scalars (one value: a gain, a sample rate stored beside the
/// signals) when some array is longer: what a file read whole holds as a table, so that
/// a file `identify` reads by name is read whole by `init` and `pod` too.
pub(crate) fn without_scalars(arrays: Vec<NamedArray>) -> Vec<NamedArray> {
    let longest = arrays
        .iter()
        .flat_map(|a| a.columns.iter().map(Vec::len))
        .max()
        .unwrap_or(0);
    let scalar = |a: &NamedArray| longest > 1 && a.columns.iter().all(|c| c.len() == 1);
    arrays.into_iter().filter(|a| !scalar(a)).collect()
}

/// Builds a table from the arrays read out of `file`: every column must have the same
/// length.
pub(crate) fn table_from_arrays(file: &str, arrays: Vec<NamedArray>) -> Result<Table> {
    let mut headers = Vec::new();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for array in arrays {
        let k = array.columns.len();
        for (j, column) in array.columns.into_iter().enumerate() {
            headers.push(if k == 1 {
                array.name.clone()
            } else {
                format!("{}[{}]", array.name, j + 1)
            });
            columns.push(column);
        }
    }
    let Some(first) = columns.first() else {
        return Err(Error::Data {
            file: file.to_string(),
            row: 0,
            column: String::new(),
            message: "no numeric variables".into(),
        });
    };
    let length = first.len();
    if let Some(k) = columns.iter().position(|c| c.len() != length) {
        return Err(Error::Data {
            file: file.to_string(),
            row: 0,
            column: headers[k].clone(),
            message: format!(
                "{} samples, but '{}' has {length}",
                columns[k].len(),
                headers[0]
            ),
        });
    }
    Ok(Table {
        file: file.to_string(),
        headers,
        columns,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scalar stored beside signals (a gain `gtau`) is left out of the whole table;
    /// two signals of different lengths are still an error naming both.
    #[test]
    fn scalars_beside_signals_are_left_out() {
        let array = |name: &str, columns: Vec<Vec<f64>>| NamedArray {
            name: name.into(),
            columns,
        };
        let whole = |arrays| table_from_arrays("f.mat", without_scalars(arrays));
        let table = whole(vec![
            array("qg", vec![vec![1.0, 2.0, 3.0]]),
            array("gtau", vec![vec![0.5]]),
            array("t", vec![vec![0.0, 0.1, 0.2]]),
        ])
        .unwrap();
        assert_eq!(table.headers, ["qg", "t"]);
        let only = whole(vec![array("gtau", vec![vec![0.5]])]).unwrap();
        assert_eq!(only.headers, ["gtau"]);
        let e = whole(vec![
            array("a", vec![vec![1.0, 2.0, 3.0]]),
            array("b", vec![vec![1.0, 2.0]]),
        ])
        .unwrap_err();
        assert!(e.to_string().contains("2 samples, but 'a' has 3"), "{e}");
    }

    /// Every order and orientation puts element (s, p) of the oriented array in column
    /// p at sample s, whatever the block boundaries: checked against the flat-index
    /// formulas of the module doc, written out per case.
    #[test]
    #[allow(clippy::needless_range_loop)] // (s, p) index the formulas, not the loop
    fn layouts_place_every_element_where_the_formulas_say() {
        for (r, c) in [(5, 3), (3, 5), (4, 1), (1, 4), (4, 4)] {
            for row_major in [true, false] {
                let layout = Layout::new(r, c, row_major).unwrap();
                let flat: Vec<f64> = (0..r * c).map(|f| f as f64).collect();
                for block in [1, 2, 3, 7, r * c] {
                    let mut columns = layout.allocate();
                    for start in (0..r * c).step_by(block) {
                        let end = (start + block).min(r * c);
                        layout.place(start, &flat[start..end], &mut columns);
                    }
                    for p in 0..layout.columns {
                        for s in 0..layout.samples {
                            // (i, j) of the stored array.
                            let (i, j) = if r < c { (p, s) } else { (s, p) };
                            let f = if row_major { i * c + j } else { i + j * r };
                            assert_eq!(columns[p][s], f as f64, "{r}x{c} {row_major} {block}");
                            assert_eq!(layout.position(f), (s, p));
                        }
                    }
                }
            }
        }
    }
}
