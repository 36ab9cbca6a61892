//! Memory and time budgets, checked before work whose size comes from user input.
//!
//! An allocation of `bytes` for `what` is allowed when
//!
//! ```text
//!   bytes ≤ limit,   limit = --max-memory (set_max_memory) if given,
//!                    else the memory the system reports available (MemAvailable),
//!                    else unlimited (a system that reports nothing),
//! ```
//!
//! and is otherwise [`Error::TooLarge`], saying how much is needed, the limit, and what
//! to reduce. Sizes are computed in `u128` (or saturating), so a product of user inputs
//! cannot overflow into a small number. The check is for one allocation, or for the
//! sum the caller knows it will hold at once; it is not an accountant of the process.
//!
//! Long work (a simulation, a bootstrap) measures its own rate over its first fraction
//! of a second and extrapolates, estimate = elapsed × total / done, refusing with the
//! same error when the estimate exceeds the time limit (a day by default; lifted by
//! `--no-time-limit`, [`set_time_limit`]`(None)`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// `u64::MAX` = no limit set: use the available memory.
static MAX_MEMORY: AtomicU64 = AtomicU64::new(u64::MAX);

/// Caps every checked allocation at `bytes` (the command line's `--max-memory`).
pub fn set_max_memory(bytes: u64) {
    MAX_MEMORY.store(bytes, Ordering::Relaxed);
}

/// The limit checked allocations must stay under, in bytes (`None`: unknown, no limit).
pub fn limit() -> Option<u64> {
    match MAX_MEMORY.load(Ordering::Relaxed) {
        u64::MAX => available_memory(),
        set => Some(set),
    }
}

/// The default time limit: one day, in seconds.
const ONE_DAY: u64 = 86_400;

/// Seconds; `u64::MAX` = no time limit.
static TIME_LIMIT: AtomicU64 = AtomicU64::new(ONE_DAY);

/// Sets the time limit (`None`: none, the command line's `--no-time-limit`).
pub fn set_time_limit(limit: Option<Duration>) {
    TIME_LIMIT.store(limit.map_or(u64::MAX, |d| d.as_secs()), Ordering::Relaxed);
}

/// How long a piece of work has run, to extrapolate its total time.
#[derive(Debug, Clone, Copy)]
pub struct Stopwatch {
    started: Instant,
    checked: bool,
}

/// Work that has run this long gives a rate worth extrapolating.
const MEASURED: Duration = Duration::from_millis(200);

impl Stopwatch {
    /// Starts timing.
    pub fn start() -> Self {
        Stopwatch {
            started: Instant::now(),
            checked: false,
        }
    }

    /// After `done` of `total` units, once the rate has been measured (once per
    /// stopwatch): refuses when the extrapolated total exceeds the time limit.
    pub fn check(&mut self, done: u64, total: u64, what: &str, reduce: &str) -> Result<()> {
        if self.checked || done == 0 {
            return Ok(());
        }
        let elapsed = self.started.elapsed();
        if elapsed < MEASURED {
            return Ok(());
        }
        self.checked = true;
        require_time(
            what,
            elapsed.as_secs_f64() * total as f64 / done as f64,
            reduce,
        )
    }
}

/// Checks that work estimated at `seconds` fits the time limit.
pub fn require_time(what: &str, seconds: f64, reduce: &str) -> Result<()> {
    let limit = TIME_LIMIT.load(Ordering::Relaxed);
    if limit != u64::MAX && seconds > limit as f64 {
        return Err(Error::TooLarge {
            what: what.to_string(),
            needed: format!("about {}", readable_duration(seconds)),
            limit: format!(
                "{} (--no-time-limit lifts it)",
                readable_duration(limit as f64)
            ),
            reduce: reduce.to_string(),
        });
    }
    Ok(())
}

