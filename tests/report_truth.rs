//! Issue 18, items 1–3 through the command line: coefficients that are not determined
//! get no standard error or interval (JSON `null`, HTML "not determined" with the
//! determined combinations), every warning reaches the text, the JSON and the HTML,
//! `identify --strict` exits 1 on what should stop a script, and a record whose force is
//! on the wrong DOF is named with the likely causes.

mod support;
use std::path::{Path, PathBuf};

use support::cli::{dampid, dampid_json, dampid_ok};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A scratch folder of this test process.
fn scratch(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("dampid-truth-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// `models/measured_chain.toml` with record 6's force column (it pushes on mass 1) said
/// to act on mass 2, its data paths made absolute, written into `folder`.
fn wrong_dof_model(folder: &Path) -> PathBuf {
    let models = std::fs::canonicalize("models").unwrap();
    let original = std::fs::read_to_string("models/measured_chain.toml").unwrap();
    let marker = "file = \"data/chain3/record_6.csv\"";
    let (before, after) = original.split_once(marker).unwrap();
    let wrong = after.replacen("dof = 1 }", "dof = 2 }", 1);
    assert_ne!(wrong, after);
    let text = format!("{before}{marker}{wrong}").replace(
        "file = \"data/",
        &format!("file = \"{}/data/", models.display()),
    );
    let file = folder.join("wrong_dof.toml");
    std::fs::write(&file, text).unwrap();
    file
}

/// The wrong-DOF record takes work out (its force is said to push on mass 2, which
/// moves against it): `identify` stops with exit 2 naming it (issue 29). Accepted, it
/// holds most of the residual: the JSON's `records` say so, a `record_dominates`
/// warning names it (and no other), and the text and HTML reports carry the same
/// warning with the likely causes. With the right DOFs no record dominates.
#[test]
fn a_force_on_the_wrong_dof_is_named_in_every_report() {
    let folder = scratch("wrong-dof");
    let model = wrong_dof_model(&folder);
    let model = model.to_str().unwrap();
    let label = "a=1.0 ω=1.4142 on mass 1";
    let refused = dampid(&["identify", model]);
    let stderr = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&format!("in 1 of 12 records ('{label}'")),
        "{stderr}"
    );
    assert!(stderr.contains("a force on the wrong DOF"), "{stderr}");
    let html = folder.join("html");
    let json = dampid_json(&[
        "identify",
        model,
        "--accept-negative-work",
        "--json",
        "--report",
        html.to_str().unwrap(),
    ]);
    let records = json["report"]["records"].as_array().unwrap();
    assert_eq!(records.len(), 12);
    let shares: f64 = records
        .iter()
        .map(|r| r["residual_share"].as_f64().unwrap())
        .sum();
    assert!((shares - 1.0).abs() < 1e-9, "shares sum to {shares}");
    let wrong = records.iter().find(|r| r["record"] == label).unwrap();
    assert!(wrong["residual_share"].as_f64().unwrap() > 0.5, "{wrong}");
    let dominating: Vec<&serde_json::Value> = json["report"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "record_dominates")
        .collect();
    assert_eq!(dominating.len(), 1, "{dominating:?}");
    assert_eq!(dominating[0]["record"], label);

    let printed = text(&dampid_ok(&["identify", model, "--accept-negative-work"]).stdout);
    for needle in [
        &format!("record '{label}' holds"),
        "force columns' DOF and sign",
        "its period",
        "steady state",
        "misses a mechanism",
    ] {
        assert!(printed.contains(needle), "text lacks {needle}: {printed}");
    }
    let page = std::fs::read_to_string(html.join("report.html")).unwrap();
    assert!(
        page.contains(&format!("record &#39;{label}&#39; holds"))
            || page.contains(&format!("record '{label}' holds"))
    );
    assert!(page.contains("<tr class=\"flag\"><td>a=1.0 ω=1.4142 on mass 1</td>"));

    let right = dampid_json(&["identify", "models/measured_chain.toml", "--json"]);
    assert!(
        !right["report"]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["kind"] == "record_dominates"),
        "no record dominates with the right DOFs"
    );
    let most = right["report"]["records"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["residual_share"].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert!(most < 0.5, "{most}");
    std::fs::remove_dir_all(&folder).ok();
}

