//! The harmonic approximation (eq. 4), stepped-sine tables, and velocities by harmonic
//! projection.
//!
//! Closed forms for a synchronous motion x_i = X_i cos(ωt − φ̄) over one period, with
//! the force a cos ωt on DOF f (derived in tests/terms.rs for one DOF):
//!
//!   ∮ ẋᵀC₀ẋ dt = π ω XᵀC₀X     ∮ Σ|ẋ_i|³ dt = (8/3) ω² Σ X_i³     ∮ Σ|ẋ_i| dt = 4 Σ X_i
//!   ∮ Σ ẋ_i² x_i² dt = π ω Σ X_i⁴ / 4                               input: π a X_f sin φ̄

mod support;

use std::f64::consts::PI;

use dampid::Error;
use dampid::prelude::*;
use dampid::prep::harmonic::{
    HarmonicApproximation, PhaseReading, SteppedSinePoint, SteppedSineTable, fundamentals,
};
use dampid::prep::velocity::harmonic_selection;
use dampid::reference::{FOUR_MASS_AMPLITUDES, four_mass_model, four_mass_system};
use dampid::simulate::{SimSettings, simulate};
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};
use support::{Harmonic, rel, row};

/// The regressor of `model` on the harmonic approximation of `table`.
fn approximation_regressor(
    approximation: &HarmonicApproximation,
    model: &DampingModel,
    table: &SteppedSineTable,
) -> dampid::Result<Regressor> {
    Regressor::build(
        model,
        &approximation.records(table)?,
        &RegressorSettings::harmonic_approximation(),
    )
}

fn point(
    label: &str,
    omega: f64,
    force_dof: usize,
    a: f64,
    x: &[f64],
    phi: &[f64],
) -> SteppedSinePoint {
    SteppedSinePoint {
        label: label.into(),
        frequency: omega,
        force_dof,
        force_amplitude: a,
        amplitudes: x.to_vec(),
        phases: phi.to_vec(),
    }
}

/// A model with one column per closed form: a nonsymmetric C₀ (only its symmetric part
/// dissipates), linear, quadratic and Coulomb laws on every DOF, and a custom law x²v.
fn closed_form_model(n: usize) -> (DampingModel, Mat<f64>) {
    let c0 = Mat::from_fn(n, n, |i, j| {
        if i == j {
            2.0 + i as f64
        } else if j == i + 1 {
            -0.7
        } else if i == j + 1 {
            -1.1
        } else {
            0.0
        }
    });
    let model = DampingModel::new()
        .with(Term::viscous("c", c0.clone()))
        .with(Term::per_dof(Linear, n, Coefficients::Shared("lin".into())))
        .with(Term::per_dof(
            Quadratic,
            n,
            Coefficients::Shared("d".into()),
        ))
        .with(Term::per_dof(Coulomb, n, Coefficients::Shared("mu".into())))
        .with(Term::per_dof(
            Custom::new("x^2 v", |x, v| x * x * v),
            n,
            Coefficients::Shared("k".into()),
        ));
    (model, c0)
}

/// The closed forms (columns and input work) of the synchronous motion of `p` with lag φ̄.
fn closed_forms(p: &SteppedSinePoint, c0: &Mat<f64>, phibar: f64) -> (Vec<f64>, f64) {
    let (w, x) = (p.frequency, &p.amplitudes);
    let n = x.len();
    let xcx: f64 = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .map(|(i, j)| x[i] * c0[(i, j)] * x[j])
        .sum();
    let columns = vec![
        PI * w * xcx,
        PI * w * x.iter().map(|x| x * x).sum::<f64>(),
        8.0 / 3.0 * w * w * x.iter().map(|x| x.powi(3)).sum::<f64>(),
        4.0 * x.iter().sum::<f64>(),
        PI * w * x.iter().map(|x| x.powi(4)).sum::<f64>() / 4.0,
    ];
    let input = PI * p.force_amplitude * x[p.force_dof] * phibar.sin();
    (columns, input)
}

