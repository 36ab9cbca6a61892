//! A campaign over many machines, split at the pipeline's one seam, the rows:
//!
//! ```text
//!   identify(records 0..n) = identify(stack(rows(record 0), …, rows(record n−1)))   bit for bit
//! ```
//!
//! because each row reads one window of one record. [`rows`] runs where a record is
//! (a worker that reads or simulates it): the steady-state check of its windows when the
//! settings ask for it (refused unless transients are accepted, as [`identify`] refuses
//! them), then its rows, plain or noise-robust, with what the fit and the report read
//! beside A and b (the noise model that the iteratively refreshed weights use, the gross
//! work of the passivity check, the velocity-noise bias, the steady-state windows),
//! its records numbered as the campaign's records `first..`. [`Regressor::stack`] joins
//! parts in record order anywhere (a tree of partial stacks equals one stack), and
//! [`identify`] fits the stacked rows ([`crate::regressor::Source::Rows`]) with the
//! same weighted fit, diagnostics and report as the records themselves.
//!
//! Only the problem's rows travel: a record's samples stay where it was read. Windows
//! of whole periods only: fixed spans and free decays add unknowns per record
//! (stored energies), which rows of different records cannot share.
//!
//! [`identify`]: crate::identify::identify

use crate::error::{Error, Result};
use crate::identify::IdentifySettings;
use crate::model::DampingModel;
use crate::record::Record;
use crate::regressor::{ParametricRegressor, Regressor, Windows};

/// The rows of `records`, the campaign's records `first..first + records.len()`, with
/// everything the fit of the stacked rows reads (module doc).
pub fn rows(
    model: &DampingModel,
    records: &[Record],
    first: usize,
    settings: &IdentifySettings,
) -> Result<Regressor> {
    // One hop into rayon's pool for the whole record: its passes' parallel iterators
    // then run on a worker, instead of each waking the pool from this thread and
    // waiting (a pair of context switches per pass, about a third of a small record's
    // time when a campaign's task calls this per record).
    rayon::scope(|_| rows_in_pool(model, records, first, settings))
}

/// [`rows`] on a worker of rayon's pool.
fn rows_in_pool(
    model: &DampingModel,
    records: &[Record],
    first: usize,
    settings: &IdentifySettings,
) -> Result<Regressor> {
    settings.validate()?;
    if !matches!(settings.regressor.windows, Windows::Cycles(_)) {
        return Err(Error::InvalidChoice {
            name: "windows of a campaign's rows".into(),
            given: "fixed spans or a free decay".into(),
            reason: "their rows carry unknowns of their own record (stored energies), which rows stacked from other records cannot share; identify such records together in one process".into(),
        });
    }
    let problem = ParametricRegressor::linear(model, records);
    let steady = match &settings.steady_state {
        Some(thresholds) => problem.steady_state(&settings.regressor, thresholds)?,
        None => None,
    };
    if let Some(steady) = &steady {
        steady.enforce()?;
    }
    let mut regressor = problem.regressor(&[], &settings.regressor)?;
    if let Some(steady) = steady {
        regressor = regressor.with_steady_state(steady)?;
    }
    Ok(regressor.numbered_from(first))
}
