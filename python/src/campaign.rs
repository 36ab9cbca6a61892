//! The campaign trio: `regressor_rows` maps one record to its `Rows` on any machine
//! (the library's `campaign::rows`: the steady-state check, the rows, and what the
//! weighted fit and the report read beside A and b), `stack_rows` joins parts in record
//! order anywhere, and `fit_rows` fits them with the library's `identify`, bit for bit
//! as `identify` of the records (docs/python.md, examples/python/campaign_dask.py).
//! `Rows` pickle as zstd-compressed CBOR bytes, so Dask or multiprocessing move them
//! between processes.

use dampid::identify::identify as run;
use dampid::progress::silent;
use dampid::regressor::{ParametricRegressor, Regressor, RowLabel};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::buffer::PyBuffer;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use crate::arrays;
use crate::error::{IntoPy, argument, to_py};
use crate::record::{Lent, PyRecord};
use crate::report::{PyReport, Source};
use crate::{PyModel, in_mode, settings, timed, with_transient_hint};

/// One record's rows, or many stacked: A, b, their labels and what the fit reads beside
/// them (the noise model of the noise-robust rows, the gross work of each row, the
/// velocity-noise bias, the steady-state check of their windows).
#[pyclass(name = "Rows", module = "dampid", frozen)]
pub(crate) struct PyRows {
    pub(crate) regressor: Regressor,
}

#[pymethods]
impl PyRows {
    /// A (equations × coefficients), a new array.
    #[getter]
    fn a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let a = self.regressor.matrix();
        numpy::ndarray::Array2::from_shape_fn((a.nrows(), a.ncols()), |(i, j)| a[(i, j)])
            .into_pyarray(py)
    }

    /// b, the input work of each row, a new array.
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.regressor.rhs().to_vec().into_pyarray(py)
    }

    /// Where each row comes from: a structured array (record, record_index, window,
    /// start_time, cycles).
    #[getter]
    fn labels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let labels: Vec<_> = (self.regressor.rows().iter())
            .map(|r| {
                let (index, window, cycles) =
                    (r.record_index as i64, r.window as i64, r.cycles as i64);
                (r.record.clone(), index, window, r.start_time, cycles)
            })
            .collect();
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", label_dtype(py)?)?;
        py.import("numpy")?
            .call_method("array", (labels,), Some(&kwargs))
    }

    /// Whether the rows carry a noise model (the noise-robust rows of the default
    /// pipeline), which `fit_rows` weights them by as `identify` does.
    #[getter]
    fn noise_robust(&self) -> bool {
        self.regressor.noise().is_some()
    }

    /// The coefficient names, one per column of A.
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.regressor.columns().to_vec()
    }

    /// The rows as bytes (CBOR, zstd-compressed): what pickling sends.
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let failed = |e: &dyn std::fmt::Display| {
            argument(format!("rows could not be written as bytes: {e}"))
        };
        let mut encoder = zstd::stream::Encoder::new(Vec::new(), 1).map_err(|e| failed(&e))?;
        ciborium::into_writer(&self.regressor, &mut encoder).map_err(|e| failed(&e))?;
        let bytes = encoder.finish().map_err(|e| failed(&e))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// Rows from the bytes of `to_bytes` (`bytes`, or any buffer of them: a
    /// `memoryview`, a `pickle.PickleBuffer`), read in place.
    #[staticmethod]
    fn from_bytes(bytes: &Bound<'_, PyAny>) -> PyResult<Self> {
        let not_rows = |e: String| {
            argument(format!(
                "these bytes are not dampid rows (from Rows.to_bytes of this version): {e}"
            ))
        };
        let regressor: Regressor = match bytes.cast::<PyBytes>() {
            Ok(b) => read(b.as_bytes()).map_err(not_rows)?,
            Err(_) => {
                let buffer = PyBuffer::<u8>::get(bytes).map_err(|_| {
                    argument("Rows.from_bytes takes bytes or a buffer of bytes".into())
                })?;
                if !buffer.is_c_contiguous() {
                    return Err(argument(
                        "Rows.from_bytes needs a contiguous buffer of bytes".into(),
                    ));
                }
                // SAFETY: a contiguous buffer of `len_bytes` bytes at `buf_ptr`, held
                // alive by `buffer` for this scope; it is only read, with the GIL held,
                // so no Python code runs to change it meanwhile.
                let view = unsafe {
                    std::slice::from_raw_parts(buffer.buf_ptr() as *const u8, buffer.len_bytes())
                };
                read(view).map_err(not_rows)?
            }
        };
        Ok(PyRows { regressor })
    }

    /// Pickling: `Rows.from_bytes(rows.to_bytes())`, the bytes in a `PickleBuffer` from
    /// protocol 5 on: with a buffer callback (as Dask sends results) they travel out of
    /// band, as their own frame, and are read in place on arrival, so the receiver never
    /// holds a second copy of a large stack.
    fn __reduce_ex__<'py>(
        slf: &Bound<'py, Self>,
        protocol: u32,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyAny>,))> {
        let py = slf.py();
        let from_bytes = slf.get_type().getattr("from_bytes")?;
        let bytes = slf.get().to_bytes(py)?.into_any();
        let payload = if protocol >= 5 {
            py.import("pickle")?
                .getattr("PickleBuffer")?
                .call1((bytes,))?
        } else {
            bytes
        };
        Ok((from_bytes, (payload,)))
    }

    fn __len__(&self) -> usize {
        self.regressor.equations()
    }

    fn __repr__(&self) -> String {
        let mut records: Vec<usize> = (self.regressor.rows().iter())
            .map(|r| r.record_index)
            .collect();
        records.dedup();
        format!(
            "Rows({} rows × {} columns from {} record(s){})",
            self.regressor.equations(),
            self.regressor.columns().len(),
            records.len(),
            if self.noise_robust() {
                ", noise-robust"
            } else {
                ""
            }
        )
    }
}

