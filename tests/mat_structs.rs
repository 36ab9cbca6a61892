//! MAT files as labs hand them over (issue 30, items 1 and 7): structs and struct arrays
//! read by path, a struct of struct arrays read as a stepped-sine table with one sweep
//! per element, a gain stored beside the signals named as a column's scale, and
//! `dampid init` / `dampid pod` reading every file `identify` reads.
//!
//! Truth: the struct file written by SciPy (tests/data/write_structs.py), whose values
//! are written out in the script; and the one-DOF oscillator of
//! `support/stepped_sine_table.rs` (viscous c plus a power law d|ẋ|^1.5 sign ẋ) put into
//! the 12-sweep layout of the lab's file, which must fit as its CSV export does.

#[path = "support/mat_writer.rs"]
mod mat_writer;
mod support;
#[path = "support/stepped_sine_table.rs"]
mod table;

use std::path::{Path, PathBuf};

use dampid::identify::identify;
use dampid::io::data_file::DataFile;
use dampid::prelude::*;
use dampid::progress::silent;
use mat_writer::{Mat, write_mat};
use support::cli::{dampid_json, dampid_ok};
use table::{C, D, Normal, response};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_mat_structs_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const STRUCTS: &str = "tests/data/structs_v7.mat";

/// SciPy's compressed struct file reads by path: a 1 × 1 struct's fields without an
/// index, nested structs, a struct array's elements 1-based, row and column vectors
/// alike, int16 as numbers; char arrays are kept as text; a cell and a complex array are
/// named with their class when asked for.
#[test]
fn struct_fields_read_by_their_matlab_path() {
    let file = DataFile::open(Path::new(STRUCTS)).unwrap();
    let column = |name: &str| file.table(&[name]).unwrap().columns[0].clone();
    assert_eq!(column("s.a"), [0.5, 1.5, 2.5]);
    assert_eq!(column("s.inner.d"), [1.0, -2.0, 3.0]);
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
    assert_eq!(column("q"), [0.0, 1.0, 2.0, 3.0]);
    let contents = file.contents().unwrap();
    let entry = |path: &str| contents.iter().find(|e| e.path == path).unwrap();
    assert_eq!(entry("s.units").text.as_deref(), Some("N"));
    assert_eq!(entry("sweeps(2).units").text.as_deref(), Some("m/s^2"));
    assert_eq!(entry("sweeps").description, "1×3 struct");
    assert_eq!(entry("sweeps(1).frequency").description, "1×4 double");
    assert_eq!(entry("s.inner.d").description, "1×3 int16");
    for (name, class) in [("c", "cell"), ("z", "complex")] {
        let message = file.table(&[name]).unwrap_err().to_string();
        assert!(message.contains(class), "{message}");
    }
    // A name the file does not have lists the columns and what is not read.
    let message = file
        .table(&["sweeps(4).frequency"])
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("sweeps(3).amplitude") && message.contains("c (1×2 cell)"),
        "{message}"
    );
}

/// The 12 sweeps (force levels, N) of the lab's file: 4 force-controlled, 8 more.
const LEVELS: [f64; 12] = [0.05, 0.1, 0.2, 0.5, 0.7, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0];
const POINTS: usize = 41;

/// One sweep's (f_hz, force, x, phase_deg) at `force` over ±3 % of 50 Hz, with 0.5 %
/// noise on force and amplitude and 0.3° on the phase.
fn sweep(force: f64, rng: &mut Normal) -> [Vec<f64>; 4] {
    let mut columns: [Vec<f64>; 4] = Default::default();
    for i in 0..POINTS {
        let f_hz = 50.0 * (0.97 + 0.06 * i as f64 / (POINTS - 1) as f64);
        let (x, phi) = response(2.0 * std::f64::consts::PI * f_hz, force, C, D);
        columns[0].push(f_hz);
        columns[1].push(force * (1.0 + 0.005 * rng.sample()));
        columns[2].push(x * (1.0 + 0.005 * rng.sample()));
        columns[3].push(phi.to_degrees() + 0.3 * rng.sample());
    }
    columns
}

/// A sweep's path and its columns (f_hz, force, x, phase_deg).
type Sweep = (String, [Vec<f64>; 4]);

