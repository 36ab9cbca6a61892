//! Records as test labs save them: channel gains and offsets (value = scale × column +
//! offset, `time_scale` for the time column), and motion from velocity or acceleration
//! sensors (issue 16, items 3 and 4).

use std::path::{Path, PathBuf};

use dampid::io::Table;
use dampid::prelude::*;

/// A fresh directory under the system's temporary directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid-sensors-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Three records of the measured three-mass chain (models/data/chain3).
fn chain3(k: usize) -> Table {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/data/chain3/record_{k}.csv"));
    dampid::io::read_table(&path).unwrap()
}

const CHAIN3_RECORDS: [(usize, usize); 3] = [(1, 1), (3, 3), (5, 1)];

/// The chain3 model with the `[[data.records]]` blocks made by `record(k, dof)`.
fn chain3_model(record: impl Fn(usize, usize) -> String) -> String {
    let mut text = String::from(
        r#"dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "dashpot"
[[terms]]
kind = "law"
law = "coulomb"
elements = [[2, 0]]
coefficient = "friction"
[identification]
quadrature = "trapezoid"
velocity = "spectral"
cycles = 2
"#,
    );
    for (k, dof) in CHAIN3_RECORDS {
        text.push_str(&record(k, dof));
    }
    text
}

fn plain_block(k: usize, dof: usize) -> String {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/data/chain3/record_{k}.csv"));
    format!(
        r#"[[data.records]]
file = "{}"
time = "t"
displacements = ["x1", "x2", "x3"]
forces = [{{ column = "f1", dof = {dof} }}]
frequency = 0.765367
"#,
        file.display()
    )
}

/// Writes record k in lab units: time in ms, displacements in mm less 5 mm, force in
/// volts of a 35.15 N/V gain.
fn write_lab_units(dir: &Path, k: usize) -> PathBuf {
    let table = chain3(k);
    let column = |name: &str| table.column(name).unwrap().to_vec();
    let headers: Vec<String> = ["t_ms", "q1", "q2", "q3", "vir"].map(String::from).to_vec();
    let mm = |name: &str| {
        column(name)
            .iter()
            .map(|x| 1e3 * x - 5.0)
            .collect::<Vec<_>>()
    };
    let columns = vec![
        column("t").iter().map(|t| 1e3 * t).collect(),
        mm("x1"),
        mm("x2"),
        mm("x3"),
        column("f1").iter().map(|f| f / 35.15).collect(),
    ];
    let path = dir.join(format!("lab_{k}.csv"));
    dampid::io::csv::write(&path, &headers, &columns).unwrap();
    path
}

fn lab_block(dir: &Path, k: usize, dof: usize, force_scale: f64) -> String {
    let file = write_lab_units(dir, k);
    format!(
        r#"[[data.records]]
file = "{}"
time = "t_ms"
time_scale = 1e-3
displacements = [{{ column = "q1", scale = 1e-3, offset = 5e-3 }}, {{ column = "q2", scale = 1e-3, offset = 5e-3 }}, {{ column = "q3", scale = 1e-3, offset = 5e-3 }}]
forces = [{{ column = "vir", dof = {dof}, scale = {force_scale} }}]
frequency = 0.765367
"#,
        file.display()
    )
}

fn values(report: &FitReport) -> Vec<f64> {
    report.coefficients.iter().map(|c| c.value).collect()
}

/// Columns in volts, millimetres (with an offset) and milliseconds, read with their
/// gains, identify the same coefficients as the physical record.
#[test]
fn gains_and_offsets_give_back_the_physical_record() {
    let dir = scratch("gains");
    let plain =
        dampid::model_file::parse(&chain3_model(plain_block), "m.toml", Path::new(".")).unwrap();
    let lab = dampid::model_file::parse(
        &chain3_model(|k, dof| lab_block(&dir, k, dof, 35.15)),
        "m.toml",
        Path::new("."),
    )
    .unwrap();
    let (a, b) = (&plain.records[0], &lab.records[0]);
    assert!((a.step() - b.step()).abs() < 1e-12 * a.step());
    assert!((a.start_time() - b.start_time()).abs() < 1e-9);
    let diff = (a.displacements() - b.displacements()).norm_max();
    assert!(diff < 1e-9, "{diff}"); // the CSV writer keeps 11 significant digits
    let expected =
        values(&dampid::identify(&plain.model, &plain.records, &plain.settings).unwrap());
    let found = values(&dampid::identify(&lab.model, &lab.records, &lab.settings).unwrap());
    for (e, f) in expected.iter().zip(&found) {
        // the files keep 11 significant digits; the friction coefficient is the most sensitive
        assert!((e - f).abs() <= 1e-5 * e.abs().max(1e-3), "{e} vs {f}");
    }
    // The preamble says which gains were applied.
    let preamble = lab.preamble(None).to_string();
    assert!(
        preamble.contains("force on DOF 1 = 35.15 × 'vir'"),
        "{preamble}"
    );
    assert!(
        preamble.contains("displacement of DOF 2 = 0.001 × 'q2' + 0.005"),
        "{preamble}"
    );
    assert!(
        preamble.contains("time = 0.001 × time column"),
        "{preamble}"
    );
    assert!(plain.preamble(None).to_string().is_empty());
    std::fs::remove_dir_all(dir).ok();
}

