//! Rows built apart, then stacked. Each row reads one window of one record, so the
//! regressor of records 0..n built in one call is, bit for bit, the stack of the
//! regressors of each record built alone, once each part numbers its records as the
//! whole does ([`Regressor::numbered_from`]):
//!
//! | of each part | stacked |
//! |---|---|
//! | A, b, row labels, noise rows, velocity-bias rows, gross work, steady-state windows | one part after the other |
//! | work groups (records) | numbered after the groups of the parts before |
//! | round-off columns | those that are round-off in every part |
//! | velocity-noise gain; displacement-noise range | the largest; the smallest and the largest |
//!
//! Parts must agree on everything else (columns, nuisance count, velocity estimator,
//! steady-state settings), and either all carry a noise model, a velocity bias, gross
//! work and a steady-state check, or none does.

use std::sync::Arc;

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::steady_state::SteadyStateReport;
use crate::regressor::Regressor;
use crate::regressor::passive::WorkScale;
use crate::regressor::robust::NoiseModel;
use crate::regressor::velocity_bias::VelocityBias;

impl Regressor {
    /// This regressor with its records numbered from `first` (row labels, gross-work
    /// groups, steady-state windows): the part of a campaign whose first record is the
    /// campaign's record `first`.
    pub fn numbered_from(mut self, first: usize) -> Self {
        let mut rows = self.rows.to_vec();
        for row in &mut rows {
            row.record_index += first;
        }
        self.rows = rows.into();
        if let Some(steady) = &mut self.steady_state {
            for window in &mut Arc::make_mut(steady).windows {
                window.record_index += first;
            }
        }
        self
    }

    /// This regressor with the steady-state check of its windows (one per row, in row
    /// order), carried to wherever the rows are fitted.
    pub fn with_steady_state(mut self, steady: SteadyStateReport) -> Result<Self> {
        if steady.windows.len() != self.rhs.len() {
            return Err(Error::mismatch(
                "steady-state windows vs regressor rows",
                self.rhs.len(),
                steady.windows.len(),
            ));
        }
        self.steady_state = Some(Arc::new(steady));
        Ok(self)
    }

    /// The parts one after the other (module doc), in the order given.
    pub fn stack(parts: Vec<Regressor>) -> Result<Regressor> {
        let Some(first) = parts.first() else {
            return Err(Error::Empty {
                what: "list of rows to stack".into(),
            });
        };
        for (p, part) in parts.iter().enumerate().skip(1) {
            agree(first, part, p)?;
        }
        let total: usize = parts.iter().map(|p| p.rhs.len()).sum();
        let columns = first.columns.len();
        let mut matrix = Mat::<f64>::zeros(total, columns);
        let mut offset = 0;
        for part in &parts {
            matrix
                .as_mut()
                .subrows_mut(offset, part.rhs.len())
                .copy_from(part.matrix.as_ref());
            offset += part.rhs.len();
        }
        let round_off = first
            .round_off
            .iter()
            .filter(|name| parts.iter().all(|p| p.round_off.contains(name)))
            .cloned()
            .collect();
        let noise = stack_noise(&parts);
        let velocity_bias = stack_velocity_bias(&parts, total);
        let work_scale = stack_work_scale(&parts);
        let steady_state = stack_steady_state(&parts);
        let mut stacked = Regressor {
            matrix,
            rhs: parts.iter().flat_map(|p| p.rhs.iter().copied()).collect(),
            columns: first.columns.clone(),
            rows: parts.iter().flat_map(|p| p.rows.iter().cloned()).collect(),
            noise: None,
            nuisance: first.nuisance,
            velocity_bias,
            work_scale: None,
            round_off,
            steady_state: None,
        };
        if let Some(noise) = noise {
            stacked = stacked.with_noise(noise)?;
        }
        if let Some(scale) = work_scale {
            stacked = stacked.with_work_scale(scale)?;
        }
        if let Some(steady) = steady_state {
            stacked = stacked.with_steady_state(steady)?;
        }
        Ok(stacked)
    }
}

