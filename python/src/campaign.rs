//! The campaign pair: `regressor_rows` maps one record to its rows (A, b and their
//! labels) on any machine, `fit_rows` fits the stacked rows once, bit for bit as
//! `identify` of the records (docs/python.md, examples/python/campaign_dask.py).

use dampid::identify::{IdentifySettings, identify as run};
use dampid::progress::silent;
use dampid::regressor::{ParametricRegressor, Regressor, RowLabel};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays;
use crate::error::{IntoPy, argument, to_py};
use crate::record::{Lent, PyRecord};
use crate::report::{PyReport, Source};
use crate::{PyModel, in_mode, settings, timed, with_transient_hint};

/// The NumPy dtype of row labels: the library's `RowLabel` fields.
fn label_dtype<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    PyList::new(
        py,
        [
            ("record", "O"),
            ("record_index", "i8"),
            ("window", "i8"),
            ("start_time", "f8"),
            ("cycles", "i8"),
        ],
    )
}

/// `regressor_rows(model, record, record_index=0, **settings) -> (A, b, labels)`: the
/// rows one record contributes (one per window), for campaigns that map records to rows
/// on many machines and fit once (`fit_rows`). `labels` is a structured array with the
/// fields of the library's row label; `record_index` numbers the record in the campaign.
#[pyfunction]
#[pyo3(signature = (model, record, record_index=0, **settings))]
#[allow(clippy::type_complexity)]
pub(crate) fn regressor_rows<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    record: &Bound<'py, PyRecord>,
    record_index: usize,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<(
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyAny>,
)> {
    let model = model.get();
    let settings = settings::settings(settings, &model.text, &model.file)?;
    let list = std::slice::from_ref(record);
    let lent = Lent::take(list)?;
    let built = in_mode(list, &lent.records, &settings).and_then(|rebuilt| {
        let records = rebuilt.as_deref().unwrap_or(&lent.records);
        let identification = &settings.identification;
        let problem = ParametricRegressor::linear(&model.model, records);
        py.detach(|| {
            if let Some(thresholds) = &identification.steady_state
                && let Some(steady) = problem.steady_state(&identification.regressor, thresholds)?
            {
                steady.enforce()?;
            }
            problem.regressor(&[], &identification.regressor)
        })
        .map_err(with_transient_hint)
    });
    lent.restore();
    let regressor = built?;
    if regressor.noise().is_some() {
        return Err(to_py(dampid::Error::InvalidChoice {
            name: "noise".into(),
            given: "auto (noise-robust rows)".into(),
            reason: "these rows carry a noise model that (A, b) cannot hold, so fit_rows would weight them differently from identify; pass noise=\"ignore\", or a velocity other than harmonic_projection".into(),
        }));
    }
    let a = regressor.matrix();
    let matrix = numpy::ndarray::Array2::from_shape_fn((a.nrows(), a.ncols()), |(i, j)| a[(i, j)]);
    let labels: Vec<_> = (regressor.rows().iter())
        .map(|r| {
            let (window, cycles) = (r.window as i64, r.cycles as i64);
            (
                r.record.clone(),
                record_index as i64,
                window,
                r.start_time,
                cycles,
            )
        })
        .collect();
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", label_dtype(py)?)?;
    let labels = py
        .import("numpy")?
        .call_method("array", (labels,), Some(&kwargs))?;
    let rhs = regressor.rhs().to_vec().into_pyarray(py);
    Ok((matrix.into_pyarray(py), rhs, labels))
}

/// `fit_rows(model, A, b, labels=None, **settings) -> Report`: the fit of stacked rows
/// (`regressor_rows` of every record), equal bit for bit to `identify` of the records
/// when the rows are stacked in record order.
#[pyfunction]
#[pyo3(signature = (model, a, b, labels=None, **settings))]
pub(crate) fn fit_rows(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    labels: Option<&Bound<'_, PyAny>>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyReport> {
    let py_model = model.get();
    let settings = settings::settings(settings, &py_model.text, &py_model.file)?;
    let matrix = arrays::matrix(a, "A")?;
    let rhs = arrays::vector(b, "b")?;
    let rows = match labels {
        None => (0..rhs.len())
            .map(|r| RowLabel {
                record: "rows".into(),
                record_index: 0,
                window: r,
                start_time: 0.0,
                cycles: 1,
                frequency: None,
            })
            .collect(),
        Some(labels) => read_labels(labels)?,
    };
    let names = py_model.model.coefficient_names();
    let regressor = Regressor::from_parts(matrix, rhs, names, rows).py_err()?;
    // The rows as they are: no steady state to check, no windows to cut.
    let fit = IdentifySettings {
        fit: settings.identification.fit.clone(),
        ..Default::default()
    };
    let mut seconds = 0.0;
    let problem = ParametricRegressor::linear(&py_model.model, &regressor);
    let found = timed(py, &mut seconds, || run(&problem, &fit, &silent)).py_err()?;
    let call = format!("dampid.fit_rows(model, A, b, ..., {})", settings.given);
    Ok(PyReport {
        text: found.report.to_string(),
        identification: found,
        model_file: (py_model.file.clone(), py_model.text.clone()),
        settings: settings.provenance(call),
        source: Source::Rows,
        library_seconds: seconds,
    })
}

/// Row labels from the structured array `regressor_rows` returns.
fn read_labels(labels: &Bound<'_, PyAny>) -> PyResult<Vec<RowLabel>> {
    let field = |name: &str| {
        labels.get_item(name).map_err(|_| {
            argument(format!(
                "labels must be the structured array regressor_rows returns (no field '{name}')"
            ))
        })
    };
    let records: Vec<String> = field("record")?.call_method0("tolist")?.extract()?;
    let index: PyReadonlyArray1<'_, i64> = field("record_index")?.extract()?;
    let window: PyReadonlyArray1<'_, i64> = field("window")?.extract()?;
    let start: PyReadonlyArray1<'_, f64> = field("start_time")?.extract()?;
    let cycles: PyReadonlyArray1<'_, i64> = field("cycles")?.extract()?;
    let (index, window) = (index.as_array(), window.as_array());
    let (start, cycles) = (start.as_array(), cycles.as_array());
    Ok(records
        .into_iter()
        .enumerate()
        .map(|(r, record)| RowLabel {
            record,
            record_index: index[r] as usize,
            window: window[r] as usize,
            start_time: start[r],
            cycles: cycles[r] as usize,
            frequency: None,
        })
        .collect())
}
