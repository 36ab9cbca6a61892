//! dampid from Python: `Model`, `Record`, `identify`, `identify_file`, `Report`, and the
//! campaign trio `regressor_rows` / `stack_rows` / `fit_rows` with their `Rows`
//! (docs/python.md).
//!
//! A front end like the `dampid` binary: it turns Python arguments into the library's
//! (records lent from NumPy, keyword settings read as a model file's
//! `[identification]`), calls the library's one pipeline (`dampid::identify::identify`,
//! or the `identify` command for a model file) with the GIL released (`Python::detach`),
//! and wraps what it returns. faer runs sequentially (`Par::Seq`, set once at import)
//! as in the binary, so results are the CLI's bit for bit whatever the thread count.

mod arrays;
mod campaign;
mod error;
mod record;
mod report;
mod settings;

use std::path::PathBuf;
use std::time::Instant;

use dampid::command::identify::IdentifyOptions;
use dampid::identify::{Identification, identify as run};
use dampid::model::DampingModel;
use dampid::model_file::parse_model;
use dampid::prep::motion::{Integration, reintegrated};
use dampid::progress::silent;
use dampid::record::Record;
use dampid::regressor::ParametricRegressor;
use dampid::report::provenance::{Setting, SettingSource};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use error::{DampidError, IntoPy, argument, to_py};
use record::{Lent, PyRecord};
use report::{PyReport, Source};
use settings::Settings;

/// The Rust side's allocator, as the `dampid` binary's (python/Cargo.toml says why).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// A damping model: the `[[terms]]` of a model file.
#[pyclass(name = "Model", module = "dampid", frozen)]
pub(crate) struct PyModel {
    pub(crate) model: DampingModel,
    /// The model file's text (for `[non_periodic]` keyword settings and the provenance).
    pub(crate) text: String,
    /// Its path, or `<model text>`.
    pub(crate) file: String,
}

#[pymethods]
impl PyModel {
    /// The model of model-file text (its `dofs`, `[matrices]` and `[[terms]]`; other
    /// sections are checked for form but not built).
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Self> {
        let file = "<model text>".to_string();
        let model = parse_model(text, &file).py_err()?;
        Ok(PyModel {
            model,
            text: text.to_string(),
            file,
        })
    }

    /// The model of the model file at `path`.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| {
            to_py(dampid::Error::ModelFile {
                file: file.clone(),
                line: 0,
                column: 0,
                message: e.to_string(),
                cause: None,
            })
        })?;
        let model = parse_model(&text, &file).py_err()?;
        Ok(PyModel { model, text, file })
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

/// A library error; a refused steady state with what accepts it from Python.
pub(crate) fn with_transient_hint(e: dampid::Error) -> PyErr {
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
                let kind = e
                    .into_inner()
                    .get_type()
                    .name()
                    .map_or("?".into(), |n| n.to_string());
                argument(format!("records[{k}] is a {kind}, not a dampid.Record"))
            })
        })
        .collect()
}

