//! `dampid init`: the template from nothing parses and runs and identifies its own
//! simulated damping; from data files the columns, the time column and the periods are
//! found, and the file parses and reads the records back; an existing file is never
//! replaced without `--force`.

use std::path::PathBuf;

mod support;
use support::cli::{dampid, dampid_json, dampid_ok};

fn scratch(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("dampid-init-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The template simulates a 2-DOF chain with dashpots 0.1, 0.05, 0.15 (its
/// `[simulation] coefficients`) and 1% sensor noise; identifying from its records
/// recovers each within three of its reported standard errors, and the model check
/// (χ²) passes, so the standard errors are the plug-in ones of that noise.
#[test]
fn the_template_from_nothing_parses_runs_and_identifies_its_truth() {
    let folder = scratch("template");
    let out = folder.join("model.toml");
    let out_arg = out.to_str().unwrap();
    let printed = text(&dampid_ok(&["init", "--out", out_arg]).stdout);
    assert!(printed.contains("wrote"), "{printed}");
    let job = dampid::model_file::load(&out, Default::default()).unwrap();
    assert_eq!(
        job.model.coefficient_names(),
        ["dashpot[0-1]", "dashpot[1-2]", "dashpot[2-3]"]
    );
    assert_eq!(job.records.len(), 3);
    let json = dampid_json(&["identify", out_arg, "--json"]);
    let coefficients = json["report"]["coefficients"].as_array().unwrap();
    for (c, truth) in coefficients.iter().zip([0.1, 0.05, 0.15]) {
        let value = c["value"].as_f64().unwrap();
        let se = c["std_error"].as_f64().unwrap();
        assert!(
            (value - truth).abs() < 3.0 * se && se < 0.05 * truth,
            "{}: {value} ± {se} against {truth}",
            c["name"]
        );
        assert_eq!(c["determined"], true);
    }
    assert_eq!(json["report"]["std_error_basis"]["basis"], "plug_in");
    // The check runs too (steady state, conditioning).
    dampid_ok(&["check", out_arg]);
    std::fs::remove_dir_all(&folder).ok();
}

/// An existing file is refused (exit 2, naming it and --force) and left as it was;
/// `--force` replaces it.
#[test]
fn init_never_replaces_a_file_without_force() {
    let folder = scratch("refuse");
    let out = folder.join("model.toml");
    std::fs::write(&out, "mine").unwrap();
    let out_arg = out.to_str().unwrap();
    let refused = dampid(&["init", "--out", out_arg]);
    assert_eq!(refused.status.code(), Some(2));
    let error = text(&refused.stderr);
    assert!(error.contains("model.toml"), "{error}");
    assert!(error.contains("--force"), "{error}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine");
    dampid_ok(&["init", "--out", out_arg, "--force"]);
    assert!(dampid::model_file::load(&out, Default::default()).is_ok());
    let names: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["model.toml"], "no temporary file is left behind");
    std::fs::remove_dir_all(&folder).ok();
}

/// From the CSV files `dampid simulate` writes: the time column `t`, displacements
/// x1…x4, the force f4 on DOF 4, and each record's period, detected from the force to
/// within 1e-6 of the simulated 2π/ω; the written file parses and reads the records.
#[test]
fn from_csv_files_the_columns_time_and_periods_are_found() {
    let folder = scratch("csv");
    let run = folder.join("run");
    dampid_ok(&[
        "simulate",
        "models/four_mass.toml",
        "--out",
        run.to_str().unwrap(),
    ]);
    let out = folder.join("mine.toml");
    let files = [run.join("record_1.csv"), run.join("record_4.csv")];
    dampid_ok(&[
        "init",
        files[0].to_str().unwrap(),
        files[1].to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let written = std::fs::read_to_string(&out).unwrap();
    for needle in [
        "file = \"run/record_1.csv\"",
        "file = \"run/record_4.csv\"",
        "time = \"t\"",
        "displacements = [\"x1\", \"x2\", \"x3\", \"x4\"]",
        "forces = [{ column = \"f4\", dof = 4 }]",
        "dofs = 4",
        "# velocities = [\"v1\", \"v2\", \"v3\", \"v4\"]",
    ] {
        assert!(written.contains(needle), "'{needle}' not in\n{written}");
    }
    let job = dampid::model_file::load(&out, Default::default()).unwrap();
    assert_eq!(job.records.len(), 2);
    let simulated = 2.0 * std::f64::consts::PI / 0.618;
    for record in job.records.iter() {
        assert!(
            ((record.period() - simulated) / simulated).abs() < 1e-6,
            "{} against {simulated}",
            record.period()
        );
    }
    std::fs::remove_dir_all(&folder).ok();
}

/// NPZ and MAT files name their columns by array (`x[1]`…); a force column without a
/// DOF number acts on DOF 1; a record too short for detection says why in a comment.
#[test]
fn from_npz_and_mat_files_the_arrays_are_columns() {
    let folder = scratch("arrays");
    for fixture in ["chain3_record1.npz", "chain3_record1_v7.mat"] {
        let out = folder.join(format!("{fixture}.toml"));
        let printed = dampid_ok(&[
            "init",
            &format!("tests/data/{fixture}"),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(text(&printed.stdout).contains("time t"));
        let written = std::fs::read_to_string(&out).unwrap();
        for needle in [
            "time = \"t\"",
            "displacements = [\"x[1]\", \"x[2]\", \"x[3]\"]",
            "forces = [{ column = \"f\", dof = 1 }]",
            "dofs = 3",
        ] {
            assert!(
                written.contains(needle),
                "{fixture}: '{needle}' not in\n{written}"
            );
        }
        // 300 rows of a 8.2-period record: fewer than two periods, so none detected.
        assert!(
            written.contains("# period = 1.0   # not detected"),
            "{written}"
        );
        // The guesses are TOML the parser accepts up to the missing period.
        let error = dampid::model_file::load(&out, Default::default())
            .unwrap_err()
            .to_string();
        assert!(error.contains("period"), "{error}");
    }
    std::fs::remove_dir_all(&folder).ok();
}
