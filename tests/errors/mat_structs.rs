//! MAT structs and named gains (issue 30, items 1 and 7): a struct array read as
//! stepped-sine sweeps with a field missing, of another length or not a vector, a path
//! that names no struct, `sweeps` on a CSV file or beside `sweep`; a file of contents
//! that are not read says what it holds and what is read; a named scale that is
//! missing, not a scalar, or in a CSV file; a damaged or deeply nested struct file is a
//! `Data` error, never a panic. Each is `Data` (or `InvalidChoice`) naming the file, the
//! element path and the field, behind the model-file error at its line.

use std::path::{Path, PathBuf};

use dampid::prelude::*;

use super::mat_writer::{Mat, mat_bytes, write_mat};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_errors_mat_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A sweep element of `n` points with fields frequency, force, amplitude, phase.
fn element(n: usize) -> Vec<Mat> {
    let f: Vec<f64> = (0..n).map(|i| 10.0 + i as f64).collect();
    vec![
        Mat::row(&f),
        Mat::column(&vec![1.0; n]),
        Mat::column(&f.iter().map(|w| 1.0 / w).collect::<Vec<_>>()),
        Mat::column(&vec![0.5; n]),
    ]
}

fn fields() -> Vec<String> {
    ["frequency", "force", "amplitude", "phase"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// The model-file error of a one-DOF `[stepped_sine]` on `file` grouped by `grouping`.
fn parse(file: &Path, grouping: &str) -> Error {
    let text = format!(
        r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[stepped_sine]
file = "{}"
frequency = "frequency"
force = "force"
amplitudes = ["amplitude"]
phases = ["phase"]
{grouping}
"#,
        file.display()
    );
    dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap_err()
}

fn data_of(e: &Error) -> (String, usize, String, String) {
    match e.innermost() {
        Error::Data {
            file,
            row,
            column,
            message,
        } => (file.clone(), *row, column.clone(), message.clone()),
        other => panic!("{other:?}"),
    }
}

/// A sweep element without a field the table names, with a field of another length, a
/// field that is a matrix, or a non-finite value: `Data` naming the file, the element
/// path and field, and for a value its 1-based point.
#[test]
fn bad_sweep_fields_name_the_element_and_the_field() {
    let cases: Vec<(&str, Mat, &str, usize, &str)> = vec![
        (
            "missing",
            Mat::Struct(
                fields()[..3].to_vec(),
                vec![{
                    let mut e = element(4);
                    e.truncate(3);
                    e
                }],
            ),
            "S.phase",
            0,
            "no field 'phase'",
        ),
        (
            "length",
            Mat::Struct(
                fields(),
                vec![element(4), {
                    let mut e = element(4);
                    e[2] = Mat::column(&[1.0, 2.0, 3.0]);
                    e
                }],
            ),
            "S(2).amplitude",
            0,
            "3 values, but the sweep's 'frequency' has 4",
        ),
        (
            "matrix",
            Mat::Struct(
                fields(),
                vec![{
                    let mut e = element(4);
                    e[1] = Mat::Double(2, 2, vec![1.0; 4]);
                    e
                }],
            ),
            "S.force",
            0,
            "2×2 double",
        ),
        (
            "nan",
            Mat::Struct(
                fields(),
                vec![{
                    let mut e = element(4);
                    e[3] = Mat::column(&[0.5, 0.5, f64::NAN, 0.5]);
                    e
                }],
            ),
            "S.phase",
            3,
            "non-finite",
        ),
    ];
    for (name, value, column, row, needle) in cases {
        let file = scratch(&format!("{name}.mat"));
        write_mat(&file, &[("S", value)]);
        let e = parse(&file, "sweeps = \"S\"");
        assert!(matches!(e, Error::ModelFile { .. }), "{e}");
        let (f, r, c, message) = data_of(&e);
        assert_eq!(
            (f.as_str(), r, c.as_str()),
            (file.display().to_string().as_str(), row, column),
            "{name}: {message}"
        );
        assert!(message.contains(needle), "{name}: {message}");
    }
}

/// A path that names no struct lists the file's structs; a column that is a field of
/// struct arrays, named without `sweeps`, says to give it; `sweeps` on a CSV file, or
/// beside `sweep`, is `InvalidChoice` saying which to give.
#[test]
fn sweeps_that_name_no_struct_array_say_what_there_is() {
    let file = scratch("good.mat");
    write_mat(
        &file,
        &[("S", Mat::Struct(fields(), vec![element(4), element(4)]))],
    );
    let (_, _, column, message) = data_of(&parse(&file, "sweeps = \"FRdata\""));
    assert_eq!(column, "FRdata");
    assert!(message.contains("S (1×2 struct)"), "{message}");
    // Without `sweeps`, a column named as a struct field says how to read the sweeps.
    let (_, _, column, message) = data_of(&parse(&file, ""));
    assert_eq!(column, "frequency");
    assert!(
        message.contains("S(2).frequency") && message.contains("`sweeps = [\"S\"]`"),
        "{message}"
    );
    let csv = scratch("table.csv");
    std::fs::write(
        &csv,
        "frequency,force,amplitude,phase\n10,1,0.1,0.5\n11,1,0.1,0.5\n12,1,0.1,0.5\n",
    )
    .unwrap();
    for (on, grouping, needle) in [
        (&csv, "sweeps = \"S\"", ".mat file"),
        (&file, "sweeps = \"S\"\nsweep = \"frequency\"", "not both"),
    ] {
        let e = parse(on, grouping);
        assert!(
            matches!(e.innermost(), Error::InvalidChoice { reason, .. } if reason.contains(needle)),
            "{e}"
        );
    }
}

/// A MAT file holding nothing that is read (a cell, a struct of text; an array without
/// a name is MATLAB's subsystem data, not a variable) says what it holds, with classes
/// and sizes, and what is read.
#[test]
fn a_file_of_unread_contents_says_what_it_holds() {
    let file = scratch("unread.mat");
    write_mat(
        &file,
        &[
            (
                "c",
                Mat::Cell(vec![Mat::row(&[1.0]), Mat::Char("a".into())]),
            ),
            (
                "meta",
                Mat::fields(vec![("units", Mat::Char("m/s^2".into()))]),
            ),
            // MATLAB's subsystem data: an array without a name, not a variable.
            ("", Mat::column(&[1.0, 2.0, 3.0])),
        ],
    );
    let e = dampid::io::read_table(&file).unwrap_err();
    let (f, _, _, message) = data_of(&e);
    assert_eq!(f, file.display().to_string());
    for needle in [
        "c (1×2 cell)",
        "meta (1×1 struct)",
        "meta.units (1×5 char)",
        "read are real numeric",
        "structs and struct arrays",
    ] {
        assert!(message.contains(needle), "'{needle}' not in {message}");
    }
}

/// `scale = "name"` naming a variable the file lacks (listing its scalars), one of
/// several values, or given for a CSV file: `Data` naming the file and the variable.
#[test]
fn a_named_scale_must_be_a_scalar_of_the_file() {
    let csv = scratch("record.csv");
    let mut text = String::from("t,x,f\n");
    for i in 0..400 {
        let t = i as f64 * 0.05;
        text.push_str(&format!("{t},{},{}\n", t.sin(), t.cos()));
    }
    std::fs::write(&csv, text).unwrap();
    for (file, scale, needle) in [
        (
            "tests/data/chain3_scalars.mat",
            "gone",
            "its scalars: gain, gtau",
        ),
        ("tests/data/chain3_scalars.mat", "t", "not a scalar"),
        (csv.to_str().unwrap(), "gtau", "give the number"),
    ] {
        let model = format!(
            r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[data.records]]
file = "{file}"
time = "t"
displacements = ["{x}"]
forces = [{{ column = "{f}", dof = 1, scale = "{scale}" }}]
period = 6.283185307179586
"#,
            x = if file.ends_with(".csv") { "x" } else { "x[1]" },
            f = "f",
        );
        let e = dampid::model_file::parse(&model, "m.toml", Path::new("."), Default::default())
            .unwrap_err();
        assert!(matches!(e, Error::ModelFile { line: 11, .. }), "{e}");
        let (f, _, column, message) = data_of(&e);
        assert!(file.ends_with(f.rsplit('/').next().unwrap()), "{f}");
        assert_eq!(column, scale);
        assert!(message.contains(needle), "'{needle}' not in {message}");
    }
}

/// Every truncation of a struct file, and every byte of it set to 0xFF, reads or is a
/// `Data` error (never a panic); a struct nested 100 deep is refused by depth.
#[test]
fn damaged_or_deep_struct_files_are_data_errors() {
    let bytes = mat_bytes(&[(
        "S",
        Mat::fields(vec![
            ("inner", Mat::Struct(fields(), vec![element(3), element(3)])),
            ("units", Mat::Char("m".into())),
        ]),
    )]);
    let file = scratch("damaged.mat");
    let read = |b: &[u8]| {
        std::fs::write(&file, b).unwrap();
        dampid::io::read_table(&file)
    };
    assert!(read(&bytes).is_ok());
    for cut in 0..bytes.len() {
        if let Err(e) = read(&bytes[..cut]) {
            assert!(matches!(e, Error::Data { .. }), "cut {cut}: {e}");
        }
    }
    for at in 128..bytes.len() {
        let mut damaged = bytes.clone();
        damaged[at] = 0xFF;
        if let Err(e) = read(&damaged) {
            assert!(
                matches!(e, Error::Data { .. } | Error::TooLarge { .. }),
                "byte {at}: {e}"
            );
        }
    }
    let mut deep = Mat::fields(vec![("x", Mat::row(&[1.0, 2.0]))]);
    for _ in 0..100 {
        deep = Mat::fields(vec![("s", deep)]);
    }
    let e = read(&mat_bytes(&[("d", deep)])).unwrap_err();
    assert!(e.to_string().contains("nested deeper than 64"), "{e}");
}
