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
    let e =
        dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap_err();
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

/// Parses a `[stepped_sine]` model of `dofs` DOFs on `csv` (columns w, a, x, phi,
/// level; a second DOF reads x and phi again) with `extra` keys in the section.
fn parse_residual(name: &str, csv: &str, dofs: usize, extra: &str) -> Error {
    let dir = std::env::temp_dir().join(format!("dampid_errors_ss_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, csv).unwrap();
    let columns = |c: &str| vec![format!("\"{c}\""); dofs].join(", ");
    let text = format!(
        r#"dofs = {dofs}
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[stepped_sine]
file = "{}"
frequency = "w"
force = "a"
amplitudes = [{}]
phases = [{}]
{extra}
"#,
        file.display(),
        columns("x"),
        columns("phi"),
    );
    dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap_err()
}

/// Two sweeps of three points each.
const SWEPT: &str = "w,a,x,phi,level\n1.0,1,0.5,1.0,1\n1.1,1,0.6,1.2,1\n1.2,1,0.5,1.4,1\n\
                     1.0,2,1.0,1.0,2\n1.1,2,1.2,1.2,2\n1.2,2,1.0,1.4,2\n";

fn is_choice(e: &Error, needle: &str) {
    assert!(
        matches!(e, Error::ModelFile { line, .. } if *line > 0),
        "{e}"
    );
    match e.innermost() {
        Error::InvalidChoice {
            name,
            given,
            reason,
        } => assert!(format!("{name} {given} {reason}").contains(needle), "{e}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn residual_without_sweeps_is_refused() {
    let e = parse_residual("r_nosweep.csv", SWEPT, 1, "residual = \"stiffness\"");
    is_choice(&e, "sweep");
}

#[test]
fn residual_on_several_dofs_is_refused() {
    let e = parse_residual(
        "r_dofs.csv",
        SWEPT,
        2,
        "sweep = \"level\"\nresidual = \"stiffness\"",
    );
    is_choice(&e, "2 DOFs");
}

#[test]
fn residual_mass_and_stiffness_needs_two_frequencies_per_sweep() {
    let csv = "w,a,x,phi,level\n1.0,1,0.5,1.0,1\n1.1,1,0.6,1.2,1\n1.2,1,0.5,1.4,1\n\
               1.0,2,1.0,1.0,2\n1.0,2,1.2,1.2,2\n1.0,2,1.0,1.4,2\n";
    let e = parse_residual(
        "r_onefreq.csv",
        csv,
        1,
        "sweep = \"level\"\nresidual = \"mass_and_stiffness\"",
    );
    is_choice(&e, "level = 2");
}

#[test]
fn residual_bounds_of_an_unknown_not_estimated_are_refused() {
    let e = parse_residual(
        "r_unused.csv",
        SWEPT,
        1,
        "sweep = \"level\"\nresidual = \"stiffness\"\nresidual_mass = [-1.0, 1.0]",
    );
    is_choice(&e, "residual_mass");
    let e = parse_residual(
        "r_unused_none.csv",
        SWEPT,
        1,
        "sweep = \"level\"\nresidual_stiffness = [-1.0, 1.0]",
    );
    is_choice(&e, "none");
}

/// Contradictory bounds: an error at the bounds' own line naming the parameter.
#[test]
fn residual_bounds_contradictory_name_the_line() {
    let e = parse_residual(
        "r_bounds.csv",
        SWEPT,
        1,
        "sweep = \"level\"\nresidual = \"stiffness\"\nresidual_stiffness = [1e-3, -1e-3]",
    );
    match &e {
        Error::ModelFile { line, .. } => assert_eq!(*line, 15, "{e}"),
        other => panic!("{other:?}"),
    }
    match e.innermost() {
        Error::InvalidParameter { name, value, .. } => {
            assert!(name.contains("r_k (level = 1)"), "{name}");
            assert_eq!(*value, 1e-3);
        }
        other => panic!("{other:?}"),
    }
}

/// The equivalent damping at estimated parameters refuses a joint covariance smaller
/// than the coefficients and law parameters, and coefficients that are not the model's
/// columns, with `DimensionMismatch` (never a panic on an index).
#[test]
fn equivalent_damping_checks_its_sizes() {
    use dampid::analysis::equivalent::equivalent_damping;
    use dampid::regressor::{NonlinearParameter, ParametricModel, ParametricRegressor};
    let dir = std::env::temp_dir().join(format!("dampid_errors_ss_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("equivalent_sizes.csv");
    std::fs::write(&file, GOOD).unwrap();
    let text = format!(
        "dofs = 1\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n[stepped_sine]\nfile = \"{}\"\nfrequency = \"w\"\nforce = \"a\"\namplitudes = [\"x\"]\nphases = [\"phi\"]\n[system]\nmass = [[1.0]]\nstiffness = [[1.0]]\n",
        file.display()
    );
    let job =
        dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap();
    let table = job.stepped_sine.as_ref().unwrap();
    let model = job.model.clone();
    let law = ParametricModel::new(
        vec![NonlinearParameter::new("p", 1.0, 0.5, 2.0)],
        move |_: &[f64]| Ok(model.clone()),
    )
    .unwrap();
    let problem = ParametricRegressor::new(law, table);
    let run = |coefficients: &[f64], covariance: &[Vec<f64>]| {
        equivalent_damping(&problem, &[1.0], coefficients, Some(covariance))
            .expect("a one-DOF table")
            .unwrap_err()
    };
    // One coefficient and one law parameter need a 2 × 2 covariance.
    match run(&[1.0], &[vec![1.0]]) {
        Error::DimensionMismatch {
            expected, found, ..
        } => assert_eq!((expected, found), (2, 1)),
        other => panic!("{other:?}"),
    }
    // Two coefficients for a model of one column.
    match run(&[1.0, 2.0], &[vec![1.0; 3], vec![1.0; 3], vec![1.0; 3]]) {
        Error::DimensionMismatch {
            expected, found, ..
        } => assert_eq!((expected, found), (2, 1)),
        other => panic!("{other:?}"),
    }
}
