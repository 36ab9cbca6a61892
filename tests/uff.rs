//! UFF dataset 58 files: fixtures written by pyuff 2.5.8 (tests/data/uff/write_uff.py)
//! give the same columns as the CSV they came from, a hand-written record reads back its
//! numbers and its exact step, and malformed files are `Error::Data` naming the line.

use std::path::Path;

use dampid::Error;
use dampid::io::read_table;
use dampid::io::table::Table;
use dampid::io::uff;

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

/// ASCII double, binary (58b), ASCII single and uneven x,y pairs, all from pyuff.
#[test]
fn pyuff_files_match_the_csv() {
    let csv = csv_rows();
    for (file, tolerance) in [
        ("tests/data/uff/chain3_ascii.uff", 1e-11),
        ("tests/data/uff/chain3_binary.uff", 0.0),
        ("tests/data/uff/chain3_single.unv", 5e-6),
        ("tests/data/uff/chain3_uneven.uff", 1e-11),
    ] {
        let table = read_table(Path::new(file)).unwrap();
        // x1 and f1 share node 1 +Z, so that name is dropped and the ID lines name them.
        assert_eq!(
            table.headers,
            ["t", "x1", "2+Z", "x2", "3+Z", "x3", "f1"],
            "{file}"
        );
        assert_same(&table, "t", csv.column("t").unwrap(), 1e-15);
        assert_same(&table, "f1", csv.column("f1").unwrap(), tolerance);
        for j in 1..=3 {
            let x = format!("x{j}");
            assert_same(&table, &x, csv.column(&x).unwrap(), tolerance);
        }
        assert_same(&table, "3+Z", csv.column("x3").unwrap(), tolerance);
        let step = table.uniform_step("t").unwrap();
        assert!((step.step - 1.0 / 20.0).abs() < 1e-14, "{file}: {step:?}");
        let records = uff::read_records(Path::new(file)).unwrap();
        assert_eq!(records.step, 1.0 / 20.0, "{file}");
    }
}

#[test]
fn records_keep_their_units() {
    let uff = uff::read_records(Path::new("tests/data/uff/chain3_binary.uff")).unwrap();
    assert_eq!(uff.records.len(), 4);
    assert_eq!(uff.records[0].ordinate.quantity(), "displacement");
    assert_eq!(uff.records[0].ordinate.units, "m");
    assert_eq!(uff.records[3].ordinate.quantity(), "excitation force");
    assert_eq!(uff.records[3].ordinate.units, "N");
    assert_eq!(uff.records[2].node_name(), "3+Z");
}

/// The model file reads the same numbers from the UFF file as from the CSV.
#[test]
fn model_file_reads_uff_data() {
    let model = |file: &str| {
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
displacements = ["x1", "x2", "x3"]
forces = [{{ column = "f1", dof = 1 }}]
frequency = 0.765367
"#
        )
    };
    let parse = |file: &str| {
        dampid::model_file::parse(&model(file), "m.toml", Path::new("."), Default::default())
            .unwrap()
    };
    let csv = std::env::temp_dir().join(format!("dampid-uff-{}.csv", std::process::id()));
    let table = csv_rows();
    dampid::io::csv::write(
        &csv,
        &table.headers,
        &table.columns,
        dampid::io::output::Overwrite::Replace,
    )
    .unwrap();
    let job_csv = parse(csv.to_str().unwrap());
    for file in [
        "tests/data/uff/chain3_binary.uff",
        "tests/data/uff/chain3_ascii.uff",
    ] {
        let job = parse(file);
        let (a, b) = (
            job.records[0].displacements(),
            job_csv.records[0].displacements(),
        );
        assert_eq!(a.shape(), b.shape());
        for j in 0..3 {
            for i in 0..a.nrows() {
                assert!((a[(i, j)] - b[(i, j)]).abs() <= 1e-11 * b[(i, j)].abs().max(1.0));
            }
        }
    }
    std::fs::remove_file(csv).ok();
}

/// The text of one dataset 58 with the given record 6 and 7 lines and data lines.
fn dataset(id: &str, record6: &str, record7: &str, data: &[&str]) -> String {
    let mut s = format!("    -1\n    58\n{id}\nNONE\nNONE\nNONE\nNONE\n{record6}\n{record7}\n");
    for _ in 0..4 {
        s.push_str("        17    0    0    0 Time                 s                   \n");
    }
    for line in data {
        s.push_str(line);
        s.push('\n');
    }
    s.push_str("    -1\n");
    s
}

const R6: &str = "    1         0    0         0       NONE         4  -2       NONE         1   3";
const R7: &str = "         2         7         1  1.50000e+00  4.88281e-04  0.00000e+00";
const DATA: [&str; 2] = [
    "  1.00000e+00 -2.50000e-01  3.00000e+02  4.00000e-03 -5.00000e+00  6.12345e+00",
    " -7.00000E-01",
];

