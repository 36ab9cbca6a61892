//! Motion columns of a stored `.npz` member are read straight into the record's
//! matrices (`io/in_place.rs`), the other formats and deflated members through a table:
//! both give the same record bit for bit, with every gain and offset applied as
//! scale × column + offset, and a truncated member is a `Data` error naming the file and
//! the member, whichever path reads it.

use std::io::Write;
use std::path::{Path, PathBuf};

use dampid::Error;
use dampid::model_file::Job;

#[path = "support/npy.rs"]
mod npy_file;
use npy_file::npy_bytes;

/// Samples of the scratch records (not a whole number of read blocks).
const N: usize = 20_011;

/// An NPY member of little-endian doubles.
fn npy(descr: &str, fortran: bool, shape: &str, data: &[f64]) -> Vec<u8> {
    let dict = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
        if fortran { "True" } else { "False" }
    );
    let data: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    npy_bytes(&dict, &data)
}

/// A scratch file path of this test.
fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("dampid-in-place-{}-{name}", std::process::id()))
}

/// Writes the members to an `.npz`, stored or deflated.
fn write_npz(path: &Path, members: &[(&str, Vec<u8>)], stored: bool) {
    let mut zip = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let method = if stored {
        zip::CompressionMethod::Stored
    } else {
        zip::CompressionMethod::Deflated
    };
    let options = zip::write::FileOptions::default()
        .compression_method(method)
        .large_file(false);
    for (name, bytes) in members {
        zip.start_file(format!("{name}.npy"), options).unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap();
}

/// Three DOFs: t (N), x (N × 3, C order: interleaved samples), v (3 × N, C order:
/// stored transposed, contiguous per DOF), f (N); values of every sign and magnitude.
fn members() -> Vec<(&'static str, Vec<u8>)> {
    let h = 1e-3;
    let t: Vec<f64> = (0..N).map(|i| i as f64 * h).collect();
    let value = |i: usize, j: usize, phase: f64| {
        let w = 2.0 * std::f64::consts::PI / 0.4;
        (w * t[i] + phase + j as f64).sin() * 10f64.powi(j as i32 - 1)
    };
    let x: Vec<f64> = (0..N)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| value(i, j, 0.0))
        .collect();
    let v: Vec<f64> = (0..3)
        .flat_map(|j| (0..N).map(move |i| (i, j)))
        .map(|(i, j)| value(i, j, 1.0))
        .collect();
    let f: Vec<f64> = (0..N).map(|i| value(i, 0, 0.5)).collect();
    vec![
        ("t", npy("<f8", false, &format!("({N},)"), &t)),
        ("x", npy("<f8", false, &format!("({N}, 3)"), &x)),
        ("v", npy("<f8", false, &format!("(3, {N})"), &v)),
        ("f", npy("<f8", false, &format!("({N},)"), &f)),
    ]
}

/// A model file reading `file` with measured velocities, gains and offsets on some
/// columns (one column named twice).
fn model(file: &Path) -> String {
    format!(
        r#"dofs = 3
[[terms]]
kind = "law"
law = "linear"
elements = "chain"
per_element = "dashpot"
[identification]
velocity = "measured"
cycles = 2
[[data.records]]
file = "{}"
time = "t"
displacements = [{{ column = "x[1]", scale = 1e-3, offset = 5e-3 }}, "x[2]", {{ column = "x[3]", scale = -2.5 }}]
velocities = ["v[1]", {{ column = "v[2]", offset = -0.25 }}, {{ column = "v[1]", scale = 3.0 }}]
forces = [{{ column = "f", dof = 1, scale = 35.15 }}]
period = 0.4
"#,
        file.display()
    )
}

fn parse(file: &Path) -> dampid::Result<Job> {
    dampid::model_file::parse(&model(file), "m.toml", Path::new("."), Default::default())
}

/// The bits of every element of `m`, column by column.
fn bits(m: faer::MatRef<'_, f64>) -> Vec<u64> {
    (0..m.ncols())
        .flat_map(|j| (0..m.nrows()).map(move |i| m[(i, j)].to_bits()))
        .collect()
}

/// The wide record's job (`wide_model`) for the archive `file`.
fn parse_wide(file: &Path) -> dampid::Result<Job> {
    dampid::model_file::parse(
        &wide_model(file),
        "m.toml",
        Path::new("."),
        Default::default(),
    )
}

/// The data error under the model file's location of a record that does not read.
fn data_error(file: &Path) -> (String, usize, String, String) {
    match parse(file).map(|_| ()).unwrap_err().innermost() {
        Error::Data {
            file,
            row,
            column,
            message,
        } => (file.clone(), *row, column.clone(), message.clone()),
        other => panic!("{other}"),
    }
}

