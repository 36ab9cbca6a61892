//! Output files as a user meets them: `dampid simulate --out` and `identify --report`
//! never replace a file without `--force`, refuse a folder holding another run, remove
//! only the extra records that run's manifest lists when forced, never follow a
//! symbolic link, leave no temporary file behind and clear those of a killed run, and
//! write files with the permissions of the umask (keeping a replaced file's mode).

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

/// `--force` removes only the record files an earlier run's `manifest.json` lists
/// (issue 29, item 8): a measured data set's `record_K.csv` beside no manifest, or
/// files the manifest does not list, are never deleted; a manifest entry that is not a
/// plain `record_K.csv` of the folder is ignored.
#[test]
fn a_forced_simulation_removes_only_what_the_earlier_manifest_lists() {
    let folder = scratch("stale");
    let out_arg = folder.to_str().unwrap();
    // A measured data set and notes, no manifest: refused, and --force deletes none.
    for k in [0, 4, 5, 12, 99, 1_000_000] {
        std::fs::write(folder.join(format!("record_{k}.csv")), "t,x1\n0,1\n").unwrap();
    }
    std::fs::write(folder.join("record_04.csv"), "t,x1\n0,1\n").unwrap();
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    let refused = dampid(&["simulate", MODEL, "--out", out_arg]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(text(&refused.stderr).contains("record_99.csv"));
    let forced = dampid_ok(&["simulate", MODEL, "--out", out_arg, "--force"]);
    assert!(
        !text(&forced.stderr).contains("removed"),
        "{}",
        text(&forced.stderr)
    );
    let names = entries(&folder);
    for kept in [
        "record_0.csv",
        "record_04.csv",
        "record_5.csv",
        "record_12.csv",
        "record_99.csv",
        "record_1000000.csv",
        "notes.txt",
    ] {
        assert!(names.contains(&kept.to_string()), "{kept} lost: {names:?}");
    }
    // four_mass.toml wrote record_1 … record_4 (record_4.csv replaced, as --force says).
    assert_eq!(
        std::fs::read_to_string(folder.join("record_4.csv")).unwrap()[..2],
        *"t,"
    );

    // A run of two records after the four-record run: record_3 and record_4, which the
    // manifest lists, go; a manifest entry pointing outside the folder is ignored.
    let outside = folder.join("outside.csv");
    std::fs::write(&outside, "keep").unwrap();
    let manifest_path = folder.join("manifest.json");
    let mut manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest_path).unwrap()).unwrap();
    let records = manifest["records"].as_array_mut().unwrap();
    assert_eq!(records.len(), 4);
    records.push(serde_json::json!({ "file": "../outside.csv", "label": "x", "period": 1.0 }));
    records.push(serde_json::json!({ "file": "notes.txt", "label": "x", "period": 1.0 }));
    std::fs::write(&manifest_path, manifest.to_string()).unwrap();
    let two = folder.join("two.toml");
    let text_two = std::fs::read_to_string(MODEL).unwrap();
    let cut = text_two
        .find("[[simulation.experiments]]\nforce_dof = 4\namplitude = 0.75")
        .unwrap();
    std::fs::write(&two, &text_two[..cut]).unwrap();
    let forced = dampid_ok(&[
        "simulate",
        two.to_str().unwrap(),
        "--out",
        out_arg,
        "--force",
    ]);
    let said = text(&forced.stderr);
    assert!(
        said.contains("record_3.csv") && said.contains("record_4.csv"),
        "{said}"
    );
    let names = entries(&folder);
    assert!(!names.contains(&"record_3.csv".to_string()), "{names:?}");
    assert!(!names.contains(&"record_4.csv".to_string()), "{names:?}");
    for kept in ["record_5.csv", "record_99.csv", "notes.txt", "outside.csv"] {
        assert!(names.contains(&kept.to_string()), "{kept} lost: {names:?}");
    }
    std::fs::remove_dir_all(&folder).ok();
}

/// Temporary files a killed run left (`kill -9` during a write) are removed by the
/// next run into the folder, which says so on stderr; one that a live process still
/// holds (its lock), a recent one and files of other naming are left alone.
#[cfg(unix)]
#[test]
fn stale_temporary_files_are_removed_by_the_next_run() {
    let folder = scratch("temporaries");
    let out_arg = folder.to_str().unwrap();
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    let make = |name: &str, age: std::time::SystemTime| {
        let file = std::fs::File::create(folder.join(name)).unwrap();
        file.set_modified(age).unwrap();
        file
    };
    drop(make(".record_7.csv.Ab12Cd.tmp", old));
    drop(make(".report.html.xYz789.tmp", old));
    let live = make(".record_8.csv.LiVe01.tmp", old);
    live.lock().unwrap();
    drop(make(
        ".record_9.csv.NeW000.tmp",
        std::time::SystemTime::now(),
    ));
    drop(make(".notes.tmp", old));
    drop(make("record_7.csv.Ab12Cd.tmp", old));

    let run = dampid_ok(&["simulate", MODEL, "--out", out_arg]);
    let said = text(&run.stderr);
    for gone in [".record_7.csv.Ab12Cd.tmp", ".report.html.xYz789.tmp"] {
        assert!(said.contains(gone), "{gone} not reported: {said}");
        assert!(!folder.join(gone).exists(), "{gone} left");
    }
    for kept in [
        ".record_8.csv.LiVe01.tmp",
        ".record_9.csv.NeW000.tmp",
        ".notes.tmp",
        "record_7.csv.Ab12Cd.tmp",
    ] {
        assert!(folder.join(kept).exists(), "{kept} removed");
        assert!(
            !said.contains(&format!("/{kept}")),
            "{kept} reported: {said}"
        );
    }
    drop(live);
    std::fs::remove_dir_all(&folder).ok();
}

/// Outputs get the permissions a normally created file gets under the umask (not
/// tempfile's 0600), and a file replaced with `--force` keeps its mode (issue 29 item 9,
/// issue 30 item 8).
#[cfg(unix)]
#[test]
fn outputs_have_the_umask_permissions_and_keep_a_replaced_files_mode() {
    use std::os::unix::fs::PermissionsExt;
    let folder = scratch("modes");
    let mode = |path: &Path| std::fs::metadata(path).unwrap().permissions().mode() & 0o777;
    // What a file created normally gets under this process's umask.
    let reference = folder.join("reference");
    std::fs::File::create(&reference).unwrap();
    let normal = mode(&reference);
    std::fs::remove_file(&reference).unwrap();

    let run = folder.join("run");
    dampid_ok(&["simulate", MODEL, "--out", run.to_str().unwrap()]);
    for name in ["record_1.csv", "data.toml", "manifest.json"] {
        assert_eq!(mode(&run.join(name)), normal, "{name}");
    }
    let report = folder.join("report");
    dampid_ok(&["identify", MODEL, "--report", report.to_str().unwrap()]);
    assert_eq!(mode(&report.join("report.html")), normal);

    for (path, kept) in [
        (run.join("record_1.csv"), 0o640),
        (report.join("report.html"), 0o604),
    ] {
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(kept)).unwrap();
    }
    dampid_ok(&["simulate", MODEL, "--out", run.to_str().unwrap(), "--force"]);
    dampid_ok(&[
        "identify",
        MODEL,
        "--report",
        report.to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(mode(&run.join("record_1.csv")), 0o640);
    assert_eq!(mode(&run.join("record_2.csv")), normal);
    assert_eq!(mode(&report.join("report.html")), 0o604);
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
