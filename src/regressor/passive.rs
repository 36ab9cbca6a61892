//! Passivity of the input work. Over whole periods of a steady periodic response the
//! stored energy returns to its start, so the input work of a window is the energy
//! the structure dissipated: b_r ≥ 0 for any passive structure. Input work that is
//! negative beyond its noise means the data are wrong, not the damping: a force or a
//! motion sensor with the wrong sign or polarity (`scale = -1`), a force on the wrong
//! DOF, displacements declared as accelerations (integrated twice, −X/ω² per
//! harmonic, an inverted motion), a stepped-sine table read with the wrong phase
//! convention (lag for lead), or windows that are not in steady state. A fit of such
//! rows returns a confident wrong answer (with `nonnegative = true` every coefficient
//! zero at its bound; unconstrained, a term of the wrong sign), so
//! [`crate::analysis::solved::solved`] refuses them before any fit with
//! [`Error::NegativeInputWork`], unless `accept_negative_work` is set
//! ([`crate::fit::FitSettings::accept_negative_work`]).
//!
//! **Groups.** Rows are pooled per record (per sweep for a stepped-sine table), and
//! once over all rows: for group g with rows R_g,
//!
//! ```text
//!   B_g = Σ_{r∈R_g} b_r,   G_g = Σ_{r∈R_g} W_r,   σ_g² = Σ_{r∈R_g} Var b_r,   N_g = Σ_{r∈R_g} N_r,
//! ```
//!
//! W_r the gross work of the row, ∫|vᵀr| dt from the raw samples
//! ([`crate::regressor::input_work`]) or π a X_f for a stepped-sine point (|sin φ| ≤ 1),
//! so that B_g/G_g is the group's power factor, in [−1, 1]; N_r the sample intervals of
//! the window.
//!
//! **Beyond what the noise explains.** A group is negative when
//!
//! - *with a noise model* (the noise-robust rows and stepped-sine tables,
//!   [`crate::regressor::Regressor::noise`]: Var b_r is the propagated variance of the
//!   residual at θ = 0): B_g < −max(Z σ_g, η G_g), Z = [`Z`] = 5 standard deviations
//!   (a good record is falsely refused with probability below 3·10⁻⁷);
//! - *without one* (plain rows: measured, central-difference or spectral velocities):
//!   B_g < −max(Z/√N_g, η) G_g. The rule is conservative: white noise on the samples
//!   contributes to b like a sum of N_g independent terms, whose spread is at most about
//!   G_g/√N_g when the noise makes up the whole gross work (central differences of
//!   noisy displacements: 0.8 G/√N), and less when the motion stands above the noise,
//!   so a passive record needs noise three times its signal to reach −5 G/√N. The
//!   price is that a wrong sign goes unnoticed where the power factor is below 5/√N
//!   (0.2 for windows of 600 samples: far off resonance); the fit then warns that it
//!   explains nothing or leans on bounds ([`crate::report::Warning::FitExplainsNothing`]).
//!
//! η = [`FLOOR`] = 10⁻⁶ keeps round-off and quadrature error of noise-free data (whose
//! propagated σ is round-off too) from counting as negative work.
//!
//! Not checked: the non-periodic mode (the input work of a span includes the change of
//! stored energy, which may leave the structure), and regressors built by hand without
//! a gross work (nothing to judge the noise by).

use crate::error::{Error, Result};
use crate::regressor::Regressor;

/// Standard deviations (or Z/√N of the gross work without a noise model) by which the
/// input work of a group must be negative to be refused.
pub const Z: f64 = 5.0;

/// η: input work above −η × the gross work is never refused (round-off and quadrature).
pub const FLOOR: f64 = 1e-6;

/// What the check needs beside b: the gross work of each row and how rows group.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorkScale {
    /// Per row: the gross work W_r ≥ |b_r| (module doc).
    pub gross: Vec<f64>,
    /// Per row: the sample intervals N_r behind it (0 for a stepped-sine point).
    pub samples: Vec<usize>,
    /// Per row: its group (record or sweep), an index into `names`.
    pub group: Vec<usize>,
    /// The name of each group (record labels, sweep names).
    pub names: Vec<String>,
    /// `record` or `sweep`.
    pub unit: String,
}

