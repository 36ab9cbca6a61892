//! One coefficient per dashpot: the paper's four-mass chain (M = I, K = tridiag(−1, 2, −1))
//! with a linear dashpot on each of its five links, walls included (dashpot[0-1] …
//! dashpot[4-5], true 0.05, 0.08, 0.12, 0.10, 0.06), plus quadratic damping d ẋ|ẋ| on
//! every mass with one shared d = 0.10: six coefficients.
//!
//! 1. The paper's experiment (first resonance, ω = 0.618, on mass 4, a ∈ {0.25, 0.5,
//!    0.75, 1}) excites almost the first mode only: the report must flag the dashpots
//!    as not separable and mark their values as not estimates.
//! 2. The experiment design (greedy D-optimal on a nominal system with every guessed
//!    coefficient 0.1) adds experiments from the four resonances, each mass, amplitudes
//!    0.5 and 1, until the column-scaled condition number is below 100. On the
//!    noise-free records of that set all six coefficients must come out within 1% of
//!    the truth (velocities from the displacements by the spectral estimator).
//!
//!   cargo run --release --example per_dashpot            # tables
//!   cargo run --release --example per_dashpot -- --json  # {"cases": [...]}
//!
//! Exits with status 1 when a target is missed.

use std::f64::consts::PI;

use dampid::analysis::design::{DesignSettings, design, simulate_candidates};
use dampid::prelude::*;
use dampid::reference::{FOUR_MASS_AMPLITUDES, FOUR_MASS_OMEGA, dashpot_chain_model};
use dampid::report::Warning;
use dampid::simulate::chain_stiffness;
use dampid::simulate::{HarmonicForce, SimSettings, System};
use faer::Mat;
use serde_json::json;

const DOFS: usize = 4;
const TRUTH: [f64; 6] = [0.05, 0.08, 0.12, 0.10, 0.06, 0.10];
const NOMINAL: [f64; 6] = [0.1; 6];
const TOLERANCE: f64 = 0.01;
const TARGET_CONDITION: f64 = 100.0;

fn model() -> DampingModel {
    dashpot_chain_model(DOFS, Coefficients::Shared("d".into()))
}

fn system(coefficients: &[f64]) -> System {
    System {
        mass: Mat::identity(DOFS, DOFS),
        stiffness: chain_stiffness(DOFS),
        damping: model(),
        damping_coefficients: coefficients.to_vec(),
        conservative: Vec::new(),
        forcing: Vec::new(),
    }
}

fn main() -> Result<()> {
    let as_json = std::env::args().any(|a| a == "--json");
    // h = 0.1 with two RK4 substeps, 800 time units of transient, 60 recorded.
    let simulation = SimSettings {
        step: 0.1,
        substeps: 2,
        transient_steps: 8_000,
        recorded_steps: 600,
    };
    let settings = IdentifySettings {
        regressor: RegressorSettings {
            windows: WindowSpec::cycles(2).into(),
            quadrature: Quadrature::Trapezoid,
            velocity: VelocitySource::Spectral { harmonics: None },
            ..Default::default()
        },
        ..IdentifySettings::default()
    };
    let names = model().coefficient_names();

    // Candidates: the paper's four first-resonance experiments on mass 4 (already run),
    // then every resonance ω_k = 2 sin(kπ/10) on every mass at amplitudes 0.5 and 1.
    let mut candidates: Vec<HarmonicForce> = FOUR_MASS_AMPLITUDES
        .iter()
        .map(|&amplitude| HarmonicForce {
            dof: 3,
            amplitude,
            frequency: FOUR_MASS_OMEGA,
            phase: 0.0,
        })
        .collect();
    for mode in 1..=DOFS {
        let frequency = 2.0 * (mode as f64 * PI / 10.0).sin();
        for dof in 0..DOFS {
            for amplitude in [0.5, 1.0] {
                candidates.push(HarmonicForce {
                    dof,
                    amplitude,
                    frequency,
                    phase: 0.0,
                });
            }
        }
    }
    let start: Vec<usize> = (0..FOUR_MASS_AMPLITUDES.len()).collect();

    // Case 1: the paper's experiments only.
    let paper: Vec<HarmonicForce> = start.iter().map(|&k| candidates[k]).collect();
    let records = simulate_candidates(&system(&TRUTH), &paper, &simulation)?;
    let resonance_only = identify(
        &ParametricRegressor::linear(&model(), &records),
        &settings,
        &silent,
    )?
    .report;
    let flagged_dashpots: Vec<String> = resonance_only
        .warnings
        .iter()
        .find_map(|w| match w {
            Warning::Unidentifiable { coefficients, .. } => Some(coefficients.clone()),
            _ => None,
        })
        .unwrap_or_default()
        .into_iter()
        .filter(|name| name.starts_with("dashpot"))
        .collect();
    let marked = resonance_only
        .coefficients
        .iter()
        .filter(|c| flagged_dashpots.contains(&c.name))
        .all(|c| !c.determined);
    let case1_pass = flagged_dashpots.len() >= 2 && marked && !resonance_only.is_estimate();

    // The design on the nominal system.
    let plan = design(
        &system(&NOMINAL),
        &model(),
        &candidates,
        &simulation,
        &settings.regressor,
        &DesignSettings {
            start: start.clone(),
            picks: 8,
            target_condition: Some(TARGET_CONDITION),
            ..DesignSettings::default()
        },
    )?;

    // Case 2: the true records of the designed set.
    let selected: Vec<HarmonicForce> = plan.selected().iter().map(|&k| candidates[k]).collect();
    let records = simulate_candidates(&system(&TRUTH), &selected, &simulation)?;
    let designed = identify(
        &ParametricRegressor::linear(&model(), &records),
        &settings,
        &silent,
    )?
    .report;
    let errors: Vec<f64> = names
        .iter()
        .zip(TRUTH)
        .map(|(name, t)| (designed.coefficient(name).unwrap_or(f64::NAN) - t).abs() / t)
        .collect();
    let case2_pass = errors.iter().all(|e| *e <= TOLERANCE) && designed.is_estimate();

    if as_json {
        println!(
            "{}",
            json!({"cases": [
                {"case": "first resonance only (the paper's experiments)", "report": resonance_only},
                {"case": "designed experiment set", "report": designed},
            ]})
        );
    } else {
        println!(
            "Four-mass chain, one linear dashpot per link plus shared quadratic d; truth {}\n",
            names
                .iter()
                .zip(TRUTH)
                .map(|(n, t)| format!("{n} = {t}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        println!("== first resonance only (the paper's experiments) ==\n{resonance_only}");
        println!("== experiment design on the nominal system (every coefficient 0.1) ==\n{plan}");
        println!("== designed experiment set ==\n{designed}");
        println!("targets:");
        println!(
            "  first resonance: dashpots flagged as not separable: [{}]; values marked not estimates: {marked} {}",
            flagged_dashpots.join(", "),
            if case1_pass { "ok" } else { "MISS" }
        );
        println!(
            "  designed set ({} experiments, condition number {:.3}): errors {} (tolerance {}%) {}",
            plan.selected().len(),
            designed.condition_number.unwrap_or(f64::INFINITY),
            names
                .iter()
                .zip(&errors)
                .map(|(n, e)| format!("{n} {:.4}%", 100.0 * e))
                .collect::<Vec<_>>()
                .join(", "),
            100.0 * TOLERANCE,
            if case2_pass { "ok" } else { "MISS" }
        );
    }
    if !(case1_pass && case2_pass) {
        eprintln!("a target was missed");
        std::process::exit(1);
    }
    Ok(())
}