/// The in-place read of a stored archive gives the record of the table path (the same
/// archive deflated) bit for bit, and each value is scale × column + offset of the
/// column as `read_table` gives it.
#[test]
fn stored_members_read_in_place_equal_the_table_path_bitwise() {
    let (stored, deflated) = (scratch("stored.npz"), scratch("deflated.npz"));
    write_npz(&stored, &members(), true);
    write_npz(&deflated, &members(), false);
    let (a, b) = (parse(&stored).unwrap(), parse(&deflated).unwrap());
    let (a, b) = (&a.records[0], &b.records[0]);
    assert_eq!(bits(a.displacements()), bits(b.displacements()));
    assert_eq!(bits(a.velocities().unwrap()), bits(b.velocities().unwrap()));
    assert_eq!(a.step().to_bits(), b.step().to_bits());
    let table = dampid::io::read_table(&stored).unwrap();
    let gains = [
        ("x[1]", 1e-3, 5e-3),
        ("x[2]", 1.0, 0.0),
        ("x[3]", -2.5, 0.0),
        ("v[1]", 1.0, 0.0),
        ("v[2]", 1.0, -0.25),
        ("v[1]", 3.0, 0.0),
    ];
    for (k, (column, scale, offset)) in gains.into_iter().enumerate() {
        let m = if k < 3 {
            a.displacements()
        } else {
            a.velocities().unwrap()
        };
        let values = table.column(column).unwrap();
        assert_eq!(values.len(), m.nrows());
        for (i, &c) in values.iter().enumerate() {
            assert_eq!(
                m[(i, k % 3)].to_bits(),
                (scale * c + offset).to_bits(),
                "{column} {i}"
            );
        }
    }
    std::fs::remove_file(stored).ok();
    std::fs::remove_file(deflated).ok();
}

/// A member cut short is a `Data` error naming the file and the member: cut by one
/// sample (its header's data still fit the member, so it is read in place and found
/// short there) or by many (it goes through the table, which finds it short).
#[test]
fn a_truncated_member_is_a_data_error_naming_file_and_member() {
    for cut in [1, N / 2] {
        let mut members = members();
        let x = &mut members[1].1;
        x.truncate(x.len() - 3 * 8 * cut);
        let path = scratch(&format!("cut{cut}.npz"));
        write_npz(&path, &members, true);
        let (file, _, column, message) = data_error(&path);
        assert_eq!(file, path.display().to_string(), "{cut}");
        assert_eq!(column, "x", "{cut}");
        assert!(message.contains("truncated"), "{cut}: {message}");
        std::fs::remove_file(path).ok();
    }
}

/// A non-finite value in a member read in place is a `Data` error at its sample and
/// column, as the table path gives it.
#[test]
fn a_non_finite_value_read_in_place_is_an_error_at_its_sample() {
    let mut members = members();
    let x = &mut members[1].1;
    let header = x.len() - 3 * 8 * N;
    // Sample 1234 (0-based), DOF 2.
    let at = header + 8 * (3 * 1234 + 1);
    x[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    for stored in [true, false] {
        let path = scratch(&format!("nan{stored}.npz"));
        write_npz(&path, &members, stored);
        let (file, row, column, message) = data_error(&path);
        assert_eq!(file, path.display().to_string());
        assert_eq!((row, column.as_str()), (1235, "x[2]"), "{stored}");
        assert!(message.contains("non-finite"), "{message}");
        std::fs::remove_file(path).ok();
    }
}

/// A damaged member read in place (one data byte changed, the value still finite) is
/// the CRC-32 error of the table path, naming the file and the member.
#[test]
fn a_damaged_member_read_in_place_is_a_crc_error() {
    let members = members();
    let path = scratch("crc.npz");
    write_npz(&path, &members, true);
    let mut bytes = std::fs::read(&path).unwrap();
    let name = bytes.windows(5).position(|w| w == b"x.npy").unwrap();
    // Local header: 30 bytes, the name's length at 26..28, the extra field's at 28..30.
    let local = name - 30;
    let extra = u16::from_le_bytes([bytes[local + 28], bytes[local + 29]]) as usize;
    let npy_header = members[1].1.len() - 3 * 8 * N;
    // The low byte of a little-endian f8: still finite.
    bytes[name + 5 + extra + npy_header + 8 * 10] ^= 1;
    std::fs::write(&path, &bytes).unwrap();
    let (file, _, column, message) = data_error(&path);
    assert_eq!(file, path.display().to_string());
    assert_eq!(column, "x");
    assert!(message.contains("CRC-32"), "{message}");
    std::fs::remove_file(path).ok();
}

/// DOFs of the wide record: 40 interleaved values per row, so that each column of a read
/// block is a stride of 40 (`io/scatter.rs`) and N is not a whole number of blocks.
const WIDE: usize = 40;

/// t, f and x (N × WIDE) in C order (interleaved rows) or Fortran order (contiguous
/// columns), x(s, j) a value of every sign and magnitude, with `nan` at (sample, column).
fn wide_members(fortran: bool, nan: Option<(usize, usize)>) -> Vec<(&'static str, Vec<u8>)> {
    wide_members_of(N, fortran, nan.as_slice())
}

/// [`wide_members`] of `n` samples with NaNs at `nans`.
fn wide_members_of(
    n: usize,
    fortran: bool,
    nans: &[(usize, usize)],
) -> Vec<(&'static str, Vec<u8>)> {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let value = |s: usize, j: usize| {
        let x = (2.0 * std::f64::consts::PI * t[s] / 0.4 + j as f64).sin();
        if nans.contains(&(s, j)) {
            f64::NAN
        } else {
            x * 10f64.powi(j as i32 % 7 - 3)
        }
    };
    let x: Vec<f64> = if fortran {
        (0..WIDE)
            .flat_map(|j| (0..n).map(move |s| (s, j)))
            .map(|(s, j)| value(s, j))
            .collect()
    } else {
        (0..n)
            .flat_map(|s| (0..WIDE).map(move |j| (s, j)))
            .map(|(s, j)| value(s, j))
            .collect()
    };
    let f: Vec<f64> = (0..n).map(|s| value(s, 0)).collect();
    vec![
        ("t", npy("<f8", false, &format!("({n},)"), &t)),
        ("x", npy("<f8", fortran, &format!("({n}, {WIDE})"), &x)),
        ("f", npy("<f8", false, &format!("({n},)"), &f)),
    ]
}

