//! `dampid.Record`: one experiment from NumPy arrays, built into the library's
//! [`dampid::record::Record`] at construction (so bad arrays fail where they are given).
//!
//! The record lives inside the Python object. `identify` lends the records of its list
//! to the library for the call and puts them back ([`Lent`]): the library reads a slice
//! of records, and moving them costs nothing where cloning would copy every sample.

use std::sync::Mutex;

use dampid::Error;
use dampid::io::table::Table;
use dampid::prelude::{Forcing, Record, RecordParts, Sensor, SensorParts, record_from_sensors};
use dampid::prep::motion::Integration;
use dampid::prep::period::detect_period;
use faer::Mat;
use pyo3::prelude::*;

use crate::arrays::{matrix, vector};
use crate::error::{IntoPy, argument, to_py};

/// One experiment: motion (N × n), force channels on DOFs numbered from 1, the time
/// base, and the driving period.
#[pyclass(name = "Record", module = "dampid", frozen)]
pub struct PyRecord {
    record: Mutex<Option<Record>>,
    label: String,
    samples: usize,
    dofs: usize,
    step: f64,
    period: f64,
    /// Why no period could be detected from the force, when none was given: raised by
    /// identifications over whole periods (and by `.period`); a non-periodic
    /// identification (`non_periodic=`) needs none, as in a model file.
    undetected: Option<Error>,
}

#[pymethods]
impl PyRecord {
    #[new]
    #[pyo3(signature = (x=None, v=None, a=None, t=None, step=None, forces=Vec::new(), frequency=None, period=None, label=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        x: Option<&Bound<'_, PyAny>>,
        v: Option<&Bound<'_, PyAny>>,
        a: Option<&Bound<'_, PyAny>>,
        t: Option<&Bound<'_, PyAny>>,
        step: Option<f64>,
        forces: Vec<(Bound<'_, PyAny>, i64)>,
        frequency: Option<f64>,
        period: Option<f64>,
        label: Option<String>,
    ) -> PyResult<Self> {
        let label = label.unwrap_or_else(|| "record".to_string());
        let (motion, sensors, velocities) = match (x, v, a) {
            (Some(x), v, None) => {
                let x = matrix(x, "x")?;
                let v = v.map(|v| matrix(v, "v")).transpose()?;
                let n = x.ncols();
                (x, vec![Sensor::Displacement; n], v)
            }
            (None, Some(v), None) => {
                let v = matrix(v, "v")?;
                let n = v.ncols();
                (v, vec![Sensor::Velocity; n], None)
            }
            (None, None, Some(a)) => {
                let a = matrix(a, "a")?;
                let n = a.ncols();
                (a, vec![Sensor::Acceleration; n], None)
            }
            (None, None, None) => {
                return Err(to_py(Error::Missing {
                    name: "motion".into(),
                    reason: "give x (displacements), or v (velocities) or a (accelerations) alone"
                        .into(),
                }));
            }
            _ => {
                return Err(to_py(Error::InvalidChoice {
                    name: "motion".into(),
                    given: "a beside x or v".into(),
                    reason: "give x (with measured v if you have them), or v alone, or a alone"
                        .into(),
                }));
            }
        };
        let samples = motion.nrows();
        let dofs = motion.ncols();
        let (step, start_time) = match (t, step) {
            (Some(t), None) => {
                let t = vector(t, "t")?;
                if t.len() != samples {
                    return Err(to_py(Error::DimensionMismatch {
                        what: "samples of t vs motion".into(),
                        expected: samples,
                        found: t.len(),
                    }));
                }
                let start = t.first().copied().unwrap_or(0.0);
                let table = Table {
                    file: "t".into(),
                    headers: vec!["t".into()],
                    columns: vec![t],
                };
                (table.uniform_step("t").py_err()?.step, start)
            }
            (None, Some(step)) => (step, 0.0),
            (given_t, _) => {
                let given = if given_t.is_some() {
                    "both t and step"
                } else {
                    "neither t nor step"
                };
                return Err(to_py(Error::InvalidChoice {
                    name: "time base".into(),
                    given: given.into(),
                    reason: "give the sample times t or the step".into(),
                }));
            }
        };
        let mut signals = Mat::zeros(samples, forces.len());
        let mut force_dofs = Vec::with_capacity(forces.len());
        for (k, (signal, dof)) in forces.iter().enumerate() {
            let what = format!("force {}", k + 1);
            let signal = vector(signal, &what)?;
            if signal.len() != samples {
                return Err(to_py(Error::DimensionMismatch {
                    what: format!("samples of {what} vs motion"),
                    expected: samples,
                    found: signal.len(),
                }));
            }
            // DOFs from 1; the library's check names the channel and the DOF from 1 too.
            let index = usize::try_from(*dof).ok().and_then(|d| d.checked_sub(1));
            let Some(index) = index else {
                return Err(to_py(Error::DofOutOfRange {
                    what: format!("force {}", k + 1),
                    dof: usize::try_from(*dof).unwrap_or(0),
                    dofs,
                }));
            };
            for (i, s) in signal.iter().enumerate() {
                signals[(i, k)] = *s;
            }
            force_dofs.push(index);
        }
        let mut undetected = None;
        let period = match (period, frequency) {
            (Some(p), None) => p,
            (None, Some(omega)) => 2.0 * std::f64::consts::PI / omega,
            (None, None) => match detect_period(signals.as_ref(), step, &label) {
                Ok(estimate) => estimate.period,
                Err(e) => {
                    // As a model file's record in the non-periodic mode: its duration
                    // (which nothing uses); a periodic identification raises `e`.
                    undetected = Some(e);
                    step * (samples.max(2) - 1) as f64
                }
            },
            (Some(p), Some(_)) => {
                return Err(to_py(Error::InvalidParameter {
                    name: "period".into(),
                    value: p,
                    reason: "give at most one of `period` or `frequency` (rad per unit time); with neither, the period is detected from the force".into(),
                }));
            }
        };
        let forcing = Forcing::on_dofs(signals, force_dofs);
        let built = if let Some(velocities) = velocities {
            Record::new(RecordParts {
                label: label.clone(),
                step,
                start_time,
                displacements: motion,
                velocities: Some(velocities),
                forcing,
                period,
            })
        } else {
            record_from_sensors(SensorParts {
                label: label.clone(),
                step,
                start_time,
                motion,
                sensors,
                forcing,
                period,
                integration: Integration::WholePeriods,
            })
        };
        let record = match (built, &undetected) {
            (Ok(record), _) => record,
            // Measured motion integrated over a period that is not there: the missing
            // period is the cause.
            (Err(_), Some(cause)) => return Err(to_py(cause.clone())),
            (Err(e), None) => return Err(to_py(e)),
        };
        Ok(PyRecord {
            record: Mutex::new(Some(record)),
            label,
            samples,
            dofs,
            step,
            period,
            undetected,
        })
    }

