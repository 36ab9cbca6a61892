//! Model files: the shipped ones run and reproduce their examples; malformed ones give
//! typed errors with the file and the line and column (or the data row).

use std::path::Path;

use dampid::Error;
use dampid::identify;
use dampid::model_file::{load, parse};
use dampid::prep::quadrature::Quadrature;
use dampid::prep::velocity::VelocitySource;
use dampid::progress::silent;
use dampid::reference::{FourMassPodStudy, StringStudy, four_mass_cases, run_four_mass_case};
use dampid::regressor::ParametricRegressor;

fn run(path: &str) -> dampid::report::FitReport {
    let job = load(Path::new(path), Default::default()).unwrap();
    dampid::identify(&job.problem(), &job.settings, &silent)
        .unwrap()
        .report
}

/// A model file's report equals the example case's, to round-off.
fn assert_matches_example(path: &str, case_name: &str) {
    let from_file = run(path);
    let case = four_mass_cases()
        .into_iter()
        .find(|c| c.name == case_name)
        .unwrap();
    let from_example = run_four_mass_case(&case, Quadrature::Rectangular)
        .unwrap()
        .report;
    for name in ["c", "d"] {
        let (a, b) = (
            from_file.coefficient(name).unwrap(),
            from_example.coefficient(name).unwrap(),
        );
        assert!((a - b).abs() < 1e-12 * b.abs(), "{path} {name}: {a} vs {b}");
    }
}

/// `models/four_mass.toml` is the paper's chain with central differences and the
/// rectangular rule: the same numbers as the example's matching case.
#[test]
fn four_mass_model_file_matches_the_example() {
    assert_matches_example("models/four_mass.toml", "chain, central differences");
}

#[test]
fn cubic_spring_model_file_matches_the_example() {
    assert_matches_example(
        "models/four_mass_cubic.toml",
        "cubic spring, four cycles, central differences",
    );
}

/// The bundled CSV data set (three-mass chain, per-dashpot viscous + friction) read from
/// files gives every coefficient within 0.1% of the generator's truth, with standard
/// errors.
#[test]
fn measured_csv_model_file_identifies_the_chain() {
    let report = run("models/measured_chain.toml");
    let truth = [
        ("dashpot[0-1]", 0.10),
        ("dashpot[1-2]", 0.05),
        ("dashpot[2-3]", 0.15),
        ("dashpot[3-4]", 0.08),
        ("friction", 0.05),
    ];
    for (name, value) in truth {
        let estimate = report.coefficient(name).unwrap();
        assert!(
            (estimate - value).abs() < 1e-3 * value,
            "{name}: {estimate}"
        );
    }
    assert!(report.coefficients.iter().all(|c| c.std_error.is_some()));
}

fn error_of(text: &str) -> Error {
    parse(text, "test.toml", Path::new("models"), Default::default()).unwrap_err()
}

fn assert_at(error: Error, line: usize, needle: &str) {
    match error {
        Error::ModelFile {
            file,
            line: l,
            column,
            message,
            ..
        } => {
            assert_eq!(file, "test.toml");
            assert_eq!(l, line, "{message}");
            assert!(column >= 1, "{message}");
            assert!(message.contains(needle), "'{needle}' not in: {message}");
        }
        other => panic!("expected a model-file error, got {other:?}"),
    }
}

const HEAD: &str = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n";

#[test]
fn toml_syntax_error_has_line_and_column() {
    assert_at(error_of("dofs = 2\n[[terms]\nkind = 1\n"), 2, "");
}

#[test]
fn unknown_key_is_rejected_with_its_line() {
    let text = format!("{HEAD}[identification]\nquadrature = \"trapezoid\"\nwindoes = 3\n");
    assert_at(error_of(&text), 9, "windoes");
}

#[test]
fn unknown_law_is_rejected_with_its_line() {
    let text = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"quadratc\"\nelements = \"each_dof\"\ncoefficient = \"d\"\n";
    assert_at(error_of(text), 2, "quadratc");
}

