//! `dampid.Report`: the library's [`Identification`] with the context its text and HTML
//! forms need (the job, or the records for the HTML plots, and the provenance).

use std::path::PathBuf;

use dampid::command::identify::{Identified, IdentifyOptions};
use dampid::identify::{Equivalent, Identification};
use dampid::model_file::Job;
use dampid::record::{Record, Sensor};
use dampid::report::html::HtmlReport;
use dampid::report::provenance::{ArrayDigest, COMMIT, Provenance, Setting, VERSION, now_utc};
use dampid::report::{Estimation, FitReport};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::{IntoPy, to_py};
use crate::record::{Lent, PyRecord};

/// Where the records of a report are, for its HTML plots and provenance.
pub enum Source {
    /// A model file's job (`identify_file`), the file's path and the options it ran
    /// with: records, title, truth and POD.
    Job(Box<Job>, PathBuf, IdentifyOptions),
    /// The `Record` objects of `identify`.
    Records(Vec<Py<PyRecord>>),
    /// Rows alone (`fit_rows`): no records.
    Rows,
}

/// The result of an identification.
#[pyclass(name = "Report", module = "dampid", frozen)]
pub struct PyReport {
    /// What the identification found: the report (with its estimated parameters, when
    /// there are any), the regressor and model at the estimate, the steady state.
    pub identification: Identification,
    /// The model's file (or `<model text>`) and text, for the provenance of arrays.
    pub model_file: (String, String),
    /// The settings of the call and every setting in effect, for the provenance.
    pub settings: Vec<Setting>,
    pub source: Source,
    /// `str(report)`: the CLI's text for a model file, the report table otherwise.
    pub text: String,
    /// Wall seconds the call spent in the library's stages (`_library_seconds`).
    pub library_seconds: f64,
}

fn names_to<T>(
    report: &FitReport,
    value: impl Fn(&dampid::report::CoefficientEstimate) -> T,
) -> Vec<(String, T)> {
    report
        .coefficients
        .iter()
        .chain(&report.nuisance)
        .map(|c| (c.name.clone(), value(c)))
        .collect()
}

impl PyReport {
    /// The report.
    fn report(&self) -> &FitReport {
        &self.identification.report
    }

    /// Its estimation, when it estimated nonlinear parameters.
    fn estimation(&self) -> Option<&Estimation> {
        self.report().estimation.as_ref()
    }
}

#[pymethods]
impl PyReport {
    /// How the fit ended ("Solved", ...).
    #[getter]
    fn status(&self) -> String {
        format!("{:?}", self.report().status)
    }

