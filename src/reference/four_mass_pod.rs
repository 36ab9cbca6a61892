//! Paper section 3.1 (Feeny 2009): the four-mass chain of section 2.2 (C = cK, quadratic
//! damping d ẋ|ẋ| on every mass, c = 0.15, d = 0.10, force a cos(0.618 t) on mass 4)
//! identified from its proper orthogonal modes. Every number is computed by
//! [`FourMassPodStudy::run`]: simulate (RK4, h = 0.1, 1000 transient steps) → POD →
//! project → identify; the study prints as a table (`Display`) or as JSON.
//!
//!   cargo run --release --example paper_four_mass_pod            # table
//!   cargo run --release --example paper_four_mass_pod -- --json  # {"cases": [...]}
//!
//! Our reading of what the paper leaves open ("saved four cycles of periodic data, whence
//! we obtained the POMs"):
//! - the POD ensemble of each amplitude is exactly the identification window: the first
//!   round(4T/h) = 407 recorded samples (4T/h = 406.68), one basis per amplitude, no
//!   mean removed;
//! - one equation per amplitude from that four-cycle window, rectangular rule (the
//!   paper's), read over the same 407 samples;
//! - velocities: the simulated velocities projected, U Uᵀ ẋ (so ẏ = Uᵀ ẋ), and as a
//!   check central differences of the projected displacements (which equal U Uᵀ times
//!   the central differences of x). The two agree to 0.2%.
//!
//! Targets (the example exits with status 1 when one is missed, [`FourMassPodStudy::all_pass`]):
//! dominant POM energy share within 0.2
//! percentage points of the paper's, dominant POMs within 0.005 componentwise, two POMs
//! within 0.5% of the truth, one POM within 2% of the paper's degraded estimate.
//!
//! Sensitivity (printed in the table, not a target): a POD ensemble that is not a whole
//! number of cycles weights some phases of the (non-synchronous) motion twice, which
//! tilts the dominant POM. Extending the ensemble past four cycles by ~6 samples moves
//! our POMs onto the paper's to 3e-4 and the one-POM estimate onto (0.1404, 0.1138),
//! which suggests the paper's ensemble ran a little past four cycles.

use std::f64::consts::PI;
use std::fmt;

use serde_json::{Value, json};

use super::check::{Check, Measure};
use super::four_mass::{
    FOUR_MASS_AMPLITUDES, FOUR_MASS_C, FOUR_MASS_D, FOUR_MASS_OMEGA, four_mass_model,
    four_mass_records_with,
};
use super::pods::{labelled, records_json};
use crate::error::Result;
use crate::identify::{IdentifySettings, identify};
use crate::prep::pod::{Pod, PodBasis, PodReport, PodSettings, Retain, reduce};
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::record::Record;
use crate::regressor::RegressorSettings;
use crate::report::FitReport;
use crate::simulate::SimSettings;

/// Cycles in the POD ensemble and in the identification window.
pub const CYCLES: usize = 4;
/// The paper's dominant POM energy shares (%), by amplitude.
pub const PAPER_DOMINANT_SHARE: [(f64, f64); 4] =
    [(1.0, 96.96), (0.75, 97.54), (0.5, 98.14), (0.25, 98.80)];
/// The paper's dominant POMs, by amplitude.
pub const PAPER_DOMINANT_POM: [(f64, [f64; 4]); 2] = [
    (0.25, [0.3659, 0.5957, 0.6035, 0.3834]),
    (1.0, [0.3601, 0.5897, 0.6059, 0.3943]),
];
/// The paper's one-POM estimate (c₁, d₁).
pub const PAPER_ONE_POM: (f64, f64) = (0.1404, 0.1138);
/// The paper's two-POM estimate (c₂, d₂).
pub const PAPER_TWO_POMS: (f64, f64) = (0.1499, 0.1003);
/// Tolerance on the energy shares, in percentage points.
pub const SHARE_TOLERANCE: f64 = 0.2;
/// Tolerance on each POM component.
pub const POM_TOLERANCE: f64 = 0.005;
/// Tolerance of the two-POM estimates, relative to the truth.
pub const TWO_POM_TOLERANCE: f64 = 0.005;
/// Tolerance of the one-POM estimates, relative to the paper's.
pub const ONE_POM_TOLERANCE: f64 = 0.02;