/// Relative tolerance per closed-form column: exact for trigonometric polynomials,
/// O(N⁻⁴) for |v|³ and O(N⁻²) for |v| with N = 512 samples per period.
const COLUMN_TOLERANCE: [f64; 5] = [1e-12, 1e-12, 1e-9, 3e-5, 1e-12];

#[test]
fn harmonic_columns_equal_the_closed_forms_for_a_hand_made_table() {
    let table = SteppedSineTable::new(vec![
        point("p0", 1.3, 1, 2.0, &[0.7, 1.2, 0.4], &[0.3, 0.5, 0.4]),
        point("p1", 0.8, 2, 0.5, &[0.2, 0.9, 1.5], &[1.2, 1.5, 1.9]),
        // Lags on both sides of ±π: the arithmetic mean is taken around π, not 0.
        point("p2", 2.0, 0, 1.0, &[1.0, 0.3, 0.6], &[3.0, -3.0, 3.1]),
    ])
    .unwrap();
    let means = [
        0.4,
        (1.2 + 1.5 + 1.9) / 3.0,
        (3.0 + (2.0 * PI - 3.0) + 3.1) / 3.0,
    ];
    let (model, c0) = closed_form_model(3);
    let regressor =
        approximation_regressor(&HarmonicApproximation::default(), &model, &table).unwrap();
    assert_eq!(regressor.equations(), 3);
    for (r, p) in table.points().iter().enumerate() {
        let (columns, input) = closed_forms(p, &c0, means[r]);
        for (k, expected) in columns.iter().enumerate() {
            let got = regressor.matrix()[(r, k)];
            assert!(
                rel(got, *expected) < COLUMN_TOLERANCE[k],
                "point {r} column {k}: {got} vs {expected}"
            );
        }
        assert!(
            rel(regressor.rhs()[r], input) < 1e-12,
            "point {r} input work {} vs {input}",
            regressor.rhs()[r]
        );
    }
    // The rows are labelled by the points.
    assert_eq!(regressor.rows()[1].record, "p1");
}

#[test]
fn phase_readings_follow_their_definitions() {
    let p = point("p", 1.0, 0, 1.0, &[1.0, 3.0], &[0.2, 0.6]);
    let mean = |reading: PhaseReading| reading.phases(&p).unwrap();
    assert!((mean(PhaseReading::ArithmeticMean)[1] - 0.4).abs() < 1e-15);
    assert!((mean(PhaseReading::CircularMean)[0] - 0.4).abs() < 1e-15);
    let weighted = (0.2f64.sin() + 3.0 * 0.6f64.sin()).atan2(0.2f64.cos() + 3.0 * 0.6f64.cos());
    assert!((mean(PhaseReading::AmplitudeWeightedMean)[0] - weighted).abs() < 1e-15);
    assert_eq!(mean(PhaseReading::Dof(1)), [0.6, 0.6]);
    assert_eq!(mean(PhaseReading::PerDof), [0.2, 0.6]);
    // Not synchronous: ∮ ẋ_1 ẋ_2 dt = π ω X_1 X_2 cos(φ_1 − φ_2).
    let model = DampingModel::new().with(Term::viscous(
        "c",
        Mat::from_fn(2, 2, |i, j| if i == j { 0.0 } else { 1.0 }),
    ));
    let table = SteppedSineTable::new(vec![p]).unwrap();
    let approximation = HarmonicApproximation {
        phase: PhaseReading::PerDof,
        ..HarmonicApproximation::default()
    };
    let a = approximation_regressor(&approximation, &model, &table)
        .unwrap()
        .matrix()[(0, 0)];
    assert!(rel(a, 2.0 * PI * 3.0 * (0.4f64).cos()) < 1e-12, "{a}");
}

