//! The new-user walkthrough (docs/walkthrough.md), run as written: its two model files,
//! the commands it shows, and what it says the outputs contain.

use std::path::Path;

use dampid::model_file::load;

mod support;
use support::cli::{dampid_json, dampid_ok};

const TRUTH: [(&str, f64); 5] = [
    ("dashpot[0-1]", 0.10),
    ("dashpot[1-2]", 0.05),
    ("dashpot[2-3]", 0.15),
    ("dashpot[3-4]", 0.08),
    ("friction", 0.05),
];

/// First try: four records at the first resonance. The periods are detected from the
/// force (2π/0.765367 to 1e-6), every window is steady, and the report flags the four
/// dashpots as not separable.
#[test]
fn first_try_is_flagged_as_not_identifiable() {
    let job = load(
        Path::new("models/walkthrough_first_try.toml"),
        Default::default(),
    )
    .unwrap();
    let period = 2.0 * std::f64::consts::PI / 0.765367;
    for detected in &job.detected_periods {
        let detected = detected.expect("no period in the file: detected");
        assert!((detected.period - period).abs() < 1e-6 * period);
    }
    assert!(
        job.steady_state()
            .unwrap()
            .expect("a periodic model file")
            .enforce()
            .is_ok()
    );
    let report = dampid::identify(&job.problem(), &job.settings, &dampid::progress::silent)
        .unwrap()
        .report;
    let identifiability = &report.identifiability;
    assert!(!identifiability.separable());
    assert!(identifiability.practical_rank < 5);
    for name in [
        "dashpot[0-1]",
        "dashpot[1-2]",
        "dashpot[2-3]",
        "dashpot[3-4]",
    ] {
        assert!(
            identifiability.unidentifiable.iter().any(|n| n == name),
            "{name}: {:?}",
            identifiability.unidentifiable
        );
    }
    let checked = dampid_ok(&["check", "models/walkthrough_first_try.toml"]);
    let printed = String::from_utf8_lossy(&checked.stdout);
    assert!(
        printed.contains("period detected from the force"),
        "{printed}"
    );
    assert!(printed.contains("cannot separate"), "{printed}");
}

/// The full file: all twelve records; every coefficient within 0.05% of the truth,
/// with standard errors, and `--report` writes the HTML report.
#[test]
fn walkthrough_model_file_identifies_the_chain() {
    let job = load(Path::new("models/walkthrough.toml"), Default::default()).unwrap();
    assert_eq!(job.records.len(), 12);
    let report = dampid::identify(&job.problem(), &job.settings, &dampid::progress::silent)
        .unwrap()
        .report;
    assert!(report.identifiability.separable());
    for (name, value) in TRUTH {
        let estimate = report.coefficient(name).unwrap();
        assert!(
            (estimate - value).abs() < 5e-4 * value,
            "{name}: {estimate}"
        );
    }
    assert!(report.coefficients.iter().all(|c| c.std_error.is_some()));

    let folder = std::env::temp_dir().join(format!("dampid-walkthrough-{}", std::process::id()));

    std::fs::remove_dir_all(&folder).ok(); // a stale folder of an earlier run
    dampid_ok(&[
        "identify",
        "models/walkthrough.toml",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.contains("<svg"));
    let value = dampid_json(&["identify", "models/walkthrough.toml", "--json"]);
    assert_eq!(value["report"]["coefficients"].as_array().unwrap().len(), 5);
    std::fs::remove_dir_all(&folder).ok();
}

/// Every `cargo run --release -- …` command in docs/walkthrough.md runs and succeeds
/// (`out/` becomes a temporary folder), and the `head` it shows is the file's start.
#[test]
fn every_walkthrough_command_works() {
    let doc = std::fs::read_to_string("docs/walkthrough.md").unwrap();
    let folder =
        std::env::temp_dir().join(format!("dampid-walkthrough-doc-{}", std::process::id()));
    let mut in_shell = false;
    let mut commands = 0;
    for line in doc.lines() {
        if line.starts_with("```") {
            in_shell = line == "```sh";
            continue;
        }
        if !in_shell {
            continue;
        }
        if let Some(rest) = line.strip_prefix("cargo run --release -- ") {
            let args: Vec<String> = rest
                .split('#')
                .next()
                .unwrap()
                .split_whitespace()
                .map(|a| {
                    if a == "out/" {
                        folder.display().to_string()
                    } else {
                        a.to_string()
                    }
                })
                .collect();
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            dampid_ok(&args);
            commands += 1;
        } else if let Some(file) = line.strip_prefix("head -3 ") {
            let text = std::fs::read_to_string(file).unwrap();
            let shown: Vec<&str> = text.lines().take(3).collect();
            assert!(doc.contains(&shown.join("\n")), "{file}");
        } else {
            panic!("a command the test does not run: {line}");
        }
    }
    assert!(commands >= 5, "{commands}");
    assert!(folder.join("report.html").exists());
    std::fs::remove_dir_all(&folder).ok();
}
