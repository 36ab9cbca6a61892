//! dampid from Python: `Model`, `Record`, `identify`, `identify_file`, `Report`, and the
//! campaign pair `regressor_rows` / `fit_rows` (docs/python.md).
//!
//! Numerical work runs with the GIL released (`Python::detach`), stage by stage
//! (steady-state check, regressor, fit), with `check_signals` between stages so that a
//! KeyboardInterrupt is honoured there. faer runs sequentially (`Par::Seq`, set once at
//! import) as in the `dampid` binary, so results are the CLI's bit for bit and do not
//! depend on the thread count.

mod arrays;
mod error;
mod record;
mod report;
mod settings;

use std::path::PathBuf;
use std::time::Instant;

use dampid::analysis::velocity_noise::assess_or_none;
use dampid::identify::identify_regressor;
use dampid::model::DampingModel;
use dampid::model_file::{Identification, parse_model};
use dampid::prelude::{SensorParts, record_from_sensors};
use dampid::prep::motion::Integration;
use dampid::prep::steady_state::{SteadyStateReport, check};
use dampid::record::Record;
use dampid::regressor::{Regressor, RowLabel};
use dampid::report::provenance::{Setting, SettingSource};
use dampid::report::{FitReport, count};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use error::{DampidError, IntoPy, argument, to_py};
use record::{Lent, PyRecord};
use report::{PyReport, Source};
use settings::Settings;

/// A damping model: the `[[terms]]` of a model file.
#[pyclass(name = "Model", module = "dampid", frozen)]
struct PyModel {
    model: DampingModel,
    /// The model file's text (for `[non_periodic]` keyword settings and the provenance).
    text: String,
    /// Its path, or `<model text>`.
    file: String,
}

#[pymethods]
impl PyModel {
    /// The model of model-file text (its `dofs`, `[matrices]` and `[[terms]]`; other
    /// sections are checked for form but not built).
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Self> {
        let file = "<model text>".to_string();
        parse_model(text, &file)
            .map(|model| PyModel {
                model,
                text: text.to_string(),
                file,
            })
            .py_err()
    }

    /// The model of the model file at `path`.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path).map_err(|e| {
            to_py(dampid::Error::ModelFile {
                file: path.display().to_string(),
                line: 0,
                column: 0,
                message: e.to_string(),
                cause: None,
            })
        })?;
        let file = path.display().to_string();
        parse_model(&text, &file)
            .map(|model| PyModel { model, text, file })
            .py_err()
    }

    /// The coefficient names, in the order of the regressor's columns.
    #[getter]
    fn coefficient_names(&self) -> Vec<String> {
        self.model.coefficient_names()
    }

    fn __repr__(&self) -> String {
        format!("Model({})", self.model.coefficient_names().join(", "))
    }
}

/// The steady-state check of `identify` and of the CLI over windows of whole periods
/// (none in the non-periodic mode).
fn steady_state(
    records: &[Record],
    settings: &Identification,
) -> dampid::Result<Option<SteadyStateReport>> {
    let Some(windows) = settings.settings.regressor.windows.cycles() else {
        return Ok(None);
    };
    check(
        records,
        windows,
        settings.settings.regressor.quadrature,
        None,
        &settings.steady_state,
    )
    .map(Some)
}

/// [`steady_state`], refusing windows that are not steady unless `accept_transient`.
fn enforce_steady_state(
    records: &[Record],
    settings: &Identification,
) -> dampid::Result<Option<SteadyStateReport>> {
    let steady = steady_state(records, settings)?;
    if let Some(steady) = &steady {
        steady.enforce()?;
    }
    Ok(steady)
}

