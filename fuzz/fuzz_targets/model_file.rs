//! Model files: `dampid::model_file::parse` on arbitrary text, then the job's regressor
//! (periodic or non-periodic, as `dampid identify` builds it) and the fit. Any `Err` is
//! fine; a panic is a bug.
//!
//! Resource limits of the harness (not of the library): a model file may ask for a
//! simulation of any length or a system of any size, which is slow or exhausts memory
//! by request rather than by bug, so inputs whose simulation would take more than
//! `MAX_WORK` DOF-steps (string simulations: mode-point-steps), whose harmonic
//! approximation synthesizes more than `MAX_SYNTHESIZED` samples per period, or whose
//! system has more than `MAX_DOFS` DOFs are skipped. Data files are read from
//! `fuzz/data/`; paths that leave it (absolute, `..`) are skipped, so that the fuzzer
//! never reads `/dev/zero` or the rest of the disk.

#![no_main]

use dampid::identify::{IdentifySettings, identify};
use dampid::progress::silent;
use dampid::regressor::ParametricRegressor;
use std::path::{Component, Path};

use dampid::model_file::{ModelFileSpec, parse};
use libfuzzer_sys::fuzz_target;

mod support;

const MAX_DOFS: usize = 64;
const MAX_WORK: u128 = 2_000_000;
/// Samples per synthesized period of a harmonic approximation.
const MAX_SYNTHESIZED: usize = 100_000;

fn within_limits(spec: &ModelFileSpec) -> bool {
    let n = spec.dofs as u128;
    if spec.dofs > MAX_DOFS {
        return false;
    }
    if let Some(sim) = &spec.simulation {
        let s = sim.get_ref();
        let steps = (s.transient_steps as u128 + s.recorded_steps as u128) * s.substeps as u128;
        if steps * (s.experiments.len() as u128).max(1) * n * n > MAX_WORK {
            return false;
        }
    }
    if let Some(string) = &spec.string_simulation {
        let s = string.get_ref();
        let steps = (s.transient_steps as u128 + s.recorded_steps as u128) * s.substeps as u128;
        let per_step = (s.modes as u128) * (s.damping_points as u128 + n);
        if steps * (s.amplitudes.len() as u128).max(1) * per_step > MAX_WORK {
            return false;
        }
    }
    if let Some(harmonic) = &spec.harmonic_approximation
        && harmonic.get_ref().samples_per_period.unwrap_or(0) > MAX_SYNTHESIZED
    {
        return false;
    }
    if let Some(data) = &spec.data {
        for record in &data.get_ref().records {
            let path = Path::new(&record.get_ref().file);
            if !path
                .components()
                .all(|c| matches!(c, Component::Normal(_) | Component::CurDir))
            {
                return false;
            }
        }
    }
    true
}

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    // The same deserialization `parse` starts with, to apply the limits above.
    if let Ok(spec) = toml::from_str::<ModelFileSpec>(text)
        && !within_limits(&spec)
    {
        return;
    }
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let Ok(job) = parse(text, "fuzz.toml", &base, Default::default()) else {
        return;
    };
    // As `dampid identify` does: periodic windows or the non-periodic balance.
    if let Ok(regressor) = job.initial_regressor()
        && let Ok(report) = identify(
            &ParametricRegressor::rows(&regressor),
            &IdentifySettings {
                fit: job.settings.fit.clone(),
                ..Default::default()
            },
            &silent,
        )
        .map(|i| i.report)
    {
        support::check(&report);
    }
});
