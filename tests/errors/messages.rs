//! Messages that say where and what (issue 29, items 9 and 10): every settings error of
//! a model file is at the line and column of its key, by one mechanism
//! (`model_file/locate.rs`), and before any record is simulated; errors that were
//! unclear name their cause; small defects (a built-in matrix name in `[matrices]`, a
//! duplicate CSV header among many columns, control characters in titles, `[design]
//! picks = 0`) are refused or made inert.

use std::path::Path;

use dampid::prelude::*;

/// A two-mass chain simulated briefly, with `identification` in `[identification]`,
/// `terms` added after the linear term, and `extra` appended.
fn model(identification: &str, terms: &str, extra: &str) -> String {
    format!(
        "title = \"chain\"\ndofs = 2\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n{terms}\n\
         [identification]\ncycles = 1\n{identification}\n\n\
         [simulation]\nmass = \"identity\"\nstiffness = \"chain\"\ncoefficients = {{ c = 0.1 }}\nstep = 0.05\n\
         transient_steps = 8000\nrecorded_steps = 400\n\n\
         [[simulation.experiments]]\nforce_dof = 1\namplitude = 1.0\nfrequency = 0.618\n{extra}"
    )
}

/// The 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle} not in {text}"));
    text[..at].matches('\n').count() + 1
}