/// A pure synchronous sine sampled off-grid (T/h = 101.67): the table read from the
/// record holds the exact amplitudes and lags, its harmonic approximation equals the
/// closed forms, and both equal the direct integration of the time series.
#[test]
fn harmonic_closed_forms_equal_numerical_synthesis_for_a_pure_sine() {
    let motion = Harmonic {
        amplitudes: vec![0.8, 1.3, 0.5],
        phases: vec![-1.1, -1.1, -1.1],
        omega: 0.618,
        per_period: 101.67,
        periods: 1.0,
        force: 0.75,
        force_phase: 0.2,
        force_dof: 2,
    };
    let record = motion.record();
    let f = fundamentals(&record, 0, 1).unwrap();
    for (j, p) in f.displacements.iter().enumerate() {
        assert!((p.amplitude - motion.amplitudes[j]).abs() < 1e-12);
        assert!((p.phase - 1.1).abs() < 1e-12, "{}", p.phase);
    }
    assert!((f.forces[0].amplitude - 0.75).abs() < 1e-12);
    assert!((f.forces[0].phase + 0.2).abs() < 1e-12);

    let table =
        SteppedSineTable::from_records(std::slice::from_ref(&record), &WindowSpec::default())
            .unwrap();
    let p = &table.points()[0];
    assert_eq!(p.force_dof, 2);
    assert!((p.phases[0] - 1.3).abs() < 1e-12, "lag {}", p.phases[0]);

    let (model, c0) = closed_form_model(3);
    let synthesized =
        approximation_regressor(&HarmonicApproximation::default(), &model, &table).unwrap();
    let (direct, direct_input) = row(
        &model,
        &record,
        Quadrature::Spectral,
        VelocitySource::Measured,
    );
    let (columns, input) = closed_forms(p, &c0, 1.3);
    for k in 0..columns.len() {
        let a = synthesized.matrix()[(0, k)];
        assert!(
            rel(a, columns[k]) < COLUMN_TOLERANCE[k],
            "column {k}: {a} vs {}",
            columns[k]
        );
        // The time series has 101.67 samples per period: the spectral rule is exact on
        // trigonometric polynomials but sees the kinks of |v| and |v|³ coarsely.
        let tolerance = [1e-10, 1e-10, 1e-5, 1e-3, 1e-10][k];
        assert!(
            rel(a, direct[k]) < tolerance,
            "column {k}: {a} vs direct {}",
            direct[k]
        );
    }
    assert!(rel(synthesized.rhs()[0], input) < 1e-12);
    assert!(rel(synthesized.rhs()[0], direct_input) < 1e-10);
}

/// x = a_0 + Σ harmonics 1, 2, 5 on two DOFs with T/h = 37.3 (not an integer).
fn multi_harmonic(noise: f64, seed: u64, periods: f64) -> (Record, Mat<f64>) {
    let omega = 2.0 * PI / 3.73;
    let h = 0.1;
    let samples = (periods * 37.3).ceil() as usize + 3;
    let shape = |t: f64, j: usize| -> (f64, f64) {
        let s = [1.0, 0.6][j];
        let x = 0.3 + s * (omega * t).cos() - 0.2 * (2.0 * omega * t).sin()
            + [0.05, 0.0][j] * (5.0 * omega * t + 0.3).cos();
        let v = -s * omega * (omega * t).sin()
            - 0.4 * omega * (2.0 * omega * t).cos()
            - [0.25, 0.0][j] * omega * (5.0 * omega * t + 0.3).sin();
        (x, v)
    };
    let mut rng = StdRng::seed_from_u64(seed);
    let normal = Normal::new(0.0, 1.0).unwrap();
    let x = Mat::from_fn(samples, 2, |i, j| {
        shape(i as f64 * h, j).0 + noise * normal.sample(&mut rng)
    });
    let v = Mat::from_fn(samples, 2, |i, j| shape(i as f64 * h, j).1);
    let record = Record::new(RecordParts {
        label: "multi".into(),
        step: h,
        start_time: 0.0,
        displacements: x,
        velocities: Some(v.clone()),
        forcing: Forcing::on_dofs(Mat::zeros(samples, 1), vec![0]),
        period: 3.73,
    })
    .unwrap();
    (record, v)
}

fn max_error(estimate: faer::MatRef<'_, f64>, truth: &Mat<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for j in 0..estimate.ncols() {
        for i in 0..estimate.nrows() {
            worst = worst.max((estimate[(i, j)] - truth[(i, j)]).abs());
        }
    }
    worst
}

