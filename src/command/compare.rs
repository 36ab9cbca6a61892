//! `dampid compare`: two models, or a list of candidate laws, fitted on the records (or
//! table) and identification settings of one model file, and compared by least squares
//! (RSS, F test, AIC, BIC, PRESS; [`crate::analysis::compare`]), each model's estimated
//! parameters at their least-squares values ([`crate::model_file::ComparedModel`]).

use std::fmt;

use serde::Serialize;

use super::Outcome;
use crate::analysis::compare::{
    CompareSettings, Comparison, Ranking, compare_candidates, rank_candidates,
};
use crate::error::Result;
use crate::model_file::{Job, candidate};
use crate::regressor::ParametricModel;
use crate::terms::laws::Registry;

/// A comparison's result under the name of the model file whose records and settings it
/// used.
#[derive(Debug, Clone, PartialEq)]
pub struct Compared<T> {
    /// The model file the records and settings came from.
    pub source: String,
    /// The comparison (two models) or the ranking (candidate laws).
    pub result: T,
}

impl<T: fmt::Display> fmt::Display for Compared<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "records and identification settings of {}\n{}",
            self.source, self.result
        )
    }
}

impl<T: Serialize> Serialize for Compared<T> {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        self.result.serialize(serializer)
    }
}

impl<T: fmt::Display + Serialize> Outcome for Compared<T> {}

/// The settings of a comparison on `job`: its rank tolerance.
fn settings(job: &Job) -> CompareSettings {
    CompareSettings {
        rank_tolerance: job.settings.fit.rank_tolerance,
        ..Default::default()
    }
}

/// Model A (`job`'s own, from the file `first`) against model B (`other`, from the file
/// `second`: only its terms are used), both on `job`'s records, windows and mode (in the
/// non-periodic mode both regressors carry the same nuisance columns).
pub fn models(
    job: &Job,
    first: &str,
    other: &ParametricModel,
    second: &str,
) -> Result<Compared<Comparison>> {
    let a = job.compared(first, &job.law)?;
    let b = job.compared(second, other)?;
    Ok(Compared {
        source: first.to_string(),
        result: compare_candidates(a.candidate(), b.candidate(), &settings(job))?,
    })
}

/// The candidate laws `specs` (`linear`, `linear+coulomb`, `power:1.5`, `power:est`, …)
/// fitted on `job`'s data (from the file `source`) and ranked.
pub fn laws(job: &Job, source: &str, specs: &[String]) -> Result<Compared<Ranking>> {
    let dofs = match (&job.stepped_sine, job.records.first()) {
        (Some(table), _) => table.table.table.dofs(),
        (None, Some(record)) => record.dofs(),
        (None, None) => 1,
    };
    let registry = Registry::builtin();
    let compared = specs
        .iter()
        .map(|spec| {
            // The errors of a candidate name it (its spec, or its label in the fit).
            let (_, law) = candidate(spec, dofs, &registry)?;
            // Its estimated exponents and the table's residual receptances (if the job
            // estimates them) at their least-squares values.
            job.compared(spec, &law)
        })
        .collect::<Result<Vec<_>>>()?;
    let candidates: Vec<_> = compared.iter().map(|c| c.candidate()).collect();
    Ok(Compared {
        source: source.to_string(),
        result: rank_candidates(&candidates, &settings(job))?,
    })
}