/// Rows from their bytes (zstd-compressed CBOR), decompressed as they are read.
fn read(bytes: &[u8]) -> Result<Regressor, String> {
    let decoder = zstd::stream::Decoder::new(bytes).map_err(|e| e.to_string())?;
    ciborium::from_reader(decoder).map_err(|e| e.to_string())
}

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

/// `regressor_rows(model, record, record_index=0, **settings) -> Rows`: the rows one
/// record contributes (one per window) with the settings of `identify`, the default
/// noise-robust pipeline included; `record_index` numbers the record in the campaign.
#[pyfunction]
#[pyo3(signature = (model, record, record_index=0, **settings))]
pub(crate) fn regressor_rows(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    record: &Bound<'_, PyRecord>,
    record_index: usize,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyRows> {
    let model = model.get();
    let settings = settings::settings(settings, &model.text, &model.file)?;
    let list = std::slice::from_ref(record);
    let lent = Lent::take(list)?;
    let built = in_mode(list, &lent.records, &settings).and_then(|rebuilt| {
        let records = rebuilt.as_deref().unwrap_or(&lent.records);
        py.detach(|| {
            dampid::campaign::rows(
                &model.model,
                records,
                record_index,
                &settings.identification,
            )
        })
        .map_err(with_transient_hint)
    });
    lent.restore();
    Ok(PyRows { regressor: built? })
}

/// `stack_rows(parts) -> Rows`: parts (`Rows`) one after the other, in the order given
/// (record order for a result equal to `identify`); a stack of stacks is the same.
#[pyfunction]
pub(crate) fn stack_rows(py: Python<'_>, parts: &Bound<'_, PyAny>) -> PyResult<PyRows> {
    let parts = rows_list(parts)?;
    let regressor = py.detach(|| Regressor::stack(parts)).py_err()?;
    Ok(PyRows { regressor })
}

/// The regressors of a sequence of `Rows`.
fn rows_list(parts: &Bound<'_, PyAny>) -> PyResult<Vec<Regressor>> {
    let items: Vec<Bound<'_, PyAny>> = parts
        .try_iter()
        .map_err(|_| argument("parts must be a list of dampid.Rows".into()))?
        .collect::<PyResult<_>>()?;
    items
        .iter()
        .enumerate()
        .map(|(k, item)| {
            item.cast::<PyRows>()
                .map(|rows| rows.get().regressor.clone())
                .map_err(|_| argument(format!("parts[{k}] is not a dampid.Rows")))
        })
        .collect()
}

/// `fit_rows(model, rows, b=None, labels=None, **settings) -> Report`: the fit of
/// `rows` (one `Rows`, or a list of them stacked in order) by the library's `identify`,
/// equal bit for bit to `identify` of the records when the rows are in record order.
/// Plain rows made by hand fit as `fit_rows(model, A, b, labels=None)` (no noise model:
/// ordinary least squares, as the settings say).
#[pyfunction]
#[pyo3(signature = (model, rows, b=None, labels=None, **settings))]
pub(crate) fn fit_rows(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    rows: &Bound<'_, PyAny>,
    b: Option<&Bound<'_, PyAny>>,
    labels: Option<&Bound<'_, PyAny>>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyReport> {
    let py_model = model.get();
    let settings = settings::settings(settings, &py_model.text, &py_model.file)?;
    let names = py_model.model.coefficient_names();
    // One Rows is fitted in place (a campaign's may be large); a list is stacked first.
    let built;
    let regressor: &Regressor = match (b, rows.cast::<PyRows>()) {
        (None, Ok(one)) => &one.get().regressor,
        (None, Err(_)) => {
            let parts = rows_list(rows).map_err(|_| {
                argument("rows must be a dampid.Rows, a list of them, or a matrix A with b".into())
            })?;
            built = py.detach(|| Regressor::stack(parts)).py_err()?;
            &built
        }
        (Some(b), _) => {
            built = hand_made(rows, b, labels, names.clone())?;
            &built
        }
    };
    if regressor.columns() != names.as_slice() {
        return Err(to_py(dampid::Error::InvalidChoice {
            name: "rows".into(),
            given: format!("columns {:?}", regressor.columns()),
            reason: format!(
                "the model's coefficients are {names:?}: fit rows with the model that built them"
            ),
        }));
    }
    let mut seconds = 0.0;
    let problem = ParametricRegressor::linear(&py_model.model, regressor);
    let found = timed(py, &mut seconds, || {
        run(&problem, &settings.identification, &silent)
    })
    .py_err()?;
    let call = format!("dampid.fit_rows(model, rows, ..., {})", settings.given);
    Ok(PyReport {
        text: found.report.to_string(),
        identification: found,
        model_file: (py_model.file.clone(), py_model.text.clone()),
        settings: settings.provenance(call),
        source: Source::Rows,
        library_seconds: seconds,
    })
}

/// Rows made by hand: A, b and (optionally) labels as `Rows.labels` gives them.
fn hand_made(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    labels: Option<&Bound<'_, PyAny>>,
    names: Vec<String>,
) -> PyResult<Regressor> {
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
    Regressor::from_parts(matrix, rhs, names, rows).py_err()
}

/// Row labels from the structured array `Rows.labels` gives.
fn read_labels(labels: &Bound<'_, PyAny>) -> PyResult<Vec<RowLabel>> {
    let field = |name: &str| {
        labels.get_item(name).map_err(|_| {
            argument(format!(
                "labels must be the structured array Rows.labels gives (no field '{name}')"
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
