//! The command line as a user runs it: `dampid pod`, exit codes for windows that are not
//! steady, for a dead force sensor and for a regressor that is zero, and progress bars
//! that stay silent when stderr is not a terminal.

use std::path::{Path, PathBuf};

use dampid::io::pod_files::{Columns, pod_of_files};
use dampid::model_file::load;
use dampid::prep::pod::{Pod, PodBasis, PodSettings, Retain};

mod support;
use support::cli::{dampid, dampid_json, dampid_ok};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

const RECORD: &str = "models/data/chain3/record_1.csv";

fn settings(basis: PodBasis) -> PodSettings {
    PodSettings {
        remove_mean: false,
        retain: Retain::Energy(0.999),
        basis,
    }
}

/// The POD of a file's x columns is the POD of the record the model file reads from it.
#[test]
fn pod_of_a_file_is_the_pod_of_its_displacements() {
    let pods = pod_of_files(
        &[PathBuf::from(RECORD)],
        &Columns::Prefix("x".into()),
        &settings(PodBasis::PerRecord),
    )
    .unwrap();
    assert_eq!(pods.len(), 1);
    assert_eq!(pods[0].columns, ["x1", "x2", "x3"]);
    let job = load(Path::new("models/measured_chain.toml"), Default::default()).unwrap();
    let direct = Pod::from_record(&job.source_records[0], &settings(PodBasis::PerRecord)).unwrap();
    for (mode, share) in pods[0].report.modes.iter().zip(direct.energy_shares()) {
        assert!((mode.energy_share - share).abs() < 1e-12);
    }
    // Named columns in another order permute the shapes' components.
    let named = pod_of_files(
        &[PathBuf::from(RECORD)],
        &Columns::Named(vec!["x3".into(), "x2".into(), "x1".into()]),
        &settings(PodBasis::PerRecord),
    )
    .unwrap();
    let (a, b) = (
        &pods[0].report.modes[0].shape,
        &named[0].report.modes[0].shape,
    );
    assert!((a[0] - b[2]).abs() < 1e-12 && (a[2] - b[0]).abs() < 1e-12);
    // By default every column but t: x, v and f.
    let all = pod_of_files(
        &[PathBuf::from(RECORD)],
        &Columns::AllButTime,
        &settings(PodBasis::PerRecord),
    )
    .unwrap();
    assert_eq!(all[0].columns.len(), 7);
}

/// A shared basis stacks the files; different columns are refused with the file named.
#[test]
fn shared_pod_stacks_files() {
    let files = [
        PathBuf::from(RECORD),
        PathBuf::from("models/data/chain3/record_5.csv"),
    ];
    let shared = pod_of_files(
        &files,
        &Columns::Prefix("x".into()),
        &settings(PodBasis::Shared),
    )
    .unwrap();
    assert_eq!(shared.len(), 1);
    let separate = pod_of_files(
        &files,
        &Columns::Prefix("x".into()),
        &settings(PodBasis::PerRecord),
    )
    .unwrap();
    assert_eq!(
        shared[0].report.samples,
        separate.iter().map(|p| p.report.samples).sum::<usize>()
    );
    assert!(matches!(
        pod_of_files(&files[..1], &Columns::Prefix("q".into()), &settings(PodBasis::Shared)),
        Err(dampid::Error::Data { ref file, .. }) if file.contains("record_1")
    ));
}

