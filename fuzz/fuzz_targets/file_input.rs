//! The binary readers take a path, so each input is written to a file first: one file
//! per fuzzing process, overwritten on every execution.

use std::path::PathBuf;

/// Writes `bytes` to `<temp>/dampid-fuzz-<pid>/input.<extension>` and returns the path.
pub fn write(bytes: &[u8], extension: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let path = dir.join(format!("input.{extension}"));
    std::fs::write(&path, bytes).expect("temporary file");
    path
}

/// Checks the invariants every table read from a file must hold.
pub fn check(table: &dampid::io::table::Table) {
    assert_eq!(table.headers.len(), table.columns.len());
    let rows = table.columns.first().map_or(0, Vec::len);
    for (header, column) in table.headers.iter().zip(&table.columns) {
        assert_eq!(column.len(), rows, "column '{header}'");
        assert!(column.iter().all(|v| v.is_finite()), "column '{header}'");
    }
}