/// The wide record's model: x as displacements with gains on some DOFs, and the same
/// member read again, reversed, as measured velocities.
fn wide_model(file: &Path) -> String {
    let column = |j: usize| match j % 3 {
        0 => format!("{{ column = \"x[{j}]\", scale = 1e-3, offset = 5e-3 }}"),
        1 => format!("\"x[{j}]\""),
        _ => format!("{{ column = \"x[{j}]\", scale = -2.5 }}"),
    };
    let x: Vec<String> = (1..=WIDE).map(column).collect();
    let v: Vec<String> = (1..=WIDE).rev().map(column).collect();
    format!(
        "dofs = {WIDE}\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\nper_element = \"dashpot\"\n\
         [identification]\nvelocity = \"measured\"\ncycles = 2\n[[data.records]]\nfile = \"{}\"\ntime = \"t\"\n\
         displacements = [{}]\nvelocities = [{}]\nforces = [{{ column = \"f\", dof = 1 }}]\nperiod = 0.4\n",
        file.display(),
        x.join(", "),
        v.join(", ")
    )
}

/// A wide member read in place, by interleaved rows (C order) or by contiguous columns
/// (Fortran order), gives the record of the table path (the same archive deflated) bit
/// for bit; a NaN in the middle of a block (sample 1234, DOF 17: C order reads blocks of
/// 409 rows, so the NaN is value 17 of row 7 of the block of rows 1227–1635) is an
/// error at its sample and column, on either path.
#[test]
fn wide_members_read_in_place_equal_the_table_path_and_locate_a_nan() {
    for fortran in [false, true] {
        let (stored, deflated) = (
            scratch(&format!("wide{fortran}.npz")),
            scratch(&format!("wide{fortran}z.npz")),
        );
        write_npz(&stored, &wide_members(fortran, None), true);
        write_npz(&deflated, &wide_members(fortran, None), false);
        let (a, b) = (parse_wide(&stored).unwrap(), parse_wide(&deflated).unwrap());
        let (a, b) = (&a.records[0], &b.records[0]);
        assert_eq!(
            bits(a.displacements()),
            bits(b.displacements()),
            "{fortran}"
        );
        assert_eq!(bits(a.velocities().unwrap()), bits(b.velocities().unwrap()));
        // Velocity column 0 is x[WIDE] with the gain of DOF WIDE (WIDE % 3 == 1: none).
        let table = dampid::io::read_table(&stored).unwrap();
        let last = table.column(&format!("x[{WIDE}]")).unwrap();
        let v = a.velocities().unwrap();
        assert!((0..N).all(|s| v[(s, 0)].to_bits() == last[s].to_bits()));
        for (stored, path) in [(true, &stored), (false, &deflated)] {
            write_npz(path, &wide_members(fortran, Some((1234, 16))), stored);
            let e = parse_wide(path).map(|_| ()).unwrap_err();
            let Error::Data {
                file, row, column, ..
            } = e.innermost()
            else {
                panic!("{e}");
            };
            assert_eq!(file, &path.display().to_string());
            assert_eq!(
                (*row, column.as_str()),
                (1235, "x[17]"),
                "{fortran} {stored}"
            );
        }
        std::fs::remove_file(stored).ok();
        std::fs::remove_file(deflated).ok();
    }
}

