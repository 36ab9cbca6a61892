//! Every term, the input work and every quadrature rule against closed forms derived
//! by hand for pure harmonic motion x = X cos ωt (v = −Xω sin ωt) over one period
//! T = 2π/ω:
//!
//!   ∫ v² dt      = X²ω² · T/2                          = π ω X²
//!   ∫ |v|³ dt    = (Xω)³ · (2/ω) ∫_0^π sin³θ dθ = (Xω)³ (2/ω)(4/3) = (8/3) ω² X³
//!   ∫ |v| dt     = Xω · (2/ω) · 2                       = 4 X
//!   ∫ |v|^{q} dt = (Xω)^q (4/ω) ∫_0^{π/2} sin^q θ dθ,  ∫_0^{π/2} sin^q = (√π/2) Γ((q+1)/2)/Γ(q/2+1)
//!   ∫ x² v² dt   = X⁴ω² ∫ cos² sin² = X⁴ω² T/8          = π ω X⁴ / 4
//!   input work of F cos(ωt + ψ) on that DOF: ∫ v f dt = −XωF ∫ sin ωt cos(ωt+ψ) dt = π X F sin ψ

mod support;

use dampid::prelude::*;
use faer::Mat;
use std::f64::consts::PI;
use support::{Harmonic, rel, row};

const RULES: [Quadrature; 3] = [
    Quadrature::Rectangular,
    Quadrature::Trapezoid,
    Quadrature::Spectral,
];

fn per_dof(law: impl Law + 'static) -> DampingModel {
    DampingModel::new().with(Term::per_dof(law, 1, Coefficients::Shared("k".into())))
}

/// With a whole number of samples per period every rule is spectrally accurate on
/// these smooth periodic integrands.
#[test]
fn linear_law_gives_pi_omega_x_squared() {
    let (x, w) = (1.7, 1.3);
    let record = Harmonic::one_dof(x, w, 400.0).record();
    for rule in RULES {
        let (a, _) = row(&per_dof(Linear), &record, rule, VelocitySource::Measured);
        assert!(rel(a[0], PI * w * x * x) < 1e-12, "{rule:?}: {}", a[0]);
    }
}

#[test]
fn quadratic_law_gives_eight_thirds_omega_squared_x_cubed() {
    let (x, w) = (0.8, 2.1);
    let record = Harmonic::one_dof(x, w, 1000.0).record();
    for rule in [Quadrature::Rectangular, Quadrature::Trapezoid] {
        let (a, _) = row(&per_dof(Quadratic), &record, rule, VelocitySource::Measured);
        // |sin|³ has a kink in its third derivative: error O(N⁻⁴).
        assert!(
            rel(a[0], 8.0 / 3.0 * w * w * x.powi(3)) < 1e-9,
            "{rule:?}: {}",
            a[0]
        );
    }
}

#[test]
fn coulomb_law_gives_four_x() {
    let (x, w) = (0.6, 0.9);
    let record = Harmonic::one_dof(x, w, 1000.0).record();
    for rule in [Quadrature::Rectangular, Quadrature::Trapezoid] {
        let (a, _) = row(&per_dof(Coulomb), &record, rule, VelocitySource::Measured);
        // |sin| has a kink: error O(N⁻²).
        assert!(rel(a[0], 4.0 * x) < 1e-5, "{rule:?}: {}", a[0]);
    }
}

