//! Where a report came from: the model file (its path and text), each data file with its
//! size and SHA-256, every setting in effect (defaults included), dampid's version and the
//! git commit it was built from (build.rs; "unknown" outside a git checkout), and the
//! date and time (UTC) the report was made. The HTML report shows it in one block.
//!
//! Records given as arrays rather than files (the Python package) are named by each
//! array's shape and the SHA-256 of its float64 values, little-endian, in C order (row
//! by row): `hashlib.sha256(numpy.ascontiguousarray(a, "<f8").tobytes())`.

use std::io::Read;
use std::path::Path;

use faer::MatRef;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};

/// dampid's version (Cargo.toml).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The git commit dampid was built from, or "unknown" (build.rs).
pub const COMMIT: &str = env!("DAMPID_GIT_COMMIT");

/// One data file read.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DataFile {
    /// Its path as the model file resolved it.
    pub path: String,
    /// Its size in bytes.
    pub bytes: u64,
    /// SHA-256 of its contents, lowercase hex.
    pub sha256: String,
}

impl DataFile {
    /// Reads `path` once, streaming, for its size and SHA-256; [`Error::Data`] naming the
    /// file when it cannot be read.
    pub fn read(path: &Path) -> Result<DataFile> {
        let fail = |e: std::io::Error| Error::Data {
            file: path.display().to_string(),
            row: 0,
            column: String::new(),
            message: format!("cannot read it for its checksum: {e}"),
        };
        let mut file = std::fs::File::open(path).map_err(fail)?;
        let mut hasher = Sha256::new();
        let mut buffer = vec![0u8; 1 << 16];
        let mut bytes = 0u64;
        loop {
            let n = file.read(&mut buffer).map_err(fail)?;
            if n == 0 {
                break;
            }
            bytes += n as u64;
            hasher.update(&buffer[..n]);
        }
        let sha256 = hex(&hasher.finalize());
        Ok(DataFile {
            path: path.display().to_string(),
            bytes,
            sha256,
        })
    }
}

/// One setting in effect: where a model file (or the command line) sets it, its value
/// as a model file writes it, and where the value came from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Setting {
    /// The model-file section (`identification`, `non_periodic`, `design`, `units`), or
    /// `command line`, or `fit (not in model files)` for internal settings.
    pub section: String,
    /// The key, as docs/model-file.md names it.
    pub key: String,
    /// The value in effect, in TOML form (`"trapezoid"`, `1`, `0.01`), or in words where
    /// it is chosen from the data (`harmonics`).
    pub value: String,
    /// Where the value came from.
    pub source: SettingSource,
}

/// Where a setting's value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SettingSource {
    /// Not set: dampid's default.
    Default,
    /// Set in the model file.
    ModelFile,
    /// Set on the command line.
    CommandLine,
    /// Set by a keyword argument of the Python package's call.
    Keyword,
}

impl SettingSource {
    /// "default", "set in model file", "command line".
    pub fn text(self) -> &'static str {
        match self {
            SettingSource::Default => "default",
            SettingSource::ModelFile => "set in model file",
            SettingSource::CommandLine => "command line",
            SettingSource::Keyword => "keyword argument",
        }
    }
}

/// One array of a record given in memory (the Python package's `dampid.Record`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArrayDigest {
    /// The record's label.
    pub record: String,
    /// Which array ("x", "v", "force 1", ...).
    pub name: String,
    /// Its shape: `[N, n]` for motion, `[N]` for a force.
    pub shape: Vec<usize>,
    /// SHA-256 of its float64 values, little-endian, row by row; lowercase hex.
    pub sha256: String,
}

impl ArrayDigest {
    /// The digest of `values` (N × n; `vector`: an N-vector held as one column, shape `[N]`).
    pub fn of(record: &str, name: &str, values: MatRef<'_, f64>, vector: bool) -> ArrayDigest {
        let (rows, cols) = values.shape();
        let mut hasher = Sha256::new();
        let mut row = Vec::with_capacity(8 * cols);
        for i in 0..rows {
            row.clear();
            for j in 0..cols {
                row.extend_from_slice(&values[(i, j)].to_le_bytes());
            }
            hasher.update(&row);
        }
        ArrayDigest {
            record: record.into(),
            name: name.into(),
            shape: if vector { vec![rows] } else { vec![rows, cols] },
            sha256: hex(&hasher.finalize()),
        }
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Everything needed to reproduce a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The model file's path.
    pub model_file: String,
    /// Its text.
    pub model_text: String,
    /// The data files it read, in order (none for simulated records).
    pub data_files: Vec<DataFile>,
    /// Records given as arrays instead of data files (the Python package): every array
    /// with its shape and SHA-256; empty for a model file's records.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub arrays: Vec<ArrayDigest>,
    /// Every setting in effect, defaults included, by model-file section and key.
    pub settings: Vec<Setting>,
    /// dampid's version.
    pub version: String,
    /// The git commit dampid was built from, or "unknown".
    pub commit: String,
    /// When the report was made, "YYYY-MM-DD HH:MM:SS UTC".
    pub date: String,
}

/// The current date and time, "YYYY-MM-DD HH:MM:SS UTC".
pub fn now_utc() -> String {
    let t = time::OffsetDateTime::now_utc();
    format!(
        "{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC",
        t.year(),
        u8::from(t.month()),
        t.day(),
        t.hour(),
        t.minute(),
        t.second()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SHA-256 of "abc" (FIPS 180-2, appendix B.1) and of the empty file.
    #[test]
    fn checksums_of_known_contents() {
        let dir = std::env::temp_dir().join(format!("dampid-sha-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let abc = dir.join("abc.txt");
        std::fs::write(&abc, "abc").unwrap();
        let file = DataFile::read(&abc).unwrap();
        assert_eq!(file.bytes, 3);
        assert_eq!(
            file.sha256,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        let empty = dir.join("empty.txt");
        std::fs::write(&empty, "").unwrap();
        assert_eq!(
            DataFile::read(&empty).unwrap().sha256,
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert!(matches!(
            DataFile::read(&dir.join("missing.csv")),
            Err(Error::Data { .. })
        ));
        std::fs::remove_dir_all(&dir).ok();
    }

    /// The digest reads the values row by row as little-endian float64: [[1, 2], [3, 4]]
    /// hashes as the bytes of 1.0, 2.0, 3.0, 4.0 written out by hand, whatever the
    /// matrix's column-major layout; a column read as a vector has shape [N].
    #[test]
    fn array_digest_is_of_c_order_bytes() {
        let m = faer::mat![[1.0, 2.0], [3.0, 4.0]];
        let mut bytes = Vec::new();
        for v in [1.0f64, 2.0, 3.0, 4.0] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        let expected = hex(&Sha256::digest(&bytes));
        let digest = ArrayDigest::of("r", "x", m.as_ref(), false);
        assert_eq!(digest.sha256, expected);
        assert_eq!(digest.shape, vec![2, 2]);
        // 1.0 is 0x3ff0000000000000: its little-endian bytes end in f0 3f.
        assert_eq!(&bytes[6..8], &[0xf0, 0x3f]);
        let column = ArrayDigest::of("r", "force 1", m.col(0).as_mat(), true);
        assert_eq!(column.shape, vec![2]);
        assert_ne!(column.sha256, expected);
    }

    #[test]
    fn date_reads_as_utc() {
        let date = now_utc();
        assert_eq!(date.len(), "2026-11-26 09:35:04 UTC".len());
        assert!(date.ends_with(" UTC") && date.starts_with("20"));
        assert!(!COMMIT.is_empty() && !VERSION.is_empty());
    }
}
