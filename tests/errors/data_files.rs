//! Data files: a column the file does not have is `UnknownName` (listing the columns it
//! has), a bad cell is `Data` with file, row and column, and a MAT file whose sizes
//! overflowed the former MAT parser is `Data` too, not a panic (both found by the `mat` fuzz
//! target).

use crate::npy_file::npy_bytes;
use dampid::io::Table;
use dampid::prelude::*;

#[test]
fn missing_column_lists_the_columns() {
    let table = dampid::io::csv::parse("t,x1\n0,1\n", "d.csv").unwrap();
    match table.column("x2") {
        Err(Error::UnknownName { what, name, known }) => {
            assert!(what.contains("d.csv"));
            assert_eq!((name.as_str(), known.as_str()), ("x2", "t, x1"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_data_cell_names_row_and_column() {
    match dampid::io::csv::parse("t,x1\n0,1\n0.1,inf\n", "d.csv") {
        Err(Error::Data {
            file, row, column, ..
        }) => assert_eq!((file.as_str(), row, column.as_str()), ("d.csv", 2, "x1")),
        other => panic!("{other:?}"),
    }
}

/// The 128-byte header of a level-5 MAT file: 116 bytes of text, the subsystem data
/// offset, version 0x0100 and the little-endian mark.
fn mat_header() -> Vec<u8> {
    let mut bytes = vec![b' '; 116];
    bytes.extend_from_slice(&[0; 8]); // subsystem data offset
    bytes.extend_from_slice(&[0x00, 0x01]); // version
    bytes.extend_from_slice(b"IM"); // little endian
    bytes
}

/// What `read_mat` makes of `bytes`, written to a temporary file named after `name`.
fn read_mat_bytes(name: &str, bytes: &[u8]) -> Result<Table> {
    let path = std::env::temp_dir().join(format!("dampid-{name}-{}.mat", std::process::id()));
    std::fs::write(&path, bytes).unwrap();
    let result = dampid::io::read_mat(&path);
    std::fs::remove_file(&path).unwrap();
    result
}

#[test]
fn mat_file_whose_dimensions_overflow_is_a_data_error() {
    // Found by the `mat` fuzz target: a numeric matrix of 65536 × 65536 makes the MAT
    // parser then used (matfile 0.5) multiply its dimensions as i32, a panic under
    // overflow checks; kept for io/mat/element.rs, which multiplies them checked.
    let mut bytes = mat_header();
    let tag = |kind: u32, size: u32| [kind.to_le_bytes(), size.to_le_bytes()].concat();
    bytes.extend(tag(14, 56)); // miMATRIX of 56 bytes:
    bytes.extend(tag(6, 8)); // array flags (miUINT32): class 6 = double, nzmax 0
    bytes.extend_from_slice(&[6, 0, 0, 0, 0, 0, 0, 0]);
    bytes.extend(tag(5, 8)); // dimensions (miINT32): 65536 × 65536
    bytes.extend_from_slice(&[65536i32.to_le_bytes(), 65536i32.to_le_bytes()].concat());
    bytes.extend(tag(1, 1)); // name (miINT8) "x", padded to 8
    bytes.extend_from_slice(b"x\0\0\0\0\0\0\0");
    bytes.extend(tag(9, 0)); // real part (miDOUBLE), empty
    let result = read_mat_bytes("dims", &bytes);
    assert!(
        matches!(&result, Err(Error::Data { file, row: 0, .. }) if file.ends_with(".mat")),
        "{result:?}"
    );
}

#[test]
fn mat_file_whose_element_size_overflows_is_a_data_error() {
    // Found by the `mat` fuzz target: a data element claiming 0xFFFFFFFF bytes made the
    // MAT parser then used (matfile 0.5) overflow while rounding the size up to its
    // padding, a panic under overflow checks. The header, then that one tag.
    let mut bytes = mat_header();
    bytes.extend_from_slice(&[0x0f, 0, 0, 0, 0xff, 0xff, 0xff, 0xff]); // miCOMPRESSED
    let result = read_mat_bytes("overflow", &bytes);
    assert!(
        matches!(&result, Err(Error::Data { file, row: 0, message, .. })
            if file.ends_with(".mat") && message.contains("MAT")),
        "{result:?}"
    );
}

/// One uncompressed miMATRIX element: array flags of `class`, dimensions 1 × `n`, the
/// name, and `data` (a whole data element, tag included).
fn mat_matrix(class: u8, name: &str, n: i32, data: &[u8]) -> Vec<u8> {
    let tag = |kind: u32, size: u32| [kind.to_le_bytes(), size.to_le_bytes()].concat();
    let mut body = tag(6, 8);
    body.extend_from_slice(&[class, 0, 0, 0, 0, 0, 0, 0]);
    body.extend(tag(5, 8));
    body.extend_from_slice(&[1i32.to_le_bytes(), n.to_le_bytes()].concat());
    body.extend(tag(1, name.len() as u32));
    let mut padded = name.as_bytes().to_vec();
    padded.resize(name.len().div_ceil(8) * 8, 0);
    body.extend(padded);
    body.extend_from_slice(data);
    let mut element = tag(14, body.len() as u32);
    element.extend(body);
    element
}

/// A MAT file with a char variable beside a numeric one (issue 29, item 10): a column it
/// does not have names the numeric variables and names the variable of a kind that is
/// not read, with its size and class, instead of "known: " with nothing after it; a MAT v4 file is named
/// as such, not "truncated".
#[test]
fn mat_variables_of_other_kinds_are_named_in_the_error() {
    let tag = |kind: u32, size: u32| [kind.to_le_bytes(), size.to_le_bytes()].concat();
    let mut bytes = mat_header();
    let mut chars = tag(4, 4); // miUINT16 "hi", padded to 8
    chars.extend_from_slice(&[b'h', 0, b'i', 0, 0, 0, 0, 0]);
    bytes.extend(mat_matrix(4, "note", 2, &chars)); // mxCHAR_CLASS
    let mut doubles = tag(9, 24); // miDOUBLE 1, 2, 3
    for v in [1.0f64, 2.0, 3.0] {
        doubles.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend(mat_matrix(6, "x", 3, &doubles)); // mxDOUBLE_CLASS
    let path = std::env::temp_dir().join(format!("dampid-kinds-{}.mat", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    let file = dampid::io::data_file::DataFile::open(&path).unwrap();
    assert_eq!(
        file.table(&["x"]).unwrap().column("x").unwrap(),
        [1.0, 2.0, 3.0]
    );
    let message = file.table(&["note"]).unwrap_err().to_string();
    for needle in ["'note'", "note (1×2 char)", "known: x"] {
        assert!(message.contains(needle), "'{needle}' not in {message}");
    }
    std::fs::remove_file(&path).ok();

    // A MAT v4 file: a 20-byte header (type 0 = double, 1 × 1, not complex, name "x\0")
    // and one value.
    let mut v4 = Vec::new();
    for word in [0i32, 1, 1, 0, 2] {
        v4.extend_from_slice(&word.to_le_bytes());
    }
    v4.extend_from_slice(b"x\0");
    v4.extend_from_slice(&1.0f64.to_le_bytes());
    v4.resize(200, 0);
    let message = read_mat_bytes("v4", &v4).unwrap_err().to_string();
    assert!(
        message.contains("MAT v4") && !message.contains("truncated"),
        "{message}"
    );
}

/// A header naming one column twice is `Data` naming the column: a model file's column
/// name must pick exactly one.
#[test]
fn duplicate_column_name_is_a_data_error() {
    match dampid::io::csv::parse("t,x1,x1\n0,1,2\n", "dup.csv") {
        Err(Error::Data { file, column, .. }) => {
            assert_eq!((file.as_str(), column.as_str()), ("dup.csv", "x1"));
        }
        other => panic!("{other:?}"),
    }
}

/// Output files: an existing target is `OutputExists` naming it; a folder that does
/// not exist is `Output` naming the file; neither leaves a file behind.
#[test]
fn output_errors_name_the_file() {
    use dampid::io::output::{Overwrite, write_file};
    let path = std::env::temp_dir().join(format!("dampid-errors-out-{}.txt", std::process::id()));
    std::fs::write(&path, "mine").unwrap();
    let exists = write_file(&path, Overwrite::Refuse, |w| {
        w.write_all(b"new").map_err(|e| Error::Output {
            path: String::new(),
            message: e.to_string(),
        })
    })
    .unwrap_err();
    assert_eq!(exists.kind(), "output_exists");
    assert!(exists.to_string().contains(&path.display().to_string()));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "mine");
    std::fs::remove_file(&path).ok();

    let nowhere = std::path::Path::new("/nonexistent-dampid-folder/report.html");
    let failed = write_file(nowhere, Overwrite::Replace, |_| Ok(())).unwrap_err();
    assert_eq!(failed.kind(), "output");
    assert!(failed.to_string().contains("report.html"), "{failed}");
}

/// A MAT file cut short loses no variable silently: every cut inside the last data
/// element (or its tag) of real v5 and compressed v7 files is `Data` saying so.
#[test]
fn truncated_mat_file_is_a_data_error() {
    for source in [
        "tests/data/chain3_record1_v5.mat",
        "tests/data/chain3_record1_v7.mat",
    ] {
        let bytes = std::fs::read(source).unwrap();
        assert!(read_mat_bytes("whole", &bytes).is_ok(), "{source}");
        for cut in [bytes.len() - 1, bytes.len() - 9, bytes.len() - 200, 131] {
            match read_mat_bytes("cut", &bytes[..cut]) {
                Err(Error::Data { message, .. }) => {
                    assert!(
                        message.contains("truncated"),
                        "{source} at {cut}: {message}"
                    )
                }
                other => panic!("{source} cut at {cut}: {other:?}"),
            }
        }
    }
}

/// A 1 kHz time column with the jitter of a real MATLAB export (2.4e-5 of a step) is
/// accepted with its mean step and its jitter; one with 2e-3 is `TimeJitter`, naming
/// the file, the column, the worst row and the jitter, and suggesting `step = h`; a
/// column that goes back is `Data`.
#[test]
fn time_jitter_is_accepted_up_to_its_tolerance() {
    let h = 1e-3;
    let column = |jitter: f64| {
        let mut csv = String::from("time,x\n");
        for i in 0..1000 {
            // sample 500 late by jitter·h: the steps around it are h(1 ± jitter)
            let wobble = if i == 500 { jitter } else { 0.0 };
            csv.push_str(&format!("{:.17e},0\n", (i as f64 + wobble) * h));
        }
        dampid::io::csv::parse(&csv, "drive.csv").unwrap()
    };
    let accepted = column(2.4e-5).uniform_step("time").unwrap();
    assert!((accepted.step - h).abs() < 1e-12 * h, "{accepted:?}");
    assert!((accepted.jitter - 2.4e-5).abs() < 1e-7, "{accepted:?}");
    let table = column(2e-3);
    let error = table.uniform_step("time").unwrap_err();
    match &error {
        Error::TimeJitter {
            file,
            column,
            row,
            jitter,
            tolerance,
            step,
        } => {
            assert_eq!((file.as_str(), column.as_str()), ("drive.csv", "time"));
            assert!(*row == 501 || *row == 502, "{row}");
            assert!((jitter - 2e-3).abs() < 1e-6, "{jitter}");
            assert_eq!(*tolerance, dampid::io::table::MAX_TIME_JITTER);
            assert!((step - h).abs() < 1e-9);
        }
        other => panic!("{other:?}"),
    }
    assert!(error.to_string().contains("`step = 0.001`"), "{error}");
    let backwards = dampid::io::csv::parse("t,x\n0,0\n2,0\n1,0\n3,0\n", "b.csv").unwrap();
    assert!(matches!(
        backwards.uniform_step("t"),
        Err(Error::Data { row: 3, .. })
    ));
}

fn read_npy_bytes(name: &str, bytes: &[u8]) -> Result<Table> {
    let path = std::env::temp_dir().join(format!("dampid-{name}-{}.npy", std::process::id()));
    std::fs::write(&path, bytes).unwrap();
    let result = dampid::io::npy::read_npy(&path);
    std::fs::remove_file(&path).unwrap();
    result
}

/// An NPY header that claims more data than the file holds is a `Data` error, found
/// before anything of the claimed size is allocated (10^12 f8 would be 8 TB): so is a
/// shape whose size overflows, and a file cut inside its data.
#[test]
fn npy_header_claiming_more_than_the_file_holds_is_a_data_error() {
    let data: Vec<u8> = [1.0f64, 2.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let whole = npy_bytes(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }",
        &data,
    );
    assert_eq!(
        read_npy_bytes("whole", &whole).unwrap().columns,
        [vec![1.0, 2.0]]
    );
    for (name, dict) in [
        (
            "huge",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000000000,), }",
        ),
        (
            "wide",
            "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 1000000000000), }",
        ),
        (
            "overflow",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296, 4294967296), }",
        ),
        (
            "square",
            "{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296), }",
        ),
    ] {
        match read_npy_bytes(name, &npy_bytes(dict, &data)) {
            Err(Error::Data { row, message, .. }) => {
                assert_eq!(row, 0, "{name}");
                assert!(
                    message.contains("holds 16 bytes") || message.contains("shape"),
                    "{name}: {message}"
                );
            }
            other => panic!("{name}: {other:?}"),
        }
    }
    match read_npy_bytes("cut", &whole[..whole.len() - 3]) {
        Err(Error::Data { message, .. }) => {
            assert!(message.contains("holds 13 bytes"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

/// A scratch folder of this test process.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `read` on another thread and waits for it (a reader that blocks on a FIFO or
/// reads `/dev/zero` without end fails the test instead of hanging it; the bound is a
/// guard against a hang, not a speed requirement).
fn without_hanging<T: Send + 'static>(read: impl FnOnce() -> T + Send + 'static) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(read()).ok());
    receive
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("the reader returned instead of blocking")
}

/// Every reader, given a path that is not a regular file: `/dev/zero` behind a symbolic
/// link named as a data file, a FIFO (opening it would wait for a writer), a folder.
/// Each is `Error::Data` naming the file, checked before the file is opened.
#[test]
fn device_fifo_or_folder_named_as_a_data_file_is_a_data_error() {
    let dir = scratch("not-a-file");
    type Reader = fn(&std::path::Path) -> Result<()>;
    let readers: [(&str, Reader); 7] = [
        ("csv", |p| dampid::io::read_table(p).map(drop)),
        ("npy", |p| dampid::io::npy::read_npy(p).map(drop)),
        ("npz", |p| dampid::io::read_npz(p).map(drop)),
        ("mat", |p| dampid::io::read_mat(p).map(drop)),
        ("uff", |p| dampid::io::uff::read(p).map(drop)),
        ("txt", |p| dampid::io::csv::read(p).map(drop)),
        ("csv", |p| {
            dampid::prep::harmonic::SteppedSineTable::load_csv(p).map(drop)
        }),
    ];
    for (k, (extension, read)) in readers.into_iter().enumerate() {
        let zero = dir.join(format!("zero{k}.{extension}"));
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let fifo = dir.join(format!("fifo{k}.{extension}"));
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let folder = dir.join(format!("folder{k}.{extension}"));
        std::fs::create_dir(&folder).unwrap();
        for (path, kind) in [
            (zero, "a device, FIFO or socket"),
            (fifo, "a device, FIFO or socket"),
            (folder, "a folder"),
        ] {
            let shown = path.display().to_string();
            match without_hanging(move || read(&path)) {
                Err(Error::Data { file, message, .. }) => {
                    assert_eq!(file, shown);
                    assert!(message.contains(kind), "{message}");
                    assert!(message.contains("not a regular file"), "{message}");
                }
                other => panic!("{shown}: {other:?}"),
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A model file whose record names `/dev/zero` through a link: the model-file error at
/// the record, whose cause is the `Data` error naming the file.
#[test]
fn model_file_record_that_is_a_device_is_refused_at_its_line() {
    let dir = scratch("model-dev-zero");
    std::os::unix::fs::symlink("/dev/zero", dir.join("run.csv")).unwrap();
    let text = "dofs = 1\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n\n[[data.records]]\nfile = \"run.csv\"\ntime = \"t\"\ndisplacements = [\"x\"]\nforces = [{ column = \"f\", dof = 1 }]\n";
    let base = dir.clone();
    let result = without_hanging(move || {
        dampid::model_file::parse(text, "m.toml", &base, Default::default())
            .map(drop)
            .map_err(|e| (e.to_string(), e.innermost().kind()))
    });
    let (message, kind) = result.unwrap_err();
    assert_eq!(kind, "data", "{message}");
    assert!(message.contains("run.csv"), "{message}");
    assert!(message.contains("not a regular file"), "{message}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A data file larger than `--max-memory` is refused before it is read, naming the file
/// and the size (exit 2).
#[test]
fn data_file_beyond_the_memory_limit_is_refused_before_reading() {
    let dir = scratch("data-too-large");
    let mut csv = String::from("t,x,f\n");
    for i in 0..2000 {
        let t = f64::from(i) * 0.01;
        csv.push_str(&format!("{t},{},{}\n", t.sin(), t.cos()));
    }
    std::fs::write(dir.join("run.csv"), &csv).unwrap();
    let model = dir.join("m.toml");
    std::fs::write(&model, "dofs = 1\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n\n[[data.records]]\nfile = \"run.csv\"\ntime = \"t\"\ndisplacements = [\"x\"]\nforces = [{ column = \"f\", dof = 1 }]\nperiod = 6.283185307179586\n").unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args(["check", "--max-memory", "10000"])
        .arg(&model)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("run.csv"), "{stderr}");
    assert!(stderr.contains("reading the data file"), "{stderr}");
    assert!(stderr.contains("10 kB"), "{stderr}");
    // Within the limit the same file is read.
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args(["check", "--max-memory", "1000000"])
        .arg(&model)
        .output()
        .unwrap();
    assert!(
        !String::from_utf8_lossy(&output.stderr).contains("reading the data file"),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}