/// `parse` of `text` fails with a model-file error at the line of `key` (a line > 0),
/// its message holding `needles` and never `:0:0`; returns the error.
fn at_line_of(text: &str, key: &str, needles: &[&str]) -> Error {
    let error =
        dampid::model_file::parse(text, "m.toml", Path::new("."), Default::default()).unwrap_err();
    let message = error.to_string();
    match &error {
        Error::ModelFile { line, column, .. } => {
            assert_eq!(*line, line_of(text, key), "{message}");
            assert!(*column > 0, "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert!(
        message.starts_with(&format!("m.toml:{}:", line_of(text, key))),
        "{message}"
    );
    assert!(!message.contains(":0:0"), "{message}");
    for needle in needles {
        assert!(message.contains(needle), "'{needle}' not in {message}");
    }
    error
}

/// Bounds, fixed values and linear constraints naming unknown coefficients, inverted
/// bounds, a negative fixed value under `nonnegative`, and `cycles`, `windows` and
/// `harmonics` of 0: each at its key's line, before the records are simulated, keeping
/// the typed error as its cause.
#[test]
fn identification_errors_are_at_their_keys() {
    let cases: [(&str, &str, &[&str], &str); 8] = [
        (
            "bounds = { nope = { lower = 0.0 } }",
            "nope",
            &["'nope'", "c"],
            "unknown_coefficient",
        ),
        (
            "bounds = { c = { lower = 1.0, upper = 0.0 } }",
            "c = { lower",
            &["'c'"],
            "infeasible_bounds",
        ),
        (
            "fixed = { nope = 1.0 }",
            "nope",
            &["'nope'"],
            "unknown_coefficient",
        ),
        (
            "nonnegative = true\nfixed = { c = -1.0 }",
            "c = -1.0",
            &["nonnegative = true", "-1"],
            "invalid_parameter",
        ),
        (
            "constraints = [{ terms = { nope = 1.0 }, relation = \"=\", value = 0.0 }]",
            "nope",
            &["'nope'"],
            "unknown_coefficient",
        ),
        (
            "windows = 0",
            "windows",
            &["at least one window"],
            "invalid_parameter",
        ),
        (
            "harmonics = 0",
            "harmonics",
            &["harmonics"],
            "invalid_parameter",
        ),
        (
            "max_state_mismatch = -1.0",
            "max_state_mismatch",
            &["max_state_mismatch"],
            "invalid_parameter",
        ),
    ];
    for (identification, key, needles, kind) in cases {
        let text = model(identification, "", "");
        let error = at_line_of(&text, key, needles);
        assert_eq!(error.innermost().kind(), kind, "{error}");
    }
    let text = model("", "", "").replace("cycles = 1", "cycles = 0");
    at_line_of(&text, "cycles", &["whole period"]);
}

/// `dofs = 0`, `terms = []` and `[data]` beside `[simulation]` are at their keys (they
/// printed `file:0:0:`).
#[test]
fn whole_file_errors_are_at_their_keys() {
    let text = model("", "", "").replace("dofs = 2", "dofs = 0");
    at_line_of(&text, "dofs", &["dofs"]);

    let text = "dofs = 2\nterms = []\n";
    let error = at_line_of(text, "terms", &["empty"]);
    assert_eq!(error.innermost().kind(), "empty");

    let data = "\n[[data.records]]\nfile = \"r.csv\"\ntime = \"t\"\ndisplacements = [\"x1\", \"x2\"]\nforces = [{ column = \"f1\", dof = 1 }]\n";
    let text = model("", "", data);
    at_line_of(&text, "data.records", &["[data] beside [simulation]"]);
}

/// An estimated law parameter whose bounds leave the law's domain (a power law's
/// exponent from −2) is refused at its term's block when the file is read, not when the
/// search reaches a negative exponent mid-fit.
#[test]
fn estimated_bounds_outside_the_laws_domain_are_refused_at_the_term() {
    let power = "\n[[terms]]\nkind = \"law\"\nlaw = \"power\"\nelements = \"each_dof\"\ncoefficient = \"p\"\nexponent = { estimate = true, initial = 1.5, lower = -2.0, upper = 3.0 }\n";
    let text = model("", power, "").replace("{ c = 0.1 }", "{ c = 0.1, p = 0.05 }");
    let error = at_line_of(
        &text,
        "exponent = {",
        &["lower bound", "p.exponent", "-2", "exponent"],
    );
    assert_eq!(error.innermost().kind(), "invalid_parameter");
}

/// `[matrices] chain = …` shadowed the built-in silently; it is refused at its key.
#[test]
fn a_matrix_named_like_a_built_in_is_refused() {
    for name in ["chain", "identity"] {
        let text = model("", "", "").replace(
            "[identification]",
            &format!("[matrices]\n{name} = [[5.0, 0.0], [0.0, 5.0]]\n\n[identification]"),
        );
        at_line_of(&text, &format!("{name} = [["), &["built-in", name]);
    }
}

/// `[design] picks = 0` is bad input (exit 2, at its key), not a design that misses its
/// target (exit 1).
#[test]
fn design_picks_of_zero_is_bad_input() {
    let text = model("", "", "\n[design]\npicks = 0\n");
    at_line_of(&text, "picks", &["picks"]);
    let dir = std::env::temp_dir().join(format!("dampid-picks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("m.toml");
    std::fs::write(&path, &text).unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"))
        .arg("design")
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

/// A title with an ANSI escape, a bell and a carriage return prints them as inert
/// escapes, in text and in JSON.
#[test]
fn control_characters_in_titles_and_labels_print_inert() {
    let text = model("", "", "").replace(
        "title = \"chain\"",
        "title = \"\\u001b[31mred\\u0007bell\\r\"",
    );
    let job =
        dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap();
    assert_eq!(job.title, "\\u{1b}[31mred\\u{7}bell\\u{d}");
    let dir = std::env::temp_dir().join(format!("dampid-ansi-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("m.toml");
    std::fs::write(&path, &text).unwrap();
    for json in [false, true] {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"));
        command.arg("identify").arg(&path);
        if json {
            command.arg("--json");
        }
        let output = command.output().unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        for stream in [&output.stdout, &output.stderr] {
            assert!(
                !stream.iter().any(|b| matches!(b, 0x1b | 0x07 | b'\r')),
                "{}",
                String::from_utf8_lossy(stream)
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A CSV header of 300,000 columns with one name twice: the duplicate is named with both
/// column numbers (the check was O(n²): 74 s), and a header without one reads.
#[test]
fn a_duplicate_among_many_csv_columns_is_found() {
    let n = 300_000;
    let mut names: Vec<String> = (0..n).map(|k| format!("c{k}")).collect();
    let row = vec!["0"; n].join(",");
    let unique = format!("{}\n{row}\n", names.join(","));
    assert_eq!(
        dampid::io::csv::parse(&unique, "wide.csv")
            .unwrap()
            .headers
            .len(),
        n
    );
    names[n - 1] = "c17".into();
    let duplicate = format!("{}\n{row}\n", names.join(","));
    let message = dampid::io::csv::parse(&duplicate, "wide.csv")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("'c17' twice (columns 18 and 300000)"),
        "{message}"
    );
}
