//! The commands of `dampid` as library calls: identify, check, compare, design,
//! simulate, init and pod. Each takes what a front end parsed (the command line, or the
//! Python package's arguments) and returns an [`Outcome`]: its text (`Display`), its
//! JSON (`Serialize`), where it has one its HTML page, and what its exit status says
//! (trusted numbers, `--strict` failures, a refusal). The front ends only parse and
//! print: `src/bin/dampid/main.rs` and `python/src/lib.rs`.
//!
//! Flow: front end → command → [`crate::model_file`] (a job: a problem and its
//! settings) → [`crate::identify::identify`] → … (ARCHITECTURE.md).

pub mod backbones;
pub mod check;
pub mod compare;
pub mod design;
pub mod identify;
pub mod init;
pub mod pod;
pub mod reference;
pub mod simulate;

use std::fmt;

use serde::Serialize;

/// What a refused steady state needs to be accepted, in the words of the command line
/// and of model files (the Python package says `accept_transient=True`).
pub const TRANSIENT_HINT: &str = "set accept_transient = true in [identification] or pass --accept-transient to use these windows anyway";

/// What a command returns: printed as text or JSON, with its exit status.
pub trait Outcome: fmt::Display + Serialize {
    /// Why `--strict` refuses it, one line each (empty: it passes).
    fn strict_failures(&self) -> Vec<String> {
        Vec::new()
    }

    /// Whether its numbers can be trusted (exit status 1 when not): a fit that
    /// converged, a design that succeeded, a reference that met its targets.
    fn trusted(&self) -> bool {
        true
    }

    /// A refusal to report after the outcome (exit status 2): the outcome says what
    /// was found, this says why it is not accepted.
    fn refused(&self) -> Option<String> {
        None
    }

    /// Lines for standard error besides the outcome (what was removed, written aside),
    /// so that standard output stays the outcome alone.
    fn notices(&self) -> Vec<String> {
        Vec::new()
    }
}

/// The exit status of an `outcome` printed under `strict`, and the `--strict` failures
/// to say (empty without `--strict`): 2 when refused, 1 when not trusted or a strict
/// failure, else 0.
pub fn exit_status(outcome: &impl Outcome, strict: bool) -> (u8, Vec<String>) {
    let failures = if strict {
        outcome.strict_failures()
    } else {
        Vec::new()
    };
    let status = if outcome.refused().is_some() {
        2
    } else if !outcome.trusted() || !failures.is_empty() {
        1
    } else {
        0
    };
    (status, failures)
}

/// `outcome` as pretty JSON, with a final newline.
pub fn json(outcome: &impl Serialize) -> crate::Result<String> {
    serde_json::to_string_pretty(outcome)
        .map(|text| format!("{text}\n"))
        .map_err(|e| crate::Error::Output {
            path: "standard output".into(),
            message: e.to_string(),
        })
}

/// The notice for a temporary file of an interrupted run that a write removed.
pub fn stale_notice(file: &std::path::Path) -> String {
    format!(
        "removed {} (a temporary file of an interrupted run)",
        file.display()
    )
}