/// The sweeps of the lab's layout by path, and the MAT file that holds them:
/// `FRdata.ForceControl(1..4)`, `FRdata.ResponseControl(1..8)`, each with `frequency`
/// 1 × 41, `force`, `amplitude`, `phase` 41 × 1 and a `units` text.
fn lab_file(name: &str) -> (PathBuf, Vec<Sweep>) {
    let mut rng = Normal(30);
    let sweeps: Vec<Sweep> = LEVELS
        .iter()
        .enumerate()
        .map(|(k, &force)| {
            let path = if k < 4 {
                format!("FRdata.ForceControl({})", k + 1)
            } else {
                format!("FRdata.ResponseControl({})", k - 3)
            };
            (path, sweep(force, &mut rng))
        })
        .collect();
    let element = |c: &[Vec<f64>; 4]| {
        vec![
            Mat::row(&c[0]),
            Mat::column(&c[1]),
            Mat::column(&c[2]),
            Mat::column(&c[3]),
            Mat::Char("Hz, N, m, deg".into()),
        ]
    };
    let fields: Vec<String> = ["frequency", "force", "amplitude", "phase", "units"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let force_control = Mat::Struct(
        fields.clone(),
        sweeps[..4].iter().map(|(_, c)| element(c)).collect(),
    );
    let response_control = Mat::Struct(
        fields,
        sweeps[4..].iter().map(|(_, c)| element(c)).collect(),
    );
    let file = scratch(name);
    write_mat(
        &file,
        &[(
            "FRdata",
            Mat::fields(vec![
                ("ForceControl", force_control),
                ("ResponseControl", response_control),
            ]),
        )],
    );
    (file, sweeps)
}

/// The viscous + power-law model on `file`, its sweeps grouped by `grouping`.
fn model(file: &Path, grouping: &str) -> String {
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
file = "{}"
frequency = {{ column = "frequency", scale = 6.283185307179586 }}
force = "force"
amplitudes = ["amplitude"]
phases = [{{ column = "phase", scale = 0.017453292519943295 }}]
{grouping}
"#,
        file.display()
    )
}

fn job(text: &str) -> Result<dampid::model_file::Job> {
    dampid::model_file::parse(text, "lab.toml", Path::new("."), Default::default())
}

