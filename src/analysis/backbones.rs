//! Backbones of the same mode from several jobs side by side: a free decay's
//! ([`crate::analysis::backbone`]: each window's amplitude X, frequency f and energy
//! decrement ζ, and the fitted law's ζ_eq(X, ω)) and a one-mode stepped-sine table's
//! ([`crate::analysis::equivalent`]: ζ_eq(X) at ω_n with its standard deviation, and each
//! sweep's measured level: X_c, f_c and the phase-slope ζ), each job identified once by
//! the library's own `identify`.
//!
//! **Ratio at common amplitudes.** Over the amplitudes both fitted curves cover,
//! [X_lo, X_hi] = [max(lo₁, lo₂), min(hi₁, hi₂)], at [`GRID`] amplitudes log-spaced from
//! X_lo to X_hi, each job's fitted ζ is interpolated linearly in (ln X, ln ζ) between its
//! own points (a power law in X is a straight line there), and
//!
//! ```text
//!   r(X) = ζ₂(X) / ζ₁(X),   sd r = r √(s₁² + s₂²),   s_j = sd ζ_j / ζ_j,
//! ```
//!
//! s_j interpolated in ln X the same way, 0 for a job without intervals (a free decay's
//! backbone has none: its interval is then the other job's alone, and `None` when
//! neither has one). Each job after the first is compared with the first.
//!
//! **What must match.** Amplitude is the displacement amplitude the job reports: at the
//! sensor for one sensor, of the modal coordinate for a modal filter (in the mode
//! shape's normalisation), of the table's response DOF. The ratio ζ is independent of
//! the modal mass, so the jobs need not share one; they must read the *same* amplitude
//! (same sensor, or the same mode-shape normalisation), and frequency in the same time
//! unit. Length and time units given in both files that differ are refused
//! ([`Error::Incomparable`]); nothing else can be checked from the files.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::analysis::backbone::Backbone;
use crate::analysis::equivalent::EquivalentDamping;
use crate::error::{Error, Result};

/// Amplitudes at which the fitted curves are compared.
pub const GRID: usize = 12;

/// What kind of test a job's backbone comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TestKind {
    /// A ringdown (`[free_decay]`).
    FreeDecay,
    /// A one-mode stepped-sine table (`[stepped_sine]`).
    SteppedSine,
}

impl fmt::Display for TestKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TestKind::FreeDecay => "free decay",
            TestKind::SteppedSine => "stepped sine",
        })
    }
}

/// ζ at one amplitude and frequency.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ZetaPoint {
    /// Displacement amplitude X.
    pub amplitude: f64,
    /// Frequency f = ω/2π (cycles per time unit).
    pub frequency: f64,
    /// Damping ratio ζ.
    pub damping_ratio: f64,
    /// Its standard deviation, where the job has one.
    pub std: Option<f64>,
}

/// Where a job comes from and the units it states.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JobLabel {
    /// The model file.
    pub file: String,
    /// Its title.
    pub title: String,
    /// `[units] length`, when given.
    pub length: Option<String>,
    /// `[units] time`, when given.
    pub time: Option<String>,
}

/// One job's backbone: measured points and the fitted law's curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobBackbone {
    /// The file, title and units.
    pub label: JobLabel,
    /// Free decay or stepped sine.
    pub kind: TestKind,
    /// The modal mass the job's coefficients are per.
    pub modal_mass: f64,
    /// Measured: a free decay's windows (energy decrement), a table's levels (phase
    /// slope at each sweep's π/2 crossing).
    pub measured: Vec<ZetaPoint>,
    /// The fitted law's ζ_eq, by increasing amplitude.
    pub fitted: Vec<ZetaPoint>,
}

impl JobBackbone {
    /// The backbone of a free decay.
    pub fn free_decay(label: JobLabel, backbone: &Backbone) -> Self {
        let point = |p: &crate::analysis::backbone::BackbonePoint, zeta: f64| ZetaPoint {
            amplitude: p.amplitude,
            frequency: p.frequency,
            damping_ratio: zeta,
            std: None,
        };
        let measured = backbone
            .points
            .iter()
            .map(|p| point(p, p.measured))
            .collect();
        let mut fitted: Vec<ZetaPoint> =
            backbone.points.iter().map(|p| point(p, p.fitted)).collect();
        fitted.sort_by(|a, b| a.amplitude.total_cmp(&b.amplitude));
        JobBackbone {
            label,
            kind: TestKind::FreeDecay,
            modal_mass: backbone.mass,
            measured,
            fitted,
        }
    }