/// The walkthrough's first try cannot separate the dashpots: the JSON gives them `null`
/// standard errors, the HTML reads "not determined" with the determined combinations and
/// no interval for them; `--strict` exits 1 and says why, the default exits 0.
#[test]
fn undetermined_coefficients_are_not_given_intervals_and_strict_fails() {
    let folder = scratch("first-try");
    let model = "models/walkthrough_first_try.toml";
    let json = dampid_json(&[
        "identify",
        model,
        "--json",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let coefficients = json["report"]["coefficients"].as_array().unwrap();
    let undetermined: Vec<&serde_json::Value> = coefficients
        .iter()
        .filter(|c| c["determined"] == false)
        .collect();
    assert!(!undetermined.is_empty());
    for c in &undetermined {
        assert!(c["std_error"].is_null(), "{c}");
        assert!(c["interval"].is_null(), "{c}");
    }
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.contains("<b>not determined</b>"));
    assert!(page.contains("Determined combinations"));
    assert!(page.contains("Provenance"));
    // No interval in the row of an undetermined dashpot.
    let row = page
        .split("<tr><td>dashpot[0-1]</td>")
        .nth(1)
        .and_then(|rest| rest.split("</tr>").next())
        .unwrap();
    assert!(
        row.contains("not determined") && !row.contains('['),
        "{row}"
    );

    let plain = dampid(&["identify", model]);
    assert_eq!(plain.status.code(), Some(0));
    let strict = dampid(&["identify", model, "--strict"]);
    assert_eq!(strict.status.code(), Some(1));
    let why = text(&strict.stderr);
    assert!(
        why.contains("strict: not determined: dashpot[0-1]"),
        "{why}"
    );
    // The report is still printed.
    assert_eq!(text(&strict.stdout), text(&plain.stdout));
    // A determined fit passes --strict.
    assert_eq!(
        dampid(&["identify", "models/measured_chain.toml", "--strict"])
            .status
            .code(),
        Some(0)
    );
    std::fs::remove_dir_all(&folder).ok();
}

/// Windows accepted although not in steady state are a warning in the text, the JSON and
/// the HTML (the HTML once left it out), and fail `--strict`.
#[test]
fn accepted_transients_are_warned_everywhere_and_fail_strict() {
    let folder = scratch("transient");
    let four = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let from_rest = four.replace("transient_steps = 1000", "transient_steps = 0");
    assert_ne!(four, from_rest);
    let file = folder.join("from_rest.toml");
    std::fs::write(&file, from_rest).unwrap();
    let path = file.to_str().unwrap();
    let html = folder.join("html");
    let json = dampid_json(&[
        "identify",
        path,
        "--accept-transient",
        "--json",
        "--report",
        html.to_str().unwrap(),
    ]);
    let warning = json["report"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["kind"] == "transient_accepted")
        .expect("a transient_accepted warning")
        .clone();
    assert!(warning["windows"].as_u64().unwrap() >= 1);
    let page = std::fs::read_to_string(html.join("report.html")).unwrap();
    assert!(page.contains("not in steady state, accepted"));
    assert!(page.contains("NOT steady (accepted)"));
    let printed = text(&dampid_ok(&["identify", path, "--accept-transient"]).stdout);
    assert_eq!(
        printed.matches("not in steady state, accepted").count(),
        1,
        "{printed}"
    );
    let strict = dampid(&["identify", path, "--accept-transient", "--strict"]);
    assert_eq!(strict.status.code(), Some(1));
    assert!(text(&strict.stderr).contains("accepted although not in steady state"));
    std::fs::remove_dir_all(&folder).ok();
}

/// `[units]` reach the coefficient table and the axes; the provenance lists each data
/// file with its size and SHA-256 (checked against the file) and the version.
#[test]
fn units_and_provenance_in_the_html_report() {
    let folder = scratch("units");
    let models = std::fs::canonicalize("models").unwrap();
    let text = std::fs::read_to_string("models/measured_chain.toml")
        .unwrap()
        .replace(
            "file = \"data/",
            &format!("file = \"{}/data/", models.display()),
        )
        + "\n[units]\nlength = \"m\"\nforce = \"N\"\ntime = \"s\"\n";
    let model = folder.join("units.toml");
    std::fs::write(&model, &text).unwrap();
    let html = folder.join("html");
    dampid_ok(&[
        "identify",
        model.to_str().unwrap(),
        "--report",
        html.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(html.join("report.html")).unwrap();
    for needle in [
        "<th>unit</th>",
        "<td>N·s/m</td>",
        "<td>N</td>",
        // Law curves are solid over the measured range and dashed beyond (the axis
        // spans both; before the dashed extension it read "(measured range)").
        "relative velocity v [m/s]",
        "dashed: beyond the measured range of relative velocity (extrapolated)",
        "damping force θ f(v) [N]",
        "[N·m]",
        "Units: length m, force N, time s.",
        "record_1.csv",
        &format!("dampid {}", env!("CARGO_PKG_VERSION")),
        "UTC",
        // The identifiability and steady-state sections, with a verdict per window.
        "<h2>Identifiability</h2>",
        "<h3>Variance inflation factors</h3>",
        "<h2>Steady state</h2>",
        "windows steady, judged by",
        "<th>verdict</th>",
        // The settings as a table of model-file keys, with where each value came from.
        "<th>section</th><th>key</th><th>value</th><th>source</th>",
        "<td class=\"left\">units</td><td class=\"left\"><code>length</code></td><td class=\"left\"><code>&quot;m&quot;</code></td><td class=\"left\">set in model file</td>",
        "<td class=\"left\">identification</td><td class=\"left\"><code>max_energy_mismatch</code></td><td class=\"left\"><code>0.01</code></td><td class=\"left\">default</td>",
        "<td class=\"left\">command line</td><td class=\"left\"><code>--strict</code></td><td class=\"left\"><code>not given</code></td>",
    ] {
        assert!(page.contains(needle), "missing {needle}");
    }
    assert!(
        !page.contains("RegressorSettings {"),
        "Rust Debug text left"
    );
    let first = models.join("data/chain3/record_1.csv");
    let bytes = std::fs::metadata(&first).unwrap().len();
    let digest = dampid::report::provenance::DataFile::read(&first).unwrap();
    assert_eq!(digest.bytes, bytes);
    assert!(page.contains(&format!(
        "<td>{bytes}</td><td><code class=\"hash\">{}</code>",
        digest.sha256
    )));
    std::fs::remove_dir_all(&folder).ok();
}