/// The lab's 12-sweep struct file identifies with no export step: one sweep per struct
/// element, named by its path, with the same coefficients as the same numbers exported
/// to CSV with a text sweep column (to 1e-12 relative), within four standard errors of
/// the truth; `sweeps` takes one struct array, a list, or the struct holding them.
#[test]
#[allow(clippy::needless_range_loop)] // point i of four columns side by side
fn a_struct_of_struct_arrays_is_a_stepped_sine_table_of_one_sweep_per_element() {
    let (mat, sweeps) = lab_file("frdata.mat");
    let csv = scratch("frdata.csv");
    let mut text = String::from("sweep,frequency,force,amplitude,phase\n");
    for (path, c) in &sweeps {
        for i in 0..POINTS {
            text.push_str(&format!(
                "{path},{:e},{:e},{:e},{:e}\n",
                c[0][i], c[1][i], c[2][i], c[3][i]
            ));
        }
    }
    std::fs::write(&csv, text).unwrap();
    let from_mat = job(&model(&mat, "sweeps = \"FRdata\"")).unwrap();
    let from_csv = job(&model(&csv, "sweep = \"sweep\"")).unwrap();
    let names = |job: &dampid::model_file::Job| {
        job.stepped_sine.as_ref().unwrap().table.sweep_names.clone()
    };
    let paths: Vec<String> = sweeps.iter().map(|(p, _)| p.clone()).collect();
    assert_eq!(names(&from_mat), paths);
    assert_eq!(names(&from_csv), paths);
    let fit = |job: &dampid::model_file::Job| {
        identify(&job.problem(), &job.settings, &silent)
            .unwrap()
            .report
    };
    let (a, b) = (fit(&from_mat), fit(&from_csv));
    for (x, y) in a.coefficients.iter().zip(&b.coefficients) {
        assert!(
            (x.value - y.value).abs() <= 1e-12 * y.value.abs(),
            "{}: {} vs {}",
            x.name,
            x.value,
            y.value
        );
    }
    for (name, truth) in [("c", C), ("d", D)] {
        let c = a.coefficients.iter().find(|c| c.name == name).unwrap();
        let se = c.std_error.expect("a standard error");
        assert!(
            (c.value - truth).abs() < 4.0 * se,
            "{name} = {} ± {se}, truth {truth}",
            c.value
        );
    }
    // One struct array; both as a list (the same sweeps as "FRdata").
    let response = job(&model(&mat, "sweeps = \"FRdata.ResponseControl\"")).unwrap();
    assert_eq!(names(&response), paths[4..]);
    let both = job(&model(
        &mat,
        "sweeps = [\"FRdata.ForceControl\", \"FRdata.ResponseControl\"]",
    ))
    .unwrap();
    assert_eq!(names(&both), paths);
    let one = job(&model(&mat, "sweeps = \"FRdata.ResponseControl(3)\"")).unwrap();
    assert_eq!(names(&one), ["FRdata.ResponseControl(3)"]);
    // The text and JSON outputs name the sweeps by path.
    let model_file = scratch("frdata.toml");
    std::fs::write(&model_file, model(&mat, "sweeps = \"FRdata\"")).unwrap();
    let out = dampid_ok(&["identify".as_ref(), model_file.as_os_str()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("FRdata.ResponseControl(8)"), "{text}");
    let json = dampid_json(&[
        "identify".as_ref(),
        model_file.as_os_str(),
        "--json".as_ref(),
    ]);
    assert!(
        json.to_string().contains("FRdata.ForceControl(1)"),
        "{json}"
    );
}

/// A scalar of the data file names a column's gain (`scale = "gtau"`): the record read
/// with `scale = "gtau"` is the record read with the number typed in, bit for bit; in a
/// stepped-sine table too (SciPy's file: `gain` = 2.5 scales the amplitudes of the
/// sweep `sweeps(2)`).
#[test]
fn a_scalar_of_the_file_is_a_gain() {
    let record = |scale: &str| {
        let text = format!(
            r#"
dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "c"
[[data.records]]
file = "tests/data/chain3_scalars.mat"
time = "t"
displacements = ["x[1]", "x[2]", "x[3]"]
forces = [{{ column = "f", dof = 1, scale = {scale} }}]
period = 8.2
"#
        );
        job(&text).unwrap().records[0].clone()
    };
    let by_name = record("\"gtau\"");
    let gtau = DataFile::open(Path::new("tests/data/chain3_scalars.mat"))
        .unwrap()
        .scalar("gtau")
        .unwrap();
    let by_number = record(&format!("{gtau:e}"));
    assert_ne!(gtau, 1.0);
    assert_eq!(by_name.forcing(), by_number.forcing());
    assert_eq!(by_name.displacements(), by_number.displacements());
    // Stepped sine: the amplitudes × gain of the same file.
    let table = |scale: &str| {
        let text = format!(
            r#"
dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[stepped_sine]
file = "{STRUCTS}"
frequency = "frequency"
force = "frequency"
amplitudes = [{{ column = "amplitude", scale = {scale} }}]
phases = [{{ column = "amplitude", scale = 0.1 }}]
sweeps = "sweeps(2)"
[identification]
weighting = "ordinary"
"#
        );
        let job = job(&text).unwrap();
        let source = job.stepped_sine.unwrap();
        source
            .table
            .table
            .points()
            .iter()
            .map(|p| p.amplitudes[0])
            .collect::<Vec<_>>()
    };
    let (named, plain) = (table("\"gain\""), table("1.0"));
    assert_eq!(named.len(), 4);
    for (n, p) in named.iter().zip(&plain) {
        assert_eq!(*n, 2.5 * p);
    }
}

/// `dampid init` and `dampid pod` read every data file shipped (models/data, tests/data),
/// a MAT file of scalars beside its signals, and the struct files; init lists a MAT
/// file's variables and struct fields in the model file it writes.
#[test]
fn init_and_pod_read_every_file_identify_reads() {
    let (lab, _) = lab_file("frdata_init.mat");
    let mut files: Vec<PathBuf> = vec![lab];
    for dir in ["models/data", "tests/data", "tests/data/uff"] {
        let mut stack = vec![PathBuf::from(dir)];
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d).unwrap() {
                let path = entry.unwrap().path();
                let data = ["csv", "npy", "npz", "mat", "uff", "unv"]
                    .iter()
                    .any(|e| path.extension().is_some_and(|x| x == *e));
                if path.is_dir() && dir == "models/data" {
                    stack.push(path);
                } else if data {
                    files.push(path);
                }
            }
        }
    }
    assert!(files.len() > 40, "{files:?}");
    for (k, file) in files.iter().enumerate() {
        let out = scratch(&format!("init_{k}.toml"));
        let init = dampid::command::init::run(
            std::slice::from_ref(file),
            &out,
            dampid::io::output::Overwrite::Replace,
        );
        assert!(init.is_ok(), "init {}: {:?}", file.display(), init.err());
        let pod = dampid::command::pod::run(
            std::slice::from_ref(file),
            &dampid::io::pod_files::Columns::AllButTime,
            &Default::default(),
        );
        assert!(pod.is_ok(), "pod {}: {:?}", file.display(), pod.err());
    }
    // The scalars file: `--columns` names read as identify reads them.
    let scalars = PathBuf::from("tests/data/chain3_scalars.mat");
    let named = dampid::command::pod::run(
        std::slice::from_ref(&scalars),
        &dampid::io::pod_files::Columns::Named(vec!["x[1]".into(), "x[2]".into()]),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(named.decompositions[0].columns, ["x[1]", "x[2]"]);
    // init lists the lab file's struct fields and suggests `sweeps`.
    let out = scratch("init_lab.toml");
    dampid::command::init::run(
        &[scratch("frdata_init.mat")],
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
}
