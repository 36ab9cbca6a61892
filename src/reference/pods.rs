//! The proper orthogonal modes of a reference study's records: one report per basis,
//! labelled by its record (or "all amplitudes (stacked)" for one basis of several
//! records), and their JSON: per record the retained count, the energy and cumulative
//! shares of every mode, and the full report.

use serde_json::{Value, json};

use crate::prep::pod::{PodReport, Reduction};
use crate::record::Record;

/// One report per basis of `reduction` of `records`, with its label.
pub(super) fn labelled(reduction: &Reduction, records: &[Record]) -> Vec<(String, PodReport)> {
    if reduction.bases.len() == 1 && records.len() > 1 {
        return vec![(
            "all amplitudes (stacked)".into(),
            reduction.bases[0].report(),
        )];
    }
    records
        .iter()
        .zip(&reduction.bases)
        .map(|(r, b)| (r.label().to_string(), b.report()))
        .collect()
}

/// The JSON of labelled reports.
pub(super) fn records_json(pods: &[(String, PodReport)]) -> Vec<Value> {
    pods.iter()
        .map(|(label, pod)| {
            json!({
                "record": label,
                "retained": pod.retained,
                "energy_shares": pod.modes.iter().map(|m| m.energy_share).collect::<Vec<_>>(),
                "cumulative_shares": pod.modes.iter().map(|m| m.cumulative_share).collect::<Vec<_>>(),
                "report": pod,
            })
        })
        .collect()
}