    /// Coefficient name → value (nuisance unknowns of a non-periodic fit included).
    #[getter]
    fn coefficients<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (name, value) in names_to(self.report(), |c| c.value) {
            dict.set_item(name, value)?;
        }
        Ok(dict)
    }

    /// Coefficient name → standard error (None where the data give none); with
    /// estimated nonlinear parameters the joint one (which includes their
    /// uncertainty; None when the fit is not an estimate).
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        if let Some(estimation) = self.estimation() {
            let estimate = self.report().is_estimate();
            for c in &estimation.coefficients {
                dict.set_item(&c.name, c.std_error.filter(|_| estimate))?;
            }
            return Ok(dict);
        }
        for (name, value) in names_to(self.report(), |c| c.std_error) {
            dict.set_item(name, value)?;
        }
        Ok(dict)
    }

    /// Coefficient name → (low, high): the bootstrap interval when one was run, else
    /// θ ± 1.96 se (the HTML report's 95% interval); None without a standard error.
    /// With estimated nonlinear parameters, the joint intervals (`joint_intervals`).
    #[getter]
    fn intervals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        if self.estimation().is_some() {
            return Ok(self.joint_intervals(py)?.unwrap_or_else(|| PyDict::new(py)));
        }
        let dict = PyDict::new(py);
        for (name, interval) in names_to(self.report(), |c| match (&c.interval, c.std_error) {
            (Some(i), _) => Some((i.lower, i.upper)),
            (None, Some(se)) => Some((c.value - 1.96 * se, c.value + 1.96 * se)),
            (None, None) => None,
        }) {
            dict.set_item(name, interval)?;
        }
        Ok(dict)
    }

    /// True when the numbers are estimates: the fit is usable and every coefficient is
    /// determined; with estimated nonlinear parameters, also the outer loop converged.
    #[getter]
    fn is_estimate(&self) -> bool {
        self.report().is_estimate()
    }

    /// Estimated nonlinear parameter name → (value, (low, high)) at the report's
    /// confidence level: the profile-likelihood interval (an end the data do not bound
    /// within the parameter's bounds is None), else the joint Wald interval; the
    /// interval is None when the fit is not an estimate (the value is then the last
    /// trial). None for a fit without estimated nonlinear parameters.
    #[getter]
    fn estimated_parameters<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(varpro) = self.estimation() else {
            return Ok(None);
        };
        let estimate = self.report().is_estimate();
        let dict = PyDict::new(py);
        for p in &varpro.parameters {
            let interval = match (&p.interval, p.joint_interval) {
                _ if !estimate => None,
                (Some(i), _) => Some((i.lower, i.upper)),
                (None, Some([l, u])) => Some((Some(l), Some(u))),
                (None, None) => None,
            };
            dict.set_item(&p.name, (p.value, interval))?;
        }
        Ok(Some(dict))
    }

    /// Coefficient name → (low, high) joint interval of a fit with estimated nonlinear
    /// parameters (from the covariance of the full Jacobian, so it includes their
    /// uncertainty); None per coefficient without one (or when the fit is not an
    /// estimate). None for a fit without estimated nonlinear parameters.
    #[getter]
    fn joint_intervals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(varpro) = self.estimation() else {
            return Ok(None);
        };
        let estimate = self.report().is_estimate();
        let dict = PyDict::new(py);
        for c in &varpro.coefficients {
            let interval = c.lower.zip(c.upper).filter(|_| estimate);
            dict.set_item(&c.name, interval)?;
        }
        Ok(Some(dict))
    }

    /// Condition number of the column-scaled regressor (None when rank deficient).
    #[getter]
    fn condition_number(&self) -> Option<f64> {
        self.report().condition_number
    }

    /// Numerical rank.
    #[getter]
    fn rank(&self) -> usize {
        self.report().rank
    }

    /// ‖b − Aθ‖ / ‖b‖.
    #[getter]
    fn relative_residual(&self) -> f64 {
        self.report().relative_residual
    }

    /// Mean residual relative to the mean |input work|.
    #[getter]
    fn residual_bias(&self) -> f64 {
        self.report().residual_bias.relative_mean
    }

    /// Wall seconds the call that made this report spent inside the library's stages
    /// (steady-state check, regressor, fit; for `identify_file` also the loading and the
    /// text): the rest of the call is the binding's own share (for benchmarks:
    /// examples/python/overhead.py).
    #[getter]
    fn _library_seconds(&self) -> f64 {
        self.library_seconds
    }

    /// The warnings in words.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.report()
            .warnings
            .iter()
            .map(|w| w.to_string())
            .collect()
    }

    /// The JSON report (the CLI's `--json` "report" object, with its "estimation" when
    /// nonlinear parameters were estimated) as a string.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(self.report())
            .map_err(|e| crate::error::argument(format!("the report does not serialize: {e}")))
    }

    /// A free decay's backbone, one dict per window (record, window, time, amplitude,
    /// frequency, measured and fitted ζ); `None` for other jobs.
    #[getter]
    fn backbone<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(backbone) = &self.identification.backbone else {
            return Ok(None);
        };
        let text = serde_json::to_string(&backbone.points)
            .map_err(|e| crate::error::argument(format!("the backbone does not serialize: {e}")))?;
        Ok(Some(py.import("json")?.call_method1("loads", (text,))?))
    }

    /// The JSON report as a dict (`json.loads(report.to_json())`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.to_json()?,))
    }

    fn __str__(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        let mut coefficients: Vec<String> = names_to(self.report(), |c| c.value)
            .into_iter()
            .map(|(n, v)| format!("{n}={v:.6e}"))
            .collect();
        if let Some(varpro) = self.estimation() {
            coefficients.extend(
                varpro
                    .parameters
                    .iter()
                    .map(|p| format!("{}={:.6e}", p.name, p.value)),
            );
        }
        format!(
            "Report(status={}, {})",
            self.status(),
            coefficients.join(", ")
        )
    }

    /// A compact HTML table for notebooks.
    fn _repr_html_(&self) -> String {
        let mut html = format!(
            "<table><caption>dampid: {} (rank {}, condition {}, relative residual {:.3e})</caption><tr><th>coefficient</th><th>value</th><th>std. error</th></tr>",
            self.status(),
            self.report().rank,
            self.report()
                .condition_number
                .map_or("-".to_string(), |c| format!("{c:.3e}")),
            self.report().relative_residual
        );
        // With estimated nonlinear parameters: the joint standard errors (none when the
        // fit is not an estimate), then the parameters.
        let estimate = self.report().is_estimate();
        let rows: Vec<(String, f64, Option<f64>)> = match self.estimation() {
            Some(varpro) => varpro
                .coefficients
                .iter()
                .map(|c| (c.name.clone(), c.value, c.std_error))
                .chain(
                    varpro
                        .parameters
                        .iter()
                        .map(|p| (p.name.clone(), p.value, p.std_error)),
                )
                .map(|(n, v, s)| (n, v, s.filter(|_| estimate)))
                .collect(),
            None => names_to(self.report(), |c| (c.value, c.std_error))
                .into_iter()
                .map(|(n, (v, s))| (n, v, s))
                .collect(),
        };
        for (name, value, se) in rows {
            html.push_str(&format!(
                "<tr><td>{}</td><td>{:.6e}</td><td>{}</td></tr>",
                escape(&name),
                value,
                se.map_or("-".to_string(), |s| format!("{s:.3e}"))
            ));
        }
        html.push_str("</table>");
        for w in &self.report().warnings {
            html.push_str(&format!("<p>⚠ {}</p>", escape(&w.to_string())));
        }
        html
    }

    /// Writes the full HTML report (the CLI's `--html`) to `path`; an existing file is
    /// refused unless `overwrite=True`.
    #[pyo3(signature = (path, overwrite=false))]
    fn write_html(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        overwrite: bool,
    ) -> PyResult<()> {
        use dampid::io::output::{Overwrite, write_file};
        let found = &self.identification;
        let page = |source: dampid::regressor::Source<'_>, provenance| {
            HtmlReport {
                title: "dampid",
                model: &found.model,
                source,
                regressor: &found.regressor,
                report: &found.report,
                truth: None,
                pod: None,
                steady: found.steady_state.as_deref(),
                equivalent: found.equivalent.as_ref().map(Equivalent::as_result),
                backbone: found.backbone.as_ref(),
                provenance: Some(&provenance),
                units: None,
            }
            .render()
        };
        let page = match &self.source {
            Source::Job(job, file, options) => {
                let settings = options.settings(job);
                let mut provenance = job.provenance(file, &settings, &[]).py_err()?;
                provenance
                    .settings
                    .splice(0..0, self.settings.iter().cloned());
                let outcome = Identified {
                    job,
                    options,
                    identification: found,
                };
                outcome.html_with(Some(&provenance))
            }
            Source::Rows => {
                // The rows came as arrays: A and b are what the fit read.
                let regressor = &found.regressor;
                let rhs = faer::ColRef::from_slice(regressor.rhs());
                let arrays = vec![
                    ArrayDigest::of("rows", "A", regressor.matrix().as_ref(), false),
                    ArrayDigest::of("rows", "b", rhs.as_mat(), true),
                ];
                page(
                    dampid::regressor::Source::Rows(regressor),
                    self.arrays_provenance(arrays),
                )
            }
            Source::Records(list) => {
                let bound: Vec<Bound<'_, PyRecord>> =
                    list.iter().map(|r| r.bind(py).clone()).collect();
                let lent = Lent::take(&bound)?;
                let arrays = lent.records.iter().flat_map(digests).collect();
                let page = page((&lent.records).into(), self.arrays_provenance(arrays));
                lent.restore();
                page
            }
        }
        .py_err()?;
        let overwrite = if overwrite {
            Overwrite::Replace
        } else {
            Overwrite::Refuse
        };
        write_file(&path, overwrite, |sink| {
            std::io::Write::write_all(sink, page.as_bytes()).map_err(|e| dampid::Error::Output {
                path: path.display().to_string(),
                message: e.to_string(),
            })
        })
        .map(drop)
        .map_err(to_py)
    }
}

