//! MAT v7.3 files (HDF5; issue 30): read into the same variables, paths, sweeps and gains
//! as level-5 files, so records, `[stepped_sine]` struct arrays, `scale = "gtau"`,
//! `dampid init` and `dampid pod` work on them unchanged.
//!
//! Truth: the fixtures of tests/data/mat73/generate.py, written by h5py (not dampid) in
//! MATLAB's v7.3 layout, beside the same numbers written as level-5 files by SciPy (the
//! record's rows of models/data/chain3/record_1.csv and tests/data/chain3_record1_v7.mat;
//! the lab's 12-sweep struct file as frdata_v7.mat); the values the script writes; and
//! the one-DOF oscillator the stepped-sine table was made from (c = 1.2566, d = 5).

mod support;

use std::path::{Path, PathBuf};

use dampid::identify::identify;
use dampid::io::data_file::DataFile;
use dampid::io::mat::Entry;
use dampid::prelude::*;
use dampid::progress::silent;

const DIR: &str = "tests/data/mat73";

fn fixture(name: &str) -> PathBuf {
    Path::new(DIR).join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_mat73_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn job(text: &str) -> Result<dampid::model_file::Job> {
    dampid::model_file::parse(text, "m.toml", Path::new("."), Default::default())
}

/// Every kind of content reads by path as in the level-5 reader: structs, nested
/// structs, struct arrays 1-based, rows and columns, int16, single, a 2 × 3 matrix, a
/// scalar; chars as text; an empty array by its size; a cell, a complex and a logical
/// array are listed and named with their class when asked for. The paths, sizes and texts
/// the level-5 file of the same structs (tests/data/structs_v7.mat, SciPy) lists are
/// listed alike.
#[test]
fn contents_read_by_their_matlab_path() {
    let file = DataFile::open(&fixture("contents_v73.mat")).unwrap();
    let column = |name: &str| file.table(&[name]).unwrap().columns[0].clone();
    assert_eq!(column("s.a"), [0.5, 1.5, 2.5]);
    assert_eq!(column("s.inner.d"), [1.0, -2.0, 3.0]);
    assert_eq!(column("q"), [0.0, 1.0, 2.0, 3.0]);
    assert_eq!(column("single"), [0.25, 0.5]);
    assert_eq!(file.scalar("gain").unwrap(), 2.5);
    for k in 1..=3 {
        let shift = (k - 1) as f64;
        let table = file
            .table(&[
                &format!("sweeps({k}).frequency"),
                &format!("sweeps({k}).amplitude"),
            ])
            .unwrap();
        assert_eq!(
            table.columns[0],
            [10.0, 11.0, 12.0, 13.0].map(|f| f + shift)
        );
        assert_eq!(table.columns[1], [1.0, 2.0, 3.0, 4.0].map(|a| a * k as f64));
    }
    // m = [0 1 2; 3 4 5] (NumPy's arange(6).reshape(2, 3)): 3 samples of 2 columns, the
    // samples along the longer dimension, m[j] MATLAB's row j.
    let m = file.table(&["m[1]", "m[2]"]).unwrap();
    assert_eq!(m.columns[0], [0.0, 1.0, 2.0]);
    assert_eq!(m.columns[1], [3.0, 4.0, 5.0]);
    let contents = file.contents().unwrap();
    let entry = |path: &str| -> &Entry {
        contents
            .iter()
            .find(|e| e.path == path)
            .unwrap_or_else(|| panic!("{path} not in {contents:?}"))
    };
    assert_eq!(entry("m").description, "2×3 double");
    assert_eq!(entry("empty").description, "0×3 double");
    assert_eq!(entry("z").description, "1×2 complex double");
    assert_eq!(entry("c").description, "1×2 cell");
    assert_eq!(entry("flags").description, "1×3 logical");
    assert_eq!(entry("single").description, "1×2 single");
    assert!(entry("q").columns && !entry("c").columns && !entry("s.units").columns);
    let v5_file = DataFile::open(Path::new("tests/data/structs_v7.mat")).unwrap();
    let v5 = v5_file.contents().unwrap();
    for e in v5.iter().filter(|e| e.path.starts_with('s')) {
        assert_eq!(entry(&e.path), e, "{}", e.path);
    }
    for (name, class) in [("c", "cell"), ("z", "complex"), ("flags", "logical")] {
        let message = file.table(&[name]).unwrap_err().to_string();
        assert!(message.contains(class), "{name}: {message}");
    }
}

/// The record (deflated chunked datasets) holds the CSV's numbers bit for bit, its gain
/// reads by name, and a model file identifies from it the same coefficients as from the
/// CSV, bit for bit; its first 300 rows are the level-5 fixture's.
#[test]
fn a_record_identifies_as_from_its_csv() {
    let v73 = DataFile::open(&fixture("chain3_record1_v73.mat")).unwrap();
    let csv = dampid::io::csv::read(Path::new("models/data/chain3/record_1.csv")).unwrap();
    for (mat, csv_name) in [
        ("t", "t"),
        ("x[1]", "x1"),
        ("x[2]", "x2"),
        ("x[3]", "x3"),
        ("f", "f1"),
    ] {
        let table = v73.table(&[mat]).unwrap();
        assert_eq!(
            table.column(mat).unwrap(),
            csv.column(csv_name).unwrap(),
            "{mat}"
        );
    }
    let v7 = DataFile::open(Path::new("tests/data/chain3_record1_v7.mat")).unwrap();
    let names = ["t", "x[1]", "x[2]", "x[3]", "f"];
    let (first, ours) = (v7.table(&names).unwrap(), v73.table(&names).unwrap());
    for name in names {
        let (a, b) = (ours.column(name).unwrap(), first.column(name).unwrap());
        assert_eq!(&a[..300], b, "{name}");
    }
    assert_eq!(v73.scalar("gtau").unwrap(), 0.02);
    let model = |file: &str, x: [&str; 3], f: &str, scale: &str| {
        format!(
            r#"dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
coefficient = "c"
[identification]
velocity = "spectral"
cycles = 1
[[data.records]]
file = "{file}"
time = "t"
displacements = ["{}", "{}", "{}"]
forces = [{{ column = "{f}", dof = 1, scale = {scale} }}]
frequency = 0.765367
"#,
            x[0], x[1], x[2]
        )
    };
    let fit = |text: &str| {
        let job = job(text).unwrap();
        identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report
            .coefficients
            .iter()
            .map(|c| c.value)
            .collect::<Vec<f64>>()
    };
    let mat = "tests/data/mat73/chain3_record1_v73.mat";
    let columns = ["x[1]", "x[2]", "x[3]"];
    let a = fit(&model(mat, columns, "f", "1.0"));
    let b = fit(&model(
        "models/data/chain3/record_1.csv",
        ["x1", "x2", "x3"],
        "f1",
        "1.0",
    ));
    assert_eq!(a, b);
    assert!(a.iter().all(|c| c.is_finite() && *c > 0.0), "{a:?}");
    // The gain by name is the gain typed in.
    let named = fit(&model(mat, columns, "f", "\"gtau\""));
    let typed = fit(&model(mat, columns, "f", "0.02"));
    assert_eq!(named, typed);
}

/// The lab's stepped-sine struct file (issue 30's layout: FRdata.ForceControl(1..4),
/// FRdata.ResponseControl(1..8)) identifies from v7.3 as from the level-5 file of the same
/// numbers, bit for bit, sweeps named by path, within four standard errors of the
/// oscillator's c and d.
#[test]
fn the_lab_struct_file_identifies_as_from_the_level5_file() {
    let model = |file: &str, grouping: &str| {
        format!(
            r#"
dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[terms]]
kind = "law"
law = "power"
exponent = 1.5
elements = "each_dof"
coefficient = "d"
[stepped_sine]
file = "{file}"
frequency = {{ column = "frequency", scale = 6.283185307179586 }}
force = "force"
amplitudes = ["amplitude"]
phases = [{{ column = "phase", scale = 0.017453292519943295 }}]
{grouping}
"#
        )
    };
    let v73 = job(&model(
        "tests/data/mat73/frdata_v73.mat",
        "sweeps = \"FRdata\"",
    ))
    .unwrap();
    let v7 = job(&model(
        "tests/data/mat73/frdata_v7.mat",
        "sweeps = \"FRdata\"",
    ))
    .unwrap();
    let names = |job: &dampid::model_file::Job| {
        job.stepped_sine.as_ref().unwrap().table.sweep_names.clone()
    };
    let mut expected: Vec<String> = (1..=4)
        .map(|k| format!("FRdata.ForceControl({k})"))
        .collect();
    expected.extend((1..=8).map(|k| format!("FRdata.ResponseControl({k})")));
    assert_eq!(names(&v73), expected);
    assert_eq!(names(&v7), expected);
    let fit = |job: &dampid::model_file::Job| {
        identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report
    };
    let (a, b) = (fit(&v73), fit(&v7));
    for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
        assert_eq!((x.value, x.std_error), (y.value, y.std_error), "{}", x.name);
    }
    for (name, truth) in [("c", 1.2566), ("d", 5.0)] {
        let c = a.coefficients.iter().find(|c| c.name == name).unwrap();
        let se = c.std_error.expect("a standard error");
        assert!(
            (c.value - truth).abs() < 4.0 * se,
            "{name} = {} ± {se}, truth {truth}",
            c.value
        );
    }
    let response = job(&model(
        "tests/data/mat73/frdata_v73.mat",
        "sweeps = \"FRdata.ResponseControl\"",
    ))
    .unwrap();
    assert_eq!(names(&response), expected[4..]);
}

