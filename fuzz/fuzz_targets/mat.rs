//! MATLAB level-5 `.mat` files: `dampid::io::read_mat` on arbitrary bytes. Any `Err` is fine; a panic is a bug, and
//! so is a table with columns of different lengths or non-finite values.

#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "file_input.rs"]
mod file_input;

fuzz_target!(
    init: {
        // The MAT parser (src/io/mat/element.rs) must not panic; the default hook
        // prints a panic's message before libfuzzer-sys catches the unwind and aborts.
        let _ = std::panic::take_hook();
    },
    |bytes: &[u8]| {
        let path = file_input::write(bytes, "mat");
        if let Ok(table) = dampid::io::read_mat(&path) {
            file_input::check(&table);
        }
    }
);