fn write(name: &str, text: &str) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("dampid-uff-{}-{name}.uff", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

/// A hand-written single-precision record, after a skipped dataset 151: its numbers,
/// its name from node 4 −Y, and the 2048 Hz step recovered from six digits.
#[test]
fn a_written_record_reads_back() {
    let header = "    -1\n   151\nmodel\nfile\nNONE\nNONE\nNONE\n    -1\n";
    let path = write(
        "round",
        &(header.to_string() + &dataset("accel 4", R6, R7, &DATA)),
    );
    let table = read_table(&path).unwrap();
    assert_eq!(table.headers, ["t", "4-Y", "accel 4"]);
    let expected = [1.0, -0.25, 300.0, 0.004, -5.0, 6.12345, -0.7];
    assert_eq!(table.column("4-Y").unwrap(), expected);
    assert_eq!(table.column("accel 4").unwrap(), expected);
    let t = table.column("t").unwrap();
    for (i, ti) in t.iter().enumerate() {
        assert_eq!(*ti, 1.5 + i as f64 / 2048.0);
    }
    // Without a whole sample rate within six digits the written step is kept.
    assert_eq!(uff::exact_step(1.23456e-3, 0.5e-8), 1.23456e-3);
    // 1/810 s is within six digits of 1.23457e-3 s.
    assert_eq!(uff::exact_step(1.23457e-3, 0.5e-8), 1.0 / 810.0);
    assert_eq!(uff::exact_step(4.88281e-4, 0.5e-9), 1.0 / 2048.0);
    std::fs::remove_file(path).ok();
}

fn data_error(text: &str, name: &str) -> (usize, String, String) {
    let path = write(name, text);
    let result = read_table(&path);
    std::fs::remove_file(path).ok();
    match result {
        Err(e @ Error::Data { .. }) => {
            assert_eq!(e.kind(), "data");
            let Error::Data {
                row,
                column,
                message,
                ..
            } = e
            else {
                unreachable!()
            };
            (row, column, message)
        }
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn malformed_files_name_the_line_and_field() {
    let good = dataset("a", R6, R7, &DATA);
    // Truncated: the file ends inside the data.
    let cut: String = good.lines().take(14).map(|l| format!("{l}\n")).collect();
    let (row, _, message) = data_error(&cut, "cut");
    assert_eq!(row, 14, "{message}");
    assert!(message.contains("truncated"), "{message}");
    // Record 7 announces more values than the data hold, or fewer.
    let more = R7.replacen("         7", "         9", 1);
    let (row, column, message) = data_error(&dataset("a", R6, &more, &DATA), "more");
    assert_eq!(
        (row, column.as_str()),
        (16, "record 7 field 2 (number of values)"),
        "{message}"
    );
    let fewer = R7.replacen("         7", "         5", 1);
    let (_, column, message) = data_error(&dataset("a", R6, &fewer, &DATA), "fewer");
    assert!(
        column.contains("number of values") && message.contains("go on"),
        "{message}"
    );
    // A non-numeric value.
    let bad = ["  1.00000e+00 -2.5000xe-01", " -7.00000E-01"];
    let (row, column, message) = data_error(&dataset("a", R6, R7, &bad), "nan");
    assert_eq!(
        (row, column.as_str()),
        (14, "record 12 field 2"),
        "{message}"
    );
    // A non-numeric record 6 field.
    let r6 = R6.replacen("    4", "    x", 1);
    let (row, column, _) = data_error(&dataset("a", &r6, R7, &DATA), "node");
    assert_eq!(
        (row, column.as_str()),
        (8, "record 6 field 6 (response node)")
    );
    // Mixed function types: a frequency response function after a time response.
    let frf = R6.replacen("    1", "    4", 1);
    let mixed = dataset("a", R6, R7, &DATA) + &dataset("b", &frf, R7, &DATA);
    let (row, column, message) = data_error(&mixed, "mixed");
    assert_eq!(
        (row, column.as_str()),
        (8 + 16, "record 6 field 1 (function type)"),
        "{message}"
    );
    // Complex ordinates.
    let complex = R7.replacen("         2", "         5", 1);
    let (_, _, message) = data_error(&dataset("a", R6, &complex, &DATA), "complex");
    assert!(message.contains("complex"), "{message}");
    // Records with different steps.
    let other = R7.replace("4.88281e-04", "1.00000e-03");
    let two = dataset("a", R6, R7, &DATA) + &dataset("b", R6, &other, &DATA);
    let (row, _, message) = data_error(&two, "steps");
    assert!(row == 9 + 16 && message.contains("step"), "{message}");
    // An uneven abscissa that is not uniform.
    let uneven = "         4         3         0  0.00000e+00  0.00000e+00  0.00000e+00";
    let pairs = [
        "  0.00000e+00   1.00000000000e+00  1.00000e-02   2.00000000000e+00",
        "  2.50000e-02   3.00000000000e+00",
    ];
    let (row, _, message) = data_error(&dataset("a", R6, uneven, &pairs), "uneven");
    assert!(row == 14 && message.contains("not uniform"), "{message}");
    // No dataset 58 at all, and a binary dataset that cannot be skipped.
    let (_, _, message) = data_error("    -1\n   151\na\n    -1\n", "none");
    assert!(message.contains("no dataset 58"), "{message}");
    let (row, _, _) = data_error("    -1\n  2414b     1     2\n", "binary");
    assert_eq!(row, 2);
}
