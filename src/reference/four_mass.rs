//! Four-mass chain (section 2.2): M = I, K = tridiag(−1, 2, −1) (walls at both ends),
//! C = c K with c = 0.15, quadratic damping d ẋ_i|ẋ_i| on every mass with d = 0.10,
//! force a cos(0.618 t) on mass 4 for a ∈ {0.25, 0.5, 0.75, 1}, RK4 with h = 0.1 and
//! 1000 transient steps; optionally a grounded cubic spring x_2³ on mass 2.
//!
//! Our reading of what the paper leaves open: one equation per amplitude, the window
//! starts at the first recorded sample, the rectangular rule (the paper's) over
//! round(kT/h) samples, and — for the "estimated" cases — central-difference
//! velocities from the recorded displacements alone.

use std::fmt;

use faer::Mat;
use serde::Serialize;
use serde_json::{Value, json};

use crate::error::Result;
use crate::identify::{IdentifySettings, identify};
use crate::model::DampingModel;
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::record::Record;
use crate::regressor::RegressorSettings;
use crate::report::FitReport;
use crate::simulate::{
    ConservativeForce, HarmonicForce, SimSettings, System, chain_stiffness, simulate,
};
use crate::terms::laws::Quadratic;
use crate::terms::{Coefficients, Term};

/// True linear damping coefficient of the four-mass chain.
pub const FOUR_MASS_C: f64 = 0.15;
/// True quadratic damping coefficient of the four-mass chain.
pub const FOUR_MASS_D: f64 = 0.10;
/// Driving frequency (first mode).
pub const FOUR_MASS_OMEGA: f64 = 0.618;
/// Forcing amplitudes.
pub const FOUR_MASS_AMPLITUDES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// The damping model of the four-mass chain: C = c K and d ẋ_i|ẋ_i| on every mass.
pub fn four_mass_model() -> DampingModel {
    DampingModel::new()
        .with(Term::stiffness_proportional("c", chain_stiffness(4)))
        .with(Term::per_dof(
            Quadratic,
            4,
            Coefficients::Shared("d".into()),
        ))
}

/// The four-mass system driven at amplitude `amplitude`, with or without the cubic
/// spring x_2³ on mass 2.
pub fn four_mass_system(amplitude: f64, cubic_spring: bool) -> System {
    System {
        mass: Mat::identity(4, 4),
        stiffness: chain_stiffness(4),
        damping: four_mass_model(),
        damping_coefficients: vec![FOUR_MASS_C, FOUR_MASS_D],
        conservative: if cubic_spring {
            vec![ConservativeForce::Cubic {
                dof: 1,
                coefficient: 1.0,
            }]
        } else {
            Vec::new()
        },
        forcing: vec![HarmonicForce {
            dof: 3,
            amplitude,
            frequency: FOUR_MASS_OMEGA,
            phase: 0.0,
        }],
    }
}

/// Simulated records for every amplitude, each long enough for `cycles` periods.
pub fn four_mass_records(cubic_spring: bool, cycles: usize) -> Result<Vec<Record>> {
    let period = 2.0 * std::f64::consts::PI / FOUR_MASS_OMEGA;
    let settings = SimSettings {
        // The paper's 200 recorded steps hold one period (101.7 samples); several
        // periods need more.
        recorded_steps: 200.max((cycles as f64 * period / 0.1).ceil() as usize + 4),
        ..SimSettings::default()
    };
    four_mass_records_with(cubic_spring, &settings)
}

/// Simulated records for every amplitude with `settings` (labels "a=…"), for studies
/// that record the chain otherwise than [`four_mass_records`].
pub fn four_mass_records_with(cubic_spring: bool, settings: &SimSettings) -> Result<Vec<Record>> {
    FOUR_MASS_AMPLITUDES
        .iter()
        .map(|&a| {
            let record = simulate(
                &four_mass_system(a, cubic_spring),
                settings,
                &crate::progress::silent,
            )?;
            let mut parts = record.into_parts();
            parts.label = format!("a={a}");
            Record::new(parts)
        })
        .collect()
}

/// One identification case of the paper's section 2.2.
#[derive(Debug, Clone, Serialize)]
pub struct FourMassCase {
    /// Case name.
    pub name: String,
    /// With the cubic spring on mass 2.
    pub cubic_spring: bool,
    /// Periods per window.
    pub cycles: usize,
    /// Velocity source.
    pub velocity: VelocitySource,
    /// The paper's printed estimate (c, d), where it gives one.
    pub paper: Option<(f64, f64)>,
    /// Largest acceptable relative error against the truth.
    pub tolerance: f64,
}

