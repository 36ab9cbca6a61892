//! NumPy and MATLAB files give the same columns as the CSV they were written from
//! (fixtures written by NumPy and SciPy, see tests/data/README.md), and a model file
//! identifies from them.

use std::path::Path;

use dampid::Error;
use dampid::io::read_table;
use dampid::io::table::Table;

fn csv_rows() -> Table {
    let full = dampid::io::csv::read(Path::new("models/data/chain3/record_1.csv")).unwrap();
    Table {
        file: full.file.clone(),
        headers: full.headers.clone(),
        columns: full.columns.iter().map(|c| c[..300].to_vec()).collect(),
    }
}

fn assert_same(table: &Table, name: &str, expected: &[f64], tolerance: f64) {
    let column = table.column(name).unwrap();
    assert_eq!(column.len(), expected.len(), "{name}");
    for (a, b) in column.iter().zip(expected) {
        assert!(
            (a - b).abs() <= tolerance * b.abs().max(1.0),
            "{name}: {a} vs {b}"
        );
    }
}

#[test]
fn npz_and_mat_files_match_the_csv() {
    let csv = csv_rows();
    for file in [
        "tests/data/chain3_record1.npz",
        "tests/data/chain3_record1_v5.mat",
        "tests/data/chain3_record1_v7.mat",
    ] {
        let table = read_table(Path::new(file)).unwrap();
        assert_same(&table, "t", csv.column("t").unwrap(), 0.0);
        assert_same(&table, "f", csv.column("f1").unwrap(), 0.0);
        for j in 1..=3 {
            assert_same(
                &table,
                &format!("x[{j}]"),
                csv.column(&format!("x{j}")).unwrap(),
                0.0,
            );
        }
    }
}

/// A Fortran-order float32 .npy is named after its file stem.
#[test]
fn fortran_order_float32_npy() {
    let csv = csv_rows();
    let table = read_table(Path::new("tests/data/x.npy")).unwrap();
    assert_eq!(table.headers, ["x[1]", "x[2]", "x[3]"]);
    assert_same(&table, "x[2]", csv.column("x2").unwrap(), 1e-7);
}

/// A model file reading a MATLAB file identifies the same record as from CSV.
#[test]
fn model_file_reads_mat_data() {
    let model = |file: &str, x: [&str; 3], f: &str| {
        format!(
            r#"dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "dashpot"
[identification]
velocity = "spectral"
cycles = 2
[[data.records]]
file = "{file}"
time = "t"
displacements = ["{}", "{}", "{}"]
forces = [{{ column = "{f}", dof = 1 }}]
frequency = 0.765367
"#,
            x[0], x[1], x[2]
        )
    };
    let job_mat = dampid::model_file::parse(
        &model(
            "tests/data/chain3_record1_v7.mat",
            ["x[1]", "x[2]", "x[3]"],
            "f",
        ),
        "m.toml",
        Path::new("."),
    )
    .unwrap();
    let csv = std::env::temp_dir().join(format!("dampid-formats-{}.csv", std::process::id()));
    let table = csv_rows();
    dampid::io::csv::write(
        &csv,
        &table.headers,
        &table.columns,
        dampid::io::output::Overwrite::Replace,
    )
    .unwrap();
    let job_csv = dampid::model_file::parse(
        &model(csv.to_str().unwrap(), ["x1", "x2", "x3"], "f1"),
        "m.toml",
        Path::new("."),
    )
    .unwrap();
    let x_mat = job_mat.records[0].displacements();
    let x_csv = job_csv.records[0].displacements();
    assert_eq!(x_mat.shape(), x_csv.shape());
    for j in 0..3 {
        for i in 0..x_mat.nrows() {
            assert!((x_mat[(i, j)] - x_csv[(i, j)]).abs() <= 1e-9 * x_csv[(i, j)].abs().max(1.0));
        }
    }
    std::fs::remove_file(csv).ok();
}

#[test]
fn unknown_format_and_bad_files_are_data_errors() {
    assert!(matches!(
        read_table(Path::new("tests/data/README.md")),
        Err(Error::Data { .. })
    ));
    assert!(matches!(
        read_table(Path::new("tests/data/missing.npz")),
        Err(Error::Data { .. })
    ));
    // A CSV file is not a MAT file.
    let fake = std::env::temp_dir().join(format!("dampid-fake-{}.mat", std::process::id()));
    std::fs::write(&fake, "t,x\n0,1\n").unwrap();
    match read_table(&fake) {
        Err(Error::Data { message, .. }) => assert!(message.contains("MAT"), "{message}"),
        other => panic!("{other:?}"),
    }
    std::fs::remove_file(fake).ok();
}