#[test]
fn harmonic_projection_recovers_noiseless_multi_harmonic_velocity_to_round_off() {
    let (record, truth) = multi_harmonic(0.0, 0, 2.0);
    // Two periods as each rule reads them (74.6 samples per window).
    for rule in [
        Quadrature::Rectangular,
        Quadrature::Trapezoid,
        Quadrature::Spectral,
    ] {
        let count = rule.samples(2.0 * record.period(), record.step());
        for harmonics in [Some(6), Some(12), None] {
            let source = VelocitySource::HarmonicProjection { harmonics };
            let v = source.window_velocities(&record, 0, count).unwrap();
            assert_eq!(v.as_ref().nrows(), count);
            let error = max_error(v.as_ref(), &truth);
            assert!(error < 1e-11, "{rule:?} {harmonics:?}: {error:e}");
        }
    }
    let count = Quadrature::Spectral.samples(2.0 * record.period(), record.step());
    let selection = harmonic_selection(&record, 0, count).unwrap();
    assert_eq!(selection.kept, [1, 2, 5]);
    assert_eq!(selection.periods, 2);
    assert_eq!(selection.samples, 75);
}

/// Harmonics 1, 3 and 7 with 7 in one channel only, a harmonic 4 far below the noise,
/// and white noise σ = 10⁻³: the automatic rule keeps exactly 1, 3 and 7, and its noise
/// estimate is the per-bin noise amplitude 2σ/√m.
#[test]
fn automatic_harmonics_keep_the_known_content_of_a_noisy_signal() {
    let omega = 2.0 * PI / 6.47;
    let (h, sigma, periods): (f64, f64, f64) = (0.1, 1e-3, 4.0);
    let samples = (periods * 64.7).ceil() as usize + 2;
    let mut rng = StdRng::seed_from_u64(7);
    let normal = Normal::new(0.0, sigma).unwrap();
    let clean = |t: f64, j: usize| match j {
        0 => (omega * t).cos() + 0.05 * (3.0 * omega * t).sin() + 1e-6 * (4.0 * omega * t).cos(),
        1 => 0.5 * (omega * t - 0.4).cos() + 0.01 * (7.0 * omega * t).cos(),
        _ => 0.0,
    };
    let x = Mat::from_fn(samples, 3, |i, j| {
        clean(i as f64 * h, j) + normal.sample(&mut rng)
    });
    let record = Record::new(RecordParts {
        label: "noisy".into(),
        step: h,
        start_time: 0.0,
        displacements: x,
        velocities: None,
        forcing: Forcing::on_dofs(Mat::zeros(samples, 1), vec![0]),
        period: 6.47,
    })
    .unwrap();
    let count = Quadrature::Trapezoid.samples(periods * 6.47, h);
    let selection = harmonic_selection(&record, 0, count).unwrap();
    assert_eq!(selection.kept, [1, 3, 7]);
    assert_eq!(selection.periods, 4);
    let expected = 2.0 * sigma / (selection.samples as f64).sqrt();
    for (j, noise) in selection.noise_amplitude.iter().enumerate() {
        assert!(
            (noise / expected - 1.0).abs() < 0.35,
            "channel {j}: {noise:e} vs {expected:e}"
        );
    }
}

/// With noise, the projection on the kept harmonics beats both differentiations.
#[test]
fn harmonic_projection_filters_noise_better_than_differences() {
    let (record, truth) = multi_harmonic(1e-3, 3, 2.0);
    let count = Quadrature::Spectral.samples(2.0 * record.period(), record.step());
    let error = |source: VelocitySource| {
        max_error(
            source
                .window_velocities(&record, 0, count)
                .unwrap()
                .as_ref(),
            &truth,
        )
    };
    let projection = error(VelocitySource::HarmonicProjection { harmonics: None });
    let spectral = error(VelocitySource::Spectral { harmonics: None });
    let central = error(VelocitySource::CentralDifference);
    assert!(
        projection < spectral / 3.0,
        "{projection:e} vs spectral {spectral:e}"
    );
    assert!(
        projection < central / 3.0,
        "{projection:e} vs central {central:e}"
    );
}

