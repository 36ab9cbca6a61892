//! Bootstrap confidence intervals by resampling windows of whole cycles.
//!
//! Each equation of the regressor is one window of whole driving periods. A replicate
//! draws m rows with replacement (the pairs bootstrap: a row carries its own A_r and
//! b_r, so amplitude-dependent, heteroscedastic errors are resampled as they occur),
//! refits them with the same [`FitSettings`] (least squares, or clarabel under the same
//! constraints), and keeps θ*. With B kept replicates and level 1 − α, the percentile
//! interval of coefficient j is
//!
//! ```text
//!   [q_{α/2}, q_{1−α/2}] of {θ*_j},   q_p = x_(⌊h⌋) + (h − ⌊h⌋)(x_(⌊h⌋+1) − x_(⌊h⌋)),
//!   h = (B − 1) p            (order statistics x_(0) ≤ … ≤ x_(B−1); R's type 7)
//! ```
//!
//! and the bootstrap standard error is the standard deviation of {θ*_j}. A replicate
//! whose resampled regressor has a lower numerical rank than the full one (too many
//! repeated rows), or whose solver did not converge, is dropped and counted; fewer than
//! half kept is an error.
//!
//! Reproducible: replicate k draws its rows from its own generator, `StdRng` seeded with
//! splitmix64(seed ⊕ splitmix64(k)), and results are collected in replicate order, so
//! they do not depend on the number of threads (rayon runs replicates in parallel).

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};
use crate::fit::svd::{numerical_rank, scaled_singular_values};
use crate::fit::{FitMethod, FitSettings, solve};
use crate::progress::Progress;
use crate::regressor::Regressor;

/// How many replicates, from which seed, at which confidence level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BootstrapSettings {
    /// Number of replicates B (default 1000).
    pub replicates: usize,
    /// Master seed (default 0).
    pub seed: u64,
    /// Confidence level 1 − α (default 0.95).
    pub level: f64,
}

impl Default for BootstrapSettings {
    fn default() -> Self {
        BootstrapSettings {
            replicates: 1000,
            seed: 0,
            level: 0.95,
        }
    }
}

impl BootstrapSettings {
    /// Rejects zero replicates and levels outside (0, 1).
    pub fn validate(&self) -> Result<()> {
        if self.replicates < 2 {
            return Err(Error::invalid(
                "replicates",
                self.replicates as f64,
                "a bootstrap needs at least 2 replicates",
            ));
        }
        if !(self.level > 0.0 && self.level < 1.0) {
            return Err(Error::invalid(
                "confidence level",
                self.level,
                "must be in (0, 1)",
            ));
        }
        Ok(())
    }
}

/// A percentile confidence interval of one coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConfidenceInterval {
    /// Coefficient name.
    pub name: String,
    /// Lower end q_{α/2}.
    pub lower: f64,
    /// Upper end q_{1−α/2}.
    pub upper: f64,
    /// Confidence level 1 − α.
    pub level: f64,
    /// Standard deviation of the replicates.
    pub std_error: f64,
}

impl ConfidenceInterval {
    /// True when `value` lies in [lower, upper].
    pub fn contains(&self, value: f64) -> bool {
        self.lower <= value && value <= self.upper
    }
}

/// What a replicate draws with replacement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Resampled {
    /// Single equations (windows of whole periods of records, or single points).
    #[default]
    Windows,
    /// Whole groups of equations: the sweeps of a stepped-sine table.
    Sweeps,
}

impl fmt::Display for Resampled {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Resampled::Windows => "windows",
            Resampled::Sweeps => "whole sweeps",
        })
    }
}

