//! The preparation stage: windows that do not fit the record are `RecordTooShort`
//! (with the samples needed and present), window settings out of range are
//! `InvalidParameter`; measured velocities on a record without them are
//! `MissingVelocities`, spectral velocities with too many harmonics `InvalidParameter`;
//! a force without a period is `NoPeriod`, and a window whose motion does not return to
//! its start is `NotSteady`.

use dampid::prelude::*;
use faer::Mat;

use crate::fixtures::*;

// ---------------------------------------------------------------------------------
// Windows
// ---------------------------------------------------------------------------------

#[test]
fn record_shorter_than_one_window_is_too_short() {
    let mut p = parts(80);
    p.label = "short".into();
    let short = Record::new(p).unwrap();
    let err = identify(
        &ParametricRegressor::linear(&shared_model(), &[short]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert_eq!(
        err,
        Error::RecordTooShort {
            record: "short".into(),
            needed: WINDOW,
            available: 80
        }
    );
    let text = err.to_string();
    assert!(
        text.contains("'short'") && text.contains("101") && text.contains("80"),
        "{text}"
    );
}

#[test]
fn too_many_requested_windows_is_too_short() {
    let settings = windows(WindowSpec::cycles(1).first(3));
    // Window 2 starts at sample 200 and reads 101 samples.
    assert!(matches!(
        identify(&ParametricRegressor::linear(&shared_model(), &[record()]), &settings, &silent),
        Err(Error::RecordTooShort { ref record, needed: 301, available: N }) if record == "fixture"
    ));
}

#[test]
fn skip_beyond_record_is_too_short() {
    let settings = windows(WindowSpec::cycles(1).skipping(500).first(1));
    assert!(matches!(
        identify(
            &ParametricRegressor::linear(&shared_model(), &[record()]),
            &settings,
            &silent
        ),
        Err(Error::RecordTooShort {
            needed: 601,
            available: N,
            ..
        })
    ));
}

/// A period so long against the step that span/h overflows to ∞ (6.4e288 over
/// 6.9e-311): every rule and velocity source reports the record too short. (The
/// `identify` fuzz target found that the rectangular rule took such a window as 0
/// samples long, from φ = ∞ − ∞ = NaN, and the harmonic-projection row then overflowed
/// a sample count.)
#[test]
fn period_beyond_any_record_is_too_short() {
    let record = record_with(|p| {
        p.step = 6.9e-311;
        p.period = 6.4e288;
    })
    .unwrap();
    for quadrature in RULES {
        for velocity in [
            VelocitySource::Measured,
            VelocitySource::HarmonicProjection { harmonics: None },
        ] {
            let mut settings = measured();
            settings.regressor.quadrature = quadrature;
            settings.regressor.velocity = velocity;
            let result = identify(
                &ParametricRegressor::linear(&shared_model(), std::slice::from_ref(&record)),
                &settings,
                &silent,
            );
            assert!(
                matches!(
                    result,
                    Err(Error::RecordTooShort {
                        needed: usize::MAX,
                        available: N,
                        ..
                    })
                ),
                "{quadrature:?}, {velocity:?}: {result:?}"
            );
        }
    }
}

#[test]
fn invalid_window_spec_is_invalid_parameter() {
    for (spec, name) in [
        (WindowSpec::cycles(0).first(1), "cycles"),
        (WindowSpec::cycles(1).first(0), "count"),
    ] {
        assert_invalid(
            identify(
                &ParametricRegressor::linear(&shared_model(), &[record()]),
                &windows(spec),
                &silent,
            ),
            name,
            0.0,
        );
    }
}

#[test]
fn rectangular_window_under_two_samples_is_invalid_parameter() {
    // A period of half a step: the rectangular rule would sum round(0.5) = 1 sample.
    let record = record_with(|p| p.period = 0.5 * H).unwrap();
    let mut settings = measured();
    settings.regressor.quadrature = Quadrature::Rectangular;
    assert_invalid(
        identify(
            &ParametricRegressor::linear(&shared_model(), &[record]),
            &settings,
            &silent,
        ),
        "window span",
        0.5 * H,
    );
}

// ---------------------------------------------------------------------------------
// Velocities
// ---------------------------------------------------------------------------------

#[test]
fn measured_velocities_on_record_without_them_are_missing() {
    let record = record_with(|p| {
        p.label = "no-v".into();
        p.velocities = None;
    })
    .unwrap();
    let err = identify(
        &ParametricRegressor::linear(&shared_model(), &[record]),
        &measured(),
        &silent,
    )
    .unwrap_err();
    assert_eq!(
        err,
        Error::MissingVelocities {
            record: "no-v".into()
        }
    );
    assert!(err.to_string().contains("'no-v'"), "{err}");
}

#[test]
fn spectral_velocities_with_too_many_harmonics_are_invalid_parameter() {
    let spectral = |harmonics: usize| {
        let mut settings = measured();
        settings.regressor.velocity = VelocitySource::Spectral {
            harmonics: Some(harmonics),
        };
        identify(
            &ParametricRegressor::linear(&shared_model(), &[record()]),
            &settings,
            &silent,
        )
    };
    // A one-period trapezoid window reads 101 samples: at most 50 harmonics fit.
    let err = assert_invalid(spectral(80), "harmonics", 80.0);
    assert!(err.to_string().contains("80"), "{err}");

    // 50 harmonics fit the samples but reach the Nyquist frequency (T/2h = 50).
    let err = assert_invalid(spectral(50), "harmonics", 50.0);
    assert!(err.to_string().contains("Nyquist"), "{err}");

    assert_invalid(spectral(0), "harmonics", 0.0);
}

// ---------------------------------------------------------------------------------
// Period and steady state
// ---------------------------------------------------------------------------------

/// A force that does not change has no period; a zero force neither.
#[test]
fn constant_force_has_no_period() {
    for level in [0.0, 2.5] {
        let force = Mat::from_fn(N, 1, |_, _| level);
        match dampid::prep::period::detect_period(force.as_ref(), H, "still") {
            Err(Error::NoPeriod {
                record, explained, ..
            }) => {
                assert_eq!(record, "still");
                assert_eq!(explained, 0.0);
            }
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn growing_motion_is_not_steady_with_its_mismatch() {
    match growing_record_is_not_steady() {
        Error::NotSteady {
            record,
            window,
            mismatch,
            threshold,
            ..
        } => {
            assert_eq!((record.as_str(), window), ("growing", 0));
            // A quarter of the starting amplitude per period, relative to the largest
            // amplitude over the two compared periods (about 1.4): about 0.18.
            assert!(mismatch > 0.15 && mismatch < 0.3, "{mismatch}");
            // max(2%, 4 σ of the noise): the growth itself leaks into the out-of-band
            // noise estimate, not to its own size.
            assert!(
                threshold >= 0.02 && threshold < mismatch / 4.0,
                "{threshold}"
            );
        }
        other => panic!("{other:?}"),
    }
}