#[test]
fn power_law_matches_wallis_integral() {
    let (x, w, p): (f64, f64, f64) = (1.1, 1.4, 0.5);
    let q: f64 = p + 1.0; // 1.5
    // ∫_0^{π/2} sin^{1.5} = (√π/2) Γ(1.25)/Γ(1.75)
    let gamma_1_25 = 0.906_402_477_055_477;
    let gamma_1_75 = 0.919_062_526_848_883;
    let wallis = PI.sqrt() / 2.0 * gamma_1_25 / gamma_1_75;
    let exact = (x * w).powf(q) * 4.0 / w * wallis;
    let record = Harmonic::one_dof(x, w, 2000.0).record();
    let (a, _) = row(
        &per_dof(PowerLaw::new(p).unwrap()),
        &record,
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    assert!(rel(a[0], exact) < 1e-6, "{} vs {exact}", a[0]);
    // p = 1 and p = 2 reproduce the linear and quadratic closed forms.
    let (a1, _) = row(
        &per_dof(PowerLaw::new(1.0).unwrap()),
        &record,
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    assert!(rel(a1[0], PI * w * x * x) < 1e-12);
    let (a2, _) = row(
        &per_dof(PowerLaw::new(2.0).unwrap()),
        &record,
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    assert!(rel(a2[0], 8.0 / 3.0 * w * w * x.powi(3)) < 1e-9);
}

#[test]
fn custom_law_of_displacement_and_velocity() {
    let (x, w) = (0.9, 1.2);
    let record = Harmonic::one_dof(x, w, 500.0).record();
    let law = Custom::new("x^2*v", |x, v| x * x * v);
    let (a, _) = row(
        &per_dof(law),
        &record,
        Quadrature::Spectral,
        VelocitySource::Measured,
    );
    assert!(rel(a[0], PI * w * x.powi(4) / 4.0) < 1e-12, "{}", a[0]);
}

#[test]
fn input_work_is_pi_x_f_sin_psi() {
    let mut motion = Harmonic::one_dof(1.3, 0.7, 300.0);
    motion.force = 2.5;
    motion.force_phase = 0.9;
    let record = motion.record();
    for rule in RULES {
        let (_, b) = row(&per_dof(Linear), &record, rule, VelocitySource::Measured);
        assert!(
            rel(b, PI * 1.3 * 2.5 * 0.9f64.sin()) < 1e-12,
            "{rule:?}: {b}"
        );
    }
}

/// Two DOFs x_1 = X_1 cos ωt, x_2 = X_2 cos(ωt + φ): ∫ v_1 v_2 dt = π ω X_1 X_2 cos φ, so
/// ∫ vᵀ C v = π ω (C_11 X_1² + (C_12 + C_21) X_1 X_2 cos φ + C_22 X_2²) and a dashpot
/// between them dissipates π ω (X_1² − 2 X_1 X_2 cos φ + X_2²).
#[test]
fn matrix_term_and_dashpot_on_two_dofs() {
    let (x1, x2, phi, w) = (1.0, 0.6, 0.8, 1.5);
    let motion = Harmonic {
        force_dof: 1,
        ..Harmonic::two_dofs([x1, x2], [0.0, phi], w, 256.0)
    };
    let record = motion.record();
    let c0 = Mat::from_fn(2, 2, |i, j| [[2.0, -0.5], [-1.0, 3.0]][i][j]);
    let model = DampingModel::new()
        .with(Term::viscous("c", c0))
        .with(Term::on_elements(
            Linear,
            vec![Element::between(0, 1)],
            Coefficients::PerElement("dashpot".into()),
        ))
        .with(Term::on_elements(
            Linear,
            vec![Element::to_ground(1)],
            Coefficients::Shared("ground".into()),
        ));
    let (a, _) = row(
        &model,
        &record,
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    let cross = x1 * x2 * phi.cos();
    assert!(rel(a[0], PI * w * (2.0 * x1 * x1 - 1.5 * cross + 3.0 * x2 * x2)) < 1e-12);
    assert!(rel(a[1], PI * w * (x1 * x1 - 2.0 * cross + x2 * x2)) < 1e-12);
    assert!(rel(a[2], PI * w * x2 * x2) < 1e-12);
}

/// Stiffness- and mass-proportional terms are matrix terms: C = K of a 2-DOF chain
/// gives π ω (2X_1² − 2X_1X_2 cos φ + 2X_2²).
#[test]
fn stiffness_and_mass_proportional_terms() {
    let (x1, x2, phi, w) = (0.5, 1.2, 0.3, 0.8);
    let motion = Harmonic::two_dofs([x1, x2], [0.0, phi], w, 128.0);
    let record = motion.record();
    let k = dampid::simulate::chain_stiffness(2);
    let m = Mat::from_fn(2, 2, |i, j| if i == j { [2.0, 0.5][i] } else { 0.0 });
    let model = DampingModel::new()
        .with(Term::stiffness_proportional("beta", k))
        .with(Term::mass_proportional("alpha", m));
    let (a, _) = row(
        &model,
        &record,
        Quadrature::Spectral,
        VelocitySource::Measured,
    );
    let cross = x1 * x2 * phi.cos();
    assert!(rel(a[0], PI * w * (2.0 * x1 * x1 - 2.0 * cross + 2.0 * x2 * x2)) < 1e-12);
    assert!(rel(a[1], PI * w * (2.0 * x1 * x1 + 0.5 * x2 * x2)) < 1e-12);
}

/// Per-element coefficients name each element; the chain helper labels walls 0 and n+1.
#[test]
fn per_dashpot_coefficient_names() {
    let model = DampingModel::new()
        .with(Term::on_elements(
            Linear,
            Element::chain_fixed_both_ends(3),
            Coefficients::PerElement("dashpot".into()),
        ))
        .with(Term::per_dof(
            Quadratic,
            3,
            Coefficients::Shared("d".into()),
        ));
    assert_eq!(
        model.coefficient_names(),
        [
            "dashpot[0-1]",
            "dashpot[1-2]",
            "dashpot[2-3]",
            "dashpot[3-4]",
            "d"
        ]
    );
}

/// When T/h = 101.67 (the paper's case) the spectral rule stays exact on the linear
/// column, the trapezoid is second order, and the rectangular rule carries the
/// span error |round(L) − L|/L times max/mean of the integrand (2 for sin²).
#[test]
fn rules_on_incommensurate_sampling() {
    let (x, w) = (1.0, 0.618);
    let record = Harmonic::one_dof(x, w, 101.67).record();
    let exact = PI * w * x * x;
    let error = |rule| {
        rel(
            row(&per_dof(Linear), &record, rule, VelocitySource::Measured).0[0],
            exact,
        )
    };
    assert!(error(Quadrature::Spectral) < 1e-11);
    assert!(error(Quadrature::Trapezoid) < 2e-4);
    assert!(error(Quadrature::Rectangular) < 2.0 * 0.33 / 101.67);
}

/// Velocities estimated from the displacements alone: spectral differentiation is exact
/// for a pure harmonic on any grid; central differences err by (ωh)²/6.
#[test]
fn estimated_velocities_match_closed_forms() {
    let (x, w) = (1.0, 0.618);
    let record = Harmonic::one_dof(x, w, 101.67).record();
    let exact = PI * w * x * x;
    let spectral = VelocitySource::Spectral { harmonics: None };
    let (a, _) = row(&per_dof(Linear), &record, Quadrature::Spectral, spectral);
    assert!(rel(a[0], exact) < 1e-10, "spectral {}", a[0]);
    let (a, _) = row(
        &per_dof(Linear),
        &record,
        Quadrature::Spectral,
        VelocitySource::CentralDifference,
    );
    let h = record.step();
    // v_cd = v sin(ωh)/(ωh), so the power is scaled by (sin(ωh)/(ωh))²
    let factor = ((w * h).sin() / (w * h)).powi(2);
    assert!(rel(a[0], exact * factor) < 1e-10, "central {}", a[0]);
}

/// A load distribution matrix: r = D s with D = [0.5, 2]ᵀ on two DOFs moving in phase
/// gives input work π F (0.5 X_1 + 2 X_2) sin ψ.
#[test]
fn distributed_load_input_work() {
    let motion = Harmonic {
        force: 1.5,
        force_phase: 0.6,
        ..Harmonic::two_dofs([1.0, 0.4], [0.0, 0.0], 1.0, 200.0)
    };
    let parts = motion.record().into_parts();
    let distribution = Mat::from_fn(2, 1, |i, _| [0.5, 2.0][i]);
    let record = Record::new(RecordParts {
        forcing: Forcing::distributed(parts.forcing.signals.clone(), distribution),
        ..parts
    })
    .unwrap();
    let (_, b) = row(
        &per_dof(Linear),
        &record,
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    assert!(rel(b, PI * 1.5 * (0.5 + 2.0 * 0.4) * 0.6f64.sin()) < 1e-12);
}

/// Element weights scale each element's column and force: weights (0.5, 2) on two DOFs
/// to ground with one shared coefficient give π ω (0.5 X_1² + 2 X_2²).
#[test]
fn element_weights_scale_each_element() {
    let (x1, x2, w) = (1.0, 0.5, 1.1);
    let motion = Harmonic::two_dofs([x1, x2], [0.0, 0.4], w, 128.0);
    let model = DampingModel::new().with(Term::weighted(
        Linear,
        Element::each_dof(2),
        vec![0.5, 2.0],
        Coefficients::Shared("c".into()),
    ));
    let (a, _) = row(
        &model,
        &motion.record(),
        Quadrature::Trapezoid,
        VelocitySource::Measured,
    );
    assert!(rel(a[0], PI * w * (0.5 * x1 * x1 + 2.0 * x2 * x2)) < 1e-12);
    let mut force = [0.0; 2];
    model.add_damping_force(&[3.0], &[0.0, 0.0], &[1.0, 1.0], &mut force);
    assert_eq!(force, [1.5, 6.0]);
}