/// The records of one identification in its mode, where they differ from the records
/// as built (`None`: use those). Over whole periods every record needs its period; in
/// the non-periodic mode the records of velocity or acceleration sensors are integrated
/// again with `high_pass`, as a model file's records are.
fn mode_records(
    list: &[Bound<'_, PyRecord>],
    records: &[Record],
    settings: &Settings,
) -> PyResult<Option<Vec<Record>>> {
    if !settings.non_periodic {
        if let Some(e) = list.iter().find_map(|r| r.get().undetected()) {
            return Err(to_py(e.clone()));
        }
        return Ok(None);
    }
    if records.iter().all(|r| r.measured_motion().is_none()) {
        return Ok(None);
    }
    let Some(cutoff) = settings.high_pass else {
        return Err(to_py(dampid::Error::Missing {
            name: "high_pass in non_periodic".into(),
            reason: "records of velocity or acceleration sensors that are not periodic are integrated with a zero-phase high-pass against drift: add \"high_pass\": f_c (the cut-off frequency, cycles per time unit, well below the slowest motion of interest) to non_periodic={...}; content below f_c is removed".into(),
        }));
    };
    records
        .iter()
        .map(|r| match r.measured_motion() {
            None => Ok(r.clone()),
            Some(motion) => record_from_sensors(SensorParts {
                label: r.label().to_string(),
                step: r.step(),
                start_time: r.start_time(),
                motion: motion.signals.clone(),
                sensors: motion.sensors.clone(),
                forcing: r.forcing().clone(),
                period: r.period(),
                integration: Integration::HighPass { cutoff },
            }),
        })
        .collect::<dampid::Result<Vec<_>>>()
        .map(Some)
        .py_err()
}

/// A library error; a record that is not steady with the CLI's advice before it.
fn with_transient_hint(e: dampid::Error) -> PyErr {
    if e.kind() == "not_steady" {
        error::raise(
            e.kind(),
            format!("pass accept_transient=True to use these windows anyway: {e}"),
        )
    } else {
        to_py(e)
    }
}

/// The records of `records` (a sequence of `Record`), at least one.
fn record_list<'py>(records: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyRecord>>> {
    let list: Vec<Bound<'py, PyAny>> = records
        .try_iter()
        .map_err(|_| argument("records must be a list of dampid.Record".into()))?
        .collect::<PyResult<_>>()?;
    if list.is_empty() {
        return Err(to_py(dampid::Error::Empty {
            what: "the list of records".into(),
        }));
    }
    list.into_iter()
        .enumerate()
        .map(|(k, r)| {
            r.cast_into::<PyRecord>().map_err(|e| {
                argument(format!(
                    "records[{k}] is a {}, not a dampid.Record",
                    e.into_inner()
                        .get_type()
                        .name()
                        .map_or("?".into(), |n| n.to_string())
                ))
            })
        })
        .collect()
}

/// `identify(model, records, **settings)`: settings are the `[identification]` keys,
/// and `non_periodic={...}` the keys of `[non_periodic]`.
#[pyfunction]
#[pyo3(signature = (model, records, **settings))]
fn identify(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    records: &Bound<'_, PyAny>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyReport> {
    let model = model.get();
    let settings = settings::settings(settings, &model.text, &model.file)?;
    let list = record_list(records)?;
    let lent = Lent::take(&list)?;
    let mut library_seconds = 0.0;
    let result = mode_records(&list, &lent.records, &settings).and_then(|rebuilt| {
        let records = rebuilt.as_deref().unwrap_or(&lent.records);
        run_identify(
            py,
            &model.model,
            records,
            &settings.identification,
            &mut library_seconds,
        )
    });
    lent.restore();
    let (regressor, report, steady) = result?;
    let text = report.to_string();
    let provenance = settings.provenance(format!(
        "dampid.identify(model, records, {})",
        settings.given
    ));
    Ok(PyReport {
        report,
        varpro: None,
        model: model.model.clone(),
        model_file: (model.file.clone(), model.text.clone()),
        regressor,
        steady,
        settings: provenance,
        source: Source::Records(list.into_iter().map(|r| r.unbind()).collect()),
        text,
        library_seconds,
    })
}

/// The provenance row of the Python call itself (`call`: as the user wrote it).
pub(crate) fn python_call(call: String) -> Setting {
    Setting {
        section: "Python call".into(),
        key: "call".into(),
        value: call,
        source: SettingSource::Keyword,
    }
}

/// `work()`, its wall time added to `seconds`: the time a call spends in the library,
/// which `Report._library_seconds` gives so that the binding's own share of a call can
/// be measured in the same call (examples/python/overhead.py).
fn timed<T>(seconds: &mut f64, work: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = work();
    *seconds += start.elapsed().as_secs_f64();
    out
}

/// The stages of `identify` (the library's `identify_with_regressor`, with the CLI's
/// steady-state check), each without the GIL, signals checked between them; their time
/// is added to `seconds`.
#[allow(clippy::type_complexity)]
fn run_identify(
    py: Python<'_>,
    model: &DampingModel,
    records: &[Record],
    settings: &Identification,
    seconds: &mut f64,
) -> PyResult<(Regressor, FitReport, Option<SteadyStateReport>)> {
    let steady = py
        .detach(|| timed(seconds, || enforce_steady_state(records, settings)))
        .map_err(with_transient_hint)?;
    py.check_signals()?;
    let regressor = py
        .detach(|| {
            timed(seconds, || {
                settings.settings.fit.validate()?;
                Regressor::build(model, records, &settings.settings.regressor)
            })
        })
        .py_err()?;
    py.check_signals()?;
    let report = py
        .detach(|| {
            timed(seconds, || {
                let noise =
                    assess_or_none(model, records, &settings.settings.regressor, &regressor);
                identify_regressor(&regressor, &settings.settings.fit).map(|r| {
                    r.with_velocity_noise(noise)
                        .with_steady_state(steady.as_ref())
                })
            })
        })
        .py_err()?;
    Ok((regressor, report, steady))
}