/// How a bootstrap was run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BootstrapSummary {
    /// Replicates drawn.
    pub replicates: usize,
    /// Replicates kept (full rank, converged).
    pub used: usize,
    /// Master seed.
    pub seed: u64,
    /// Confidence level.
    pub level: f64,
    /// The fit each replicate used.
    pub method: FitMethod,
    /// What a replicate drew: windows, or whole sweeps.
    #[serde(default)]
    pub resampled: Resampled,
    /// How many units (windows or sweeps) there are to draw from; a replicate draws as
    /// many, with replacement.
    #[serde(default)]
    pub groups: usize,
    /// Replicates dropped because their outer loop (estimated parameters) did not
    /// converge.
    #[serde(default)]
    pub not_converged: usize,
    /// Replicates dropped because their fit was not usable (solver status, a numerical
    /// failure, or a rank below the full data's).
    #[serde(default)]
    pub unusable: usize,
    /// Regressors built by the replicates (estimated parameters: each trial of each
    /// outer loop rebuilds one; 0 when the rows of one regressor are resampled).
    #[serde(default)]
    pub evaluations: u64,
}

impl BootstrapSummary {
    /// The summary of `used` kept of `settings.replicates` replicates refitted with
    /// `fit`, which drew from `units` (`resampled`); the others counted as unusable.
    pub(crate) fn of(
        settings: &BootstrapSettings,
        fit: &FitSettings,
        used: usize,
        units: &Groups,
        resampled: Resampled,
    ) -> Self {
        BootstrapSummary {
            replicates: settings.replicates,
            used,
            seed: settings.seed,
            level: settings.level,
            method: if fit.constraints.is_empty() {
                FitMethod::LeastSquares
            } else {
                FitMethod::Constrained
            },
            resampled,
            groups: units.count(),
            not_converged: 0,
            unusable: settings.replicates - used,
            evaluations: 0,
        }
    }
}

/// The result of a bootstrap.
#[derive(Debug, Clone, PartialEq)]
pub struct Bootstrap {
    /// How it was run.
    pub summary: BootstrapSummary,
    /// One interval per estimated nonlinear parameter, in parameter order (empty when
    /// nothing nonlinear is estimated).
    pub parameters: Vec<ConfidenceInterval>,
    /// One interval per coefficient, in column order.
    pub coefficients: Vec<ConfidenceInterval>,
    /// (η*, θ*) of each kept replicate (η* first, when estimated), in replicate order.
    pub samples: Vec<Vec<f64>>,
    /// The units each replicate drew (indices in 0..`summary.groups`), every replicate
    /// in replicate order, kept or not.
    pub drawn: Vec<Vec<usize>>,
}

/// splitmix64: a bijective 64-bit mixer (Steele, Lea, Flood 2014).
pub(crate) fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The generator of replicate `k` under master seed `seed`.
pub(crate) fn replicate_rng(seed: u64, k: usize) -> StdRng {
    StdRng::seed_from_u64(splitmix64(seed ^ splitmix64(k as u64)))
}

/// The numerical rank of the column-scaled `regressor`.
pub(crate) fn rank_of(regressor: &Regressor, tolerance: f64) -> usize {
    numerical_rank(
        &scaled_singular_values(regressor.matrix(), regressor.rhs()),
        tolerance,
    )
}

/// The bootstrap of the rows of `regressor`: each replicate draws, with replacement,
/// as many units as there are, single rows (`groups` `None`: windows) or whole groups
/// of rows (`groups[r]` the group of row r, the sweep of a stepped-sine point: the
/// cluster bootstrap, so that errors correlated within a group, a drift of the sensor
/// over one sweep or the residual compliance of one level, are resampled as they
/// occur; fewer than two groups is an error), refits them with `fit` and returns
/// percentile intervals. `progress(done, total)` counts replicates as they finish
/// (from the worker threads, in any order; `done` counts up);
/// [`crate::cancel::check`] runs before each. `dampid identify --bootstrap` runs it
/// through [`crate::identify::identify`], which resamples a table's sweeps and, with
/// estimated parameters, refits the whole variable projection per replicate.
pub fn bootstrap(
    regressor: &Regressor,
    fit: &FitSettings,
    settings: &BootstrapSettings,
    groups: Option<&[usize]>,
    progress: Progress<'_>,
) -> Result<Bootstrap> {
    let (units, resampled) = match groups {
        None => (Groups::rows(regressor.equations()), Resampled::Windows),
        Some(groups) => (
            Groups::of(groups, regressor.equations())?,
            Resampled::Sweeps,
        ),
    };
    resample(regressor, fit, settings, progress, &units, resampled)
}

