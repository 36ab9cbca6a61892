//! The non-periodic mode (`dampid::regressor::nonperiodic`) against simulations whose truth is
//! known: a closed-loop drive with viscous and Coulomb friction and a constant force
//! (from a model file and from the command line), the start-up transient of a two-mass
//! chain (masses and springs unknown, or known), the invariants (force scaling, an
//! added spring), and a typed error for each kind of bad input.

use dampid::progress::silent;
use dampid::regressor::ParametricRegressor;
use std::path::{Path, PathBuf};

use dampid::error::Error;
use dampid::fit::{Constraints, FitSettings};
use dampid::identify::{IdentifySettings, identify};
use dampid::model::DampingModel;
use dampid::model_file::parse;
use dampid::prep::velocity::VelocitySource;
use dampid::record::{Forcing, Record, RecordParts};
use dampid::reference::drive::{DriveSettings, closed_loop_drive, drive_model};
use dampid::regressor::SpanWindows;
use dampid::regressor::nonperiodic::{Kinetic, Potential, StorageModel};
use dampid::regressor::{Regressor, RegressorSettings};
use dampid::report::FitReport;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use dampid::terms::laws::Linear;
use dampid::terms::{Coefficients, Element, Term};
use faer::Mat;

mod support;
use support::cli::{dampid_json, dampid_ok};

/// Windows of `length` with `storage`: trapezoid rule, central-difference velocities.
fn spans(length: f64, storage: StorageModel) -> RegressorSettings {
    RegressorSettings::non_periodic(SpanWindows {
        storage,
        ..SpanWindows::new(length)
    })
}

/// The fixed spans of `settings`, to edit.
fn span(settings: &mut RegressorSettings) -> &mut SpanWindows {
    settings.windows.spans_mut().unwrap()
}

/// 0.25 s windows, an unknown mass and an unknown constant force on DOF 1.
fn drive_balance() -> RegressorSettings {
    spans(
        0.25,
        StorageModel {
            offsets: vec![0],
            ..StorageModel::default()
        },
    )
}

fn build(
    model: &DampingModel,
    records: &[Record],
    settings: &RegressorSettings,
) -> dampid::Result<Regressor> {
    Regressor::build(model, records, settings)
}

fn fit(regressor: &Regressor, fit: &FitSettings) -> FitReport {
    identify(
        &ParametricRegressor::rows(regressor),
        &IdentifySettings {
            fit: fit.clone(),
            ..Default::default()
        },
        &silent,
    )
    .map(|i| i.report)
    .unwrap()
}

fn relative_error(report: &FitReport, name: &str, truth: f64) -> f64 {
    let estimate = report
        .coefficient(name)
        .unwrap_or_else(|| panic!("no {name}"));
    (estimate - truth).abs() / truth.abs()
}

