//! Keyword settings (`identify(model, records, cycles=2, nonnegative=True)`) as the
//! `[identification]` table of a model file, read by the library's own translation
//! ([`dampid::model_file::identification`]): same keys, same values, same errors. The
//! keyword `non_periodic={...}` is the model file's `[non_periodic]` section, read by
//! [`dampid::model_file::non_periodic_identification`] against the model's text (its
//! `dofs` and `[matrices]`).

use dampid::identify::IdentifySettings;
use dampid::model_file::{
    IDENTIFICATION_KEYS, identification, non_periodic_identification, settings_in_effect,
};
use dampid::report::provenance::{Setting, SettingSource};
use dampid::report::units::Units;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::error::{IntoPy, argument, to_py};

/// The settings of one call.
pub struct Settings {
    /// `[identification]` (and `[non_periodic]`) as the library reads them, with the
    /// steady-state check of the windows.
    pub identification: IdentifySettings,
    /// `[non_periodic]`: windows of fixed spans with stored-energy unknowns.
    pub non_periodic: bool,
    /// `[non_periodic] high_pass`: the cut-off of the integration of velocity or
    /// acceleration records that are not periodic.
    pub high_pass: Option<f64>,
    /// The keywords as given, `key=value, ...` (for the report's provenance).
    pub given: String,
    /// The keywords laid out as a model file's sections (`identification`,
    /// `non_periodic`), so the provenance marks the keys they set.
    pub given_table: toml::Table,
}

impl Settings {
    /// The provenance rows of a call written as `call`: the call, then every setting in
    /// effect, those given as keywords marked so.
    pub fn provenance(&self, call: String) -> Vec<Setting> {
        let mut rows = vec![crate::python_call(call)];
        rows.extend(settings_in_effect(
            &self.identification,
            None,
            &Units::default(),
            (&self.given_table, SettingSource::Keyword),
        ));
        rows
    }
}

/// The settings of `kwargs` (none: the model-file defaults) for the model of
/// `model_text` (named `file` in errors).
pub fn settings(
    kwargs: Option<&Bound<'_, PyDict>>,
    model_text: &str,
    file: &str,
) -> PyResult<Settings> {
    let mut table = toml::Table::new();
    let mut non_periodic = None;
    let mut given = Vec::new();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            if key != "non_periodic" && !IDENTIFICATION_KEYS.contains(&key.as_str()) {
                return Err(to_py(dampid::Error::UnknownName {
                    what: "setting ([identification] key)".into(),
                    name: key,
                    known: [IDENTIFICATION_KEYS, &["non_periodic"]].concat().join(", "),
                }));
            }
            given.push(format!("{key}={}", value.repr()?));
            let value = to_toml(&value, &key)?;
            if key == "non_periodic" {
                let toml::Value::Table(section) = value else {
                    return Err(argument(format!(
                        "non_periodic = {value}: give a dict of the [non_periodic] keys, e.g. non_periodic={{\"window\": 0.25}}"
                    )));
                };
                non_periodic = Some(section);
            } else {
                table.insert(key, value);
            }
        }
    }
    let mut given_table = toml::Table::new();
    given_table.insert("identification".into(), toml::Value::Table(table.clone()));
    if let Some(section) = &non_periodic {
        given_table.insert("non_periodic".into(), toml::Value::Table(section.clone()));
    }
    let (identification, high_pass) = match &non_periodic {
        None => (identification(&table).py_err()?, None),
        Some(section) => non_periodic_identification(&table, section, model_text, file).py_err()?,
    };
    Ok(Settings {
        identification,
        non_periodic: non_periodic.is_some(),
        high_pass,
        given: given.join(", "),
        given_table,
    })
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
