//! One experiment: uniformly sampled displacements x (N × n), applied forces, optional
//! measured velocities, and the driving period T.
//!
//! Applied forces are stored as force channels s(t) (N × c) with the generalized force
//! they produce, r(t) = D s(t), where column k of D (n × c) is the load distribution of
//! channel k. A force on one DOF is a unit column; a full generalized force record is
//! D = I. The input power is then v^T r = Σ_k s_k(t) (d_k · v(t)).

use faer::{Mat, MatRef};

use crate::error::{Error, Result, check_finite};

/// How the force channels map onto the generalized forces r(t) = D s(t).
#[derive(Debug, Clone, PartialEq)]
pub enum LoadDistribution {
    /// Channel k acts on DOF `dofs[k]` alone (D has unit columns).
    Dofs(Vec<usize>),
    /// A dense n × c distribution matrix (spatial load shapes, weights included).
    Matrix(Mat<f64>),
}

/// Applied force channels and where they act.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing {
    /// N × c force signals, one column per channel.
    pub signals: Mat<f64>,
    /// Where each channel acts.
    pub distribution: LoadDistribution,
}

impl Forcing {
    /// A full generalized-force record (N × n): channel i acts on DOF i.
    pub fn generalized(forces: Mat<f64>) -> Self {
        let dofs = (0..forces.ncols()).collect();
        Forcing {
            signals: forces,
            distribution: LoadDistribution::Dofs(dofs),
        }
    }

    /// Force channels (N × c), channel k acting on DOF `dofs[k]` (0-based).
    pub fn on_dofs(signals: Mat<f64>, dofs: Vec<usize>) -> Self {
        Forcing {
            signals,
            distribution: LoadDistribution::Dofs(dofs),
        }
    }

    /// Force channels (N × c) with a dense load-distribution matrix (n × c).
    pub fn distributed(signals: Mat<f64>, distribution: Mat<f64>) -> Self {
        Forcing {
            signals,
            distribution: LoadDistribution::Matrix(distribution),
        }
    }

    fn validate(&self, samples: usize, dofs: usize) -> Result<()> {
        if self.signals.nrows() != samples {
            return Err(Error::mismatch(
                "rows (samples) of force signals vs displacements",
                samples,
                self.signals.nrows(),
            ));
        }
        check_finite("force signals", self.signals.as_ref())?;
        let channels = self.signals.ncols();
        match &self.distribution {
            LoadDistribution::Dofs(list) => {
                if list.len() != channels {
                    return Err(Error::mismatch(
                        "force DOF list length vs force channels",
                        channels,
                        list.len(),
                    ));
                }
                for (k, &dof) in list.iter().enumerate() {
                    if dof >= dofs {
                        return Err(Error::dof_index(
                            format!("force channel {}", k + 1),
                            dof,
                            dofs,
                        ));
                    }
                }
            }
            LoadDistribution::Matrix(d) => {
                if d.nrows() != dofs {
                    return Err(Error::mismatch(
                        "rows of load distribution vs DOFs",
                        dofs,
                        d.nrows(),
                    ));
                }
                if d.ncols() != channels {
                    return Err(Error::mismatch(
                        "columns of load distribution vs force channels",
                        channels,
                        d.ncols(),
                    ));
                }
                check_finite("load distribution", d.as_ref())?;
            }
        }
        Ok(())
    }
}

/// The parts of a record, by name. Pass to [`Record::new`], which validates them.
#[derive(Debug, Clone)]
pub struct RecordParts {
    /// A label for reports and errors (e.g. "a=0.25").
    pub label: String,
    /// Sampling step h > 0.
    pub step: f64,
    /// Time of the first sample (used only for labels and plots).
    pub start_time: f64,
    /// N × n displacements.
    pub displacements: Mat<f64>,
    /// Optional N × n measured velocities.
    pub velocities: Option<Mat<f64>>,
    /// Applied force channels.
    pub forcing: Forcing,
    /// Driving period T > 0 (2π/ω).
    pub period: f64,
}

/// A validated experiment record. Construct with [`Record::new`].
#[derive(Debug, Clone)]
pub struct Record {
    parts: RecordParts,
    /// Force channels that are not zero everywhere (found once, when validating).
    active_channels: Vec<usize>,
    /// The force channels' names (their data-file columns), one per channel; empty
    /// when the record was built without them.
    channel_names: Vec<String>,
}