impl PyReport {
    /// The provenance of a report on arrays: the model's text, every array's shape and
    /// SHA-256, the settings, version, commit and date.
    fn arrays_provenance(&self, arrays: Vec<ArrayDigest>) -> Provenance {
        Provenance {
            model_file: self.model_file.0.clone(),
            model_text: self.model_file.1.clone(),
            data_files: Vec::new(),
            arrays,
            settings: self.settings.clone(),
            version: VERSION.into(),
            commit: COMMIT.into(),
            date: now_utc(),
        }
    }
}

/// The arrays of `record` as the caller gave them (as float64): the motion its sensors
/// measured ("x", with "v" when measured velocities were given; or "v" or "a" alone),
/// then each force channel as an N-vector.
fn digests(record: &Record) -> Vec<ArrayDigest> {
    let label = record.label();
    let mut out = Vec::new();
    match record.measured_motion() {
        Some(motion) => {
            let name = match motion.sensors.first() {
                Some(Sensor::Acceleration) => "a",
                _ => "v",
            };
            out.push(ArrayDigest::of(label, name, motion.signals.as_ref(), false));
        }
        None => {
            out.push(ArrayDigest::of(label, "x", record.displacements(), false));
            if let Some(v) = record.velocities() {
                out.push(ArrayDigest::of(label, "v", v, false));
            }
        }
    }
    let signals = &record.forcing().signals;
    for k in 0..signals.ncols() {
        out.push(ArrayDigest::of(
            label,
            &format!("force {}", k + 1),
            signals.col(k).as_mat(),
            true,
        ));
    }
    out
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
