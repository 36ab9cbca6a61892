//! A whole job, sizes included: arbitrary bytes as a model file
//! (`dampid::model_file::parse`: load the data or simulate), then the job's regressor
//! (periodic or non-periodic, as `dampid identify` builds it), the fit, and the model
//! check (`analysis::check`), under the limits a user sets on the command line rather
//! than the harness's: `budget::set_max_memory(512 MiB)` (`--max-memory`) and a time
//! limit of `TIME_LIMIT` seconds for the work the library times (simulations,
//! bootstraps, designs). Unlike the `model_file` target, no input is skipped for its
//! size: a simulation of 10¹² steps, 10⁵ DOFs or 10⁹ harmonics must be refused by the
//! library's own checks with `Error::TooLarge` (or another typed error), not by
//! exhausting memory (libFuzzer's `-rss_limit_mb` and `-malloc_limit_mb` turn that
//! into a crash) or by running past libFuzzer's `-timeout`.
//!
//! Seeds: the model files of `models/` (`fuzz/seeds/job/`). Data paths are resolved
//! against `models/`, so seeds that read `models/data/` load their records; a path that
//! leaves that folder (absolute, `..`) is skipped, so that a run never reads the rest
//! of the disk. Any `Err` is fine; a panic is a bug, and so is a fit that claims
//! success with non-finite coefficients or calls coefficients determined below a
//! positive threshold (`support::check`).

#![no_main]

use dampid::identify::{IdentifySettings, identify};
use dampid::progress::silent;
use dampid::regressor::ParametricRegressor;
use std::path::{Component, Path};
use std::time::Duration;

use dampid::model_file::{ModelFileSpec, parse};
use libfuzzer_sys::fuzz_target;

mod support;

/// The memory limit checked allocations must fit (`--max-memory 512MiB`).
const MAX_MEMORY: u64 = 512 << 20;
/// Seconds of estimated work the library accepts (`budget::set_time_limit`).
const TIME_LIMIT: u64 = 2;

/// Data paths (records and a stepped-sine table) stay inside `models/` (the harness's
/// limit, not the library's).
fn reads_only_models(spec: &ModelFileSpec) -> bool {
    let inside = |file: &str| {
        Path::new(file)
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir))
    };
    let records = spec.data.as_ref().is_none_or(|data| {
        data.get_ref()
            .records
            .iter()
            .all(|record| inside(&record.get_ref().file))
    });
    let table = spec
        .stepped_sine
        .as_ref()
        .is_none_or(|table| inside(&table.get_ref().file));
    records && table
}

fuzz_target!(
    init: {
        dampid::budget::set_max_memory(MAX_MEMORY);
        dampid::budget::set_time_limit(Some(Duration::from_secs(TIME_LIMIT)));
    },
    |bytes: &[u8]| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return;
        };
        if let Ok(spec) = toml::from_str::<ModelFileSpec>(text)
            && !reads_only_models(&spec)
        {
            return;
        }
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models");
        let Ok(job) = parse(text, "fuzz.toml", &base, Default::default()) else {
            return;
        };
        let Ok(regressor) = job.initial_regressor() else {
            return;
        };
        if let Ok(report) = identify(&ParametricRegressor::rows(&regressor), &IdentifySettings { fit: job.settings.fit.clone(), ..Default::default() }, &silent).map(|i| i.report) {
            support::check(&report);
        }
        // `dampid check` reads the same solve: any outcome but a panic.
        let _ = dampid::analysis::check::RegressorCheck::new(&regressor, &job.settings.fit);
    }
);