/// The units a replicate draws with replacement: single rows (windows), or whole
/// groups of rows (sweeps).
#[derive(Debug, Clone)]
pub(crate) struct Groups {
    /// The rows of each group, in row order; `None` when every row is its own group.
    members: Option<Vec<Vec<usize>>>,
    /// The number of groups.
    count: usize,
}

impl Groups {
    /// Every one of `m` rows a group of its own.
    pub(crate) fn rows(m: usize) -> Self {
        Groups {
            members: None,
            count: m,
        }
    }

    /// `groups[r]` the group of row r of `m`; fewer than two non-empty groups is an error.
    pub(crate) fn of(groups: &[usize], m: usize) -> Result<Self> {
        if groups.len() != m {
            return Err(Error::mismatch(
                "bootstrap groups vs regressor rows",
                m,
                groups.len(),
            ));
        }
        let mut members: Vec<Vec<usize>> = Vec::new();
        for (r, &g) in groups.iter().enumerate() {
            if g >= members.len() {
                members.resize(g + 1, Vec::new());
            }
            members[g].push(r);
        }
        members.retain(|m| !m.is_empty());
        if members.len() < 2 {
            return Err(Error::choice(
                "bootstrap groups",
                format!("{} group(s)", members.len()),
                "resampling whole groups (sweeps) needs at least two of them",
            ));
        }
        Ok(Groups {
            count: members.len(),
            members: Some(members),
        })
    }

    /// The number of groups.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// As many groups as there are, drawn with replacement (indices in 0..count).
    pub(crate) fn draw(&self, rng: &mut StdRng) -> Vec<usize> {
        let k = self.count;
        (0..k).map(|_| rng.random_range(0..k)).collect()
    }

    /// The rows of the groups `drawn`, group after group.
    pub(crate) fn rows_of(&self, drawn: &[usize]) -> Vec<usize> {
        match &self.members {
            None => drawn.to_vec(),
            Some(members) => drawn
                .iter()
                .flat_map(|&g| members[g].iter().copied())
                .collect(),
        }
    }
}

/// The bootstrap with replicates that draw `units`.
fn resample(
    regressor: &Regressor,
    fit: &FitSettings,
    settings: &BootstrapSettings,
    progress: Progress<'_>,
    units: &Groups,
    resampled: Resampled,
) -> Result<Bootstrap> {
    settings.validate()?;
    fit.validate()?;
    let m = regressor.equations();
    let p = regressor.columns().len();
    if m < p.max(1) {
        return Err(Error::TooFewEquations {
            equations: m,
            coefficients: p,
        });
    }
    crate::budget::require(
        &format!(
            "{} bootstrap replicates of {p} coefficients",
            settings.replicates
        ),
        // Each kept replicate: p values, its Vec and Option headers and allocator
        // overhead (about 6 words).
        crate::budget::f64s((settings.replicates as u128).saturating_mul(p as u128 + 6)),
        "reduce the replicates (--bootstrap N); 1000 to 2000 give 95% intervals",
    )?;
    let full_rank = rank_of(regressor, fit.rank_tolerance);
    let one_replicate = |k: usize| -> Result<(Vec<usize>, Option<Vec<f64>>)> {
        let mut rng = replicate_rng(settings.seed, k);
        let drawn = units.draw(&mut rng);
        let rows = units.rows_of(&drawn);
        // The rows keep their noise model, so a weighted fit stays weighted.
        let resampled = regressor.select_rows(&rows)?;
        if rank_of(&resampled, fit.rank_tolerance) < full_rank {
            return Ok((drawn, None));
        }
        match solve(&resampled, fit) {
            Ok(f) if f.status.is_usable() => Ok((drawn, Some(f.coefficients))),
            Ok(_) | Err(Error::Numerical { .. }) => Ok((drawn, None)),
            Err(e) => Err(e),
        }
    };
    let outcomes = run_replicates(settings, progress, &one_replicate)?;
    let (drawn, kept): (Vec<Vec<usize>>, Vec<Option<Vec<f64>>>) = outcomes.into_iter().unzip();
    let samples: Vec<Vec<f64>> = kept.into_iter().flatten().collect();
    let used = samples.len();
    if 2 * used < settings.replicates {
        return Err(Error::Numerical {
            stage: "bootstrap".into(),
            detail: format!(
                "only {used} of {} resampled regressors kept their rank and converged; add windows (equations) before bootstrapping",
                settings.replicates
            ),
        });
    }
    let coefficients = regressor
        .columns()
        .iter()
        .enumerate()
        .map(|(j, name)| percentile_interval(name, samples.iter().map(|s| s[j]), settings.level))
        .collect();
    Ok(Bootstrap {
        summary: BootstrapSummary::of(settings, fit, used, units, resampled),
        parameters: Vec::new(),
        coefficients,
        samples,
        drawn,
    })
}