impl Record {
    /// Validates shapes, finiteness, the step and the period.
    pub fn new(parts: RecordParts) -> Result<Self> {
        if !(parts.step.is_finite() && parts.step > 0.0) {
            return Err(Error::invalid(
                "step",
                parts.step,
                "must be finite and positive",
            ));
        }
        if !(parts.period.is_finite() && parts.period > 0.0) {
            return Err(Error::invalid(
                "period",
                parts.period,
                "must be finite and positive",
            ));
        }
        if !parts.start_time.is_finite() {
            return Err(Error::invalid(
                "start_time",
                parts.start_time,
                "must be finite",
            ));
        }
        let (samples, dofs) = parts.displacements.shape();
        if dofs == 0 {
            return Err(Error::Empty {
                what: "displacement DOFs".into(),
            });
        }
        if samples < 3 {
            return Err(Error::RecordTooShort {
                record: parts.label.clone(),
                needed: 3,
                available: samples,
            });
        }
        check_finite("displacements", parts.displacements.as_ref())?;
        if let Some(v) = &parts.velocities {
            if v.shape() != (samples, dofs) {
                let (what, expected, found) = if v.nrows() != samples {
                    ("rows of velocities vs displacements", samples, v.nrows())
                } else {
                    ("columns of velocities vs displacements", dofs, v.ncols())
                };
                return Err(Error::mismatch(what, expected, found));
            }
            check_finite("velocities", v.as_ref())?;
        }
        parts.forcing.validate(samples, dofs)?;
        let signals = &parts.forcing.signals;
        let active_channels = (0..signals.ncols())
            .filter(|&k| signals.col_as_slice(k).iter().any(|s| *s != 0.0))
            .collect();
        Ok(Record {
            parts,
            active_channels,
            channel_names: Vec::new(),
        })
    }

    /// This record with a name for each force channel (the data-file columns they came
    /// from), for messages about a channel; an empty list leaves them unnamed.
    pub fn with_channel_names(mut self, names: Vec<String>) -> Result<Self> {
        let channels = self.parts.forcing.signals.ncols();
        if !names.is_empty() && names.len() != channels {
            return Err(Error::mismatch(
                "force channel names vs force channels",
                channels,
                names.len(),
            ));
        }
        self.channel_names = names;
        Ok(self)
    }

    /// The name of force channel `k` (0-based), when the record has names.
    pub fn channel_name(&self, k: usize) -> Option<&str> {
        self.channel_names.get(k).map(String::as_str)
    }

    /// The force channels' names, one per channel, or empty.
    pub fn channel_names(&self) -> &[String] {
        &self.channel_names
    }

    /// The record's label.
    pub fn label(&self) -> &str {
        &self.parts.label
    }
    /// Sampling step h.
    pub fn step(&self) -> f64 {
        self.parts.step
    }
    /// Time of the first sample.
    pub fn start_time(&self) -> f64 {
        self.parts.start_time
    }
    /// Driving period T.
    pub fn period(&self) -> f64 {
        self.parts.period
    }
    /// Number of samples N.
    pub fn samples(&self) -> usize {
        self.parts.displacements.nrows()
    }
    /// Number of DOFs n.
    pub fn dofs(&self) -> usize {
        self.parts.displacements.ncols()
    }
    /// N × n displacements.
    pub fn displacements(&self) -> MatRef<'_, f64> {
        self.parts.displacements.as_ref()
    }
    /// N × n measured velocities, if any.
    pub fn velocities(&self) -> Option<MatRef<'_, f64>> {
        self.parts.velocities.as_ref().map(|v| v.as_ref())
    }
    /// Applied force channels.
    pub fn forcing(&self) -> &Forcing {
        &self.parts.forcing
    }
    /// The force channels that are not zero everywhere, in order: the only ones whose
    /// input work can differ from zero.
    pub fn active_channels(&self) -> &[usize] {
        &self.active_channels
    }
    /// The validated parts, for transforms that build a new record from this one.
    pub fn parts(&self) -> &RecordParts {
        &self.parts
    }
    /// Consumes the record and returns its parts.
    pub fn into_parts(self) -> RecordParts {
        self.parts
    }
}

/// Column j of a column-major matrix view as a slice.
pub(crate) fn col<'a>(m: MatRef<'a, f64>, j: usize) -> &'a [f64] {
    m.col(j)
        .try_as_col_major()
        .expect("dampid stores matrices column-major")
        .as_slice()
}