/// The cases of section 2.2, each with simulated and with estimated velocities.
pub fn four_mass_cases() -> Vec<FourMassCase> {
    let mut cases = Vec::new();
    let variants = [
        ("chain", false, 1, Some((0.1499, 0.1003)), 0.005),
        (
            "cubic spring, one cycle",
            true,
            1,
            Some((0.1496, 0.1036)),
            0.04,
        ),
        (
            "cubic spring, four cycles",
            true,
            4,
            Some((0.1499, 0.1009)),
            0.01,
        ),
    ];
    for (name, cubic_spring, cycles, paper, tolerance) in variants {
        for (source, velocity) in [
            ("simulated velocities", VelocitySource::Measured),
            ("central differences", VelocitySource::CentralDifference),
        ] {
            cases.push(FourMassCase {
                name: format!("{name}, {source}"),
                cubic_spring,
                cycles,
                velocity,
                paper,
                tolerance,
            });
        }
    }
    cases
}

/// Outcome of one case: the report and the relative errors of c and d.
#[derive(Debug, Clone, Serialize)]
pub struct CaseOutcome {
    /// Fit report.
    pub report: FitReport,
    /// |ĉ − c|/c.
    pub error_c: f64,
    /// |d̂ − d|/d.
    pub error_d: f64,
}

impl CaseOutcome {
    /// True when both errors are within the case's tolerance.
    pub fn passes(&self, case: &FourMassCase) -> bool {
        self.error_c <= case.tolerance && self.error_d <= case.tolerance
    }
}

/// Simulates and identifies one case with quadrature `quadrature`.
pub fn run_four_mass_case(case: &FourMassCase, quadrature: Quadrature) -> Result<CaseOutcome> {
    let records = four_mass_records(case.cubic_spring, case.cycles)?;
    let settings = IdentifySettings {
        regressor: RegressorSettings {
            windows: WindowSpec::cycles(case.cycles).first(1).into(),
            quadrature,
            velocity: case.velocity,
            ..RegressorSettings::default()
        },
        ..IdentifySettings::default()
    };
    let report = identify(
        &crate::regressor::ParametricRegressor::linear(&four_mass_model(), &records),
        &settings,
        &crate::progress::silent,
    )?
    .report;
    let c = report.coefficient("c").unwrap_or(f64::NAN);
    let d = report.coefficient("d").unwrap_or(f64::NAN);
    Ok(CaseOutcome {
        error_c: (c - FOUR_MASS_C).abs() / FOUR_MASS_C,
        error_d: (d - FOUR_MASS_D).abs() / FOUR_MASS_D,
        report,
    })
}

/// Every four-mass case with its outcome, as a table (`Display`) or as JSON.
#[derive(Debug, Clone)]
pub struct FourMassSummary {
    /// The quadrature rule used.
    pub quadrature: Quadrature,
    /// Each case and its outcome.
    pub cases: Vec<(FourMassCase, CaseOutcome)>,
}

impl FourMassSummary {
    /// Runs every case of [`four_mass_cases`] with `quadrature`.
    pub fn run(quadrature: Quadrature) -> Result<Self> {
        let cases = four_mass_cases()
            .into_iter()
            .map(|case| {
                let outcome = run_four_mass_case(&case, quadrature)?;
                Ok((case, outcome))
            })
            .collect::<Result<_>>()?;
        Ok(FourMassSummary { quadrature, cases })
    }

    /// True when every case is within its tolerance.
    pub fn all_pass(&self) -> bool {
        self.cases
            .iter()
            .all(|(case, outcome)| outcome.passes(case))
    }

    /// `{"cases": [{"case": NAME, "report": REPORT}, ...]}`.
    pub fn to_json(&self) -> Value {
        let cases: Vec<Value> = self
            .cases
            .iter()
            .map(|(case, outcome)| json!({"case": case.name, "report": outcome.report}))
            .collect();
        json!({ "cases": cases })
    }
}

impl fmt::Display for FourMassSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Four-mass chain (Feeny 2009, section 2.2): true c = {FOUR_MASS_C}, d = {FOUR_MASS_D}; {:?} rule, one window per amplitude",
            self.quadrature
        )?;
        writeln!(
            f,
            "{:<48} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>6}",
            "case", "paper c", "paper d", "ours c", "ours d", "err c", "err d", "tol"
        )?;
        for (case, outcome) in &self.cases {
            let (pc, pd) = case.paper.unwrap_or((f64::NAN, f64::NAN));
            let c = outcome.report.coefficient("c").unwrap_or(f64::NAN);
            let d = outcome.report.coefficient("d").unwrap_or(f64::NAN);
            writeln!(
                f,
                "{:<48} {:>8.4} {:>8.4} {:>9.5} {:>9.5} {:>7.3}% {:>7.3}% {:>5.1}% {}",
                case.name,
                pc,
                pd,
                c,
                d,
                100.0 * outcome.error_c,
                100.0 * outcome.error_d,
                100.0 * case.tolerance,
                if outcome.passes(case) { "ok" } else { "MISS" }
            )?;
        }
        Ok(())
    }
}
