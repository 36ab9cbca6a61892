//! NumPy arrays in, faer matrices out: one copy, from the caller's memory straight into
//! the library's column-major layout.
//!
//! float64 arrays in C or Fortran order (or any strides) are borrowed as they are
//! (`PyReadonlyArray::as_array`, an ndarray view on NumPy's buffer): Python makes no
//! copy, and the copy into the record's `faer::Mat` is the only one (a Fortran-order
//! column is one contiguous run). Arrays of another real dtype (integers, bool,
//! float32) are converted by NumPy to float64 first (`astype`, a second copy, said in
//! the docs); complex, object or string arrays are refused with their dtype named.

use faer::Mat;
use numpy::ndarray::ArrayView2;
use numpy::{
    PyArrayDescrMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::error::argument;

/// `obj` as a float64 array of dimension `ndim`, converted from another real dtype
/// when it has one; `what` names the argument in errors.
fn float64<'py>(obj: &Bound<'py, PyAny>, what: &str, ndim: usize) -> PyResult<Bound<'py, PyAny>> {
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let array = if obj.cast::<PyUntypedArray>().is_ok() {
        obj.clone()
    } else {
        // Lists and other sequences: NumPy reads them (a copy of Python objects anyway).
        numpy
            .call_method1("asarray", (obj,))
            .map_err(|e| argument(format!("{what}: not an array of numbers ({e})")))?
    };
    let untyped = array
        .cast::<PyUntypedArray>()
        .map_err(|_| argument(format!("{what}: not an array of numbers")))?;
    if untyped.ndim() != ndim {
        let shape: Vec<String> = untyped.shape().iter().map(|s| s.to_string()).collect();
        let expected = if ndim == 2 {
            "2-D (samples × DOFs)"
        } else {
            "1-D (samples)"
        };
        return Err(argument(format!(
            "{what} must be {expected}, got shape ({})",
            shape.join(", ")
        )));
    }
    let dtype = untyped.dtype();
    let kind = dtype.kind();
    if dtype.is_equiv_to(&numpy::dtype::<f64>(py)) {
        return Ok(array);
    }
    match kind {
        b'b' | b'i' | b'u' | b'f' => Ok(array.call_method1("astype", ("float64",))?),
        _ => Err(argument(format!(
            "{what} has dtype {}, which is not real numbers; give float64 (integer, bool and float32 arrays are converted)",
            dtype.str()?
        ))),
    }
}

/// An N × n array as a faer matrix (the one copy; see the module doc).
pub fn matrix(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Mat<f64>> {
    let array = float64(obj, what, 2)?;
    let readonly: PyReadonlyArray2<'_, f64> = array.extract()?;
    Ok(columns(readonly.as_array()))
}

/// Rows of a C-order array copied per block: `BLOCK` rows of every column at a time,
/// so the block read (BLOCK × n doubles) stays in cache while each column is written
/// in one run.
const BLOCK: usize = 256;

/// `view` copied into a column-major matrix, by the fastest route its layout allows:
/// Fortran order column by column (`copy_from_slice`), C order as a blocked transpose,
/// other strides element by element.
fn columns(view: ArrayView2<'_, f64>) -> Mat<f64> {
    let (rows, cols) = view.dim();
    let mut out = Mat::<f64>::zeros(rows, cols);
    if let Some(source) = view.t().to_slice() {
        // Fortran order: column j is source[j·N .. (j+1)·N].
        for j in 0..cols {
            out.col_as_slice_mut(j)
                .copy_from_slice(&source[j * rows..(j + 1) * rows]);
        }
    } else if let Some(source) = view.to_slice() {
        // C order: x[i, j] is source[i·n + j].
        for start in (0..rows).step_by(BLOCK) {
            let end = (start + BLOCK).min(rows);
            for j in 0..cols {
                let column = &mut out.col_as_slice_mut(j)[start..end];
                for (k, value) in column.iter_mut().enumerate() {
                    *value = source[(start + k) * cols + j];
                }
            }
        }
    } else {
        for j in 0..cols {
            for (value, x) in out.col_as_slice_mut(j).iter_mut().zip(view.column(j)) {
                *value = *x;
            }
        }
    }
    out
}

/// An N-vector as a `Vec` (one copy).
pub fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let array = float64(obj, what, 1)?;
    let readonly: PyReadonlyArray1<'_, f64> = array.extract()?;
    Ok(readonly.as_array().iter().copied().collect())
}
