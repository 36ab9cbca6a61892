//! UFF dataset 58 files (ASCII and binary 58b): `dampid::io::uff::read` on arbitrary
//! bytes. Any `Err` is fine; a panic is a bug, and so is a table with columns of
//! different lengths or non-finite values.

#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "file_input.rs"]
mod file_input;

fuzz_target!(|bytes: &[u8]| {
    let path = file_input::write(bytes, "uff");
    if let Ok(table) = dampid::io::uff::read(&path) {
        file_input::check(&table);
    }
});