/// Runs the dampid binary with `args` and returns its output, which must be a success.
fn scratch(name: &str) -> PathBuf {
    let folder =
        std::env::temp_dir().join(format!("dampid-nonperiodic-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok(); // a stale folder of an earlier run
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

fn write_drive_csv(record: &Record, path: &Path) {
    let n = record.samples();
    dampid::io::csv::write(
        path,
        &["t".into(), "x".into(), "force".into()],
        &[
            (0..n).map(|i| i as f64 * record.step()).collect(),
            record.displacements().col(0).iter().copied().collect(),
            record.forcing().signals.col_as_slice(0).to_vec(),
        ],
        dampid::io::output::Overwrite::Replace,
    )
    .unwrap();
}

/// The issue's acceptance case: a drive record (position and motor force only, with
/// sensor noise) under closed-loop, non-periodic motion, identified from a model file.
/// Viscous and Coulomb friction within 0.5%, the mass reported as a nuisance estimate
/// within 0.5%, the constant force within 0.5%.
#[test]
fn closed_loop_drive_from_a_model_file() {
    let settings = DriveSettings {
        position_noise: 1e-6,
        force_noise: 0.05,
        seed: 11,
        ..DriveSettings::default()
    };
    let record = closed_loop_drive(&settings).unwrap();
    let folder = scratch("drive");
    write_drive_csv(&record, &folder.join("drive.csv"));
    let text = r#"
dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "viscous"
[[terms]]
kind = "law"
law = "coulomb"
elements = "each_dof"
coefficient = "coulomb"
[identification]
nonnegative = true
[non_periodic]
window = 0.25
offsets = [1]
[[data.records]]
file = "drive.csv"
time = "t"
displacements = ["x"]
forces = [{ column = "force", dof = 1 }]
"#;
    let job = parse(text, "drive.toml", &folder, Default::default()).unwrap();
    assert!(job.steady_state().unwrap().is_none());
    let regressor = job.initial_regressor().unwrap();
    assert_eq!(regressor.nuisance_count(), 2);
    let report = fit(&regressor, &job.settings.fit);
    let damping: Vec<&str> = report
        .coefficients
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    let nuisance: Vec<&str> = report.nuisance.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(damping, ["viscous", "coulomb"]);
    assert_eq!(nuisance, ["mass[1]", "offset[1]"]);
    for (name, truth) in settings.truth() {
        let error = relative_error(&report, &name, truth);
        assert!(error < 5e-3, "{name}: error {error:.2e}\n{report}");
    }
    let text = report.to_string();
    assert!(text.contains("nuisance unknowns"), "{text}");
    std::fs::remove_dir_all(folder).ok();
}

/// The bundled model file through the command line: the JSON report lists the mass
/// apart from the damping coefficients, near the simulation's 2 kg.
#[test]
fn bundled_drive_model_runs_from_the_command_line() {
    let json = dampid_json(&["identify", "models/drive_nonperiodic.toml", "--json"]);
    let value_of = |list: &str, name: &str| {
        json["report"][list]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .and_then(|c| c["value"].as_f64())
    };
    let truth = DriveSettings::default();
    let mass = value_of("nuisance", "mass[1]").expect("mass among the nuisance estimates");
    assert!((mass - truth.mass).abs() < 0.01 * truth.mass, "mass {mass}");
    assert!(value_of("coefficients", "mass[1]").is_none());
    let viscous = value_of("coefficients", "viscous").unwrap();
    assert!((viscous - truth.viscous).abs() < 0.01 * truth.viscous);
}

/// Scaling the force by k scales every coefficient by k: the damping, the mass and the
/// constant force alike (every column is linear in the motion, b in the force).
#[test]
fn scaling_the_force_scales_every_coefficient() {
    let settings = DriveSettings {
        samples: 5_001,
        ..DriveSettings::default()
    };
    let record = closed_loop_drive(&settings).unwrap();
    let scaled = {
        let mut parts = record.parts().clone();
        parts.forcing = Forcing::on_dofs(
            Mat::from_fn(record.samples(), 1, |i, _| {
                3.5 * record.forcing().signals[(i, 0)]
            }),
            vec![0],
        );
        Record::new(parts).unwrap()
    };
    let model = drive_model();
    let one = fit(
        &build(&model, &[record], &drive_balance()).unwrap(),
        &FitSettings::default(),
    );
    let three = fit(
        &build(&model, &[scaled], &drive_balance()).unwrap(),
        &FitSettings::default(),
    );
    for (a, b) in one
        .coefficients
        .iter()
        .chain(&one.nuisance)
        .zip(three.coefficients.iter().chain(&three.nuisance))
    {
        assert!(
            (b.value - 3.5 * a.value).abs() < 1e-9 * b.value.abs(),
            "{}: {} vs 3.5 × {}",
            a.name,
            b.value,
            a.value
        );
    }
}

/// A spring to ground is a conservative force: with a stiffness column it changes the
/// damping estimates by no more than the identification error, and the stiffness
/// estimate finds the spring.
#[test]
fn an_added_spring_only_adds_a_stiffness_estimate() {
    let base = DriveSettings {
        samples: 10_001,
        ..DriveSettings::default()
    };
    let sprung = DriveSettings {
        spring: 500.0,
        ..base.clone()
    };
    let model = drive_model();
    let without = fit(
        &build(
            &model,
            &[closed_loop_drive(&base).unwrap()],
            &drive_balance(),
        )
        .unwrap(),
        &FitSettings::default(),
    );
    let balance = spans(
        0.25,
        StorageModel {
            potential: Potential::Elements(Element::each_dof(1)),
            offsets: vec![0],
            ..StorageModel::default()
        },
    );
    let with = fit(
        &build(&model, &[closed_loop_drive(&sprung).unwrap()], &balance).unwrap(),
        &FitSettings::default(),
    );
    assert!(
        relative_error(&with, "stiffness[1]", 500.0) < 1e-3,
        "{with}"
    );
    for name in ["viscous", "coulomb", "mass[1]", "offset[1]"] {
        let (a, b) = (
            without.coefficient(name).unwrap(),
            with.coefficient(name).unwrap(),
        );
        assert!((a - b).abs() < 1e-3 * a.abs(), "{name}: {a} vs {b}");
    }
}

/// Nonnegativity holds the damping only: a constant force of negative sign (the load
/// pulling the other way) is estimated as such under `nonnegative`.
#[test]
fn nonnegative_fits_leave_the_nuisance_free() {
    let settings = DriveSettings {
        offset: -4.9,
        samples: 5_001,
        ..DriveSettings::default()
    };
    let regressor = build(
        &drive_model(),
        &[closed_loop_drive(&settings).unwrap()],
        &drive_balance(),
    )
    .unwrap();
    let constrained = FitSettings {
        constraints: Constraints::nonnegative(),
        ..FitSettings::default()
    };
    let report = fit(&regressor, &constrained);
    assert!(
        relative_error(&report, "offset[1]", -4.9) < 1e-3,
        "{report}"
    );
    assert!(relative_error(&report, "viscous", 8.0) < 1e-3, "{report}");
}

/// Two masses between walls, springs 2, 1, 1.5 and dashpots 0.10, 0.05, 0.08, started
/// from rest by a harmonic force on mass 1: the record is the start-up transient, never
/// steady. The non-periodic balance with a lumped mass per DOF and a spring per chain
/// element finds all eight coefficients; with M and K known it needs only the three
/// dashpots.
#[test]
fn start_up_transient_of_a_two_mass_chain() {
    let mass = Mat::from_fn(2, 2, |i, j| match (i, j) {
        (0, 0) => 1.0,
        (1, 1) => 1.5,
        _ => 0.0,
    });
    let springs = [2.0, 1.0, 1.5];
    let stiffness = Mat::from_fn(2, 2, |i, j| match (i, j) {
        (0, 0) => springs[0] + springs[1],
        (1, 1) => springs[1] + springs[2],
        _ => -springs[1],
    });
    let dashpots = [0.10, 0.05, 0.08];
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        Element::chain_fixed_both_ends(2),
        Coefficients::PerElement("dashpot".into()),
    ));
    let record = simulate(
        &System {
            mass: mass.clone(),
            stiffness: stiffness.clone(),
            damping: model.clone(),
            damping_coefficients: dashpots.to_vec(),
            conservative: vec![],
            forcing: vec![HarmonicForce {
                dof: 0,
                amplitude: 1.0,
                frequency: 0.8,
                phase: 0.0,
            }],
        },
        &SimSettings {
            step: 0.025,
            substeps: 2,
            transient_steps: 0,
            recorded_steps: 6_001,
        },
        &dampid::progress::silent,
    )
    .unwrap();
    let unknown = RegressorSettings {
        velocity: VelocitySource::Measured,
        ..spans(
            2.0,
            StorageModel {
                kinetic: Kinetic::LumpedPerDof,
                potential: Potential::Elements(Element::chain_fixed_both_ends(2)),
                offsets: vec![],
            },
        )
    };
    let report = fit(
        &build(&model, std::slice::from_ref(&record), &unknown).unwrap(),
        &FitSettings::default(),
    );
    let truth = [
        ("dashpot[0-1]", dashpots[0]),
        ("dashpot[1-2]", dashpots[1]),
        ("dashpot[2-3]", dashpots[2]),
        ("mass[1]", 1.0),
        ("mass[2]", 1.5),
        ("stiffness[0-1]", springs[0]),
        ("stiffness[1-2]", springs[1]),
        ("stiffness[2-3]", springs[2]),
    ];
    for (name, value) in truth {
        let error = relative_error(&report, name, value);
        assert!(error < 1e-3, "{name}: error {error:.2e}\n{report}");
    }
    let mut known = unknown.clone();
    span(&mut known).storage = StorageModel {
        kinetic: Kinetic::Known(mass),
        potential: Potential::Known(stiffness),
        offsets: vec![],
    };
    let regressor = build(&model, std::slice::from_ref(&record), &known).unwrap();
    assert_eq!(regressor.nuisance_count(), 0);
    let report = fit(&regressor, &FitSettings::default());
    for (name, value) in &truth[..3] {
        let error = relative_error(&report, name, *value);
        assert!(error < 1e-3, "{name}: error {error:.2e}\n{report}");
    }
}

fn short_record(samples: usize) -> Record {
    Record::new(RecordParts {
        label: "short".into(),
        step: 0.01,
        start_time: 0.0,
        displacements: Mat::from_fn(samples, 1, |i, _| (i as f64 * 0.01).sin()),
        velocities: None,
        forcing: Forcing::on_dofs(Mat::from_fn(samples, 1, |_, _| 1.0), vec![0]),
        period: 1.0,
    })
    .unwrap()
}

/// Each kind of bad input gets its typed error, naming the field.
#[test]
fn bad_settings_and_records_get_typed_errors() {
    let model = drive_model();
    let record = short_record(101);
    let with = |f: &dyn Fn(&mut RegressorSettings)| {
        let mut settings = drive_balance();
        f(&mut settings);
        build(&model, std::slice::from_ref(&record), &settings).unwrap_err()
    };
    let name_of = |e: Error| match e {
        Error::InvalidParameter { name, .. } | Error::InvalidChoice { name, .. } => name,
        other => panic!("expected InvalidParameter or InvalidChoice, got {other:?}"),
    };
    assert_eq!(
        name_of(with(
            &|s| s.velocity = VelocitySource::Spectral { harmonics: None }
        )),
        "velocity"
    );
    assert_eq!(
        name_of(with(
            &|s| s.quadrature = dampid::prep::quadrature::Quadrature::Spectral
        )),
        "quadrature"
    );
    assert_eq!(name_of(with(&|s| span(s).length = f64::NAN)), "window");
    assert_eq!(name_of(with(&|s| span(s).length = 0.001)), "window");
    assert!(matches!(
        with(&|s| span(s).length = 5.0),
        Error::RecordTooShort { needed: 501, .. }
    ));
    assert!(matches!(
        with(&|s| span(s).storage.offsets = vec![4]),
        Error::DofOutOfRange { dof: 5, .. }
    ));
    assert!(matches!(
        with(&|s| span(s).storage.potential = Potential::Known(Mat::zeros(2, 2))),
        Error::DimensionMismatch { .. }
    ));
    assert!(matches!(
        with(&|s| s.velocity = VelocitySource::Measured),
        Error::MissingVelocities { .. }
    ));
    assert!(matches!(
        build(&model, &[], &drive_balance()),
        Err(Error::Empty { .. })
    ));
}

/// `dampid compare` in the non-periodic mode, on the bundled drive record (simulated
/// with viscous 8 N s/m and Coulomb 3 N): viscous friction alone leaves a residual the
/// noise cannot explain, so the Coulomb term is needed. Both regressors carry the same
/// mass and offset columns, so the models are nested and the F-test is on the damping.
#[test]
fn compare_command_in_the_non_periodic_mode() {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/drive_nonperiodic.toml");
    let text = std::fs::read_to_string(&bundled).unwrap();
    let coulomb = "[[terms]]\nkind = \"law\"\nlaw = \"coulomb\"\nelements = \"each_dof\"\ncoefficient = \"coulomb\"\n";
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/drive/drive.csv");
    assert!(text.contains(coulomb) && text.contains("file = \"data/drive/drive.csv\""));
    let viscous_only = text.replace(coulomb, "").replace(
        "file = \"data/drive/drive.csv\"",
        &format!("file = {:?}", data.display().to_string()),
    );
    let folder = scratch("compare");
    let viscous = folder.join("viscous_only.toml");
    std::fs::write(&viscous, viscous_only).unwrap();

    let args: [&std::ffi::OsStr; 4] = [
        "compare".as_ref(),
        viscous.as_os_str(),
        bundled.as_os_str(),
        "--json".as_ref(),
    ];
    let json = dampid_json(&args);
    assert_eq!(json["nested_in"], "first", "{json}");
    assert_eq!(json["verdict"], "larger_needed", "{json}");
    let second: Vec<&str> = json["second"]["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    assert_eq!(second, ["viscous", "coulomb", "mass[1]", "offset[1]"]);
    std::fs::remove_dir_all(folder).ok();
}

/// Malformed `[non_periodic]` sections are model-file errors with a line, or name the
/// unknown value.
#[test]
fn malformed_non_periodic_sections_are_reported() {
    let record = short_record(1001);
    let folder = scratch("malformed");
    write_drive_csv(&record, &folder.join("r.csv"));
    let file = |section: &str| {
        format!(
            r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
{section}
[[data.records]]
file = "r.csv"
time = "t"
displacements = ["x"]
forces = [{{ column = "force", dof = 1 }}]
"#
        )
    };
    let error =
        |section: &str| parse(&file(section), "m.toml", &folder, Default::default()).unwrap_err();
    match error("[non_periodic]\nwindow = 0.5\nmass_per_dof = true") {
        Error::ModelFile { line, message, .. } => {
            assert_eq!(line, 9, "{message}");
            assert!(message.contains("mass_per_dof"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    match error("[non_periodic]\nwindow = 0.5\nmass = \"lumped\"") {
        Error::ModelFile { message, .. } => assert!(message.contains("lumped"), "{message}"),
        other => panic!("{other:?}"),
    }
    match error("[non_periodic]\nwindow = 0.5\noffsets = [2]") {
        Error::ModelFile { message, .. } => assert!(message.contains("offset"), "{message}"),
        other => panic!("{other:?}"),
    }
    match error(
        "[identification]\nvelocity = \"harmonic_projection\"\n[non_periodic]\nwindow = 0.5",
    ) {
        Error::ModelFile { message, .. } => assert!(message.contains("velocity"), "{message}"),
        other => panic!("{other:?}"),
    }
    match error("[non_periodic]\nwindow = 0.5\n[pod]\nmodes = 1") {
        Error::ModelFile { message, .. } => assert!(message.contains("[pod]"), "{message}"),
        other => panic!("{other:?}"),
    }
    // Without [non_periodic] the same record needs a period: a constant force has none.
    assert!(matches!(
        parse(&file(""), "m.toml", &folder, Default::default()).unwrap_err(),
        Error::ModelFile { .. } | Error::NoPeriod { .. }
    ));
    std::fs::remove_dir_all(folder).ok();
}

/// The HTML report of a non-periodic fit lists the nuisance estimates apart and labels
/// the balance plot with the stored energy it includes.
#[test]
fn html_report_of_a_non_periodic_fit() {
    let folder = scratch("html");
    dampid_ok(&[
        "identify",
        "models/drive_nonperiodic.toml",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.contains("nuisance unknowns of the energy balance"));
    assert!(page.contains("dissipated + stored work"));
    assert!(page.matches("<svg").count() >= 3);
    std::fs::remove_dir_all(folder).ok();
}

/// A free decay of m ẍ + c ẋ + k x = 0 (m = 1, k = 4, ζ = 0.05, so c = 2ζ√(km) = 0.2):
/// x = e^{−ζω t} cos ω_d t and its exact velocity, 10 s at h = 1 ms, with a force
/// channel that reads zero.
fn free_decay() -> Record {
    let (omega, zeta, h, n): (f64, f64, f64, usize) = (2.0, 0.05, 1e-3, 10_001);
    let omega_d = omega * (1.0 - zeta * zeta).sqrt();
    let t = |i: usize| i as f64 * h;
    let x = |t: f64| (-zeta * omega * t).exp() * (omega_d * t).cos();
    let v = |t: f64| {
        (-zeta * omega * t).exp()
            * (-zeta * omega * (omega_d * t).cos() - omega_d * (omega_d * t).sin())
    };
    Record::new(RecordParts {
        label: "free decay".into(),
        step: h,
        start_time: 0.0,
        displacements: Mat::from_fn(n, 1, |i, _| x(t(i))),
        velocities: Some(Mat::from_fn(n, 1, |i, _| v(t(i)))),
        forcing: Forcing::on_dofs(Mat::zeros(n, 1), vec![0]),
        period: 1.0,
    })
    .unwrap()
}

/// The drive record with its motor force zeroed (an unplugged load cell), or with no
/// force channel at all: with an unknown mass and offset nothing enters the right-hand
/// side, so every equation reads "damping work + Δ(½ m v²) + f Δx = 0", solved by
/// θ = 0. It used to be a fit with status Solved; it is `NoInputWork` naming the record
/// and the channel. The same holds for a free decay whose stored energy is unknown,
/// but with m and k known the energy it loses, −Δ(½ m v² + ½ k x²) = c ∫ v² dt, is the
/// right-hand side and c = 0.2 comes out.
#[test]
fn dead_force_sensor_is_no_input_work_unless_stored_energy_is_known() {
    let drive = closed_loop_drive(&DriveSettings::default()).unwrap();
    let samples = drive.samples();
    for (signals, dofs, channels) in [
        (
            Mat::zeros(samples, 1),
            vec![0],
            "force channel 1 (on DOF 1)",
        ),
        (Mat::zeros(samples, 0), vec![], "no force channel"),
    ] {
        let dead = Record::new(RecordParts {
            forcing: Forcing::on_dofs(signals, dofs),
            ..drive.parts().clone()
        })
        .unwrap();
        let err = build(&drive_model(), &[dead], &drive_balance()).unwrap_err();
        match &err {
            Error::NoInputWork {
                record,
                window,
                channels: named,
                reason,
            } => {
                assert_eq!(record, drive.label());
                assert_eq!(*window, None);
                assert_eq!(named, channels);
                assert!(reason.contains("no known stored energy"), "{err}");
            }
            other => panic!("expected NoInputWork, got {other:?}"),
        }
    }
    let model =
        DampingModel::new().with(Term::per_dof(Linear, 1, Coefficients::Shared("c".into())));
    let measured = |storage| RegressorSettings {
        velocity: VelocitySource::Measured,
        ..spans(1.0, storage)
    };
    let decay = free_decay();
    assert!(matches!(
        build(
            &model,
            std::slice::from_ref(&decay),
            &measured(StorageModel::default())
        ),
        Err(Error::NoInputWork { .. })
    ));
    let known = StorageModel {
        kinetic: Kinetic::Known(Mat::identity(1, 1)),
        potential: Potential::Known(Mat::from_fn(1, 1, |_, _| 4.0)),
        offsets: vec![],
    };
    let report = fit(
        &build(&model, &[decay], &measured(known)).unwrap(),
        &FitSettings::default(),
    );
    let error = relative_error(&report, "c", 0.2);
    assert!(error < 1e-5, "error {error:.2e}\n{report}");
}