/// One identification: its fit report, the POD of each record and the checks.
#[derive(Debug, Clone)]
pub struct FourMassPodCase {
    /// Case name.
    pub name: String,
    /// The fit.
    pub report: FitReport,
    /// Labels of the bases' records, and the bases' reports.
    pub pods: Vec<(String, PodReport)>,
    /// Comparisons with the paper (empty for informational cases).
    pub checks: Vec<Check>,
}

/// Everything the study computes, as a table (`Display`) or as JSON.
#[derive(Debug, Clone)]
pub struct FourMassPodStudy {
    /// Samples per record (= POD ensemble = identification window).
    pub samples: usize,
    /// POD checks (shares and shapes).
    pub pod_checks: Vec<Check>,
    /// Identification cases.
    pub cases: Vec<FourMassPodCase>,
    /// Ensemble-length sensitivity: (POD samples, c₁, d₁, dominant POM at a = 1).
    pub sensitivity: Vec<(usize, f64, f64, Vec<f64>)>,
}

/// The paper's period and the rectangular window's sample count for four cycles.
fn window_samples() -> usize {
    let period = 2.0 * PI / FOUR_MASS_OMEGA;
    Quadrature::Rectangular.samples(CYCLES as f64 * period, SimSettings::default().step)
}

/// Simulated records of `samples` samples for every amplitude (labels "a=…").
fn records(samples: usize) -> Result<Vec<Record>> {
    let settings = SimSettings {
        recorded_steps: samples,
        ..SimSettings::default()
    };
    four_mass_records_with(false, &settings)
}

fn identify_settings(velocity: VelocitySource) -> IdentifySettings {
    IdentifySettings {
        regressor: RegressorSettings {
            windows: WindowSpec::cycles(CYCLES).first(1).into(),
            quadrature: Quadrature::Rectangular,
            velocity,
            ..Default::default()
        },
        ..IdentifySettings::default()
    }
}

fn pod_settings(retained: usize, basis: PodBasis) -> PodSettings {
    PodSettings {
        remove_mean: false,
        retain: Retain::Count(retained),
        basis,
    }
}

fn coefficient_checks(report: &FitReport, retained: usize) -> Vec<Check> {
    let c = report.coefficient("c").unwrap_or(f64::NAN);
    let d = report.coefficient("d").unwrap_or(f64::NAN);
    if retained == 1 {
        vec![
            Check::against(
                "c (vs paper)",
                PAPER_ONE_POM.0,
                PAPER_ONE_POM.0,
                c,
                Measure::Relative,
                ONE_POM_TOLERANCE,
            ),
            Check::against(
                "d (vs paper)",
                PAPER_ONE_POM.1,
                PAPER_ONE_POM.1,
                d,
                Measure::Relative,
                ONE_POM_TOLERANCE,
            ),
        ]
    } else {
        vec![
            Check::against(
                "c (vs truth)",
                PAPER_TWO_POMS.0,
                FOUR_MASS_C,
                c,
                Measure::Relative,
                TWO_POM_TOLERANCE,
            ),
            Check::against(
                "d (vs truth)",
                PAPER_TWO_POMS.1,
                FOUR_MASS_D,
                d,
                Measure::Relative,
                TWO_POM_TOLERANCE,
            ),
        ]
    }
}

