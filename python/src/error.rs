//! `dampid.DampidError`: every error of the library, and every bad argument, as a
//! `ValueError` subclass with the CLI's message and the error's `kind`
//! (`dampid::Error::kind`, or `"argument"` for what only Python can get wrong).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pyo3::create_exception!(
    dampid,
    DampidError,
    PyValueError,
    "An error of dampid: bad arrays, settings, model files or data that cannot be identified. \
     `str(e)` is the message the dampid CLI prints; `e.kind` names the error class."
);

/// A `DampidError` with `message` and `kind`.
pub fn raise(kind: &str, message: String) -> PyErr {
    Python::attach(|py| {
        let err = DampidError::new_err(message);
        // Setting an attribute on a fresh exception object cannot fail in practice; if it
        // did, the error still carries its message.
        let _ = err.value(py).setattr("kind", kind);
        err
    })
}

/// The library's error as a `DampidError`.
pub fn to_py(e: dampid::Error) -> PyErr {
    raise(e.kind(), e.to_string())
}

/// An argument only Python can get wrong (a dtype, a shape), as a `DampidError`.
pub fn argument(message: String) -> PyErr {
    raise("argument", message)
}

/// `Result<T, dampid::Error>` → `PyResult<T>`.
pub trait IntoPy<T> {
    /// The library's error as a `DampidError`.
    fn py_err(self) -> PyResult<T>;
}

impl<T> IntoPy<T> for dampid::Result<T> {
    fn py_err(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}