    /// The record's label.
    #[getter]
    fn label(&self) -> &str {
        &self.label
    }

    /// Samples N.
    #[getter]
    fn samples(&self) -> usize {
        self.samples
    }

    /// DOFs n.
    #[getter]
    fn dofs(&self) -> usize {
        self.dofs
    }

    /// The sampling step h.
    #[getter]
    fn step(&self) -> f64 {
        self.step
    }

    /// The driving period T (given, from the frequency, or detected from the force);
    /// `DampidError` when none was given and none could be detected.
    #[getter]
    fn period(&self) -> PyResult<f64> {
        match &self.undetected {
            Some(e) => Err(to_py(e.clone())),
            None => Ok(self.period),
        }
    }

    fn __repr__(&self) -> String {
        let period = match self.undetected {
            Some(_) => "none detected".to_string(),
            None => self.period.to_string(),
        };
        format!(
            "Record(label={:?}, samples={}, dofs={}, step={}, period={period})",
            self.label, self.samples, self.dofs, self.step
        )
    }
}

impl PyRecord {
    /// Why this record has no period, if it has none.
    pub fn undetected(&self) -> Option<&Error> {
        self.undetected.as_ref()
    }
}

/// Records lent by their Python objects for one call, put back by [`Lent::restore`].
pub struct Lent<'py> {
    /// The records, in list order.
    pub records: Vec<Record>,
    /// For each: the object it came from, or `None` for a repeat of an earlier entry (a
    /// clone, returned to nobody).
    owners: Vec<Option<Bound<'py, PyRecord>>>,
}

impl<'py> Lent<'py> {
    /// Takes the records out of `list` (repeated objects are cloned from the first).
    pub fn take(list: &[Bound<'py, PyRecord>]) -> PyResult<Self> {
        let mut lent = Lent {
            records: Vec::with_capacity(list.len()),
            owners: Vec::with_capacity(list.len()),
        };
        for item in list {
            if let Some(first) = list.iter().position(|other| other.is(item))
                && first < lent.records.len()
            {
                let copy = lent.records[first].clone();
                lent.records.push(copy);
                lent.owners.push(None);
                continue;
            }
            let taken = item.get().record.lock().ok().and_then(|mut r| r.take());
            let Some(record) = taken else {
                lent.restore();
                return Err(argument(format!(
                    "record '{}' is in use by an identification running in another thread; pass a different Record object",
                    item.get().label
                )));
            };
            lent.records.push(record);
            lent.owners.push(Some(item.clone()));
        }
        Ok(lent)
    }

    /// Puts every record back into its object.
    pub fn restore(self) {
        for (record, owner) in self.records.into_iter().zip(self.owners) {
            if let Some(owner) = owner
                && let Ok(mut slot) = owner.get().record.lock()
            {
                *slot = Some(record);
            }
        }
    }
}
