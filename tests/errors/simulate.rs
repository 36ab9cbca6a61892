//! The simulator: a singular mass matrix, a diverging integration and a force or law
//! returning NaN are `Numerical` (stage "simulation"), never a record of NaN; springs
//! and forces on missing DOFs are `DofOutOfRange`; a system without forcing or DOFs is
//! `Empty`; matrices of the wrong size `DimensionMismatch`; settings, forces and
//! coefficients out of range `InvalidParameter`.

use std::sync::Arc;

use dampid::prelude::*;
use dampid::simulate::{ConservativeForce, HarmonicForce, SimSettings, simulate};
use faer::Mat;

use crate::fixtures::*;

#[test]
fn singular_mass_matrix_is_numerical() {
    for mass in [Mat::<f64>::zeros(2, 2), Mat::from_fn(2, 2, |_, _| 1.0)] {
        let err = simulate_with(|sys| sys.mass = mass).unwrap_err();
        assert!(
            matches!(
                &err,
                Error::Numerical { stage, detail }
                    if stage == "simulation" && detail.contains("singular")
            ),
            "{err:?}"
        );
        assert!(err.to_string().contains("singular"), "{err}");
    }
}

#[test]
fn diverging_simulation_is_numerical_not_nan() {
    // Stiff K = 1e6 I with a step h = 1: h √k = 1000, far beyond RK4's stability limit.
    let mut sys = system();
    sys.stiffness = Mat::from_fn(2, 2, |i, j| if i == j { 1e6 } else { 0.0 });
    let settings = SimSettings {
        step: 1.0,
        substeps: 1,
        transient_steps: 0,
        recorded_steps: 200,
    };
    let err = simulate(&sys, &settings, &dampid::progress::silent).unwrap_err();
    assert!(
        matches!(
            &err,
            Error::Numerical { stage, detail }
                if stage == "simulation" && detail.contains("diverged")
        ),
        "{err:?}"
    );
}

#[test]
fn custom_law_returning_nan_in_simulation_is_numerical() {
    let broken_law = simulate_with(|sys| {
        sys.damping = DampingModel::new().with(Term::per_dof(
            Custom::new("broken", |_x, _v| f64::NAN),
            2,
            Coefficients::Shared("c".into()),
        ))
    });
    let broken_force = simulate_with(|sys| {
        sys.conservative = vec![ConservativeForce::Custom(Arc::new(|_x, out| {
            out[0] += f64::NAN
        }))]
    });
    for result in [broken_law, broken_force] {
        assert!(matches!(
            result,
            Err(Error::Numerical { ref stage, .. }) if stage == "simulation"
        ));
    }
}

#[test]
fn invalid_sim_settings_are_invalid_parameter() {
    let mut settings = sim_settings();
    settings.substeps = 0;
    let err = assert_invalid(
        simulate(&system(), &settings, &dampid::progress::silent),
        "substeps",
        0.0,
    );
    assert!(err.to_string().contains("substeps"), "{err}");

    for step in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let mut settings = sim_settings();
        settings.step = step;
        assert_invalid(
            simulate(&system(), &settings, &dampid::progress::silent),
            "step",
            step,
        );
    }

    let mut settings = sim_settings();
    settings.recorded_steps = 2;
    assert_invalid(
        simulate(&system(), &settings, &dampid::progress::silent),
        "recorded_steps",
        2.0,
    );
}

/// Sizes are checked before allocation, and time from a measured rate: a record of
/// 10¹⁵ samples is `TooLarge` (memory) at once, 10¹⁵ transient steps `TooLarge` (time)
/// after a fraction of a second, each naming the setting to reduce.
#[test]
fn absurd_simulation_sizes_are_too_large() {
    let mut settings = sim_settings();
    settings.recorded_steps = 1_000_000_000_000_000;
    let memory = simulate(&system(), &settings, &dampid::progress::silent).unwrap_err();
    assert_eq!(memory.kind(), "too_large");
    assert!(memory.to_string().contains("recorded_steps"), "{memory}");

    let mut settings = sim_settings();
    settings.transient_steps = 1_000_000_000_000_000;
    let time = simulate(&system(), &settings, &dampid::progress::silent).unwrap_err();
    assert_eq!(time.kind(), "too_large");
    let message = time.to_string();
    assert!(
        message.contains("years") && message.contains("transient_steps"),
        "{message}"
    );
}

