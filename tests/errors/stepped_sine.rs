//! `[stepped_sine]` tables: every bad cell is `Data` naming the file, the 1-based data
//! row and the column (behind the model-file error at the section's line).

use std::path::Path;

use dampid::prelude::*;

/// Writes `csv` to a scratch file and parses a one-DOF `[stepped_sine]` model on it.
fn parse_table(name: &str, csv: &str) -> (String, Error) {
    let dir = std::env::temp_dir().join(format!("dampid_errors_ss_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, csv).unwrap();
    let text = format!(
        r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[stepped_sine]
file = "{}"
frequency = "w"
force = "a"
amplitudes = ["x"]
phases = ["phi"]
"#,
        file.display()
    );
    let e = dampid::model_file::parse(&text, "m.toml", Path::new(".")).unwrap_err();
    (file.display().to_string(), e)
}

const GOOD: &str = "w,a,x,phi\n1.0,1,0.5,1.0\n1.1,1,0.6,1.2\n1.2,1,0.5,1.4\n";

fn data_at(e: &Error) -> (String, usize, String, String) {
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

#[test]
fn missing_column_names_file_and_column() {
    let (file, e) = parse_table("missing.csv", "w,a,x\n1.0,1,0.5\n1.1,1,0.6\n1.2,1,0.5\n");
    assert!(
        matches!(e, Error::ModelFile { line, .. } if line > 0),
        "{e}"
    );
    let (f, row, column, message) = data_at(&e);
    assert_eq!(
        (f.as_str(), row, column.as_str()),
        (file.as_str(), 0, "phi")
    );
    assert!(message.contains("w, a, x"), "{message}");
}

#[test]
fn non_positive_amplitude_names_row_and_column() {
    let csv = GOOD.replace("1.1,1,0.6,1.2", "1.1,1,0,1.2");
    let (file, e) = parse_table("zero.csv", &csv);
    let (f, row, column, _) = data_at(&e);
    assert_eq!((f.as_str(), row, column.as_str()), (file.as_str(), 2, "x"));
    let csv = GOOD.replace("1.2,1,0.5,1.4", "1.2,-1,0.5,1.4");
    let (_, e) = parse_table("negative_force.csv", &csv);
    assert_eq!(data_at(&e).1, 3);
    assert_eq!(data_at(&e).2, "a");
}

#[test]
fn phase_out_of_range_names_row_and_column() {
    // 80 rad: a phase in degrees read without its scale.
    let csv = GOOD.replace("1.0,1,0.5,1.0", "1.0,1,0.5,80");
    let (file, e) = parse_table("degrees.csv", &csv);
    let (f, row, column, message) = data_at(&e);
    assert_eq!(
        (f.as_str(), row, column.as_str()),
        (file.as_str(), 1, "phi")
    );
    assert!(message.contains("0.017453292519943295"), "{message}");
}

#[test]
fn too_few_points_per_sweep_for_the_scatter() {
    let (_, e) = parse_table("short.csv", "w,a,x,phi\n1.0,1,0.5,1.0\n1.1,1,0.6,1.2\n");
    assert!(matches!(e.innermost(), Error::InvalidChoice { .. }), "{e}");
}
