//! Regressions: inputs that once panicked, looped without end or gave a wrong number,
//! each with the typed error (or right number) the library gives now. Sizes that
//! overflow are `RecordTooShort` or `InvalidParameter`; a numerically singular mass
//! matrix is `Numerical`; huge but finite data fits or fails cleanly; bounds that admit
//! no value, element weights that do not match and windows under one step are rejected.

use dampid::fit;
use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;
use crate::support::regressors::from_rows;

#[test]
fn huge_period_is_too_short_not_a_panic() {
    // A window of T = 1e20 needs 1e22 samples: more than usize holds. The window
    // length saturates to usize::MAX in Quadrature::length and `whole + 1` overflows.
    let record = record_with(|p| p.period = 1e20).unwrap();
    assert!(matches!(
        identify(&ParametricRegressor::linear(&shared_model(), &[record]), &measured(), &silent),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_skip_is_too_short_not_a_panic() {
    let settings = windows(WindowSpec::cycles(1).skipping(usize::MAX).first(1));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&shared_model(), &[record()]), &settings, &silent),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_window_count_is_too_short_not_a_panic() {
    let settings = windows(WindowSpec::cycles(1).first(usize::MAX));
    assert!(matches!(
        identify(&ParametricRegressor::linear(&shared_model(), &[record()]), &settings, &silent),
        Err(Error::RecordTooShort { available: N, needed, .. }) if needed > N
    ));
}

#[test]
fn huge_transient_is_invalid_not_a_panic() {
    let mut settings = sim_settings();
    settings.transient_steps = usize::MAX;
    assert!(matches!(
        dampid::simulate::simulate(&system(), &settings, &dampid::progress::silent),
        Err(Error::InvalidParameter { ref name, .. }) if name.contains("steps")
    ));
}

#[test]
fn singular_mass_with_roundoff_pivot_is_numerical() {
    // M = [[1,2,3],[4,5,6],[7,8,9]] has rank 2; partial-pivot LU leaves a last pivot
    // of order 1e-16, so M⁻¹ is finite (entries ~1e16) and the check that looks for
    // non-finite entries of M⁻¹ misses it. With 3 recorded steps the state has not
    // overflowed yet, so no divergence error either.
    let mut sys = system();
    sys.mass = Mat::from_fn(3, 3, |i, j| (3 * i + j + 1) as f64);
    sys.stiffness = Mat::identity(3, 3);
    sys.damping =
        DampingModel::new().with(Term::per_dof(Linear, 3, Coefficients::Shared("c".into())));
    let mut settings = sim_settings();
    settings.recorded_steps = 3;
    let result = dampid::simulate::simulate(&sys, &settings, &dampid::progress::silent);
    assert!(
        matches!(
            &result,
            Err(Error::Numerical { stage, detail })
                if stage == "simulation" && detail.contains("singular")
        ),
        "{:?}",
        result.map(|r| r.displacements().norm_max())
    );
}

#[test]
fn large_but_finite_records_give_the_right_number() {
    // The fixture scaled by 1e80 in displacement, velocity and force: every value is
    // finite and the regressor entries (~1e160) are finite, but Σ b_r² = inf. The
    // energy balance is scale-free, so c is still 0.3.
    let record = record_with(|p| {
        p.displacements = Mat::from_fn(N, 2, |i, j| 1e80 * displacements(N)[(i, j)]);
        p.velocities = Some(Mat::from_fn(N, 2, |i, j| 1e80 * velocities(N)[(i, j)]));
        p.forcing = Forcing::generalized(Mat::from_fn(N, 2, |i, j| 1e80 * forces(N)[(i, j)]));
    })
    .unwrap();
    match identify(
        &ParametricRegressor::linear(&shared_model(), &[record]),
        &measured(),
        &silent,
    ) {
        Ok(report) => {
            let c = report.coefficient("c").unwrap();
            assert!((c - C_TRUE).abs() < 1e-6, "c = {c}");
        }
        Err(e) => assert!(matches!(e, Error::Numerical { .. }), "{e:?}"),
    }

    // The same through a hand-built regressor: A = b = 1e160 · [1, 1] gives θ = 1.
    let regressor = from_rows(&[&[1e160], &[1e160]], &[1e160, 1e160]);
    match fit::solve(&regressor, &FitSettings::default()) {
        Ok(fit) => assert!(
            (fit.coefficients[0] - 1.0).abs() < 1e-12,
            "θ = {:?}",
            fit.coefficients
        ),
        Err(e) => assert!(matches!(e, Error::Numerical { .. }), "{e:?}"),
    }
}

/// Entries near f64::MAX are finite, but a column's or the right-hand side's norm can
/// overflow. The fit's scaling then falls back to the largest entry, so that a
/// bound 0 (nonnegativity) or ±∞ (none) stays 0 or ±∞ instead of 0 · ∞ = NaN (the
/// `identify` fuzz target found the panic this caused in the constrained fit). The
/// system is consistent, and plain and nonnegative fits give θ = 1.
#[test]
fn regressor_whose_column_norm_overflows_fits_or_fails_cleanly() {
    let huge = 1.5e308;
    for column in [[huge, huge, huge], [huge, huge, 1.0], [1.0, 2.0, 3.0]] {
        // One column a, and b = a.
        let rows: Vec<&[f64]> = column.iter().map(std::slice::from_ref).collect();
        let regressor = from_rows(&rows, &column);
        for constraints in [Constraints::default(), Constraints::nonnegative()] {
            let settings = FitSettings {
                constraints,
                ..FitSettings::default()
            };
            let fit = fit::solve(&regressor, &settings).unwrap();
            let theta = fit.coefficients[0];
            assert!(
                fit.status.is_usable() && (theta - 1.0).abs() < 1e-9,
                "{column:?}: θ = {theta}, {:?}",
                fit.status
            );
        }
    }
}

#[test]
fn infinite_bounds_that_admit_no_value_are_rejected() {
    // [inf, inf] passes `lower > upper` and would count as fixed (lower == upper);
    // [−inf, −inf] likewise from above.
    for (lower, upper) in [(Some(f64::INFINITY), None), (None, Some(f64::NEG_INFINITY))] {
        let settings = two_windows(bound("c[1]", lower, upper));
        let result = identify(
            &ParametricRegressor::linear(&per_dof_model(), &[record()]),
            &settings,
            &silent,
        );
        assert!(
            matches!(
                &result,
                Err(Error::InfeasibleBounds { name, .. } | Error::InvalidParameter { name, .. })
                    if name.contains("c[1]")
            ),
            "bounds {lower:?}..{upper:?}: {result:?}"
        );
    }
}

#[test]
fn nan_phase_is_reported_with_its_value() {
    assert_invalid(
        simulate_with(|sys| sys.forcing[0].phase = f64::NAN),
        "forcing phase",
        f64::NAN,
    );
}

#[test]
fn element_weights_that_do_not_match_the_elements_are_checked() {
    // Two elements, one weight: accumulating the second element's column once indexed
    // past the end of the weights and panicked.
    let weighted = |weights: Vec<f64>| {
        DampingModel::new().with(Term::weighted(
            Linear,
            Element::each_dof(2),
            weights,
            Coefficients::Shared("c".into()),
        ))
    };
    assert!(matches!(
        identify(&ParametricRegressor::linear(&weighted(vec![0.5]), &[record()]), &measured(), &silent),
        Err(Error::DimensionMismatch { ref what, expected: 2, found: 1 })
            if what.contains("element weights")
    ));
    // The same through a model file.
    let text = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\nweights = [1.0, 2.0, 3.0]\n[simulation]\nmass = \"identity\"\nstiffness = \"chain\"\ncoefficients = { c = 0.1 }\nstep = 0.1\ntransient_steps = 0\nrecorded_steps = 10\nexperiments = [{ force_dof = 1, amplitude = 1.0, frequency = 1.0 }]\n";
    match parse_model(text, "w.toml") {
        Err(Error::ModelFile { line, message, .. }) => {
            assert_eq!(line, 2, "{message}");
            assert!(message.contains("element weights"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // A non-finite weight names its position.
    assert!(matches!(
        identify(&ParametricRegressor::linear(&weighted(vec![0.5, f64::NAN]), &[record()]), &measured(), &silent),
        Err(Error::NonFinite { ref what, row: 1, column: 0, value })
            if what.contains("element weights") && value.is_nan()
    ));
}

#[test]
fn window_shorter_than_one_step_is_invalid_not_an_endless_loop() {
    // Found by the `identify` fuzz target: with a period of a tiny fraction of a step
    // and as many windows as fit (`count: None`), round(j·T/h) stayed 0, every window
    // "fit" at sample 0, and cutting windows ran until memory ran out.
    let record = record_with(|p| p.period = 1e-30).unwrap();
    for quadrature in RULES {
        let mut settings = windows(WindowSpec::cycles(1));
        settings.regressor.quadrature = quadrature;
        assert_invalid(
            identify(
                &ParametricRegressor::linear(&shared_model(), std::slice::from_ref(&record)),
                &settings,
                &silent,
            ),
            "window span",
            1e-30,
        );
    }
}