fn awkward_table() -> SteppedSineTable {
    SteppedSineTable::new(vec![
        point(
            "a=0.25, \"first\"",
            0.618,
            3,
            1.0 / 3.0,
            &[0.1 + 0.2, 1e-20, 2.5e17, 0.0],
            &[-PI + 1e-9, PI, -0.0, 1.0 / 7.0],
        ),
        point(
            "",
            12.5,
            0,
            0.0,
            &[1.0, 2.0, 3.0, 4.0],
            &[0.1, 0.2, 0.3, 0.4],
        ),
    ])
    .unwrap()
}

#[test]
fn table_csv_round_trip_is_exact() {
    let table = awkward_table();
    let mut buffer = Vec::new();
    table.write_csv(&mut buffer, "memory").unwrap();
    let text = String::from_utf8(buffer.clone()).unwrap();
    assert!(
        text.starts_with(
            "label,frequency,force_dof,force_amplitude,amplitude_1,phase_1,amplitude_2,phase_2"
        ),
        "{text}"
    );
    // DOFs are 1-based in files.
    assert!(text.lines().nth(1).unwrap().contains(",4,"), "{text}");
    let back = SteppedSineTable::read_csv(buffer.as_slice(), "memory").unwrap();
    assert_eq!(back, table);
    // And through serde (JSON), which validates too.
    let json = serde_json::to_string(&table).unwrap();
    let again: SteppedSineTable = serde_json::from_str(&json).unwrap();
    assert_eq!(again, table);
    let bad = json.replacen(
        "\"force_amplitude\":0.3333333333333333",
        "\"force_amplitude\":-1.0",
        1,
    );
    assert_ne!(bad, json);
    assert!(serde_json::from_str::<SteppedSineTable>(&bad).is_err());
    // Through a file.
    let path = std::env::temp_dir().join(format!("dampid_table_{}.csv", std::process::id()));
    table
        .save_csv(&path, dampid::io::output::Overwrite::Replace)
        .unwrap();
    assert_eq!(SteppedSineTable::load_csv(&path).unwrap(), table);
    std::fs::remove_file(&path).unwrap();
}

/// The paper's four-mass chain (h = 0.1, 1000 transient steps, 200 recorded steps): a
/// table of first-period fundamentals, written to CSV and read back, gives the paper's
/// harmonic estimates c_h = 0.1341, d_h = 0.1216 to within 2%.
#[test]
fn papers_harmonic_estimates_from_the_table() {
    let records: Vec<Record> = FOUR_MASS_AMPLITUDES
        .iter()
        .map(|&a| {
            simulate(
                &four_mass_system(a, false),
                &SimSettings::default(),
                &dampid::progress::silent,
            )
            .unwrap()
        })
        .collect();
    let table = SteppedSineTable::from_records(&records, &WindowSpec::default()).unwrap();
    let mut csv = Vec::new();
    table.write_csv(&mut csv, "memory").unwrap();
    let table = SteppedSineTable::read_csv(csv.as_slice(), "memory").unwrap();
    let report = identify(
        &ParametricRegressor::linear(
            &four_mass_model(),
            &HarmonicApproximation::default().records(&table).unwrap(),
        ),
        &IdentifySettings::harmonic_approximation(FitSettings::default()),
        &silent,
    )
    .unwrap()
    .report;
    let c = report.coefficient("c").unwrap();
    let d = report.coefficient("d").unwrap();
    assert!(rel(c, 0.1341) < 0.02, "c_h = {c}");
    assert!(rel(d, 0.1216) < 0.02, "d_h = {d}");
}

// ---------------------------------------------------------------------------------
// Typed errors

fn good() -> SteppedSinePoint {
    point("good", 1.0, 1, 1.0, &[1.0, 2.0], &[0.1, 0.2])
}

