//! MATLAB `.mat` files, level 5 (MATLAB v5 to v7, compressed or not; v7.3 is HDF5 and is
//! not read), with the matfile crate. Every real numeric 1-D or 2-D variable becomes
//! columns (as for NPY arrays: `x[1]`…`x[k]` for N × k); complex and non-numeric variables are skipped.

use std::path::Path;

use matfile::{MatFile, NumericData};

use crate::error::{Error, Result};
use crate::io::arrays::{NamedArray, table_from_arrays};
use crate::io::table::Table;

fn real_values(data: &NumericData) -> Option<Vec<f64>> {
    macro_rules! convert {
        ($real:expr, $imag:expr) => {
            if $imag.is_some() {
                None
            } else {
                Some($real.iter().map(|&v| v as f64).collect())
            }
        };
    }
    match data {
        NumericData::Double { real, imag } => convert!(real, imag),
        NumericData::Single { real, imag } => convert!(real, imag),
        NumericData::Int8 { real, imag } => convert!(real, imag),
        NumericData::UInt8 { real, imag } => convert!(real, imag),
        NumericData::Int16 { real, imag } => convert!(real, imag),
        NumericData::UInt16 { real, imag } => convert!(real, imag),
        NumericData::Int32 { real, imag } => convert!(real, imag),
        NumericData::UInt32 { real, imag } => convert!(real, imag),
        NumericData::Int64 { real, imag } => convert!(real, imag),
        NumericData::UInt64 { real, imag } => convert!(real, imag),
    }
}

/// Reads the real numeric variables of a `.mat` file.
pub fn read_mat(path: &Path) -> Result<Table> {
    let file = path.display().to_string();
    let error = |message: String| Error::Data {
        file: file.clone(),
        row: 0,
        column: String::new(),
        message,
    };
    let reader = std::fs::File::open(path).map_err(|e| error(e.to_string()))?;
    // matfile 0.5 panics on some malformed files (a data element whose size is within 8
    // of u32::MAX overflows its padding arithmetic; found by the `mat` fuzz target), so
    // a panic in the parser is turned into the same typed error as a parse failure.
    let parsed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        MatFile::parse(std::io::BufReader::new(reader))
    }))
    .map_err(|_| error("not a level-5 MAT file: the MAT parser failed on it".into()))?;
    let mat =
        parsed.map_err(|e| error(format!("not a level-5 MAT file (v7.3 files are HDF5): {e}")))?;
    let arrays = mat
        .arrays()
        .iter()
        .filter_map(|a| {
            let size = a.size();
            let values = real_values(a.data())?;
            (size.len() == 2).then(|| NamedArray {
                name: a.name().to_string(),
                rows: size[0],
                columns: size[1],
                column_major: values,
            })
        })
        .collect();
    table_from_arrays(&file, arrays)
}