/// The records of the `list` (lent as `records`) in the mode of `settings`: every record
/// needs its period over whole periods; over fixed spans, records of velocity or
/// acceleration sensors are integrated again with `high_pass`, as a model file's are; a
/// free decay's records become their modes' ([`dampid::prep::free_decay::isolate_with`],
/// through the modal filter of several sensors when one is given).
pub(crate) fn in_mode(
    list: &[Bound<'_, PyRecord>],
    records: &[Record],
    settings: &Settings,
) -> PyResult<Option<Vec<Record>>> {
    if let Some(decay) = &settings.free_decay {
        return records
            .iter()
            .map(|r| {
                dampid::prep::free_decay::isolate_with(r, settings.modal_filter.as_ref(), decay)
                    .map(|d| d.record)
            })
            .collect::<dampid::Result<Vec<_>>>()
            .map(Some)
            .py_err();
    }
    if !settings.non_periodic {
        if let Some(e) = list.iter().find_map(|r| r.get().undetected()) {
            return Err(to_py(e.clone()));
        }
        return Ok(None);
    }
    match settings.high_pass {
        Some(cutoff) => reintegrated(records, Integration::HighPass { cutoff }).py_err(),
        None if records.iter().all(|r| r.measured_motion().is_none()) => Ok(None),
        None => Err(to_py(dampid::Error::Missing {
            name: "high_pass in non_periodic".into(),
            reason: "records of velocity or acceleration sensors that are not periodic are integrated with a zero-phase high-pass against drift: add \"high_pass\": f_c (the cut-off frequency, cycles per time unit, well below the slowest motion of interest) to non_periodic={...}; content below f_c is removed".into(),
        })),
    }
}

/// `work()` without the GIL, its wall time kept: the time a call spends in the library,
/// which `Report._library_seconds` gives (examples/python/overhead.py).
pub(crate) fn timed<T: Send>(
    py: Python<'_>,
    seconds: &mut f64,
    work: impl FnOnce() -> T + Send,
) -> T {
    let start = Instant::now();
    let out = py.detach(work);
    *seconds += start.elapsed().as_secs_f64();
    out
}

/// `identify(model, records, **settings)`: settings are the `[identification]` keys,
/// `non_periodic={...}` the keys of `[non_periodic]` and `free_decay={...}` those of
/// `[free_decay]`.
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
    let mut seconds = 0.0;
    let found = in_mode(&list, &lent.records, &settings).and_then(|rebuilt| {
        let records = rebuilt.as_deref().unwrap_or(&lent.records);
        let problem = ParametricRegressor::linear(&model.model, records);
        timed(py, &mut seconds, || {
            run(&problem, &settings.identification, &silent)
        })
        .map_err(with_transient_hint)
    });
    lent.restore();
    let found = found?;
    let call = format!("dampid.identify(model, records, {})", settings.given);
    Ok(PyReport {
        text: found.report.to_string(),
        identification: found,
        model_file: (model.file.clone(), model.text.clone()),
        settings: settings.provenance(call),
        source: Source::Records(list.into_iter().map(|r| r.unbind()).collect()),
        library_seconds: seconds,
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

/// `identify_file(path)`: `dampid identify PATH` (data paths relative to the file's
/// folder, `path` relative to the working directory), returning its report; `str()`
/// of it is the CLI's text.
#[pyfunction]
#[pyo3(signature = (path, accept_transient=false, accept_negative_work=false))]
fn identify_file(
    py: Python<'_>,
    path: PathBuf,
    accept_transient: bool,
    accept_negative_work: bool,
) -> PyResult<PyReport> {
    let python = |yes: bool| if yes { "True" } else { "False" };
    let call = format!(
        "dampid.identify_file({:?}, accept_transient={}, accept_negative_work={})",
        path.display().to_string(),
        python(accept_transient),
        python(accept_negative_work)
    );
    let options = IdentifyOptions {
        accept_transient,
        accept_negative_work,
        command_line: call.clone(),
        ..Default::default()
    };
    let mut seconds = 0.0;
    let loaded = timed(py, &mut seconds, || {
        dampid::model_file::load(&path, Default::default())
    });
    let job = loaded.py_err()?;
    py.check_signals()?;
    let found: Identification = timed(py, &mut seconds, || {
        dampid::command::identify::run(&job, &options, &silent)
    })
    .map_err(|e| {
        if e.kind() == "not_steady" {
            // The CLI's message: its context, then the error.
            let hint = dampid::command::TRANSIENT_HINT;
            error::raise(e.kind(), format!("{}: {hint}: {e}", path.display()))
        } else {
            to_py(e)
        }
    })?;
    let text = dampid::command::identify::Identified {
        job: &job,
        options: &options,
        identification: &found,
    }
    .to_string();
    Ok(PyReport {
        identification: found,
        model_file: (path.display().to_string(), String::new()),
        // The call as the page's first setting row; the job's own rows (the model
        // file's keys) follow it in the page.
        settings: vec![python_call(call)],
        source: Source::Job(Box::new(job), path, options),
        text,
        library_seconds: seconds,
    })
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
    m.add_class::<campaign::PyRows>()?;
    m.add_function(wrap_pyfunction!(campaign::regressor_rows, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::stack_rows, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::fit_rows, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