#[test]
fn bad_tables_are_typed_errors() {
    let mut nan = good();
    nan.amplitudes[1] = f64::NAN;
    assert!(matches!(
        SteppedSineTable::new(vec![good(), nan]),
        Err(Error::NonFinite {
            row: 1,
            column: 1,
            ..
        })
    ));
    let mut nan_phase = good();
    nan_phase.phases[0] = f64::INFINITY;
    assert!(matches!(
        SteppedSineTable::new(vec![nan_phase]),
        Err(Error::NonFinite {
            row: 0,
            column: 0,
            ..
        })
    ));
    let mut negative = good();
    negative.amplitudes[0] = -0.5;
    assert!(matches!(
        SteppedSineTable::new(vec![negative]),
        Err(Error::InvalidParameter { value, .. }) if value == -0.5
    ));
    let mut negative_force = good();
    negative_force.force_amplitude = -1.0;
    assert!(matches!(
        SteppedSineTable::new(vec![negative_force]),
        Err(Error::InvalidParameter { .. })
    ));
    let mut frequency = good();
    frequency.frequency = 0.0;
    assert!(matches!(
        SteppedSineTable::new(vec![frequency]),
        Err(Error::InvalidParameter { .. })
    ));
    let three = point("three", 1.0, 0, 1.0, &[1.0, 2.0, 3.0], &[0.0, 0.0, 0.0]);
    assert!(matches!(
        SteppedSineTable::new(vec![good(), three]),
        Err(Error::DimensionMismatch {
            expected: 2,
            found: 3,
            ..
        })
    ));
    let mut short_phases = good();
    short_phases.phases.pop();
    assert!(matches!(
        SteppedSineTable::new(vec![short_phases]),
        Err(Error::DimensionMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
    let mut far = good();
    far.force_dof = 2;
    assert!(matches!(
        SteppedSineTable::new(vec![far]),
        Err(Error::DofOutOfRange {
            dof: 3,
            dofs: 2,
            ..
        })
    ));
    assert!(matches!(
        SteppedSineTable::new(vec![]),
        Err(Error::Empty { .. })
    ));
    let table = SteppedSineTable::new(vec![good()]).unwrap();
    let (model, _) = closed_form_model(2);
    let reading = HarmonicApproximation {
        phase: PhaseReading::Dof(5),
        ..HarmonicApproximation::default()
    };
    assert!(matches!(
        approximation_regressor(&reading, &model, &table),
        Err(Error::DofOutOfRange { dof: 6, .. })
    ));
    let coarse = HarmonicApproximation {
        samples_per_period: 4,
        ..HarmonicApproximation::default()
    };
    assert!(matches!(
        approximation_regressor(&coarse, &model, &table),
        Err(Error::InvalidParameter { .. })
    ));
    // A model for other DOFs than the table's.
    let (wrong, _) = closed_form_model(3);
    assert!(approximation_regressor(&HarmonicApproximation::default(), &wrong, &table).is_err());
}

fn csv_error(text: &str) -> (usize, String, String) {
    match SteppedSineTable::read_csv(text.as_bytes(), "t.csv") {
        Err(Error::Data {
            file,
            row,
            column,
            message,
        }) => {
            assert_eq!(file, "t.csv");
            (row, column, message)
        }
        other => panic!("expected a data error, got {other:?}"),
    }
}

#[test]
fn bad_table_files_name_the_row_and_column() {
    let header =
        "label,frequency,force_dof,force_amplitude,amplitude_1,phase_1,amplitude_2,phase_2\n";
    let ok = "p,1.0,2,1.0,1.0,0.1,2.0,0.2\n";
    assert!(SteppedSineTable::read_csv(format!("{header}{ok}").as_bytes(), "t.csv").is_ok());
    let (row, column, _) = csv_error(&format!("{header}{ok}q,1.0,2,1.0,NaN,0.1,2.0,0.2\n"));
    assert_eq!((row, column.as_str()), (2, "amplitude_1"));
    let (row, column, _) = csv_error(&format!("{header}q,1.0,2,1.0,1.0,0.1,-2.0,0.2\n"));
    assert_eq!((row, column.as_str()), (1, "amplitude_2"));
    let (row, column, message) = csv_error(&format!("{header}q,1.0,3,1.0,1.0,0.1,2.0,0.2\n"));
    assert_eq!((row, column.as_str()), (1, "force_dof"));
    assert!(message.contains("1..2"), "{message}");
    let (_, column, _) = csv_error(&format!("{header}q,1.0,0,1.0,1.0,0.1,2.0,0.2\n"));
    assert_eq!(column, "force_dof");
    let (_, column, message) = csv_error(&format!("{header}q,fast,2,1.0,1.0,0.1,2.0,0.2\n"));
    assert_eq!(column, "frequency");
    assert!(message.contains("fast"));
    // A row with a missing field.
    let (row, _, _) = csv_error(&format!("{header}q,1.0,2,1.0,1.0,0.1,2.0\n"));
    assert_eq!(row, 1);
    // Headers: a phase column missing, a misnamed column, no data.
    let (row, _, _) =
        csv_error("label,frequency,force_dof,force_amplitude,amplitude_1\np,1,1,1,1\n");
    assert_eq!(row, 0);
    let (row, column, _) =
        csv_error("label,frequency,force_dof,force_amplitude,amplitude_1,phase_2\np,1,1,1,1,0\n");
    assert_eq!((row, column.as_str()), (0, "phase_2"));
    let (row, _, message) = csv_error(header);
    assert_eq!(row, 0);
    assert!(message.contains("no data"));
}

#[test]
fn too_few_samples_per_window_are_typed_errors() {
    let record = Harmonic::one_dof(1.0, 1.0, 100.0).record();
    // 10 samples are a tenth of a period: no whole period to project on.
    let projection = VelocitySource::HarmonicProjection { harmonics: None };
    assert!(matches!(
        projection.window_velocities(&record, 0, 10),
        Err(Error::InvalidParameter { ref name, .. }) if name == "samples per window"
    ));
    assert!(matches!(
        harmonic_selection(&record, 0, 10),
        Err(Error::InvalidParameter { ref name, .. }) if name == "samples per window"
    ));
    // A window past the record's end.
    assert!(matches!(
        projection.window_velocities(&record, 150, 101),
        Err(Error::RecordTooShort { .. })
    ));
    // More harmonics than one period of 101 samples can hold, and zero harmonics.
    for harmonics in [60, 0] {
        let fixed = VelocitySource::HarmonicProjection {
            harmonics: Some(harmonics),
        };
        assert!(matches!(
            fixed.window_velocities(&record, 0, 101),
            Err(Error::InvalidParameter { ref name, .. }) if name == "harmonics"
        ));
    }
    // Through the regressor: a one-period window of a record sampled 2.4 times per
    // period holds 3 samples, enough for the fundamental only; 1.6 per period is not.
    let coarse = Harmonic::one_dof(1.0, 1.0, 2.4).record();
    let mut settings = IdentifySettings::default();
    settings.regressor.velocity = projection;
    let model =
        DampingModel::new().with(Term::per_dof(Linear, 1, Coefficients::Shared("c".into())));
    assert!(
        identify(
            &ParametricRegressor::linear(&model, &[coarse.clone(), coarse]),
            &settings,
            &silent
        )
        .is_ok()
    );
    let coarser = Harmonic::one_dof(1.0, 1.0, 1.6).record();
    assert!(matches!(
        identify(
            &ParametricRegressor::linear(&model, &[coarser]),
            &settings,
            &silent
        ),
        Err(Error::InvalidParameter { .. })
    ));
    // The fundamentals of a window longer than the record.
    assert!(matches!(
        fundamentals(&record, 0, 5),
        Err(Error::RecordTooShort { .. })
    ));
    assert!(matches!(
        fundamentals(&record, 0, 0),
        Err(Error::InvalidParameter { .. })
    ));
}

#[test]
fn tables_need_one_force_channel_on_one_dof() {
    let parts = Harmonic::one_dof(1.0, 1.0, 50.0).record().into_parts();
    let two = Mat::from_fn(parts.displacements.nrows(), 2, |i, _| i as f64);
    let record = Record::new(RecordParts {
        forcing: Forcing::on_dofs(two, vec![0, 0]),
        ..parts
    })
    .unwrap();
    assert!(matches!(
        SteppedSineTable::from_records(&[record], &WindowSpec::default()),
        Err(Error::DimensionMismatch {
            expected: 1,
            found: 2,
            ..
        })
    ));
    assert!(matches!(
        SteppedSineTable::from_records(&[], &WindowSpec::default()),
        Err(Error::Empty { .. })
    ));
}
