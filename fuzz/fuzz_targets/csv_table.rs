//! CSV tables: `Table::parse` on arbitrary text, then every column by name. Any `Err`
//! is fine; a panic is a bug, and so is a table that breaks its own invariants.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let Ok(table) = dampid::io::csv::parse(text, "fuzz.csv") else {
        return;
    };
    assert_eq!(table.headers.len(), table.columns.len());
    let rows = table.rows();
    assert!(rows > 0);
    for header in &table.headers {
        let column = table.column(header).expect("a header names a column");
        assert_eq!(column.len(), rows);
        assert!(column.iter().all(|v| v.is_finite()));
    }
    let _ = table.column("\u{0}no such column");
});