impl FourMassPodStudy {
    /// Simulates, decomposes and identifies every case.
    pub fn run() -> Result<Self> {
        let samples = window_samples();
        let records = records(samples)?;
        let model = four_mass_model();

        // POD checks: one basis per amplitude from all its samples.
        let mut pod_checks = Vec::new();
        let per_record = reduce(&records, &pod_settings(2, PodBasis::PerRecord))?;
        for (a, share) in PAPER_DOMINANT_SHARE {
            let index = FOUR_MASS_AMPLITUDES
                .iter()
                .position(|&x| x == a)
                .unwrap_or(0);
            let ours = 100.0 * per_record.bases[index].energy_shares()[0];
            pod_checks.push(Check::against(
                format!("dominant POM share, a={a} (%)"),
                share,
                share,
                ours,
                Measure::PercentagePoints,
                SHARE_TOLERANCE,
            ));
        }
        for (a, shape) in PAPER_DOMINANT_POM {
            let index = FOUR_MASS_AMPLITUDES
                .iter()
                .position(|&x| x == a)
                .unwrap_or(0);
            let ours = per_record.bases[index].mode(0).unwrap_or(&[]).to_vec();
            for (i, (&p, &o)) in shape.iter().zip(&ours).enumerate() {
                pod_checks.push(Check::against(
                    format!("dominant POM, a={a}, u_{}", i + 1),
                    p,
                    p,
                    o,
                    Measure::Absolute,
                    POM_TOLERANCE,
                ));
            }
        }

        let mut cases = Vec::new();
        let variants = [
            (
                "one POM",
                1,
                VelocitySource::Measured,
                PodBasis::PerRecord,
                true,
            ),
            (
                "two POMs",
                2,
                VelocitySource::Measured,
                PodBasis::PerRecord,
                true,
            ),
            (
                "one POM, central differences",
                1,
                VelocitySource::CentralDifference,
                PodBasis::PerRecord,
                true,
            ),
            (
                "two POMs, central differences",
                2,
                VelocitySource::CentralDifference,
                PodBasis::PerRecord,
                true,
            ),
            (
                "four POMs (full order)",
                4,
                VelocitySource::Measured,
                PodBasis::PerRecord,
                false,
            ),
            (
                "two POMs, one basis shared by all amplitudes",
                2,
                VelocitySource::Measured,
                PodBasis::Shared,
                false,
            ),
        ];
        for (name, retained, velocity, basis, checked) in variants {
            let reduction = reduce(&records, &pod_settings(retained, basis))?;
            let report = identify(
                &crate::regressor::ParametricRegressor::linear(&model, &reduction.records),
                &identify_settings(velocity),
                &crate::progress::silent,
            )?
            .report;
            let checks = if checked {
                coefficient_checks(&report, retained)
            } else {
                Vec::new()
            };
            cases.push(FourMassPodCase {
                name: name.into(),
                pods: labelled(&reduction, &records),
                report,
                checks,
            });
        }

        // Sensitivity to the POD ensemble's length (the identification window is fixed).
        let long = self::records(samples + 12)?;
        let mut sensitivity = Vec::new();
        for extra in 0..=12 {
            let n = samples + extra;
            let mut projected = Vec::new();
            let mut pom = Vec::new();
            for record in &long {
                let pod = Pod::from_displacements(
                    record.displacements().subrows(0, n),
                    &pod_settings(1, PodBasis::PerRecord),
                )?;
                if record.label() == "a=1" {
                    pom = pod.mode(0).unwrap_or(&[]).to_vec();
                }
                projected.push(pod.project(record)?);
            }
            let report = identify(
                &crate::regressor::ParametricRegressor::linear(&model, &projected),
                &identify_settings(VelocitySource::Measured),
                &crate::progress::silent,
            )?
            .report;
            sensitivity.push((
                n,
                report.coefficient("c").unwrap_or(f64::NAN),
                report.coefficient("d").unwrap_or(f64::NAN),
                pom,
            ));
        }
        Ok(FourMassPodStudy {
            samples,
            pod_checks,
            cases,
            sensitivity,
        })
    }

    /// True when every check passes.
    pub fn all_pass(&self) -> bool {
        self.pod_checks
            .iter()
            .chain(self.cases.iter().flat_map(|c| &c.checks))
            .all(|c| c.passes)
    }

    /// `{"cases": [{"case", "report", "pod", "checks"}, ...]}`; the POD checks ride on the
    /// first case.
    pub fn to_json(&self) -> Value {
        let cases: Vec<Value> = self
            .cases
            .iter()
            .enumerate()
            .map(|(k, case)| {
                let records = records_json(&case.pods);
                let mut checks = case.checks.clone();
                if k == 0 {
                    checks.extend(self.pod_checks.iter().cloned());
                }
                json!({
                    "case": case.name,
                    "report": case.report,
                    "pod": {"samples": self.samples, "records": records},
                    "checks": checks,
                })
            })
            .collect();
        json!({ "cases": cases })
    }
}

fn write_checks(f: &mut fmt::Formatter<'_>, title: &str, checks: &[Check]) -> fmt::Result {
    for c in checks {
        let (error, tolerance) = match c.measure {
            Measure::Relative => (
                format!("{:.3}%", 100.0 * c.error),
                format!("{:.1}%", 100.0 * c.tolerance),
            ),
            _ => (format!("{:.4}", c.error), format!("{}", c.tolerance)),
        };
        writeln!(
            f,
            "  {:<44} {:<30} {:>9.4} {:>9.4} {:>9} {:>6}  {}",
            title,
            c.quantity,
            c.paper,
            c.ours,
            error,
            tolerance,
            if c.passes { "ok" } else { "MISS" }
        )?;
    }
    Ok(())
}