/// `dampid pod --json` prints what the library function returns.
#[test]
fn pod_command_prints_the_energy_table() {
    let value = dampid_json(&["pod", RECORD, "--prefix", "x", "--json"]);
    let shares: Vec<f64> = value["decompositions"][0]["report"]["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["energy_share"].as_f64().unwrap())
        .collect();
    let library = pod_of_files(
        &[PathBuf::from(RECORD)],
        &Columns::Prefix("x".into()),
        &settings(PodBasis::PerRecord),
    )
    .unwrap();
    let expected: Vec<f64> = library[0]
        .report
        .modes
        .iter()
        .map(|m| m.energy_share)
        .collect();
    assert_eq!(shares, expected);
    let table = dampid_ok(&["pod", RECORD, "--columns", "x1,x2,x3"]);
    let printed = text(&table.stdout);
    assert!(
        printed.contains("x1, x2, x3") && printed.contains("cumulative"),
        "{printed}"
    );
    let missing = dampid(&["pod", RECORD, "--columns", "x9"]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(text(&missing.stderr).contains("x9"));
}

/// A model file whose records start from rest: check and identify exit with 2 and say
/// which window, when and by how much; --accept-transient lets identify run.
#[test]
fn unsteady_windows_exit_with_2_unless_accepted() {
    let folder = std::env::temp_dir().join(format!("dampid-cli-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let four = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let from_rest = four.replace("transient_steps = 1000", "transient_steps = 0");
    assert_ne!(four, from_rest);
    let file = folder.join("from_rest.toml");
    std::fs::write(&file, from_rest).unwrap();
    let path = file.to_str().unwrap();
    for command in ["check", "identify"] {
        let out = dampid(&[command, path]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let error = text(&out.stderr);
        for needle in [
            "not in steady state",
            "window 0",
            "t = 0",
            "--accept-transient",
        ] {
            assert!(
                error.contains(needle),
                "{command}: '{needle}' not in {error}"
            );
        }
    }
    let accepted = dampid_ok(&["identify", path, "--accept-transient"]);
    assert!(text(&accepted.stdout).contains("not in steady state, accepted"));
    std::fs::remove_dir_all(&folder).ok();
}

/// Progress bars draw on stderr only when it is a terminal: piped, identify writes
/// nothing there (indicatif's stderr target hides itself).
#[test]
fn progress_bars_are_silent_when_stderr_is_not_a_terminal() {
    let out = dampid_ok(&["identify", "models/four_mass.toml"]);
    assert_eq!(text(&out.stderr), "");
    let check = dampid_ok(&["check", "models/measured_chain.toml"]);
    assert_eq!(text(&check.stderr), "");
}

/// `identify --bootstrap N` adds percentile intervals from N resampled refits.
#[test]
fn identify_with_bootstrap_prints_intervals() {
    let json = dampid_json(&[
        "identify",
        "models/measured_chain.toml",
        "--bootstrap",
        "200",
        "--json",
    ]);
    assert_eq!(json["report"]["bootstrap"]["replicates"], 200);
    for c in json["report"]["coefficients"].as_array().unwrap() {
        let (lower, upper) = (
            c["interval"]["lower"].as_f64().unwrap(),
            c["interval"]["upper"].as_f64().unwrap(),
        );
        let value = c["value"].as_f64().unwrap();
        assert!(lower <= value && value <= upper, "{c}");
    }
}

/// `identify --bootstrap N` on a job with an estimated exponent: every replicate refits
/// the variable projection on resampled windows; the text and the JSON carry the
/// percentile intervals of the exponent and the coefficients, which hold the estimates.
/// `--report` is still refused for such jobs, and says so.
#[test]
fn identify_with_bootstrap_of_an_estimated_exponent() {
    let model = "tests/data/power_exponent_small.toml";
    let json = dampid_json(&["identify", model, "--bootstrap", "50", "--json"]);
    let report = &json["report"];
    let varpro = &report["estimation"];
    let bootstrap = &report["bootstrap"];
    assert_eq!(bootstrap["replicates"], 50, "{bootstrap}");
    assert_eq!(bootstrap["resampled"], "windows");
    assert_eq!(bootstrap["groups"], 12);
    assert!(bootstrap["used"].as_u64().unwrap() >= 25);
    let value = varpro["parameters"][0]["value"].as_f64().unwrap();
    let interval = &varpro["parameters"][0]["bootstrap"];
    assert_eq!(interval["name"], "d.exponent");
    let (lower, upper) = (
        interval["lower"].as_f64().unwrap(),
        interval["upper"].as_f64().unwrap(),
    );
    assert!(lower <= upper && (value - 1.7).abs() < 0.01, "{interval}");
    for c in report["coefficients"].as_array().unwrap() {
        let i = &c["interval"];
        assert_eq!(c["name"], i["name"]);
        assert!(i["std_error"].as_f64().unwrap() > 0.0, "{i}");
    }
    let out = dampid_ok(&["identify", model, "--bootstrap", "50"]);
    let printed = text(&out.stdout);
    assert!(
        printed.contains("bootstrap: ") && printed.contains("windows resampled (12 to draw from)"),
        "{printed}"
    );
    // --report with --bootstrap: the page carries the percentile intervals too.
    let folder = std::env::temp_dir().join(format!("dampid_cli_varpro_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    dampid_ok(&[
        "identify",
        model,
        "--bootstrap",
        "50",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.contains("<h2>Bootstrap</h2>"), "no bootstrap section");
    assert!(page.contains("windows with replacement"));
    let _ = std::fs::remove_dir_all(&folder);
}

/// `dampid design` sees every mode: the same simulated candidates in the non-periodic
/// mode (windows of 10 time units, a mass per DOF and a spring per link as nuisance
/// unknowns beside the six damping coefficients) are designed like the periodic ones,
/// with the conditioning of all fifteen columns.
#[test]
fn design_runs_in_the_non_periodic_mode() {
    let folder = std::env::temp_dir().join(format!("dampid-cli-design-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let periodic = std::fs::read_to_string("models/per_dashpot.toml").unwrap();
    let spans = periodic.replace(
        "velocity = \"spectral\"\ncycles = 2",
        "velocity = \"central_difference\"",
    ) + "\n[non_periodic]\nwindow = 10.0\nstiffness = \"chain\"\n";
    assert!(spans.contains("central_difference"));
    let file = folder.join("per_dashpot_spans.toml");
    std::fs::write(&file, spans).unwrap();
    let out = dampid(&["design", file.to_str().unwrap(), "--json"]);
    // 0: the target condition is reached; 1: the best set found misses it.
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "{}",
        text(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let steps = report["steps"].as_array().unwrap();
    assert!(steps.len() >= 2, "{report}");
    let singular_values = steps[0]["singular_values"].as_array().unwrap();
    assert_eq!(singular_values.len(), 6 + 4 + 5, "{report}");
    let columns = report["coefficients"].as_array().unwrap();
    assert!(
        columns.iter().any(|c| c == "mass[1]") && columns.iter().any(|c| c == "stiffness[0-1]"),
        "{report}"
    );
    std::fs::remove_dir_all(&folder).ok();
}

/// `--seed` picks the bootstrap's draw: the same seed gives the same intervals, another
/// seed other ones; without `--bootstrap` it is refused.
#[test]
fn bootstrap_seed_selects_the_draw() {
    let intervals = |seed: &str| {
        let json = dampid_json(&[
            "identify",
            "models/measured_chain.toml",
            "--bootstrap",
            "50",
            "--seed",
            seed,
            "--json",
        ]);
        assert_eq!(
            json["report"]["bootstrap"]["seed"],
            seed.parse::<u64>().unwrap()
        );
        json["report"]["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["interval"].clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(intervals("7"), intervals("7"));
    assert_ne!(intervals("7"), intervals("8"));
    let refused = dampid(&["identify", "models/measured_chain.toml", "--seed", "7"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        text(&refused.stderr).contains("--bootstrap"),
        "{}",
        text(&refused.stderr)
    );
}

/// README's sample output of its first command is the real output: every line of the
/// excerpt (but the "…") is a line `dampid identify models/four_mass.toml` prints.
#[test]
fn readme_sample_output_is_the_real_output() {
    let readme = std::fs::read_to_string("README.md").unwrap();
    let start = readme
        .find("```text\nFour-mass chain")
        .expect("README's sample output block");
    let block = &readme[start + "```text\n".len()..];
    let block = &block[..block.find("```").unwrap()];
    let out = dampid_ok(&["identify", "models/four_mass.toml"]);
    let printed = text(&out.stdout);
    let lines: Vec<&str> = printed.lines().collect();
    for line in block.lines().filter(|l| *l != "…") {
        assert!(lines.contains(&line), "README line not printed: {line:?}");
    }
}

/// A copy of `model` (a file in models/) in a scratch folder `name`, its data files read
/// from models/data, except `dead` (a path under models/data), whose last column (the
/// force) is written as zeros: an unplugged load cell. `edit` changes the model text.
fn with_dead_force(
    name: &str,
    model: &str,
    dead: &str,
    edit: impl Fn(String) -> String,
) -> (PathBuf, PathBuf) {
    let folder = std::env::temp_dir().join(format!("dampid-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let data = std::fs::canonicalize("models/data").unwrap();
    let text = std::fs::read_to_string(Path::new("models").join(model)).unwrap();
    let zeroed = folder.join("dead.csv");
    let original = std::fs::read_to_string(Path::new("models/data").join(dead)).unwrap();
    let mut lines = original.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for line in lines {
        let (head, _) = line.rsplit_once(',').unwrap();
        out.push_str(&format!("{head},0\n"));
    }
    std::fs::write(&zeroed, out).unwrap();
    let text = text
        .replace(
            &format!("file = \"data/{dead}\""),
            &format!("file = \"{}\"", zeroed.display()),
        )
        .replace("file = \"data/", &format!("file = \"{}/", data.display()));
    assert!(text.contains(&zeroed.display().to_string()));
    let file = folder.join(model);
    std::fs::write(&file, edit(text)).unwrap();
    (folder, file)
}

/// `check` and `identify` of `file` exit with 2, and stderr holds every one of `needles`.
#[track_caller]
fn exits_with_2_saying(file: &Path, needles: &[&str]) {
    for command in ["check", "identify"] {
        let out = dampid(&[command, file.to_str().unwrap()]);
        let error = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{command}: {error}");
        assert_eq!(text(&out.stdout), "", "{command}");
        for needle in needles {
            assert!(
                error.contains(needle),
                "{command}: '{needle}' not in {error}"
            );
        }
    }
}

/// A dead force sensor (its column all zeros, or `forces = []`) used to give every
/// coefficient as 0, "determined", with exit 0; `check` called the data valid. Both
/// commands now exit with 2, naming the record and the channel (numbered from 1, with
/// its column and DOF) and saying what to check: in the periodic mode (the measured
/// chain) and in the non-periodic mode (the drive).
#[test]
fn dead_force_sensor_exits_with_2_in_both_modes() {
    let (folder, file) = with_dead_force(
        "dead-chain",
        "measured_chain.toml",
        "chain3/record_1.csv",
        |t| t,
    );
    exits_with_2_saying(
        &file,
        &[
            "record 'a=0.5 ω=0.7654 on mass 1'",
            "force channel 1 ('f1', on DOF 1)",
            "no input work",
            "check the force sensor and its column in the model file",
        ],
    );
    let none = file.with_file_name("no_forces.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &none,
        text.replace("forces = [{ column = \"f1\", dof = 1 }]", "forces = []"),
    )
    .unwrap();
    exits_with_2_saying(
        &none,
        &[
            "record 'a=0.5 ω=0.7654 on mass 1'",
            "no force channel",
            "`forces`",
        ],
    );
    std::fs::remove_dir_all(&folder).ok();

    let (folder, file) = with_dead_force(
        "dead-drive",
        "drive_nonperiodic.toml",
        "drive/drive.csv",
        |t| t,
    );
    exits_with_2_saying(
        &file,
        &[
            "record 'closed-loop moves'",
            "force channel 1 ('force', on DOF 1)",
            "no input work",
            "check the force sensor and its column in the model file",
            "free decay",
        ],
    );
    let none = file.with_file_name("no_forces.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &none,
        text.replace("forces = [{ column = \"force\", dof = 1 }]", "forces = []"),
    )
    .unwrap();
    exits_with_2_saying(&none, &["record 'closed-loop moves'", "no force channel"]);
    std::fs::remove_dir_all(&folder).ok();
}

/// Element weights of zero for every term make every column of the regressor zero:
/// the data carry no information on any coefficient. It used to print "practical rank:
/// 0 of 5" and then "every coefficient is determined", exit 0; both commands now exit
/// with 2 and name the coefficients.
#[test]
fn zero_regressor_exits_with_2() {
    let folder = std::env::temp_dir().join(format!("dampid-cli-zero-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let data = std::fs::canonicalize("models/data").unwrap();
    let model = std::fs::read_to_string("models/measured_chain.toml").unwrap();
    let zero = model
        .replace(
            "per_element = \"dashpot\"",
            "per_element = \"dashpot\"\nweights = [0.0, 0.0, 0.0, 0.0]",
        )
        .replace(
            "coefficient = \"friction\"",
            "coefficient = \"friction\"\nweights = [0.0]",
        )
        .replace("file = \"data/", &format!("file = \"{}/", data.display()));
    assert_eq!(zero.matches("weights").count(), 2);
    let file = folder.join("zero.toml");
    std::fs::write(&file, zero).unwrap();
    exits_with_2_saying(
        &file,
        &[
            "these data carry no information on dashpot[0-1], dashpot[1-2], dashpot[2-3], dashpot[3-4] and friction",
            "every column of the regressor",
            "weights or matrices",
        ],
    );
    std::fs::remove_dir_all(&folder).ok();
}

/// Absurd sizes are refused up front with exit 2, naming the setting to reduce: DOFs
/// whose matrices do not fit in memory, harmonics beyond what a window holds, a
/// transient of 10¹⁵ steps (refused from its measured rate) and 10⁹ bootstrap replicates.
#[test]
fn absurd_sizes_exit_with_2_before_allocating() {
    let folder = std::env::temp_dir().join(format!("dampid-cli-sizes-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let four = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let cases = [
        ("dofs", four.replace("dofs = 4", "dofs = 100000"), "dofs"),
        (
            "harmonics",
            four.replace(
                "velocity = \"central_difference\"",
                "velocity = \"harmonic_projection\"\nharmonics = 1000000000",
            ),
            "harmonics",
        ),
        (
            "transient",
            four.replace(
                "transient_steps = 1000",
                "transient_steps = 1000000000000000",
            ),
            "transient_steps",
        ),
    ];
    for (name, text, needle) in cases {
        assert_ne!(text, four, "{name}");
        let file = folder.join(format!("{name}.toml"));
        std::fs::write(&file, text).unwrap();
        let out = dampid(&["identify", file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let error = text_of(&out.stderr);
        assert!(error.contains(needle), "{name}: {error}");
    }
    let replicates = dampid(&[
        "identify",
        "models/four_mass.toml",
        "--bootstrap",
        "1000000000000",
    ]);
    assert_eq!(replicates.status.code(), Some(2));
    assert!(text_of(&replicates.stderr).contains("--bootstrap"));
    std::fs::remove_dir_all(&folder).ok();
}

fn text_of(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `dampid check` on a job with an estimated exponent examines the regressor at the
/// exponent's initial value and says so, by name and value, in the text and the JSON.
#[test]
fn check_names_the_parameters_it_holds_at_their_initial_values() {
    let json = support::cli::dampid_json(&["check", "models/four_mass_power.toml", "--json"]);
    assert_eq!(json["held_at_initial"][0][0], "d.exponent");
    assert_eq!(json["held_at_initial"][0][1], 1.0);
    let out = support::cli::dampid_ok(&["check", "models/four_mass_power.toml"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("held at their initial values for this check: d.exponent = 1"),
        "{text}"
    );
}

/// `--strict` on a variable projection: an exponent whose bounds exclude the truth
/// (1.7, bounds [2, 4]) ends on its lower bound, which is a warning flag without
/// `--strict` (exit 0) and a failure with it (exit 1, the reason on stderr).
#[test]
fn strict_refuses_an_estimated_parameter_on_its_bound() {
    let text = std::fs::read_to_string("tests/data/power_exponent_small.toml")
        .unwrap()
        .replace(
            "initial = 1.0, lower = 0.5, upper = 4.0 }",
            "initial = 2.5, lower = 2.0, upper = 4.0 }",
        );
    let file =
        std::env::temp_dir().join(format!("dampid_strict_bound_{}.toml", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let path = file.to_str().unwrap();
    let plain = dampid(&["identify", path]);
    assert_eq!(
        plain.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&plain.stderr)
    );
    assert!(String::from_utf8_lossy(&plain.stdout).contains("(on a bound)"));
    let strict = dampid(&["identify", path, "--strict"]);
    assert_eq!(strict.status.code(), Some(1));
    let said = String::from_utf8_lossy(&strict.stderr);
    assert!(
        said.contains("strict: estimated parameter d.exponent = 2"),
        "{said}"
    );
    let _ = std::fs::remove_file(&file);
}

/// Windows accepted although not in steady state are warnings of a variable projection
/// too: with `--accept-transient --strict` the estimated-exponent job started without
/// its transient exits 1 and names them.
#[test]
fn strict_variable_projection_names_accepted_transient_windows() {
    let text = std::fs::read_to_string("tests/data/power_exponent_small.toml")
        .unwrap()
        .replace("transient_steps = 5000", "transient_steps = 0");
    let file = std::env::temp_dir().join(format!(
        "dampid_strict_transient_{}.toml",
        std::process::id()
    ));
    std::fs::write(&file, text).unwrap();
    let out = dampid(&[
        "identify",
        file.to_str().unwrap(),
        "--accept-transient",
        "--strict",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("window(s) accepted although not in steady state"),
        "{said}"
    );
    let _ = std::fs::remove_file(&file);
}
