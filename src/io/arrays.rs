//! Named arrays from binary files (NumPy, MATLAB) as table columns. A 1-D variable `x`
//! (or an N × 1 one) becomes the column `x`; an N × k variable becomes the columns
//! `x[1]` … `x[k]` (1-based, like DOFs in model files). Rows are samples, so a variable
//! stored k × N with k < N is taken transposed. Every column must have the same length.

use crate::error::{Error, Result};
use crate::io::table::Table;

/// Array data in column-major order with its shape (rows, columns).
pub(crate) struct NamedArray {
    pub name: String,
    pub rows: usize,
    pub columns: usize,
    pub column_major: Vec<f64>,
}

/// Builds a table from the arrays read out of `file`.
pub(crate) fn table_from_arrays(file: &str, arrays: Vec<NamedArray>) -> Result<Table> {
    let mut headers = Vec::new();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for array in arrays {
        let (mut rows, mut cols, mut data) = (array.rows, array.columns, array.column_major);
        if rows < cols {
            // Samples along the longer dimension: transpose k × N to N × k.
            let transposed = (0..rows)
                .flat_map(|i| (0..cols).map(move |j| (i, j)))
                .map(|(i, j)| data[i + j * rows])
                .collect::<Vec<_>>();
            // transposed is row-major of the k × N array = column-major of N × k.
            data = transposed;
            std::mem::swap(&mut rows, &mut cols);
        }
        for (k, value) in data.iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::Data {
                    file: file.to_string(),
                    row: k % rows.max(1) + 1,
                    column: array.name.clone(),
                    message: format!("non-finite value {value}"),
                });
            }
        }
        for j in 0..cols {
            headers.push(if cols == 1 {
                array.name.clone()
            } else {
                format!("{}[{}]", array.name, j + 1)
            });
            columns.push(data[j * rows..(j + 1) * rows].to_vec());
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
