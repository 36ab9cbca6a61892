//! Data that identify two power-law exponents on the paper's four-mass chain, shared by
//! tests/varpro.rs and benches/varpro.rs (`#[path]`).
//!
//! The chain (unit masses, unit springs, both ends fixed) is symmetric, so every mode
//! shape has mirror-symmetric magnitudes, |φ₁| = (0.588, 0.951, 0.951, 0.588) and
//! |φ₂| = (0.951, 0.588, 0.588, 0.951). Two laws on mirror-image masses (1–2 and 3–4)
//! therefore dissipate in the same ratio in any one mode, and records at one resonance
//! are nearly one mode shape: their columns d₁ and d₂ (and ∂/∂p₁, ∂/∂p₂) are nearly
//! collinear, and four force levels give four distinct equations for five unknowns (c,
//! d₁, d₂, p₁, p₂). Here the laws sit on the ends (masses 1 and 4) and on the middle
//! (masses 2 and 3), whose shares swap between modes 1 and 2, and the chain is driven
//! at mass 4 at both of its first two resonances, six force levels each, with distinct
//! true exponents: C = 0.15 K, 0.1|v|^1.5 sign(v) on masses 1 and 4, 0.1|v|^2.5 sign(v)
//! on masses 2 and 3. Column-scaled full Jacobian [A, ∂r/∂p₁, ∂r/∂p₂] at the truth:
//! condition number 4.9e2 here against 6.7e6 on the single-resonance data of the former
//! bench (docs/laws.md).

#![allow(dead_code)]

use dampid::prelude::*;
use dampid::reference::{FOUR_MASS_C, four_mass_system};
use dampid::simulate::{SimSettings, chain_stiffness, simulate};
use dampid::terms::laws::PowerLaw;
use dampid::terms::{Coefficients, Element, Term};

/// True exponent of the law on the ends (masses 1 and 4).
pub const P1: f64 = 1.5;
/// True exponent of the law on the middle (masses 2 and 3).
pub const P2: f64 = 2.5;
/// True coefficients of both laws.
pub const D: f64 = 0.1;
/// True stiffness-proportional coefficient.
pub const C: f64 = FOUR_MASS_C;
/// Force amplitudes at each resonance.
pub const AMPLITUDES: [f64; 6] = [0.25, 0.5, 0.75, 1.0, 1.5, 2.0];
/// Whole periods recorded per record.
pub const CYCLES: usize = 8;

/// The first two natural frequencies of the fixed–fixed chain, 2 sin(kπ/10).
pub fn resonances() -> [f64; 2] {
    [1, 2].map(|k| 2.0 * (k as f64 * std::f64::consts::PI / 10.0).sin())
}

/// C = c K, d₁|v|^p₁ sign(v) on masses 1 and 4, d₂|v|^p₂ sign(v) on masses 2 and 3.
pub fn model(p1: f64, p2: f64) -> dampid::Result<DampingModel> {
    Ok(DampingModel::new()
        .with(Term::stiffness_proportional("c", chain_stiffness(4)))
        .with(Term::on_elements(
            PowerLaw::new(p1)?,
            vec![Element::to_ground(0), Element::to_ground(3)],
            Coefficients::Shared("d1".into()),
        ))
        .with(Term::on_elements(
            PowerLaw::new(p2)?,
            vec![Element::to_ground(1), Element::to_ground(2)],
            Coefficients::Shared("d2".into()),
        )))
}

/// The chain simulated with the true model, driven at mass 4 at each resonance and
/// each amplitude, 5000 steps into the steady state, `CYCLES` whole periods recorded.
pub fn records() -> Vec<Record> {
    let mut records = Vec::new();
    for omega in resonances() {
        let period = 2.0 * std::f64::consts::PI / omega;
        let settings = SimSettings {
            transient_steps: 5000,
            recorded_steps: (CYCLES as f64 * period / 0.1).ceil() as usize + 4,
            ..SimSettings::default()
        };
        for &a in &AMPLITUDES {
            let mut system = four_mass_system(a, false);
            system.forcing[0].frequency = omega;
            system.damping = model(P1, P2).unwrap();
            system.damping_coefficients = vec![C, D, D];
            records.push(simulate(&system, &settings, &dampid::progress::silent).unwrap());
        }
    }
    records
}