impl fmt::Display for FourMassPodStudy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let period = 2.0 * PI / FOUR_MASS_OMEGA;
        writeln!(
            f,
            "Four-mass chain reduced by POD (Feeny 2009, section 3.1): true c = {FOUR_MASS_C}, d = {FOUR_MASS_D}, ω = {FOUR_MASS_OMEGA}"
        )?;
        writeln!(
            f,
            "Reading: RK4 h = 0.1, 1000 transient steps; POD ensemble = identification window = the first {} samples (4T/h = {:.2}),",
            self.samples,
            CYCLES as f64 * period / 0.1
        )?;
        writeln!(
            f,
            "         one basis per amplitude, no mean removed; one four-cycle equation per amplitude, rectangular rule;"
        )?;
        writeln!(
            f,
            "         velocities: simulated velocities projected (U Uᵀ ẋ); central differences as a check."
        )?;
        writeln!(f)?;
        writeln!(
            f,
            "  {:<44} {:<30} {:>9} {:>9} {:>9} {:>6}",
            "case", "quantity", "paper", "ours", "error", "tol"
        )?;
        write_checks(f, "POD, one basis per amplitude", &self.pod_checks)?;
        for case in &self.cases {
            if case.checks.is_empty() {
                let c = case.report.coefficient("c").unwrap_or(f64::NAN);
                let d = case.report.coefficient("d").unwrap_or(f64::NAN);
                writeln!(
                    f,
                    "  {:<44} c = {c:.5} ({:+.3}% vs truth), d = {d:.5} ({:+.3}% vs truth)  (not a target)",
                    case.name,
                    100.0 * (c - FOUR_MASS_C) / FOUR_MASS_C,
                    100.0 * (d - FOUR_MASS_D) / FOUR_MASS_D
                )?;
            } else {
                write_checks(f, &case.name, &case.checks)?;
            }
        }
        writeln!(f)?;
        writeln!(f, "POD energy shares (%) per amplitude, two POMs retained:")?;
        if let Some(case) = self.cases.iter().find(|c| c.name == "two POMs") {
            for (label, pod) in &case.pods {
                let shares: Vec<String> = pod
                    .modes
                    .iter()
                    .map(|m| format!("{:.4}", 100.0 * m.energy_share))
                    .collect();
                writeln!(
                    f,
                    "  {label:<8} [{}]  two POMs: {:.5}%",
                    shares.join(", "),
                    100.0 * pod.retained_share
                )?;
            }
        }
        writeln!(f)?;
        writeln!(
            f,
            "Sensitivity (not a target): POD ensemble of N samples from the start of the record, same window:"
        )?;
        writeln!(
            f,
            "  {:>5} {:>8} {:>8}   dominant POM at a = 1 (paper: [0.3601, 0.5897, 0.6059, 0.3943])",
            "N", "c1", "d1"
        )?;
        let paper_pom = PAPER_DOMINANT_POM[1].1;
        let distance = |pom: &[f64]| {
            pom.iter()
                .zip(&paper_pom)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        };
        let closest = self
            .sensitivity
            .iter()
            .min_by(|a, b| distance(&a.3).total_cmp(&distance(&b.3)));
        for (n, c, d, pom) in &self.sensitivity {
            if !(n - self.samples).is_multiple_of(3) && closest.map(|x| x.0) != Some(*n) {
                continue;
            }
            let shape: Vec<String> = pom.iter().map(|v| format!("{v:.4}")).collect();
            writeln!(f, "  {n:>5} {c:>8.4} {d:>8.4}   [{}]", shape.join(", "))?;
        }
        if let Some((n, c, d, pom)) = closest {
            writeln!(
                f,
                "  An ensemble that is not whole cycles tilts the POM. Closest to the paper's POM: N = {n} ({} samples past four cycles),",
                n - self.samples
            )?;
            writeln!(
                f,
                "  max |Δu| = {:.4}, with (c1, d1) = ({c:.4}, {d:.4}) against the paper's ({}, {}).",
                distance(pom),
                PAPER_ONE_POM.0,
                PAPER_ONE_POM.1
            )?;
        }
        Ok(())
    }
}