#[test]
fn cubic_spring_on_missing_dof_is_dof_out_of_range() {
    let cubic = |dof: usize, coefficient: f64| {
        simulate_with(|sys| sys.conservative = vec![ConservativeForce::Cubic { dof, coefficient }])
    };
    let err = cubic(2, 1.0).unwrap_err();
    assert_eq!(
        err,
        Error::DofOutOfRange {
            what: "cubic spring".into(),
            dof: 3,
            dofs: 2
        }
    );
    assert!(err.to_string().contains("cubic spring"), "{err}");

    assert_invalid(cubic(0, f64::NAN), "cubic spring coefficient", f64::NAN);
}

#[test]
fn harmonic_force_on_missing_dof_is_dof_out_of_range() {
    assert_eq!(
        simulate_with(|sys| sys.forcing[0].dof = 9).unwrap_err(),
        Error::DofOutOfRange {
            what: "harmonic force".into(),
            dof: 10,
            dofs: 2
        }
    );
}

#[test]
fn harmonic_forces_at_two_frequencies_are_invalid_parameter() {
    let result = simulate_with(|sys| {
        sys.forcing.push(HarmonicForce {
            dof: 0,
            amplitude: 0.5,
            frequency: 1.5,
            phase: 0.0,
        })
    });
    let err = assert_invalid(result, "forcing frequency", 1.5);
    assert!(err.to_string().contains("1.5"), "{err}");
}

#[test]
fn invalid_harmonic_force_is_invalid_parameter() {
    for frequency in [0.0, -1.0, f64::NAN] {
        assert_invalid(
            simulate_with(|sys| sys.forcing[0].frequency = frequency),
            "forcing frequency",
            frequency,
        );
    }
    assert_invalid(
        simulate_with(|sys| sys.forcing[0].amplitude = f64::INFINITY),
        "forcing amplitude",
        f64::INFINITY,
    );
}

#[test]
fn system_without_forcing_or_dofs_is_empty() {
    assert!(matches!(
        simulate_with(|sys| sys.forcing.clear()),
        Err(Error::Empty { ref what }) if what == "forcing"
    ));
    assert!(matches!(
        simulate_with(|sys| sys.mass = Mat::zeros(0, 0)),
        Err(Error::Empty { ref what }) if what == "mass matrix"
    ));
}

#[test]
fn system_matrices_and_coefficients_are_checked() {
    assert!(matches!(
        simulate_with(|sys| sys.stiffness = Mat::identity(3, 3)),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 3 })
            if what.contains("stiffness")
    ));
    assert!(matches!(
        simulate_with(|sys| sys.mass[(1, 0)] = f64::NAN),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what == "mass" && value.is_nan()
    ));
    assert!(matches!(
        simulate_with(|sys| sys.damping_coefficients = vec![0.1, 0.2]),
        Err(Error::DimensionMismatch { ref what, expected: 1, found: 2 })
            if what.contains("damping coefficients")
    ));
    assert_invalid(
        simulate_with(|sys| sys.damping_coefficients = vec![f64::NAN]),
        "damping coefficient 0",
        f64::NAN,
    );
    let result = simulate_with(|sys| {
        sys.damping = DampingModel::new().with(Term::on_elements(
            Linear,
            vec![Element::between(0, 2)],
            Coefficients::Shared("c".into()),
        ))
    });
    assert!(matches!(
        result,
        Err(Error::DofOutOfRange {
            dof: 3,
            dofs: 2,
            ..
        })
    ));
}

/// A design whose candidates' records would not fit in memory together is `TooLarge`
/// before the first simulation: 1000 candidates × 10¹² recorded steps × (2·2 + 1)
/// values of 8 bytes is 4·10¹⁶ bytes, naming the candidates and `recorded_steps`.
#[test]
fn design_candidates_beyond_memory_are_too_large() {
    let mut settings = sim_settings();
    settings.recorded_steps = 1_000_000_000_000;
    let force = system().forcing[0];
    let candidates = vec![force; 1000];
    let e = dampid::analysis::design::simulate_candidates(&system(), &candidates, &settings)
        .unwrap_err();
    assert_eq!(e.kind(), "too_large");
    let message = e.to_string();
    assert!(
        message.contains("1000 design candidates") && message.contains("recorded_steps"),
        "{message}"
    );
}

/// A POD of 10⁵ sensors needs its 10⁵ × 10⁵ correlation matrix (and partial sums of
/// that size): about 1.6 TB, refused before allocating it, naming the sensors. The
/// samples themselves (1 × 10⁵) are small.
#[test]
fn pod_of_too_many_sensors_is_too_large() {
    let x = Mat::from_fn(1, 100_000, |_, j| 1.0 + j as f64);
    let settings = PodSettings {
        retain: Retain::Count(1),
        ..PodSettings::default()
    };
    let e = Pod::from_displacements(x.as_ref(), &settings).unwrap_err();
    assert_eq!(e.kind(), "too_large");
    assert!(e.to_string().contains("100000 sensors"), "{e}");
}