/// Samples of the large record: its x member (N × 40 doubles, 19 MB) is read in two
/// parts by two threads (`io/parts.rs`: parts of at least 8 MiB).
const LARGE: usize = 60_013;

/// A large member read in parallel parts, by interleaved rows (C order) or by whole
/// columns (Fortran order), gives the record of the table path bit for bit; with a NaN
/// in each part, the error is at the first in file order (C order: sample 10,001 of
/// DOF 31, in the first part; Fortran order: sample 50,001 of DOF 4, whose column comes
/// first); a byte changed in the last part is the CRC-32 error.
#[test]
fn large_members_read_in_parts_equal_the_table_path_and_name_the_first_error() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        for fortran in [false, true] {
            let (stored, deflated) = (
                scratch(&format!("large{fortran}.npz")),
                scratch(&format!("large{fortran}z.npz")),
            );
            let members = wide_members_of(LARGE, fortran, &[]);
            write_npz(&stored, &members, true);
            write_npz(&deflated, &members, false);
            let (a, b) = (parse_wide(&stored).unwrap(), parse_wide(&deflated).unwrap());
            let (a, b) = (&a.records[0], &b.records[0]);
            assert_eq!(
                bits(a.displacements()),
                bits(b.displacements()),
                "{fortran}"
            );
            assert_eq!(bits(a.velocities().unwrap()), bits(b.velocities().unwrap()));

            let nans = [(50_000, 3), (10_000, 30)];
            write_npz(&stored, &wide_members_of(LARGE, fortran, &nans), true);
            let e = parse_wide(&stored).map(|_| ()).unwrap_err();
            let Error::Data { row, column, .. } = e.innermost() else {
                panic!("{e}");
            };
            let first = if fortran {
                (50_001, "x[4]")
            } else {
                (10_001, "x[31]")
            };
            assert_eq!((*row, column.as_str()), first, "{fortran}");

            // The low byte of the member's last double: still finite.
            write_npz(&stored, &members, true);
            let mut bytes = std::fs::read(&stored).unwrap();
            let name = bytes.windows(5).position(|w| w == b"x.npy").unwrap();
            let local = name - 30;
            let extra = u16::from_le_bytes([bytes[local + 28], bytes[local + 29]]) as usize;
            let x = &members[1].1;
            bytes[name + 5 + extra + x.len() - 8] ^= 1;
            std::fs::write(&stored, &bytes).unwrap();
            let e = parse_wide(&stored).map(|_| ()).unwrap_err();
            let Error::Data {
                column, message, ..
            } = e.innermost()
            else {
                panic!("{e}");
            };
            assert_eq!(column, "x");
            assert!(message.contains("CRC-32"), "{message}");
            std::fs::remove_file(stored).ok();
            std::fs::remove_file(deflated).ok();
        }
    });
}

/// A stored member with bytes after its data (the header asks for fewer than the member
/// holds) is read in place like the same member without them, and its CRC-32 covers
/// them: one of them changed is the CRC error.
#[test]
fn bytes_after_a_members_data_are_in_its_crc() {
    let mut padded = members();
    padded[1].1.extend_from_slice(&[7u8; 24]);
    let (path, plain) = (scratch("padded.npz"), scratch("unpadded.npz"));
    write_npz(&path, &padded, true);
    write_npz(&plain, &members(), true);
    let (a, b) = (parse(&path).unwrap(), parse(&plain).unwrap());
    assert_eq!(
        bits(a.records[0].displacements()),
        bits(b.records[0].displacements())
    );
    let mut bytes = std::fs::read(&path).unwrap();
    let name = bytes.windows(5).position(|w| w == b"x.npy").unwrap();
    let local = name - 30;
    let extra = u16::from_le_bytes([bytes[local + 28], bytes[local + 29]]) as usize;
    bytes[name + 5 + extra + padded[1].1.len() - 1] ^= 1;
    std::fs::write(&path, &bytes).unwrap();
    let (_, _, column, message) = data_error(&path);
    assert_eq!(column, "x");
    assert!(message.contains("CRC-32"), "{message}");
    std::fs::remove_file(path).ok();
    std::fs::remove_file(plain).ok();
}