    /// The equivalent damping of a one-mode stepped-sine table.
    pub fn stepped_sine(label: JobLabel, equivalent: &EquivalentDamping) -> Self {
        let hz = |omega: f64| omega / (2.0 * std::f64::consts::PI);
        let measured = equivalent
            .levels
            .iter()
            .filter_map(|l| {
                l.measured.map(|zeta| ZetaPoint {
                    amplitude: l.amplitude,
                    frequency: hz(l.frequency),
                    damping_ratio: zeta,
                    std: None,
                })
            })
            .collect();
        let mut fitted: Vec<ZetaPoint> = equivalent
            .points
            .iter()
            .map(|p| ZetaPoint {
                amplitude: p.amplitude,
                frequency: hz(equivalent.modal.natural_frequency),
                damping_ratio: p.damping_ratio,
                std: p.damping_ratio_std,
            })
            .collect();
        fitted.sort_by(|a, b| a.amplitude.total_cmp(&b.amplitude));
        JobBackbone {
            label,
            kind: TestKind::SteppedSine,
            modal_mass: equivalent.modal.mass,
            measured,
            fitted,
        }
    }

    /// The fitted curve's smallest and largest amplitude (positive ζ only).
    pub fn fitted_range(&self) -> Option<(f64, f64)> {
        let usable = self.usable();
        Some((usable.first()?.amplitude, usable.last()?.amplitude))
    }

    /// The fitted points that can be interpolated in logs (X > 0, ζ > 0, finite).
    fn usable(&self) -> Vec<&ZetaPoint> {
        self.fitted
            .iter()
            .filter(|p| {
                p.amplitude > 0.0
                    && p.damping_ratio > 0.0
                    && p.amplitude.is_finite()
                    && p.damping_ratio.is_finite()
            })
            .collect()
    }

    /// The fitted ζ at `amplitude` and its relative standard deviation (0 without
    /// intervals), interpolated in (ln X, ln ζ) (module doc); `None` outside the range.
    pub fn fitted_at(&self, amplitude: f64) -> Option<(f64, Option<f64>)> {
        let usable = self.usable();
        let (first, last) = (usable.first()?, usable.last()?);
        if !(amplitude >= first.amplitude && amplitude <= last.amplitude) {
            return None;
        }
        let relative = |p: &ZetaPoint| p.std.map(|s| s / p.damping_ratio);
        let k = usable
            .partition_point(|p| p.amplitude <= amplitude)
            .clamp(1, usable.len());
        let (a, b) = (usable[k - 1], usable[(k).min(usable.len() - 1)]);
        if b.amplitude <= a.amplitude {
            return Some((a.damping_ratio, relative(a)));
        }
        let t = (amplitude / a.amplitude).ln() / (b.amplitude / a.amplitude).ln();
        let zeta = (a.damping_ratio.ln() * (1.0 - t) + b.damping_ratio.ln() * t).exp();
        let std = match (relative(a), relative(b)) {
            (Some(sa), Some(sb)) => Some(sa * (1.0 - t) + sb * t),
            _ => None,
        };
        Some((zeta, std))
    }
}

/// The two fitted ζ and their ratio at one amplitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RatioPoint {
    /// X.
    pub amplitude: f64,
    /// The first job's fitted ζ₁(X).
    pub first: f64,
    /// The other job's fitted ζ₂(X).
    pub second: f64,
    /// r = ζ₂/ζ₁.
    pub ratio: f64,
    /// Its standard deviation (module doc), when either job has intervals.
    pub ratio_std: Option<f64>,
}

/// One job against the first over their common amplitudes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairComparison {
    /// The first job's index (0).
    pub first: usize,
    /// The other's.
    pub second: usize,
    /// The amplitudes both fitted curves cover (`None`: they do not overlap).
    pub common: Option<(f64, f64)>,
    /// The ratio at [`GRID`] amplitudes log-spaced over `common`.
    pub points: Vec<RatioPoint>,
    /// The largest |r − 1| over them.
    pub largest_deviation: Option<f64>,
}

/// The backbones of several jobs and each one against the first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Backbones {
    /// Every job's backbone, in the order given.
    pub jobs: Vec<JobBackbone>,
    /// Each job after the first against the first.
    pub pairs: Vec<PairComparison>,
}

/// Refuses `what` given differently in two jobs.
fn same_unit(
    a: &JobLabel,
    b: &JobLabel,
    what: &str,
    unit: fn(&JobLabel) -> &Option<String>,
) -> Result<()> {
    match (unit(a), unit(b)) {
        (Some(x), Some(y)) if x.trim() != y.trim() => Err(Error::Incomparable {
            files: format!("{} and {}", a.file, b.file),
            what: format!("[units] {what} '{x}' and '{y}'"),
            reason: format!(
                "amplitudes and frequencies must be in the same units; give both files the same {what} unit and data in it"
            ),
        }),
        _ => Ok(()),
    }
}

