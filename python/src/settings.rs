//! Keyword settings (`identify(model, records, cycles=2, nonnegative=True)`) as the
//! `[identification]` table of a model file, read by the library's own translation
//! ([`dampid::model_file::identification`]): same keys, same values, same errors. The
//! keyword `non_periodic={...}` is the model file's `[non_periodic]` section, read by
//! [`dampid::model_file::non_periodic_identification`] against the model's text (its
//! `dofs` and `[matrices]`), and `free_decay={...}` the `[free_decay]` section, read by
//! [`dampid::model_file::free_decay_identification`].

use dampid::identify::IdentifySettings;
use dampid::model_file::{
    IDENTIFICATION_KEYS, free_decay_identification, identification, non_periodic_identification,
    settings_in_effect,
};
use dampid::prep::free_decay::{DecaySettings, ModalFilter};
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
    /// `[free_decay]`: each record a ringdown of one mode, isolated before identifying.
    pub free_decay: Option<DecaySettings>,
    /// `free_decay={"mode_shape": [...]}` or `{"modal_filter": "pod"}`: each record holds
    /// several sensors, projected onto the mode first.
    pub modal_filter: Option<ModalFilter>,
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
    let mut free_decay = None;
    let mut given = Vec::new();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            if key != "non_periodic"
                && key != "free_decay"
                && !IDENTIFICATION_KEYS.contains(&key.as_str())
            {
                return Err(to_py(dampid::Error::UnknownName {
                    what: "setting ([identification] key)".into(),
                    name: key,
                    known: [IDENTIFICATION_KEYS, &["non_periodic", "free_decay"]]
                        .concat()
                        .join(", "),
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
            } else if key == "free_decay" {
                let toml::Value::Table(section) = value else {
                    return Err(argument(format!(
                        "free_decay = {value}: give a dict of the [free_decay] keys, e.g. free_decay={{\"mass\": 1.0}}"
                    )));
                };
                free_decay = Some(section);
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
    if let Some(section) = &free_decay {
        given_table.insert("free_decay".into(), toml::Value::Table(section.clone()));
    }
    let (identification, high_pass, decay, modal_filter) = match (&non_periodic, &free_decay) {
        (Some(_), Some(_)) => {
            return Err(argument(
                "give non_periodic={...} or free_decay={...}, not both".into(),
            ));
        }
        (None, None) => (identification(&table).py_err()?, None, None, None),
        (Some(section), None) => {
            let (settings, high_pass) =
                non_periodic_identification(&table, section, model_text, file).py_err()?;
            (settings, high_pass, None, None)
        }
        (None, Some(section)) => {
            let (settings, decay, filter) = free_decay_identification(&table, section).py_err()?;
            (settings, None, Some(decay), filter)
        }
    };
    Ok(Settings {
        identification,
        non_periodic: non_periodic.is_some(),
        high_pass,
        free_decay: decay,
        modal_filter,
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
