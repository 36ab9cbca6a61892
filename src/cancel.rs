//! Cancellation of long work: a process-wide flag, set from outside (the command line's
//! Ctrl-C handler through [`flag`], a program's own thread through [`request`]), read by
//! the library between steps.
//!
//! Long operations call [`check`] between units of work: every 64 integration steps of
//! a simulation, before each record read or simulated, before each window's
//! steady-state check and its row of the regressor, before each bootstrap replicate,
//! before each design candidate's evaluation. Once [`request`] has been called, the next check returns
//! [`Error::Cancelled`] naming the work that stopped, and the operation returns it
//! without producing a result. Nothing is written by a cancelled operation: outputs
//! are written after the work (io/output.rs, through a temporary file renamed into
//! place), and the commit checks the flag before its first rename, so a run cancelled
//! even while its files are written (`simulate --out`, `identify --report`) leaves none.
//!
//! The flag is process-wide, like [`crate::budget::set_max_memory`]: a program that
//! cancels one operation and then starts another calls [`clear`] in between.
//! [`check_flag`] reads a flag of the caller's own, for code that keeps one per job.
//! [`request_after`] arms a countdown that sets the flag after that many checks, so a
//! test can stop an operation at a chosen step without timing.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, LazyLock};

use crate::error::{Error, Result};

/// Set by [`request`] (or by a signal handler holding [`flag`]), read by [`check`].
static REQUESTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));

/// Checks left before the flag is set ([`request_after`]); `u64::MAX` = not armed.
static COUNTDOWN: AtomicU64 = AtomicU64::new(u64::MAX);

/// Asks every running and future library operation to stop at its next check
/// (async-signal-safe: one atomic store).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// The process-wide flag itself, for a signal handler that stores `true` in it (the
/// command line: `signal_hook::flag::register(SIGINT, dampid::cancel::flag())`).
pub fn flag() -> Arc<AtomicBool> {
    Arc::clone(&REQUESTED)
}

/// True once [`request`] has been called (and not [`clear`]ed).
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Lowers the flag and disarms any countdown, so that new work runs.
pub fn clear() {
    COUNTDOWN.store(u64::MAX, Ordering::SeqCst);
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Sets the flag after `checks` more calls of [`check`] (0: at the next one). For
/// tests of cancellation at a given step.
pub fn request_after(checks: u64) {
    COUNTDOWN.store(checks, Ordering::SeqCst);
}

/// Between steps of `what`: [`Error::Cancelled`] once cancellation is requested.
pub fn check(what: &str) -> Result<()> {
    if COUNTDOWN.load(Ordering::Relaxed) != u64::MAX {
        // Counts down to 0, then sets the flag; concurrent checks may each take one.
        let left = COUNTDOWN.fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
            (n != u64::MAX).then_some(n.saturating_sub(1))
        });
        if left == Ok(0) {
            request();
        }
    }
    check_flag(&REQUESTED, what)
}

/// [`Error::Cancelled`] naming `what` when `flag` is set.
pub fn check_flag(flag: &AtomicBool, what: &str) -> Result<()> {
    if flag.load(Ordering::Relaxed) {
        return Err(Error::Cancelled {
            what: what.to_string(),
        });
    }
    Ok(())
}

/// `result`, with a cancellation inside it renamed to `what`: an operation that runs
/// another checked one (the design builds regressors) names itself, whichever of the
/// checks, its own or the inner one's, saw the flag first.
pub fn within<T>(what: &str, result: Result<T>) -> Result<T> {
    result.map_err(|e| match e {
        Error::Cancelled { .. } => Error::Cancelled {
            what: what.to_string(),
        },
        other => other,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A caller's own flag: clear passes, set is `Cancelled` naming the work.
    #[test]
    fn own_flag_cancels() {
        let flag = AtomicBool::new(false);
        assert!(check_flag(&flag, "x").is_ok());
        flag.store(true, Ordering::SeqCst);
        let e = check_flag(&flag, "the bootstrap").unwrap_err();
        assert_eq!(e.kind(), "cancelled");
        assert!(e.to_string().contains("the bootstrap"), "{e}");
    }

    /// An inner operation's cancellation takes the outer one's name; other errors pass.
    #[test]
    fn within_renames_only_cancellation() {
        let flag = AtomicBool::new(true);
        let e = within("the design", check_flag(&flag, "building the regressor")).unwrap_err();
        assert!(e.to_string().contains("the design"), "{e}");
        let other: Result<()> = Err(Error::Cancelled { what: "x".into() });
        assert_eq!(within("y", other).unwrap_err().kind(), "cancelled");
    }
}