/// The jobs' backbones side by side, each after the first compared with the first
/// (module doc); [`Error::Incomparable`] when their units differ, [`Error::Empty`]
/// with fewer than two jobs.
pub fn compare(jobs: Vec<JobBackbone>) -> Result<Backbones> {
    if jobs.len() < 2 {
        return Err(Error::Empty {
            what: "backbones to compare (two jobs or more)".into(),
        });
    }
    let first = &jobs[0];
    for other in &jobs[1..] {
        same_unit(&first.label, &other.label, "length", |l| &l.length)?;
        same_unit(&first.label, &other.label, "time", |l| &l.time)?;
    }
    let pairs = (1..jobs.len()).map(|k| pair(&jobs, 0, k)).collect();
    Ok(Backbones { jobs, pairs })
}

/// Job `b` against job `a` (module doc).
fn pair(jobs: &[JobBackbone], a: usize, b: usize) -> PairComparison {
    let (ja, jb) = (&jobs[a], &jobs[b]);
    let common = match (ja.fitted_range(), jb.fitted_range()) {
        (Some((lo_a, hi_a)), Some((lo_b, hi_b))) => {
            let (lo, hi) = (lo_a.max(lo_b), hi_a.min(hi_b));
            (lo <= hi).then_some((lo, hi))
        }
        _ => None,
    };
    let mut points = Vec::new();
    if let Some((lo, hi)) = common {
        let count = if hi > lo { GRID } else { 1 };
        for i in 0..count {
            let x = if count == 1 {
                lo
            } else {
                // The ends exactly, so that both curves hold them.
                match i {
                    0 => lo,
                    _ if i == count - 1 => hi,
                    _ => lo * (hi / lo).powf(i as f64 / (count - 1) as f64),
                }
            };
            let (Some((za, sa)), Some((zb, sb))) = (ja.fitted_at(x), jb.fitted_at(x)) else {
                continue;
            };
            let ratio = zb / za;
            let ratio_std = match (sa, sb) {
                (None, None) => None,
                (sa, sb) => {
                    Some(ratio * (sa.unwrap_or(0.0).powi(2) + sb.unwrap_or(0.0).powi(2)).sqrt())
                }
            };
            points.push(RatioPoint {
                amplitude: x,
                first: za,
                second: zb,
                ratio,
                ratio_std,
            });
        }
    }
    let largest_deviation = points
        .iter()
        .map(|p| (p.ratio - 1.0).abs())
        .max_by(f64::total_cmp);
    PairComparison {
        first: a,
        second: b,
        common,
        points,
        largest_deviation,
    }
}

impl fmt::Display for Backbones {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let label = crate::format::label;
        writeln!(f, "backbones of {} jobs:", self.jobs.len())?;
        for (k, job) in self.jobs.iter().enumerate() {
            let range = job
                .fitted_range()
                .map_or("no fitted curve".to_string(), |(lo, hi)| {
                    format!("amplitude {} to {}", label(lo), label(hi))
                });
            writeln!(
                f,
                "  [{}] {} ({}): {}, {} measured points, {range}, modal mass {}",
                k + 1,
                job.label.file,
                job.label.title,
                job.kind,
                job.measured.len(),
                job.modal_mass
            )?;
        }
        for pair in &self.pairs {
            let (a, b) = (&self.jobs[pair.first], &self.jobs[pair.second]);
            let Some((lo, hi)) = pair.common else {
                writeln!(
                    f,
                    "[{}] against [{}]: no common amplitudes (the fitted curves do not overlap)",
                    pair.second + 1,
                    pair.first + 1
                )?;
                continue;
            };
            writeln!(
                f,
                "[{}] {} against [{}] {}, fitted ζ over the common amplitudes {} to {}:",
                pair.second + 1,
                b.kind,
                pair.first + 1,
                a.kind,
                label(lo),
                label(hi)
            )?;
            writeln!(
                f,
                "  {:>12} {:>12} {:>12} {:>22}",
                "amplitude",
                format!("ζ [{}]", pair.first + 1),
                format!("ζ [{}]", pair.second + 1),
                "ratio (95%)"
            )?;
            for p in &pair.points {
                let ratio = match p.ratio_std {
                    Some(s) => format!("{:.4} ± {:.4}", p.ratio, 1.96 * s),
                    None => format!("{:.4}", p.ratio),
                };
                writeln!(
                    f,
                    "  {:>12} {:>12.4e} {:>12.4e} {:>22}",
                    label(p.amplitude),
                    p.first,
                    p.second,
                    ratio
                )?;
            }
            if let Some(d) = pair.largest_deviation {
                writeln!(f, "  largest |ratio − 1|: {:.2}%", 100.0 * d)?;
            }
        }
        writeln!(
            f,
            "  (ζ fitted: each job's law at its own frequency, interpolated in log X and log ζ; every point in the JSON; the amplitudes must be the same displacement: same sensor or mode-shape normalisation)"
        )
    }
}