impl WorkScale {
    /// The rows `indices` (with repeats), as [`Regressor::select_rows`] selects them.
    pub(crate) fn select(&self, indices: &[usize]) -> Self {
        WorkScale {
            gross: indices.iter().map(|&i| self.gross[i]).collect(),
            samples: indices.iter().map(|&i| self.samples[i]).collect(),
            group: indices.iter().map(|&i| self.group[i]).collect(),
            names: self.names.clone(),
            unit: self.unit.clone(),
        }
    }
}

/// One group's sums.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    net: f64,
    gross: f64,
    /// Σ (std_r / unit)², the variance in units of the first row's gross work (so that
    /// data of any scale neither underflow nor overflow when squared).
    variance: f64,
    unit: f64,
    samples: usize,
    rows: usize,
}

impl Sums {
    fn add(&mut self, b: f64, gross: f64, std: Option<f64>, samples: usize) {
        if self.rows == 0 {
            self.unit = if gross > 0.0 && gross.is_finite() {
                gross
            } else {
                1.0
            };
        }
        self.net += b;
        self.gross += gross;
        self.variance += (std.unwrap_or(0.0) / self.unit).powi(2);
        self.samples += samples;
        self.rows += 1;
    }

    /// The most negative net work the noise explains (a negative number).
    fn threshold(&self, noise: bool) -> f64 {
        let allowed = if noise {
            (Z * self.unit * self.variance.sqrt()).max(FLOOR * self.gross)
        } else {
            let n = self.samples.max(1) as f64;
            (Z / n.sqrt()).max(FLOOR) * self.gross
        };
        -allowed
    }

    fn negative(&self, noise: bool) -> bool {
        self.rows > 0 && self.gross > 0.0 && self.net < self.threshold(noise)
    }
}

/// The groups of `regressor` whose input work is negative beyond its noise, with the
/// pooled rows as the last entry when they are too: `(name, net / gross)`; empty when
/// the regressor carries no [`WorkScale`] (nothing to judge the noise by).
pub fn negative_groups(regressor: &Regressor) -> Vec<(String, f64)> {
    let Some(scale) = regressor.work_scale() else {
        return Vec::new();
    };
    let noise = regressor.noise();
    let mut groups = vec![Sums::default(); scale.names.len()];
    let mut all = Sums::default();
    let zero = vec![0.0; regressor.columns().len()];
    // one scratch buffer for every row's std (the same numbers as `RowNoise::std`)
    let mut buffer = Vec::new();
    for (r, &b) in regressor.rhs().iter().enumerate() {
        let std = noise.map(|n| n.rows[r].std_with(&zero, &mut buffer));
        let (gross, samples) = (scale.gross[r], scale.samples[r]);
        if let Some(g) = groups.get_mut(scale.group[r]) {
            g.add(b, gross, std, samples);
        }
        all.add(b, gross, std, samples);
    }
    let mut out: Vec<(String, f64)> = groups
        .iter()
        .zip(&scale.names)
        .filter(|(g, _)| g.negative(noise.is_some()))
        .map(|(g, name)| (name.clone(), g.net / g.gross))
        .collect();
    if out.is_empty() && all.negative(noise.is_some()) {
        out.push(("all equations together".into(), all.net / all.gross));
    }
    out
}