#[test]
fn unknown_identifier_in_an_expression_is_rejected() {
    let text = "dofs = 2\n\n[[terms]]\nkind = \"law\"\nlaw = \"expression\"\nexpression = \"sign(v)*abs(w)^1.5\"\nelements = \"each_dof\"\ncoefficient = \"k\"\n[data]\nrecords = []\n";
    assert_at(error_of(text), 3, "unknown identifier 'w'");
}

#[test]
fn unknown_matrix_name_lists_the_known_ones() {
    let text = "dofs = 2\n[[terms]]\nkind = \"viscous\"\ncoefficient = \"c\"\nmatrix = \"K2\"\n[data]\nrecords = []\n";
    assert_at(error_of(text), 2, "identity, chain");
}

#[test]
fn shared_and_per_element_together_are_rejected() {
    let text = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\nper_element = \"d\"\n[data]\nrecords = []\n";
    assert_at(error_of(text), 6, "exactly one of"); // at `coefficient`
}

#[test]
fn records_must_come_from_one_source() {
    match error_of(HEAD) {
        Error::ModelFile { message, .. } => assert!(message.contains("[simulation]")),
        other => panic!("{other:?}"),
    }
}

/// A data file that names a missing column, holds NaN, or has an uneven time step.
#[test]
fn data_errors_name_file_row_and_column() {
    let folder = std::env::temp_dir().join(format!("dampid-model-file-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let mut csv = String::from("t,x1,x2,f\n");
    for i in 0..50 {
        let t = i as f64 * 0.1;
        csv.push_str(&format!("{t},{},{},{}\n", t.cos(), t.sin(), t.cos()));
    }
    std::fs::write(folder.join("good.csv"), &csv).unwrap();
    let nan = csv.replacen(&format!("\n0.1,{},", 0.1f64.cos()), "\n0.1,NaN,", 1);
    assert_ne!(nan, csv);
    std::fs::write(folder.join("nan.csv"), nan).unwrap();
    std::fs::write(
        folder.join("uneven.csv"),
        csv.replacen("\n0.2,", "\n0.25,", 1),
    )
    .unwrap();
    let model = |file: &str, x: &str| {
        format!(
            "{HEAD}[[data.records]]\nfile = \"{file}\"\ntime = \"t\"\ndisplacements = [\"x1\", \"{x}\"]\nforces = [{{ column = \"f\", dof = 2 }}]\nperiod = 6.283185307179586\n"
        )
    };
    let parse_in = |text: String| parse(&text, "test.toml", &folder, Default::default());

    assert!(parse_in(model("good.csv", "x2")).is_ok());
    match parse_in(model("good.csv", "x3")).unwrap_err() {
        Error::ModelFile { line, message, .. } => {
            assert_eq!(line, 7);
            assert!(
                message.contains("unknown column")
                    && message.contains("x3")
                    && message.contains("x1, x2"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    match parse_in(model("nan.csv", "x2")).unwrap_err() {
        Error::ModelFile { message, .. } => assert!(
            message.contains("row 2") && message.contains("x1"),
            "{message}"
        ),
        other => panic!("{other:?}"),
    }
    match parse_in(model("uneven.csv", "x2")).unwrap_err() {
        Error::ModelFile { message, .. } => assert!(
            message.contains("row 3") && message.contains("'t'"),
            "{message}"
        ),
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(&folder).ok();
}

#[test]
fn missing_model_file_is_a_model_file_error() {
    assert!(matches!(
        load(Path::new("models/does_not_exist.toml"), Default::default()),
        Err(Error::ModelFile { line: 0, .. })
    ));
}

// ---------------------------------------------------------------------------------
// Model files of the section 3 examples: the same numbers as the examples
// ---------------------------------------------------------------------------------

/// `a` and `b` agree to 1e-9 relative, coefficient by coefficient.
fn assert_same_estimates(
    path: &str,
    from_file: &dampid::report::FitReport,
    from_example: &dampid::report::FitReport,
) {
    for name in ["c", "d"] {
        let (a, b) = (
            from_file.coefficient(name).unwrap(),
            from_example.coefficient(name).unwrap(),
        );
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{path} {name}: {a} vs {b}");
    }
}

/// models/four_mass_pod.toml is the example's "two POMs" case: the same POD energy
/// shares and the same c, d.
#[test]
fn four_mass_pod_model_file_matches_the_example() {
    let path = "models/four_mass_pod.toml";
    let job = load(Path::new(path), Default::default()).unwrap();
    let from_file = dampid::identify(&job.problem(), &job.settings, &silent)
        .unwrap()
        .report;
    let study = FourMassPodStudy::run().unwrap();
    let case = study.cases.iter().find(|c| c.name == "two POMs").unwrap();
    assert_same_estimates(path, &from_file, &case.report);
    let reduction = job.pod.as_ref().unwrap();
    for (basis, (_, example)) in reduction.bases.iter().zip(&case.pods) {
        assert_eq!(basis.retained(), 2);
        for (a, b) in basis.energy_shares().iter().zip(&example.modes) {
            assert!((a - b.energy_share).abs() < 1e-12);
        }
    }
}

/// models/string.toml is the example's noise-free two-mode case.
#[test]
fn string_model_file_matches_the_example() {
    let path = "models/string.toml";
    let job = load(Path::new(path), Default::default()).unwrap();
    assert!(
        job.steady_state()
            .unwrap()
            .expect("a periodic model file")
            .enforce()
            .is_ok()
    );
    let from_file = dampid::identify(&job.problem(), &job.settings, &silent)
        .unwrap()
        .report;
    let study = StringStudy::run(1, false).unwrap();
    let case = study
        .cases
        .iter()
        .find(|c| c.name == "noise-free, 2 modes")
        .unwrap();
    assert_same_estimates(path, &from_file, &case.report);
    assert_eq!(
        job.truth.unwrap(),
        vec![("c".to_string(), 0.4), ("d".to_string(), 0.5)]
    );
}

/// models/four_mass_harmonic.toml is the example's target case: stepped-sine points
/// from the first whole period of each record, arithmetic mean lag, eq. 4. The
/// example's library path is repeated here (its `run` is private to the example).
#[test]
fn harmonic_model_file_matches_the_example() {
    use dampid::prelude::*;
    use dampid::prep::harmonic::{HarmonicApproximation, SteppedSineTable};
    use dampid::reference::{FOUR_MASS_AMPLITUDES, four_mass_model, four_mass_system};
    use dampid::simulate::{SimSettings, simulate};

    let path = "models/four_mass_harmonic.toml";
    let job = load(Path::new(path), Default::default()).unwrap();
    let from_file = dampid::identify(&job.problem(), &job.settings, &silent)
        .unwrap()
        .report;

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
    let first_period = WindowSpec::cycles(1).first(1);
    let table = SteppedSineTable::from_records(&records, &first_period).unwrap();
    let from_example = identify(
        &ParametricRegressor::linear(
            &four_mass_model(),
            &HarmonicApproximation::default().records(&table).unwrap(),
        ),
        &IdentifySettings::harmonic_approximation(FitSettings::default()),
        &silent,
    )
    .unwrap()
    .report;
    assert_same_estimates(path, &from_file, &from_example);
    // The same stepped-sine points (labels aside).
    for (a, b) in job
        .harmonic
        .as_ref()
        .unwrap()
        .points()
        .iter()
        .zip(table.points())
    {
        assert_eq!(
            (a.frequency, a.force_dof, a.force_amplitude),
            (b.frequency, b.force_dof, b.force_amplitude)
        );
        assert_eq!((&a.amplitudes, &a.phases), (&b.amplitudes, &b.phases));
    }
    // The paper's c_h = 0.1341, d_h = 0.1216 within 2%.
    assert!((from_file.coefficient("c").unwrap() - 0.1341).abs() < 0.02 * 0.1341);
    assert!((from_file.coefficient("d").unwrap() - 0.1216).abs() < 0.02 * 0.1216);
}

/// Every shipped model file loads, and its windows are steady.
#[test]
fn every_shipped_model_file_is_steady() {
    for entry in std::fs::read_dir("models").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let job = load(&path, Default::default()).unwrap();
            // The non-periodic mode has no steady state to check.
            if let Some(report) = job.steady_state().unwrap() {
                assert!(report.enforce().is_ok(), "{}:\n{report}", path.display());
            } else {
                // A stepped-sine table has no time records to check either, and a free
                // decay is not in steady state by nature.
                assert!(
                    job.settings.regressor.windows.spans().is_some()
                        || job.settings.regressor.windows.decay().is_some()
                        || job.stepped_sine.is_some(),
                    "{}",
                    path.display()
                );
            }
        }
    }
}

/// `[pod]` and `[harmonic_approximation]` reject what they cannot use, at their line.
#[test]
fn pod_and_harmonic_sections_are_checked() {
    let four = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let with = |section: &str| {
        let text = format!("{four}\n{section}");
        parse(&text, "test.toml", Path::new("models"), Default::default()).unwrap_err()
    };
    match with("[pod]\nmodes = 5\n") {
        Error::ModelFile { message, line, .. } => {
            assert!(message.contains("retained modes"), "{message}");
            assert!(line > 40);
        }
        other => panic!("{other:?}"),
    }
    match with("[pod]\nmodes = 2\nenergy = 0.9\n") {
        Error::ModelFile { message, .. } => assert!(message.contains("at most one"), "{message}"),
        other => panic!("{other:?}"),
    }
    match with("[harmonic_approximation]\nphase = \"dof\"\n") {
        Error::ModelFile { message, .. } => assert!(message.contains("needs `dof`"), "{message}"),
        other => panic!("{other:?}"),
    }
    match with("[harmonic_approximation]\nphase = \"dof\"\ndof = 7\n") {
        Error::ModelFile { message, .. } => assert!(message.contains("DOF 7"), "{message}"),
        other => panic!("{other:?}"),
    }
}

/// `[identification]` selects the pipeline: harmonic projection is the default velocity
/// (noise-robust with `noise = "auto"`), the plain one is one line away, and a noise
/// correction the velocity source cannot support is a typed error naming `noise`.
#[test]
fn identification_selects_the_noise_pipeline() {
    let four = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let with = |identification: &str| {
        let text = four.replace(
            "velocity = \"central_difference\"   # from the displacements alone",
            identification,
        );
        assert_ne!(text, four);
        parse(&text, "test.toml", Path::new("models"), Default::default()).unwrap()
    };
    let robust = with("");
    assert_eq!(
        robust.settings.regressor.velocity,
        VelocitySource::HarmonicProjection { harmonics: None }
    );
    let report = identify(
        &ParametricRegressor::linear(&robust.model, &robust.records),
        &robust.settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!(report.noise.is_some());
    let plain = with(
        "velocity = \"harmonic_projection\"\nharmonics = 3\nnoise = \"ignore\"\nweighting = \"ordinary\"\nwork_form = \"derivative_free\"",
    );
    assert_eq!(
        plain.settings.regressor.velocity,
        VelocitySource::HarmonicProjection { harmonics: Some(3) }
    );
    let report = identify(
        &ParametricRegressor::linear(&plain.model, &plain.records),
        &plain.settings,
        &silent,
    )
    .unwrap()
    .report;
    assert!(report.noise.is_none());
    let wrong = with("noise = \"correct\"\nvelocity = \"central_difference\"");
    let error = identify(
        &ParametricRegressor::linear(&wrong.model, &wrong.records),
        &wrong.settings,
        &silent,
    )
    .unwrap_err();
    assert!(
        matches!(&error, Error::InvalidChoice { name, given, .. } if name == "noise" && given == "correct"),
        "{error}"
    );
    match parse(
        &four.replace("windows = 1 ", "noise = \"sometimes\"\nwindows = 1 "),
        "test.toml",
        Path::new("models"),
        Default::default(),
    ) {
        Err(Error::ModelFile { message, .. }) => assert!(
            message.contains("sometimes") || message.contains("variant"),
            "{message}"
        ),
        other => panic!("{other:?}"),
    }
}
