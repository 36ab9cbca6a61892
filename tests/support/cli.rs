//! Running the `dampid` binary from an integration test.

use std::ffi::OsStr;
use std::process::{Command, Output};

/// Runs the binary with `args` and returns its output, whether it succeeded or not.
pub fn dampid<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args(args)
        .output()
        .expect("the dampid binary runs")
}

/// Runs the binary with `args`; fails the test, showing the command and its stderr,
/// unless it succeeds.
pub fn dampid_ok<S: AsRef<OsStr>>(args: &[S]) -> Output {
    let output = dampid(args);
    assert!(
        output.status.success(),
        "dampid {}: {}",
        args.iter()
            .map(|a| a.as_ref().to_string_lossy())
            .collect::<Vec<_>>()
            .join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// The JSON a successful run prints on stdout.
pub fn dampid_json<S: AsRef<OsStr>>(args: &[S]) -> serde_json::Value {
    let output = dampid_ok(args);
    serde_json::from_slice(&output.stdout).expect("stdout is JSON")
}
