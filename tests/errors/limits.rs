//! Limits that hold before allocating and time limits that include every loop (issue 29,
//! items 5 and 6): each case is refused with `TooLarge` (exit 2) naming the setting to
//! reduce and a readable size, before the allocation or within a fraction of a second,
//! and the model-file path itself gets the checks of a data path.

use std::path::{Path, PathBuf};
use std::process::Output;

use dampid::prelude::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid-limits-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A two-mass chain simulated for `recorded` steps per experiment, `experiments`
/// experiments, with `extra` appended (a section or more experiments).
fn chain(recorded: usize, experiments: usize, simulation: &str, extra: &str) -> String {
    let mut text = format!(
        "dofs = 2\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n\n\
         [simulation]\nmass = \"identity\"\nstiffness = \"chain\"\ncoefficients = {{ c = 0.1 }}\nstep = 0.05\n\
         transient_steps = 8000\nrecorded_steps = {recorded}\n{simulation}\n"
    );
    for k in 0..experiments {
        text.push_str(&format!(
            "\n[[simulation.experiments]]\nforce_dof = 1\namplitude = {}\nfrequency = 0.618\n",
            1.0 + k as f64
        ));
    }
    text.push('\n');
    text.push_str(extra);
    text
}

/// Runs `dampid ARGS MODEL` on `text` written as `name` in `dir`.
fn run(dir: &Path, name: &str, text: &str, args: &[&str]) -> (Output, String) {
    let model = dir.join(name);
    std::fs::write(&model, text).unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args(args)
        .arg(&model)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    (output, stderr)
}