/// Part `p` agrees with the first part on what stacking cannot merge.
fn agree(first: &Regressor, part: &Regressor, p: usize) -> Result<()> {
    let differs = |what: &str, reason: String| Error::InvalidChoice {
        name: format!("rows to stack, part {}", p + 1),
        given: what.to_string(),
        reason,
    };
    if part.columns != first.columns {
        return Err(differs(
            "other columns",
            format!(
                "its columns are {:?}, the first part's {:?}: every part must come from the same model",
                part.columns, first.columns
            ),
        ));
    }
    if part.nuisance != first.nuisance {
        return Err(differs(
            "other nuisance columns",
            "every part must come from the same settings".into(),
        ));
    }
    let carried = |r: &Regressor| {
        [
            ("a noise model (noise-robust rows)", r.noise.is_some()),
            ("a velocity-noise bias", r.velocity_bias.is_some()),
            ("the gross work of its rows", r.work_scale.is_some()),
            ("a steady-state check", r.steady_state.is_some()),
        ]
    };
    for ((what, has), (_, first_has)) in carried(part).into_iter().zip(carried(first)) {
        if has != first_has {
            let (yes, no) = if has {
                ("it", "the first part")
            } else {
                ("the first part", "it")
            };
            return Err(differs(
                "rows of other settings",
                format!(
                    "{yes} carries {what} and {no} does not: every part must be built with the same settings"
                ),
            ));
        }
    }
    if let (Some(a), Some(b)) = (&part.velocity_bias, &first.velocity_bias)
        && a.estimator != b.estimator
    {
        return Err(differs(
            "another velocity estimator",
            format!(
                "its velocities are {}, the first part's {}",
                a.estimator, b.estimator
            ),
        ));
    }
    if let (Some(a), Some(b)) = (&part.steady_state, &first.steady_state)
        && (a.settings != b.settings || a.energy_known != b.energy_known)
    {
        return Err(differs(
            "another steady-state check",
            "every part must be checked with the same thresholds".into(),
        ));
    }
    if let (Some(a), Some(b)) = (&part.work_scale, &first.work_scale)
        && a.unit != b.unit
    {
        return Err(differs(
            "rows of another kind",
            format!(
                "its rows come from {}s, the first part's from {}s",
                a.unit, b.unit
            ),
        ));
    }
    Ok(())
}

fn stack_noise(parts: &[Regressor]) -> Option<NoiseModel> {
    parts[0].noise.as_ref()?;
    let mut noise = NoiseModel {
        rows: Vec::new(),
        windows: Vec::new(),
    };
    for part in parts.iter().filter_map(|p| p.noise.as_ref()) {
        noise.rows.extend(part.rows.iter().cloned());
        noise.windows.extend(part.windows.iter().cloned());
    }
    Some(noise)
}

fn stack_velocity_bias(parts: &[Regressor], total: usize) -> Option<VelocityBias> {
    let first = parts[0].velocity_bias.as_ref()?;
    let biases: Vec<&VelocityBias> = parts
        .iter()
        .filter_map(|p| p.velocity_bias.as_ref())
        .collect();
    let mut matrix = Mat::<f64>::zeros(total, first.matrix.ncols());
    let mut offset = 0;
    for b in &biases {
        matrix
            .as_mut()
            .subrows_mut(offset, b.matrix.nrows())
            .copy_from(b.matrix.as_ref());
        offset += b.matrix.nrows();
    }
    // As VelocityBias::of folds its windows: the largest gain, the noise range.
    let gain = biases.iter().fold(0.0f64, |g, b| g.max(b.gain));
    let lowest = biases
        .iter()
        .fold(f64::INFINITY, |l, b| l.min(b.displacement_noise[0]));
    let highest = biases
        .iter()
        .fold(0.0f64, |h, b| h.max(b.displacement_noise[1]));
    Some(VelocityBias {
        estimator: first.estimator.clone(),
        matrix,
        gain,
        displacement_noise: [lowest.min(highest), highest],
    })
}

fn stack_work_scale(parts: &[Regressor]) -> Option<WorkScale> {
    let first = parts[0].work_scale.as_ref()?;
    let mut scale = WorkScale {
        gross: Vec::new(),
        samples: Vec::new(),
        group: Vec::new(),
        names: Vec::new(),
        unit: first.unit.clone(),
    };
    for part in parts.iter().filter_map(|p| p.work_scale.as_ref()) {
        let before = scale.names.len();
        scale.gross.extend_from_slice(&part.gross);
        scale.samples.extend_from_slice(&part.samples);
        scale.group.extend(part.group.iter().map(|g| g + before));
        scale.names.extend(part.names.iter().cloned());
    }
    Some(scale)
}

fn stack_steady_state(parts: &[Regressor]) -> Option<SteadyStateReport> {
    let first = parts[0].steady_state.as_ref()?;
    Some(SteadyStateReport {
        settings: first.settings,
        energy_known: first.energy_known,
        windows: parts
            .iter()
            .filter_map(|p| p.steady_state.as_ref())
            .flat_map(|s| s.windows.iter().cloned())
            .collect(),
    })
}
