//! Output files as a user meets them: `dampid simulate --out` and `identify --report`
//! never replace a file without `--force`, refuse a folder holding another run, remove
//! that run's extra records when forced, never follow a symbolic link and leave no
//! temporary file behind.

use std::path::{Path, PathBuf};

mod support;
use support::cli::{dampid, dampid_ok};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("dampid-outputs-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

fn entries(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

const MODEL: &str = "models/four_mass.toml";

/// A second `simulate` into the same folder is refused (exit 2, naming a file and
/// `--force`) and changes nothing; with `--force` it replaces the run.
#[test]
fn simulate_refuses_another_runs_folder_unless_forced() {
    let folder = scratch("simulate");
    let out = folder.join("run");
    let out_arg = out.to_str().unwrap();
    dampid_ok(&["simulate", MODEL, "--out", out_arg]);
    let first = entries(&out);
    assert!(first.contains(&"manifest.json".to_string()), "{first:?}");
    assert!(first.iter().all(|n| !n.ends_with(".tmp")), "{first:?}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let listed = manifest["records"].as_array().unwrap();
    // The folder holds the records, the manifest and the [data] stub data.toml.
    assert_eq!(listed.len() + 2, first.len(), "every record is listed");
    assert!(first.contains(&"data.toml".to_string()), "{first:?}");
    assert_eq!(manifest["source"], MODEL);
    let before = std::fs::read(out.join("record_1.csv")).unwrap();
    std::fs::write(out.join("record_1.csv"), b"edited by hand").unwrap();

    let again = dampid(&["simulate", MODEL, "--out", out_arg]);
    assert_eq!(again.status.code(), Some(2));
    let error = text(&again.stderr);
    for needle in ["record_1.csv", "--force", "another run"] {
        assert!(error.contains(needle), "'{needle}' not in {error}");
    }
    assert_eq!(
        std::fs::read(out.join("record_1.csv")).unwrap(),
        b"edited by hand"
    );

    dampid_ok(&["simulate", MODEL, "--out", out_arg, "--force"]);
    assert_eq!(std::fs::read(out.join("record_1.csv")).unwrap(), before);
    assert_eq!(entries(&out), first);
    std::fs::remove_dir_all(&folder).ok();
}

/// `--force` removes an earlier run's extra `record_K.csv`, so a model listing the
/// folder's records never mixes two runs; files that are not records are left alone.
#[test]
fn a_forced_simulation_removes_the_earlier_runs_extra_records() {
    let folder = scratch("stale");
    std::fs::write(folder.join("record_99.csv"), "t,x1\n0,1\n").unwrap();
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    let out_arg = folder.to_str().unwrap();
    let refused = dampid(&["simulate", MODEL, "--out", out_arg]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(text(&refused.stderr).contains("record_99.csv"));

    let forced = dampid_ok(&["simulate", MODEL, "--out", out_arg, "--force"]);
    assert!(text(&forced.stderr).contains("removed"));
    let names = entries(&folder);
    assert!(!names.contains(&"record_99.csv".to_string()), "{names:?}");
    assert!(names.contains(&"notes.txt".to_string()));
    assert!(names.contains(&"record_1.csv".to_string()));
    std::fs::remove_dir_all(&folder).ok();
}

/// An existing report is refused before any work; `--force` replaces it; a symbolic
/// link named report.html is replaced, and the file it pointed to is untouched.
#[test]
fn the_html_report_is_never_replaced_silently() {
    let folder = scratch("report");
    let report = folder.join("report.html");
    std::fs::write(&report, "an earlier report").unwrap();
    let folder_arg = folder.to_str().unwrap();
    let refused = dampid(&["identify", MODEL, "--report", folder_arg]);
    assert_eq!(refused.status.code(), Some(2));
    let error = text(&refused.stderr);
    assert!(
        error.contains("report.html") && error.contains("--force"),
        "{error}"
    );
    assert!(refused.stdout.is_empty(), "refused before any fit");
    assert_eq!(
        std::fs::read_to_string(&report).unwrap(),
        "an earlier report"
    );

    dampid_ok(&["identify", MODEL, "--report", folder_arg, "--force"]);
    assert!(
        std::fs::read_to_string(&report)
            .unwrap()
            .starts_with("<!DOCTYPE html>")
    );

    #[cfg(unix)]
    {
        let outside = folder.join("outside.txt");
        std::fs::write(&outside, "keep me").unwrap();
        std::fs::remove_file(&report).unwrap();
        std::os::unix::fs::symlink(&outside, &report).unwrap();
        let through_link = dampid(&["identify", MODEL, "--report", folder_arg]);
        assert_eq!(through_link.status.code(), Some(2));
        assert!(text(&through_link.stderr).contains("symbolic link"));
        dampid_ok(&["identify", MODEL, "--report", folder_arg, "--force"]);
        assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep me");
        assert!(!report.is_symlink());
    }
    assert!(entries(&folder).iter().all(|n| !n.ends_with(".tmp")));
    std::fs::remove_dir_all(&folder).ok();
}

/// Ctrl-C during `simulate --out` (SIGINT to the child while it simulates a long
/// transient): the run stops at its next check, exits with 130 naming the cancelled
/// work, and leaves neither the output folder's files nor a temporary file.
#[cfg(unix)]
#[test]
fn ctrl_c_during_simulate_leaves_no_file() {
    let folder = scratch("ctrl-c");
    // four_mass.toml with 10⁹ transient steps: minutes of work at any speed.
    let model = folder.join("long.toml");
    let long = std::fs::read_to_string(MODEL)
        .unwrap()
        .replace("transient_steps = 1000", "transient_steps = 1000000000");
    assert!(long.contains("1000000000"));
    std::fs::write(&model, long).unwrap();
    let out = folder.join("run");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args(["--no-time-limit", "simulate"])
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let started = std::time::Instant::now();
    let output = child.wait_with_output().unwrap();
    let error = text(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{error}");
    assert!(error.contains("cancelled"), "{error}");
    assert!(started.elapsed() < std::time::Duration::from_secs(10));
    assert!(
        !out.exists() || entries(&out).is_empty(),
        "{:?}",
        entries(&out)
    );
    assert_eq!(entries(&folder), ["long.toml"]);
    std::fs::remove_dir_all(&folder).ok();
}