/// [`Error::NegativeInputWork`] when some record or sweep of `regressor` (or all of them
/// together) takes in negative work beyond its noise (module doc); `accept` lets it
/// through.
pub fn require_passive(regressor: &Regressor, accept: bool) -> Result<()> {
    if accept {
        return Ok(());
    }
    let negative = negative_groups(regressor);
    let Some(scale) = regressor.work_scale().filter(|_| !negative.is_empty()) else {
        return Ok(());
    };
    let total_abs: f64 = regressor.rhs().iter().map(|b| b.abs()).sum();
    let negative_abs: f64 = regressor
        .rhs()
        .iter()
        .filter(|b| **b < 0.0)
        .map(|b| b.abs())
        .sum();
    let negative_rows = regressor.rhs().iter().filter(|b| **b < 0.0).count();
    let rule = if regressor.noise().is_some() {
        format!("its net input work is below −{Z} standard deviations of its propagated noise")
    } else {
        format!(
            "its net input work is below −{Z}/√N of its gross work ∫|vᵀr| dt over its N samples"
        )
    };
    let causes = if scale.unit == "sweep" {
        "the phase convention of the table (`phase_convention = \"lag\"` for x = X cos(ωt − φ), \
         `\"lead\"` for an FRF's phase), the sign of the force or response columns, \
         `response` (displacement, velocity or acceleration phase) or `force_dof`"
    } else {
        "the sign or polarity of a force or motion sensor (`scale = -1` on a column), a \
         force on the wrong DOF (`dof` of `forces`), displacements declared as velocities \
         or accelerations (or the reverse), or windows not in steady state"
    };
    let groups = negative
        .iter()
        .map(|(name, ratio)| format!("'{name}' (net {ratio:.3} of gross)"))
        .collect();
    Err(Error::NegativeInputWork {
        unit: scale.unit.to_string(),
        groups,
        total: scale.names.len(),
        share: if total_abs > 0.0 {
            negative_abs / total_abs
        } else {
            0.0
        },
        reason: format!(
            "{negative_rows} of {} equations take work out; {rule}, which a passive \
             structure cannot do over whole periods; likely causes: {causes}; set \
             accept_negative_work = true in [identification] (or pass \
             --accept-negative-work) to fit anyway",
            regressor.equations()
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regressor::RowLabel;
    use faer::Mat;

    fn regressor(b: &[f64], gross: &[f64], samples: usize, groups: &[usize]) -> Regressor {
        let rows = b
            .iter()
            .enumerate()
            .map(|(r, _)| RowLabel {
                record: format!("r{}", groups[r]),
                record_index: groups[r],
                window: r,
                start_time: 0.0,
                cycles: 1,
                frequency: None,
            })
            .collect();
        let names = (0..=groups.iter().copied().max().unwrap_or(0))
            .map(|g| format!("r{g}"))
            .collect();
        Regressor::from_parts(
            Mat::from_fn(b.len(), 1, |_, _| 1.0),
            b.to_vec(),
            vec!["c".into()],
            rows,
        )
        .unwrap()
        .with_work_scale(WorkScale {
            gross: gross.to_vec(),
            samples: vec![samples; b.len()],
            group: groups.to_vec(),
            names,
            unit: "record".into(),
        })
        .unwrap()
    }

    /// Raw rule by hand: 100 samples per row, two rows per record, so N_g = 200 and
    /// the threshold is −5/√200 = −0.354 of the gross work. Record 0 at −0.5 of its
    /// gross work is refused, record 1 at −0.3 is not (noise can explain it), record
    /// 2 at +0.9 is passive.
    #[test]
    fn the_raw_rule_by_hand() {
        let r = regressor(
            &[-0.5, -0.5, -0.3, -0.3, 0.9, 0.9],
            &[1.0; 6],
            100,
            &[0, 0, 1, 1, 2, 2],
        );
        let negative = negative_groups(&r);
        assert_eq!(negative.len(), 1, "{negative:?}");
        assert_eq!(negative[0].0, "r0");
        assert!((negative[0].1 + 0.5).abs() < 1e-12);
        let e = require_passive(&r, false).unwrap_err();
        assert_eq!(e.kind(), "negative_input_work");
        // Σ_{b<0}|b| / Σ|b| = 1.6 / 3.4.
        match &e {
            Error::NegativeInputWork { share, total, .. } => {
                assert!((share - 1.6 / 3.4).abs() < 1e-12);
                assert_eq!(*total, 3);
            }
            other => panic!("{other}"),
        }
        assert!(require_passive(&r, true).is_ok());
    }

    /// Slightly negative work of noise-free data (round-off, below η of the gross) is
    /// not refused; no work scale, no check.
    #[test]
    fn round_off_and_hand_built_rows_pass() {
        let r = regressor(&[-1e-9, 1.0], &[1.0, 1.0], 1_000_000, &[0, 1]);
        assert!(negative_groups(&r).is_empty());
        let plain = Regressor::from_parts(
            Mat::from_fn(1, 1, |_, _| 1.0),
            vec![-1.0],
            vec!["c".into()],
            {
                vec![RowLabel {
                    record: "r".into(),
                    record_index: 0,
                    window: 0,
                    start_time: 0.0,
                    cycles: 1,
                    frequency: None,
                }]
            },
        )
        .unwrap();
        assert!(require_passive(&plain, false).is_ok());
    }
}
