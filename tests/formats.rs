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
        Default::default(),
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
        Default::default(),
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

/// Big-endian f8 in C order, and a compressed archive with x in Fortran order, give the
/// CSV's values exactly.
#[test]
fn big_endian_npy_and_compressed_npz() {
    let csv = csv_rows();
    let table = read_table(Path::new("tests/data/x_big_endian.npy")).unwrap();
    assert_eq!(
        table.headers,
        ["x_big_endian[1]", "x_big_endian[2]", "x_big_endian[3]"]
    );
    for j in 1..=3 {
        assert_same(
            &table,
            &format!("x_big_endian[{j}]"),
            csv.column(&format!("x{j}")).unwrap(),
            0.0,
        );
    }
    let table = read_table(Path::new("tests/data/chain3_compressed.npz")).unwrap();
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

/// A model file reading `file` with the columns t, x[1..3], f (or others).
fn chain3_model(file: &str, x: [&str; 3], f: &str) -> String {
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
}

fn parse_model(text: &str) -> dampid::Result<dampid::model_file::Job> {
    dampid::model_file::parse(text, "m.toml", Path::new("."), Default::default())
}

/// Only the arrays a record names are read: an `.npz` with a 0-d text description, a
/// 3-D array and a scalar beside the record's arrays, and a `.mat` with scalars beside
/// them (written by tests/data/write_selected.py), give the same record as the plain
/// files. The whole-file read still refuses them, and a record that names an unusable
/// array gets an error naming it.
#[test]
fn records_read_only_the_arrays_they_name() {
    let x = ["x[1]", "x[2]", "x[3]"];
    let plain = parse_model(&chain3_model("tests/data/chain3_record1.npz", x, "f")).unwrap();
    for file in [
        "tests/data/chain3_extra.npz",
        "tests/data/chain3_scalars.mat",
        "tests/data/chain3_compressed.npz",
    ] {
        let job = parse_model(&chain3_model(file, x, "f")).unwrap();
        assert_eq!(
            job.records[0].displacements(),
            plain.records[0].displacements(),
            "{file}"
        );
        assert_eq!(
            job.records[0].forcing(),
            plain.records[0].forcing(),
            "{file}"
        );
    }
    match read_table(Path::new("tests/data/chain3_extra.npz")) {
        Err(Error::Data {
            column, message, ..
        }) => {
            assert_eq!(column, "cube");
            assert!(message.contains("[2, 3, 4]"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Read whole (as `init` and `pod` read it), the scalars stored beside the signals
    // are left out (issue 30, item 7).
    let whole = read_table(Path::new("tests/data/chain3_scalars.mat")).unwrap();
    assert_eq!(whole.headers, ["t", "x[1]", "x[2]", "x[3]", "f"]);
    for (name, words) in [
        ("description", "dtype"),
        ("cube", "[2, 3, 4]"),
        ("cube[2]", "[2, 3, 4]"),
    ] {
        let error = parse_model(&chain3_model("tests/data/chain3_extra.npz", x, name)).unwrap_err();
        let text = error.to_string();
        let cause = match &error {
            Error::ModelFile {
                cause: Some(cause), ..
            } => cause.as_ref().clone(),
            other => panic!("{other:?}"),
        };
        assert!(
            matches!(&cause, Error::Data { column, .. } if name.starts_with(column.as_str())),
            "{cause:?}"
        );
        assert!(text.contains(words), "{text}");
    }
    // A scalar named beside the record's arrays has another length.
    let error = parse_model(&chain3_model("tests/data/chain3_scalars.mat", x, "gain")).unwrap_err();
    assert!(error.to_string().contains("'gain'"), "{error}");
    // A name no array has lists the usable columns only.
    let error = parse_model(&chain3_model("tests/data/chain3_extra.npz", x, "g")).unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("unknown column") && text.contains("x[3]"),
        "{text}"
    );
    assert!(!text.contains("description"), "{text}");
}

/// Several records naming one file open it once; each gets its own columns.
#[test]
fn a_file_named_by_several_records_is_opened_once() {
    use dampid::io::data_file::DataFiles;
    let path = Path::new("tests/data/chain3_extra.npz");
    let mut files = DataFiles::new([path, path, path]);
    let a = files.table(path, &["t", "x[2]"]).unwrap();
    let b = files.table(path, &["f"]).unwrap();
    let c = files.table(path, &["x[1]", "t"]).unwrap();
    assert_eq!(files.opened(), 1);
    assert_eq!(a.column("t").unwrap(), c.column("t").unwrap());
    assert_eq!(b.headers, ["f"]);
    let csv = csv_rows();
    assert_same(&a, "x[2]", csv.column("x2").unwrap(), 0.0);
    // After its last record the file is let go of; a fourth use opens it again.
    files.table(path, &["f"]).unwrap();
    assert_eq!(files.opened(), 2);
}

/// A damaged stored member (one data byte changed) is an error naming its CRC, as
/// NumPy's zipfile reports it; the bytes are found from the zip local header.
#[test]
fn a_damaged_npz_member_is_a_crc_error() {
    let mut bytes = std::fs::read("tests/data/chain3_record1.npz").unwrap();
    let name = bytes.windows(5).position(|w| w == b"x.npy").unwrap();
    // Local header: 30 bytes, the name at 26..28 (length) and 28..30 (extra length).
    let header = name - 30;
    let extra = u16::from_le_bytes([bytes[header + 28], bytes[header + 29]]) as usize;
    let data = name + 5 + extra;
    // The low byte of a little-endian f8 after the 128-byte NPY header: still finite.
    bytes[data + 128 + 8 * 10] ^= 1;
    let path = std::env::temp_dir().join(format!("dampid-crc-{}.npz", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    match read_table(&path) {
        Err(Error::Data {
            column, message, ..
        }) => {
            assert_eq!(column, "x");
            assert!(message.contains("CRC-32"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    std::fs::remove_file(path).ok();
}

/// CSV text as people write it (spaces, tabs, CRLF, comments, blank lines, signs,
/// short and long mantissas, exponents) reads the same by the fast path and by the csv
/// crate: a comment line holding a quote sends the same text to the csv crate (the
/// fast path leaves any quote to it), which skips the comment.
#[test]
fn csv_fast_and_general_paths_agree() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(17);
    let cell = |rng: &mut rand::rngs::StdRng| -> String {
        let v: f64 = rng.random_range(-1e3..1e3) * 10f64.powi(rng.random_range(-12..12));
        let text = match rng.random_range(0..6) {
            0 => format!("{v:e}"),
            1 => format!("{v:.10e}"),
            2 => format!("{v}"),
            3 => format!("{v:+.3}"),
            4 => format!("{}", v.round() as i64),
            _ => format!("{v:.17E}"),
        };
        match rng.random_range(0..4) {
            0 => format!(" {text}\t"),
            _ => text,
        }
    };
    for case in 0..200 {
        let k = rng.random_range(1..6);
        let header = (0..k)
            .map(|j| format!(" c{j} "))
            .collect::<Vec<_>>()
            .join(",");
        let mut body = String::new();
        for _ in 0..rng.random_range(1..40) {
            let row: Vec<String> = (0..k).map(|_| cell(&mut rng)).collect();
            body.push_str(&row.join(","));
            body.push_str(["\n", "\r\n", "\n\n", "\n# note\n"][rng.random_range(0..4)]);
        }
        let fast = dampid::io::csv::parse(&format!("# a test\n{header}\n{body}"), "f.csv");
        let general = dampid::io::csv::parse(
            &format!("# a test\n{header}\n# \"quoted\"\n{body}"),
            "f.csv",
        );
        assert_eq!(fast.unwrap(), general.unwrap(), "case {case}");
    }
    let quoted = dampid::io::csv::parse("\"t\",\"x\"\n\"0\",\" 1.5\"\n", "q.csv").unwrap();
    assert_eq!(quoted.columns, [vec![0.0], vec![1.5]]);
    // A bad cell is worded by the csv crate's path, row and column as before.
    match dampid::io::csv::parse("t,x\n0,1\n# c\n0.1,abc\n", "b.csv") {
        Err(Error::Data {
            row,
            column,
            message,
            ..
        }) => {
            assert_eq!((row, column.as_str()), (2, "x"));
            assert!(message.contains("'abc'"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

/// A CSV file larger than the 16 MiB buffer the fast path streams it through (lines
/// cut at the buffer's end are carried over) reads the same as its text.
#[test]
fn csv_file_larger_than_the_read_buffer() {
    let mut text = String::from("# written by a test\nt,x,y\n");
    let mut i = 0u64;
    while text.len() < 40 << 20 {
        text.push_str(&format!("{i},{:.10e},{}\r\n", (i as f64).sin(), i % 97));
        i += 1;
    }
    let path = std::env::temp_dir().join(format!("dampid-large-{}.csv", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    let read = dampid::io::csv::read(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let parsed = dampid::io::csv::parse(&text, &path.display().to_string()).unwrap();
    assert_eq!(read.rows() as u64, i);
    assert_eq!(read, parsed);
    assert_eq!(read.column("t").unwrap()[(i - 1) as usize], (i - 1) as f64);
}
