//! Progress reporting without terminal I/O. Long library operations (simulating many
//! experiments, reading and building many records) call a [`Progress`] callback with
//! the work done and the total, in whatever unit the operation counts; the command line
//! turns the calls into a progress bar. The library never writes to a terminal.

/// `progress(done, total)`: `done` of `total` units of work are finished.
pub type Progress<'a> = &'a (dyn Fn(u64, u64) + Sync);

/// A callback that ignores every report.
pub fn silent(_done: u64, _total: u64) {}