/// `identify_file(path)`: `dampid identify PATH` (data paths relative to the file's
/// folder, `path` relative to the working directory), returning its report; `str()`
/// of it is the CLI's text.
#[pyfunction]
#[pyo3(signature = (path, accept_transient=false))]
fn identify_file(py: Python<'_>, path: PathBuf, accept_transient: bool) -> PyResult<PyReport> {
    let mut library_seconds = 0.0;
    let seconds = &mut library_seconds;
    let mut job = py
        .detach(|| timed(seconds, || dampid::model_file::load(&path)))
        .py_err()?;
    py.check_signals()?;
    job.steady_state.accept_transient |= accept_transient;
    let steady = py
        .detach(|| timed(seconds, || job.steady_state()))
        .py_err()?;
    if let Some(Err(e)) = steady.as_ref().map(|s| s.enforce()) {
        // The CLI's message: its context, then the error.
        return Err(error::raise(
            e.kind(),
            format!(
                "{}: set accept_transient = true in [identification] or pass --accept-transient to use these windows anyway: {e}",
                path.display()
            ),
        ));
    }
    py.check_signals()?;
    // The call as the page's first setting row; the job's own rows (the model file's
    // keys; `accept_transient` marked as set by the call when it overrides the file)
    // follow it in the page.
    let settings = vec![python_call(format!(
        "dampid.identify_file({:?}, accept_transient={})",
        path.display().to_string(),
        if accept_transient { "True" } else { "False" }
    ))];
    if job.estimates_nonlinear() {
        return identify_file_varpro(py, job, path, steady, settings, library_seconds);
    }
    let seconds = &mut library_seconds;
    let regressor = py
        .detach(|| {
            timed(seconds, || {
                job.settings.fit.validate()?;
                job.regressor()
            })
        })
        .py_err()?;
    py.check_signals()?;
    let report = py
        .detach(|| {
            timed(seconds, || {
                let noise = assess_or_none(
                    &job.model,
                    &job.records,
                    &job.settings.regressor,
                    &regressor,
                );
                identify_regressor(&regressor, &job.settings.fit).map(|r| {
                    r.with_velocity_noise(noise)
                        .with_steady_state(steady.as_ref())
                })
            })
        })
        .py_err()?;
    // The CLI's text: title, counts, preamble, report, truth, equivalent damping.
    let text = timed(seconds, || {
        let mut text = format!(
            "{}\n{}, {}\n{}{report}",
            job.title,
            count(job.records.len(), "record"),
            count(report.residuals.len(), "equation"),
            job.preamble(steady.as_ref())
        );
        if let Some(truth) = &job.truth {
            text.push_str(&report.against(truth).to_string());
        }
        match job.equivalent_damping(&report) {
            Some(Ok(e)) => text.push_str(&e.to_string()),
            Some(Err(e)) => text.push_str(&format!("equivalent damping not computed: {e}\n")),
            None => {}
        }
        text
    });
    Ok(PyReport {
        report,
        varpro: None,
        model: job.model.clone(),
        model_file: (path.display().to_string(), String::new()),
        regressor,
        steady,
        settings,
        source: Source::Job(Box::new(job), path),
        text,
        library_seconds,
    })
}