/// Exit 2 with a `TooLarge` message naming `needles`.
fn refused(output: &Output, stderr: &str, needles: &[&str]) {
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("beyond the limit"), "{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "'{needle}' not in {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// `[harmonic_approximation] samples_per_period` of 10¹² (a 56 TB allocation) and 10⁸
/// (5.6 GB) under `--max-memory 1G`: refused before the synthesized records are
/// allocated; 10⁷ (records that fit) is refused before the spectral basis of 10⁷ × 9·10⁶
/// columns that faer panicked on.
#[test]
fn samples_per_period_is_checked_before_allocating() {
    let dir = scratch("samples");
    for (count, needle) in [
        ("1000000000000", "samples_per_period"),
        ("100000000", "samples_per_period"),
        ("10000000", "harmonic basis"),
    ] {
        let text = chain(
            400,
            1,
            "",
            &format!("[harmonic_approximation]\nsamples_per_period = {count}\n"),
        );
        let (output, stderr) = run(&dir, "m.toml", &text, &["identify", "--max-memory", "1G"]);
        refused(&output, &stderr, &[needle, "1.0 GB"]);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `recorded_steps` × experiments in total: three records of 3·10⁷ samples fit one at a
/// time in 4 GB (1.2 GB each) but not together; refused before the first is simulated.
#[test]
fn simulated_records_are_checked_in_total() {
    let dir = scratch("records");
    let (output, stderr) = run(
        &dir,
        "m.toml",
        &chain(30_000_000, 3, "", ""),
        &["identify", "--max-memory", "4G"],
    );
    refused(
        &output,
        &stderr,
        &["3 records", "recorded_steps", "m.toml:"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `[string_simulation] damping_points = 10⁹` (48 GB of mode shapes): refused.
#[test]
fn string_damping_points_are_checked_before_allocating() {
    let dir = scratch("string");
    let text = "dofs = 4\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n\n\
        [[terms]]\nkind = \"law\"\nlaw = \"quadratic\"\nelements = \"each_dof\"\ncoefficient = \"d\"\n\n\
        [string_simulation]\nforce_position = 0.2\nfrequency = 3.0\namplitudes = [1.0, 2.0]\nmodes = 4\n\
        damping_points = 1000000000\ncoefficients = { c = 0.1, d = 0.05 }\nlinear = \"c\"\nquadratic = \"d\"\n\
        step = 0.01\ntransient_steps = 100\nrecorded_steps = 400\n";
    let (output, stderr) = run(&dir, "m.toml", text, &["identify", "--max-memory", "1G"]);
    refused(&output, &stderr, &["damping_points", "48 GB"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A deflated `.npz` member whose header claims 2·10⁶ × 3 float64 (48 MB, in a file of
/// some 50 kB): refused under `--max-memory 10M` before the values are allocated, and
/// never inflated whole into memory; within the limit the same file reads.
#[test]
fn an_npz_member_claiming_more_than_the_budget_is_refused() {
    use std::io::Write;
    let dir = scratch("npz");
    let rows = 2_000_000usize;
    let header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, 3), }}");
    let padded = (header.len() + 11).div_ceil(64) * 64 - 11;
    let mut npy = b"\x93NUMPY\x01\x00".to_vec();
    npy.extend_from_slice(&(padded as u16).to_le_bytes());
    npy.extend_from_slice(format!("{header:<width$}\n", width = padded - 1).as_bytes());
    let file = std::fs::File::create(dir.join("big.npz")).unwrap();
    let mut zip = zip::ZipWriter::new(file);
    let options =
        zip::write::FileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    zip.start_file("x.npy", options).unwrap();
    zip.write_all(&npy).unwrap();
    let zeros = vec![0u8; 3 * 8 * 1000];
    for _ in 0..rows / 1000 {
        zip.write_all(&zeros).unwrap();
    }
    zip.finish().unwrap();
    let size = std::fs::metadata(dir.join("big.npz")).unwrap().len();
    assert!(size < 1_000_000, "{size} bytes");
    let text = "dofs = 2\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\ncoefficient = \"c\"\n\n\
        [[data.records]]\nfile = \"big.npz\"\nstep = 0.01\ndisplacements = [\"x[1]\", \"x[2]\"]\n\
        forces = [{ column = \"x[3]\", dof = 1 }]\nperiod = 1.0\n";
    let (output, stderr) = run(&dir, "m.toml", text, &["check", "--max-memory", "10M"]);
    refused(&output, &stderr, &["'x'", "big.npz", "48 MB"]);
    // Read within the limit: the all-zero force is then the data's problem, not memory.
    let (_, stderr) = run(&dir, "m.toml", text, &["check", "--max-memory", "1G"]);
    assert!(!stderr.contains("beyond the limit"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The model-file path gets a data path's checks: `/dev/zero` behind a symbolic link
/// and a FIFO are `ModelFile` errors naming the file, at once (no 11.5 GB read, no wait
/// for a writer).
#[cfg(unix)]
#[test]
fn a_model_file_that_is_a_device_or_fifo_is_refused() {
    let dir = scratch("model-path");
    let zero = dir.join("zero.toml");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let fifo = dir.join("fifo.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    for path in [zero, fifo, dir.clone()] {
        let shown = path.display().to_string();
        let (send, receive) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let result = dampid::model_file::load(&path, Default::default()).map(drop);
            send.send(result.map_err(|e| (e.kind(), e.to_string())))
                .ok();
        });
        let (kind, message) = receive
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("the model file was refused instead of read or waited on")
            .unwrap_err();
        assert_eq!(kind, "model_file", "{message}");
        assert!(message.contains(&shown), "{message}");
        assert!(message.contains("not a regular file"), "{message}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A Latin-1 model file: the line and column of its first byte that is not UTF-8, and
/// what to do, instead of "stream did not contain valid UTF-8" at 0:0.
#[test]
fn a_latin1_model_file_names_the_line_of_its_first_accent() {
    let dir = scratch("latin1");
    let path = dir.join("m.toml");
    let mut bytes = b"dofs = 2\n# Pr".to_vec();
    bytes.push(0xfc); // ü in Latin-1
    bytes.extend_from_slice(b"fung\n");
    std::fs::write(&path, bytes).unwrap();
    let error = dampid::model_file::load(&path, Default::default()).unwrap_err();
    match &error {
        Error::ModelFile { line, column, .. } => assert_eq!((*line, *column), (2, 5), "{error}"),
        other => panic!("{other}"),
    }
    let message = error.to_string();
    assert!(
        message.contains("UTF-8") && message.contains("0xfc"),
        "{message}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `substeps = 10¹²` is in the time estimate (it was missing, so one recorded step ran
/// for ever): `TooLarge` naming `substeps`, in well under a second of simulation.
#[test]
fn substeps_are_in_the_time_estimate() {
    let system = dampid::simulate::System {
        mass: faer::Mat::identity(1, 1),
        stiffness: faer::Mat::identity(1, 1),
        damping: DampingModel::new().with(Term::per_dof(
            dampid::terms::laws::Linear,
            1,
            Coefficients::Shared("c".into()),
        )),
        damping_coefficients: vec![0.1],
        conservative: Vec::new(),
        forcing: vec![dampid::simulate::HarmonicForce {
            dof: 0,
            amplitude: 1.0,
            frequency: 1.0,
            phase: 0.0,
        }],
    };
    let settings = dampid::simulate::SimSettings {
        step: 0.05,
        substeps: 1_000_000_000_000,
        transient_steps: 100,
        recorded_steps: 100,
    };
    let error =
        dampid::simulate::simulate(&system, &settings, &dampid::progress::silent).unwrap_err();
    assert_eq!(error.kind(), "too_large", "{error}");
    let message = error.to_string();
    assert!(
        message.contains("substeps") && message.contains("years"),
        "{message}"
    );
}

/// An expression that is NaN at some state (sqrt of a negative velocity) in a simulation
/// is named as such, with the term and the state, not "diverged … reduce the step".
#[test]
fn an_undefined_expression_in_a_simulation_names_the_term() {
    let text = chain(
        400,
        1,
        "",
        "",
    )
    .replace(
        "coefficient = \"c\"\n",
        "coefficient = \"c\"\n\n[[terms]]\nkind = \"law\"\nlaw = \"expression\"\nexpression = \"sqrt(v)\"\nelements = \"each_dof\"\ncoefficient = \"e\"\n",
    )
    .replace("{ c = 0.1 }", "{ c = 0.1, e = 0.05 }");
    let error =
        dampid::model_file::parse(&text, "m.toml", Path::new("."), Default::default()).unwrap_err();
    assert_eq!(error.innermost().kind(), "numerical", "{error}");
    let message = error.to_string();
    for needle in [
        "coefficient(s) e",
        "NaN",
        "not defined there",
        "not a step-size problem",
    ] {
        assert!(message.contains(needle), "'{needle}' not in {message}");
    }
    assert!(!message.contains("reduce the step"), "{message}");
}
