//! NumPy `.npy` (one array, named after the file stem) and `.npz` (every array in the
//! archive, by name) files, read with npyz. Real dtypes f8, f4, i8, i4 are converted to
//! f64; C and Fortran order are both handled.

use std::io::Read;
use std::path::Path;

use npyz::{DType, NpyFile, Order, TypeChar};

use crate::error::{Error, Result};
use crate::io::arrays::{NamedArray, table_from_arrays};
use crate::io::table::Table;

fn data_error(file: &str, column: &str, message: impl std::fmt::Display) -> Error {
    Error::Data {
        file: file.to_string(),
        row: 0,
        column: column.to_string(),
        message: message.to_string(),
    }
}

fn read_array<R: Read>(npy: NpyFile<R>, name: &str, file: &str) -> Result<NamedArray> {
    let shape: Vec<usize> = npy.shape().iter().map(|&d| d as usize).collect();
    let (rows, columns) = match shape.as_slice() {
        [n] => (*n, 1),
        [r, c] => (*r, *c),
        _ => {
            return Err(data_error(
                file,
                name,
                format!("shape {shape:?}: expected one or two dimensions"),
            ));
        }
    };
    let order = npy.order();
    let dtype = npy.dtype();
    let DType::Plain(type_str) = &dtype else {
        return Err(data_error(
            file,
            name,
            "structured arrays are not supported",
        ));
    };
    let error = |e: std::io::Error| data_error(file, name, e);
    let values: Vec<f64> = match (type_str.type_char(), type_str.size_field()) {
        (TypeChar::Float, 8) => npy.into_vec::<f64>().map_err(error)?,
        (TypeChar::Float, 4) => npy
            .into_vec::<f32>()
            .map_err(error)?
            .into_iter()
            .map(f64::from)
            .collect(),
        (TypeChar::Int, 8) => npy
            .into_vec::<i64>()
            .map_err(error)?
            .into_iter()
            .map(|v| v as f64)
            .collect(),
        (TypeChar::Int, 4) => npy
            .into_vec::<i32>()
            .map_err(error)?
            .into_iter()
            .map(f64::from)
            .collect(),
        _ => {
            return Err(data_error(
                file,
                name,
                format!("dtype {type_str} is not a supported real type (f8, f4, i8, i4)"),
            ));
        }
    };
    let column_major = match order {
        Order::Fortran => values,
        Order::C => (0..columns)
            .flat_map(|j| (0..rows).map(move |i| (i, j)))
            .map(|(i, j)| values[i * columns + j])
            .collect(),
    };
    Ok(NamedArray {
        name: name.to_string(),
        rows,
        columns,
        column_major,
    })
}

/// Reads a `.npy` file; its array is named after the file stem.
pub fn read_npy(path: &Path) -> Result<Table> {
    let file = path.display().to_string();
    let name = path
        .file_stem()
        .map_or("x".into(), |s| s.to_string_lossy().into_owned());
    let reader = std::fs::File::open(path).map_err(|e| data_error(&file, "", e))?;
    let npy =
        NpyFile::new(std::io::BufReader::new(reader)).map_err(|e| data_error(&file, "", e))?;
    table_from_arrays(&file, vec![read_array(npy, &name, &file)?])
}

/// Reads every array of a `.npz` archive.
pub fn read_npz(path: &Path) -> Result<Table> {
    let file = path.display().to_string();
    let mut archive = npyz::npz::NpzArchive::open(path).map_err(|e| data_error(&file, "", e))?;
    let mut names: Vec<String> = archive.array_names().map(str::to_string).collect();
    names.sort();
    let mut arrays = Vec::new();
    for name in names {
        let npy = archive
            .by_name(&name)
            .map_err(|e| data_error(&file, &name, e))?
            .ok_or_else(|| data_error(&file, &name, "listed but not found in the archive"))?;
        arrays.push(read_array(npy, &name, &file)?);
    }
    table_from_arrays(&file, arrays)
}
