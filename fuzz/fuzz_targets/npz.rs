//! NumPy `.npz` archives: `dampid::io::read_npz` on arbitrary bytes. Any `Err` is fine; a panic is a bug, and
//! so is a table with columns of different lengths or non-finite values.

#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "file_input.rs"]
mod file_input;

fuzz_target!(
    init: {
        // The NPY header parser (npyz) multiplies a shape's dimensions unchecked, a panic
        // under the fuzz build's overflow checks that io::npy turns into a typed error
        // (catch_unwind); libfuzzer-sys's panic hook would abort before the unwind
        // reaches it. The default hook lets a caught panic pass; one that escapes still
        // ends the run (as in the `mat` target).
        let _ = std::panic::take_hook();
    },
    |bytes: &[u8]| {
        let path = file_input::write(bytes, "npz");
        if let Ok(table) = dampid::io::read_npz(&path) {
            file_input::check(&table);
        }
    }
);