/// Runs replicates 0..B of `one` (`None`: dropped) and returns their outcomes in
/// replicate order, whatever the number of threads: [`crate::cancel::check`] before
/// each, `progress(done, total)` after each (from the worker threads, `done` counting
/// up). The first replicates (up to 64, or 200 ms) run one by one and time the rest
/// against the time budget ([`crate::budget::require_time`]); each replicate k has its
/// own seeded generator ([`replicate_rng`]), so the split changes no result.
pub(crate) fn run_replicates<T: Send>(
    settings: &BootstrapSettings,
    progress: Progress<'_>,
    one: &(dyn Fn(usize) -> Result<T> + Sync),
) -> Result<Vec<T>> {
    let total = settings.replicates as u64;
    let done = AtomicU64::new(0);
    let replicate = |k: usize| -> Result<T> {
        crate::cancel::check("the bootstrap")?;
        let kept = one(k)?;
        progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
        Ok(kept)
    };
    let started = std::time::Instant::now();
    let mut outcomes: Vec<T> = Vec::new();
    while outcomes.len() < settings.replicates.min(64)
        && started.elapsed() < std::time::Duration::from_millis(200)
    {
        outcomes.push(replicate(outcomes.len())?);
    }
    let timed = outcomes.len();
    let per_replicate = started.elapsed().as_secs_f64() / timed.max(1) as f64;
    crate::budget::require_time(
        &format!("{} bootstrap replicates", settings.replicates),
        per_replicate * (settings.replicates - timed) as f64
            / rayon::current_num_threads().max(1) as f64,
        "reduce the replicates (--bootstrap N); 1000 to 2000 give 95% intervals",
    )?;
    let rest: Vec<T> = (timed..settings.replicates)
        .into_par_iter()
        .map(replicate)
        .collect::<Result<_>>()?;
    outcomes.extend(rest);
    Ok(outcomes)
}

/// The percentile interval (type 7) at `level` and the standard deviation of the
/// replicates' `values` of coefficient `name` (at least one value).
pub(crate) fn percentile_interval(
    name: &str,
    values: impl Iterator<Item = f64>,
    level: f64,
) -> ConfidenceInterval {
    let mut values: Vec<f64> = values.collect();
    values.sort_by(f64::total_cmp);
    let used = values.len();
    let alpha = 1.0 - level;
    let mean = values.iter().sum::<f64>() / used as f64;
    let variance =
        values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (used - 1).max(1) as f64;
    ConfidenceInterval {
        name: name.to_string(),
        lower: quantile(&values, alpha / 2.0),
        upper: quantile(&values, 1.0 - alpha / 2.0),
        level,
        std_error: variance.sqrt(),
    }
}

/// Quantile `q` of sorted, non-empty `values` (linear interpolation, type 7).
fn quantile(values: &[f64], q: f64) -> f64 {
    let h = (values.len() - 1) as f64 * q;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(values.len() - 1);
    values[lo] + (h - lo as f64) * (values[hi] - values[lo])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Type-7 quantiles of 1..=5 are 1 + 4q.
    #[test]
    fn quantile_interpolates_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert!((quantile(&v, 0.025) - 1.1).abs() < 1e-12);
    }

    /// splitmix64 of 0 is the published first output for seed 0.
    #[test]
    fn splitmix_reference_value() {
        assert_eq!(splitmix64(0), 0xe220_a839_7b1d_cdaf);
    }
}