/// `40 s`, `12 min`, `5.0 h`, `3.0 days`, `2.1e6 years`.
pub fn readable_duration(seconds: f64) -> String {
    const DAY: f64 = 86_400.0;
    const YEAR: f64 = 365.25 * DAY;
    if seconds < 60.0 {
        format!("{seconds:.0} s")
    } else if seconds < 3600.0 {
        format!("{:.0} min", seconds / 60.0)
    } else if seconds < DAY {
        format!("{:.1} h", seconds / 3600.0)
    } else if seconds < YEAR {
        let days = seconds / DAY;
        if days < 1.5 {
            "1 day".into()
        } else {
            format!("{days:.1} days")
        }
    } else if seconds < 1e4 * YEAR {
        format!("{:.1} years", seconds / YEAR)
    } else {
        format!("{:.1e} years", seconds / YEAR)
    }
}

/// `MemAvailable` of /proc/meminfo, in bytes (Linux); `None` elsewhere. Read at most
/// every [`REREAD`] (checks run per window), else the last reading.
fn available_memory() -> Option<u64> {
    static LAST: std::sync::Mutex<Option<(Instant, Option<u64>)>> = std::sync::Mutex::new(None);
    let mut last = LAST
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    match *last {
        Some((at, value)) if at.elapsed() < REREAD => value,
        _ => {
            let value = read_available_memory();
            *last = Some((Instant::now(), value));
            value
        }
    }
}

/// How long a reading of the available memory stands.
const REREAD: Duration = Duration::from_millis(100);

fn read_available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// `count` values of `f64`, in bytes.
pub fn f64s(count: u128) -> u128 {
    count.saturating_mul(8)
}

/// Checks that `bytes` for `what` fit the limit; `reduce` says what to make smaller.
pub fn require(what: &str, bytes: u128, reduce: &str) -> Result<()> {
    match limit() {
        Some(limit) if bytes > u128::from(limit) => Err(Error::TooLarge {
            what: what.to_string(),
            needed: readable_bytes(bytes),
            limit: format!("{} available", readable_bytes(u128::from(limit))),
            reduce: reduce.to_string(),
        }),
        _ => Ok(()),
    }
}

/// Checks that `records` records of `samples` samples × `channels` channels each (f64)
/// fit the limit together, as a job holds them all at once, plus one record's worth
/// for the work on the records (a record being built beside those already done, the
/// windows' working copies): (`records` + 1) × `samples` × `channels` × 8 bytes.
pub fn require_records(
    what: &str,
    records: usize,
    samples: usize,
    channels: usize,
    reduce: &str,
) -> Result<()> {
    let one = (samples as u128).saturating_mul(channels as u128);
    require(
        &format!(
            "{what}: {records} record{} × {} samples × {channels} channels",
            if records == 1 { "" } else { "s" },
            crate::format::integer(samples as u128)
        ),
        f64s(one.saturating_mul(records as u128 + 1)),
        reduce,
    )
}

/// `1.5 GB`, `820 MB`, `12 kB`, `512 bytes` (decimal units, 2 significant digits).
pub fn readable_bytes(bytes: u128) -> String {
    let units = ["bytes", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1000.0 && unit + 1 < units.len() {
        value /= 1000.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else if value >= 1000.0 {
        format!("{value:.3e} {}", units[unit])
    } else if value >= 10.0 {
        format!("{value:.0} {}", units[unit])
    } else {
        format!("{value:.1} {}", units[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_sizes() {
        assert_eq!(readable_bytes(512), "512 bytes");
        assert_eq!(readable_bytes(1_500_000_000), "1.5 GB");
        assert_eq!(readable_bytes(820_000_000), "820 MB");
        assert_eq!(readable_bytes(u128::MAX), "3.403e20 EB");
    }

    #[test]
    fn readable_durations() {
        assert_eq!(readable_duration(40.0), "40 s");
        assert_eq!(readable_duration(86_400.0), "1 day");
        assert_eq!(readable_duration(3.0 * 86_400.0), "3.0 days");
        assert_eq!(readable_duration(1e15), "3.2e7 years");
    }

    /// A product of user inputs saturates instead of wrapping into a small size.
    #[test]
    fn sizes_saturate() {
        assert_eq!(f64s(u128::MAX / 2), u128::MAX);
    }
}
