//! Keyword settings (`identify(model, records, cycles=2, nonnegative=True)`) as the
//! `[identification]` table of a model file, read by the library's own translation
//! ([`dampid::model_file::identification`]): same keys, same values, same errors.

use dampid::model_file::{Identification, identification};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::error::{IntoPy, argument};

/// The settings of `kwargs` (none: the model-file defaults).
pub fn settings(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Identification> {
    let mut table = toml::Table::new();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let value = to_toml(&value, &key)?;
            table.insert(key, value);
        }
    }
    identification(&table).py_err()
}

/// A Python value as TOML: bool, int, float, str, dict and list/tuple.
fn to_toml(value: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    // bool before int: Python's bool is an int.
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if value.cast::<PyInt>().is_ok() {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.cast::<PyFloat>().is_ok() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_str()?.to_string()));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let inner = to_toml(&v, key)?;
            table.insert(k, inner);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.cast::<PyList>().is_ok() || value.cast::<PyTuple>().is_ok() {
        let items = value
            .try_iter()?
            .map(|v| to_toml(&v?, key))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    // NumPy scalars and other numbers.
    if let Ok(f) = value.extract::<f64>() {
        return Ok(toml::Value::Float(f));
    }
    Err(argument(format!(
        "setting {key} = {}: give a bool, int, float, str, dict or list, as in a model file's [identification]",
        value.repr()?
    )))
}