/// `dampid init` lists a v7.3 file's variables and struct fields (and suggests the
/// sweeps); `dampid pod` reads its columns whole or by name.
#[test]
fn init_and_pod_read_v73_files() {
    for name in [
        "chain3_record1_v73.mat",
        "contents_v73.mat",
        "frdata_v73.mat",
    ] {
        let out = scratch(&format!("init_{name}.toml"));
        let init = dampid::command::init::run(
            &[fixture(name)],
            &out,
            dampid::io::output::Overwrite::Replace,
        );
        assert!(init.is_ok(), "init {name}: {:?}", init.err());
    }
    let out = scratch("init_lab.toml");
    dampid::command::init::run(
        &[fixture("frdata_v73.mat")],
        &out,
        dampid::io::output::Overwrite::Replace,
    )
    .unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    for needle in [
        "FRdata.ResponseControl(8).amplitude  41×1 double",
        "FRdata.ForceControl(2).frequency     1×41 double",
        "FRdata.ForceControl(1).units         1×13 char \"Hz, N, m, deg\"",
        "sweeps = [\"FRdata.ForceControl\", \"FRdata.ResponseControl\"]",
    ] {
        assert!(text.contains(needle), "'{needle}' not in\n{text}");
    }
    let record = fixture("chain3_record1_v73.mat");
    let named = dampid::command::pod::run(
        std::slice::from_ref(&record),
        &dampid::io::pod_files::Columns::Named(vec!["x[1]".into(), "x[2]".into()]),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(named.decompositions[0].columns, ["x[1]", "x[2]"]);
    let csv = dampid::command::pod::run(
        &[PathBuf::from("models/data/chain3/record_1.csv")],
        &dampid::io::pod_files::Columns::Named(vec!["x1".into(), "x2".into()]),
        &Default::default(),
    )
    .unwrap();
    let report = |pod: &dampid::command::pod::Decompositions| {
        serde_json::to_value(&pod.decompositions[0]).unwrap()["report"].clone()
    };
    assert_eq!(report(&named), report(&csv));
    // The CLI: `dampid pod FILE.mat --columns …`.
    let out = support::cli::dampid_ok(&[
        "pod".as_ref(),
        record.as_os_str(),
        "--columns".as_ref(),
        "x[1],x[2],x[3]".as_ref(),
    ]);
    assert!(out.status.success());
}
