//! MAT v7.3 (HDF5) files that cannot be read: every truncation and many damaged bytes
//! of the fixtures (tests/data/mat73/generate.py), an HDF5 file without MATLAB's header,
//! a struct array whose element refers to itself, and contents that are not columns.
//! Each is `Data` (or `TooLarge`) naming the file, never a panic.

use std::path::{Path, PathBuf};

use dampid::prelude::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_errors_mat73_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The `Data` error's file and message, behind any model-file error.
fn data_of(e: &Error) -> (String, String) {
    match e.innermost() {
        Error::Data { file, message, .. } => (file.clone(), message.clone()),
        other => panic!("{other:?}"),
    }
}

/// Cuts of a v7.3 file (at every byte of its first 600, then every 97th), and bytes set
/// to 0xFF or flipped by 0x5A (every 37th from the HDF5 start), read or are
/// `Data`/`TooLarge` naming the file, never a panic nor gigabytes of fill values (a
/// damaged dimension, found here, read 12 GB before `v73::plausible`).
#[test]
fn damaged_v73_files_are_data_errors() {
    for name in [
        "contents_v73.mat",
        "frdata_v73.mat",
        "chain3_record1_v73.mat",
    ] {
        let bytes = std::fs::read(Path::new("tests/data/mat73").join(name)).unwrap();
        let file = scratch(name);
        let read = |b: &[u8]| {
            std::fs::write(&file, b).unwrap();
            dampid::io::mat::contents(&file)
        };
        assert!(read(&bytes).is_ok(), "{name}");
        let check = |what: &str, result: Result<Vec<dampid::io::mat::Entry>>| {
            if let Err(e) = result {
                match &e {
                    Error::Data { file: f, .. } => {
                        assert_eq!(f, &file.display().to_string(), "{name} {what}: {e}")
                    }
                    Error::TooLarge { .. } => {}
                    other => panic!("{name} {what}: {other:?}"),
                }
            }
        };
        let cuts = (0..600).chain((600..bytes.len()).step_by(97));
        for cut in cuts {
            check(&format!("cut at {cut}"), read(&bytes[..cut]));
        }
        for at in (512..bytes.len()).step_by(37) {
            for damage in [|b: u8| b ^ 0x5A, |_| 0xFF] {
                let mut damaged = bytes.clone();
                damaged[at] = damage(damaged[at]);
                check(&format!("byte {at}"), read(&damaged));
            }
        }
    }
}

/// An HDF5 file without MATLAB's 512-byte header is not guessed at: `Data` saying so.
#[test]
fn hdf5_without_matlab_header_says_so() {
    let bytes = std::fs::read("tests/data/mat73/contents_v73.mat").unwrap();
    let file = scratch("plain.mat");
    std::fs::write(&file, &bytes[512..]).unwrap();
    let e = dampid::io::read_table(&file).unwrap_err();
    let (f, message) = data_of(&e);
    assert_eq!(f, file.display().to_string());
    assert!(
        message.contains("without MATLAB's 512-byte v7.3 header"),
        "{message}"
    );
}

/// A struct array whose element refers to itself is refused by path, not followed
/// forever; the file's other variables are not read past it.
#[test]
fn a_reference_cycle_is_a_data_error() {
    let file = Path::new("tests/data/mat73/cycle_v73.mat");
    let e = dampid::io::read_table(file).unwrap_err();
    let (f, message) = data_of(&e);
    assert_eq!(f, file.display().to_string());
    assert!(
        message.contains("MAT v7.3") && message.contains("top(1).next"),
        "{message}"
    );
}

/// Contents of a v7.3 file that are not columns, named by a record or as sweeps, say
/// what they are and what the file holds.
#[test]
fn unread_v73_contents_say_what_they_are() {
    let file = "tests/data/mat73/contents_v73.mat";
    let model = |x: &str| {
        format!(
            r#"dofs = 1
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[data.records]]
file = "{file}"
step = 0.1
displacements = ["{x}"]
forces = [{{ column = "q", dof = 1 }}]
period = 1.0
"#
        )
    };
    for (x, needles) in [
        ("c", ["cell", "1×2"]),
        ("z", ["complex", "real"]),
        ("flags", ["logical", "1×3"]),
        ("nothing", ["s.inner.d", "sweeps(3).amplitude"]),
    ] {
        let e = dampid::model_file::parse(&model(x), "m.toml", Path::new("."), Default::default())
            .unwrap_err();
        let message = e.to_string();
        for needle in needles {
            assert!(message.contains(needle), "{x}: '{needle}' not in {message}");
        }
    }
}

/// A damaged dimension (byte 25836 of the record file is in the dataspace of a dataset:
/// flipped, it claims 1 509 950 140 values, beyond the stored maximum 700, which h5py
/// refuses too) is `Data` saying the file is damaged, not gigabytes of fill values.
#[test]
fn a_damaged_dimension_is_refused() {
    let mut bytes = std::fs::read("tests/data/mat73/chain3_record1_v73.mat").unwrap();
    bytes[25836] ^= 0x5A;
    let file = scratch("dimension.mat");
    std::fs::write(&file, &bytes).unwrap();
    let e = dampid::io::mat::contents(&file).unwrap_err();
    let (f, message) = data_of(&e);
    assert_eq!(f, file.display().to_string());
    assert!(
        message.contains("1509950140") && message.contains("damaged"),
        "{message}"
    );
}