/// `identify_file` of a job with estimated law parameters or residual receptances: the
/// variable-projection fit `dampid identify` runs, its text (report, then the
/// equivalent damping of a one-mode stepped-sine job at η̂) and the report at η̂.
fn identify_file_varpro(
    py: Python<'_>,
    job: dampid::model_file::Job,
    path: PathBuf,
    steady: Option<SteadyStateReport>,
    settings: Vec<Setting>,
    mut library_seconds: f64,
) -> PyResult<PyReport> {
    let seconds = &mut library_seconds;
    let fit = py
        .detach(|| {
            timed(seconds, || {
                job.settings.fit.validate()?;
                job.identify_varpro().unwrap_or_else(|| {
                    Err(dampid::Error::InvalidChoice {
                        name: "identify_file".into(),
                        given: path.display().to_string(),
                        reason: "the job estimates no nonlinear parameter".into(),
                    })
                })
            })
        })
        .py_err()?;
    py.check_signals()?;
    // The CLI's text: title, report, equivalent damping (none when not an estimate).
    let text = timed(seconds, || {
        let mut text = format!("{}\n{}", job.title, fit.report);
        match job.equivalent_damping_varpro(&fit.model, &fit.report) {
            Some(Ok(e)) if fit.report.is_estimate() => text.push_str(&e.to_string()),
            Some(Ok(_)) => {
                text.push_str("equivalent damping not computed: the fit is not an estimate\n")
            }
            Some(Err(e)) => text.push_str(&format!("equivalent damping not computed: {e}\n")),
            None => {}
        }
        text
    });
    let dampid::model_file::VarProFit {
        regressor,
        model,
        report,
    } = fit;
    Ok(PyReport {
        report: report.fit.clone(),
        varpro: Some(report),
        model,
        model_file: (path.display().to_string(), String::new()),
        regressor,
        steady,
        settings,
        source: Source::Job(Box::new(job), path),
        text,
        library_seconds,
    })
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

/// `regressor_rows(model, record, record_index=0, **settings) -> (A, b, labels)`: the
/// rows one record contributes (one per window), for campaigns that map records to rows
/// on many machines and fit once (`fit_rows`). `labels` is a structured array with the
/// fields of the library's row label; `record_index` numbers the record in the campaign.
#[pyfunction]
#[pyo3(signature = (model, record, record_index=0, **settings))]
#[allow(clippy::type_complexity)]
fn regressor_rows<'py>(
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
    let built = mode_records(list, &lent.records, &settings).and_then(|rebuilt| {
        let records = rebuilt.as_deref().unwrap_or(&lent.records);
        let identification = &settings.identification;
        py.detach(|| {
            enforce_steady_state(records, identification)?;
            Regressor::build(&model.model, records, &identification.settings.regressor)
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
    let labels: Vec<_> = regressor
        .rows()
        .iter()
        .map(|r| {
            (
                r.record.clone(),
                record_index as i64,
                r.window as i64,
                r.start_time,
                r.cycles as i64,
            )
        })
        .collect();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", label_dtype(py)?)?;
    let labels = numpy.call_method("array", (labels,), Some(&kwargs))?;
    Ok((
        matrix.into_pyarray(py),
        regressor.rhs().to_vec().into_pyarray(py),
        labels,
    ))
}

/// `fit_rows(model, A, b, labels=None, **settings) -> Report`: the fit of stacked rows
/// (`regressor_rows` of every record), equal bit for bit to `identify` of the records
/// when the rows are stacked in record order.
#[pyfunction]
#[pyo3(signature = (model, a, b, labels=None, **settings))]
fn fit_rows(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    labels: Option<&Bound<'_, PyAny>>,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyReport> {
    let py_model = model.get();
    let settings = settings::settings(settings, &py_model.text, &py_model.file)?;
    let model = &py_model.model;
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
            })
            .collect(),
        Some(labels) => read_labels(labels)?,
    };
    let regressor = Regressor::from_parts(matrix, rhs, model.coefficient_names(), rows).py_err()?;
    let fit = &settings.identification.settings.fit;
    let mut fit_seconds = 0.0;
    let report = py
        .detach(|| {
            timed(&mut fit_seconds, || {
                fit.validate()?;
                identify_regressor(&regressor, fit)
            })
        })
        .py_err()?;
    let text = report.to_string();
    let provenance = settings.provenance(format!(
        "dampid.fit_rows(model, A, b, ..., {})",
        settings.given
    ));
    Ok(PyReport {
        report,
        varpro: None,
        model: model.clone(),
        model_file: (py_model.file.clone(), py_model.text.clone()),
        regressor,
        steady: None,
        settings: provenance,
        source: Source::Rows,
        text,
        library_seconds: fit_seconds,
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
    let (index, window, start, cycles) = (
        index.as_array(),
        window.as_array(),
        start.as_array(),
        cycles.as_array(),
    );
    Ok(records
        .into_iter()
        .enumerate()
        .map(|(r, record)| RowLabel {
            record,
            record_index: index[r] as usize,
            window: window[r] as usize,
            start_time: start[r],
            cycles: cycles[r] as usize,
        })
        .collect())
}

#[pymodule]
#[pyo3(name = "dampid")]
fn dampid_python(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // As the dampid binary: faer sequential, so results are bitwise the CLI's.
    faer::set_global_parallelism(faer::Par::Seq);
    m.add("DampidError", m.py().get_type::<DampidError>())?;
    m.add_class::<PyModel>()?;
    m.add_class::<PyRecord>()?;
    m.add_class::<PyReport>()?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(identify_file, m)?)?;
    m.add_function(wrap_pyfunction!(regressor_rows, m)?)?;
    m.add_function(wrap_pyfunction!(fit_rows, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