/// The invariant "force × k scales every coefficient by k", through `scale`.
#[test]
fn force_scale_k_scales_every_coefficient_by_k() {
    let dir = scratch("invariant");
    let identify_with = |scale: f64| {
        let job = dampid::model_file::parse(
            &chain3_model(|k, dof| lab_block(&dir, k, dof, scale)),
            "m.toml",
            Path::new("."),
        )
        .unwrap();
        values(&dampid::identify(&job.model, &job.records, &job.settings).unwrap())
    };
    let base = identify_with(35.15);
    for k in [2.5, -0.4, 1e3] {
        let scaled = identify_with(35.15 * k);
        for (b, s) in base.iter().zip(&scaled) {
            assert!(
                (s - k * b).abs() <= 1e-8 * (k * b).abs().max(1e-6),
                "k = {k}: {s} vs {}",
                k * b
            );
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

/// A scale of 0, a non-finite scale and a non-finite offset are typed errors at the
/// line of their column.
#[test]
fn zero_or_non_finite_gains_are_errors_at_their_line() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/chain3/record_1.csv");
    let gains = [
        ("scale = 0.0", "scale", 0.0),
        ("scale = nan", "scale", f64::NAN),
        ("offset = inf", "offset", f64::INFINITY),
    ];
    for (gain, key, value) in gains {
        for on_motion in [false, true] {
            let (displacements, forces, column, bad_line) = if on_motion {
                (
                    format!("displacements = [\"x1\", {{ column = \"x2\", {gain} }}, \"x3\"]"),
                    "forces = [{ column = \"f1\", dof = 1 }]".to_string(),
                    "x2",
                    11,
                )
            } else {
                (
                    "displacements = [\"x1\", \"x2\", \"x3\"]".to_string(),
                    format!("forces = [{{ column = \"f1\", dof = 1, {gain} }}]"),
                    "f1",
                    12,
                )
            };
            let text = format!(
                "dofs = 3\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n\n[[data.records]]\nfile = \"{}\"\ntime = \"t\"\n{displacements}\n{forces}\nfrequency = 0.765367\n",
                file.display(),
            );
            match dampid::model_file::parse(&text, "m.toml", Path::new(".")) {
                Err(Error::ModelFile {
                    line,
                    cause: Some(cause),
                    ..
                }) => {
                    assert_eq!(line, bad_line, "{text}");
                    match *cause {
                        Error::InvalidParameter { name, value: v, .. } => {
                            assert_eq!(name, format!("{key} of column '{column}'"));
                            assert!(v == value || (v.is_nan() && value.is_nan()));
                        }
                        other => panic!("{other:?}"),
                    }
                }
                other => panic!("{text}\n{other:?}"),
            }
        }
    }
    // time_scale too
    let text = format!(
        "dofs = 3\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n\n[[data.records]]\nfile = \"{}\"\ntime = \"t\"\ntime_scale = 0.0\ndisplacements = [\"x1\", \"x2\", \"x3\"]\nforces = [{{ column = \"f1\", dof = 1 }}]\nfrequency = 0.765367\n",
        file.display()
    );
    let err = dampid::model_file::parse(&text, "m.toml", Path::new(".")).unwrap_err();
    assert!(matches!(&err, Error::ModelFile { line: 11, .. }), "{err}");
    assert!(
        matches!(err.innermost(), Error::InvalidParameter { .. }),
        "{err}"
    );
}
