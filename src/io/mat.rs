//! MATLAB `.mat` files: level 5 (MATLAB v5 to v7, compressed or not), parsed by
//! `mat/element.rs`, and v7.3 (HDF5 behind MATLAB's 512-byte header), read by
//! `mat/v73.rs` into the same tree; this file dispatches on the header. Every real numeric 1-D or 2-D array can become
//! columns (as for NPY arrays: `x[1]`…`x[k]` for N × k), at the top level or inside
//! structs and struct arrays nested to any depth, named by its MATLAB path:
//! `s.a`, `FRdata.ResponseControl(3).amplitude` (1-based linear indices as MATLAB writes
//! them; a 1 × 1 struct has none). Complex, N-D, logical, cell, sparse and object
//! variables are kept with the reason they cannot be columns (an error only when a record
//! names them, skipped by the whole-file read); char arrays are kept as text (units,
//! descriptions) for messages and `dampid init`. A file cut short inside a data element
//! is an error, not a table without that variable.

use std::path::Path;

mod element;
mod sweeps;
mod v73;

pub(crate) use sweeps::sweep_table;

use crate::error::{Error, Result};
use element::Value;

/// One variable of a MAT file: its name and its values column-major with its
/// dimensions (r, c), or why it cannot be table columns.
pub(crate) struct Variable {
    pub name: String,
    pub values: std::result::Result<(usize, usize, Vec<f64>), String>,
}

/// The file holds whole data elements (a file copied or written incompletely would
/// otherwise lose its last variable; checked first for this message). Each element is an 8-byte tag (type, byte count; a small element packs both
/// and its data into 8 bytes) followed by its data, padded to 8 bytes unless compressed.
/// Returns the number of data elements (variables) the file holds.
fn complete(bytes: &[u8]) -> std::result::Result<usize, String> {
    const HEADER: usize = 128;
    const COMPRESSED: u32 = 15;
    let length = bytes.len();
    let v4 = "a MAT v4 file (MATLAB's save -v4: no 128-byte text header, which level-5 files start with) is not read; save the variables with -v7 or -v6";
    if bytes.starts_with(b"\x89HDF\r\n\x1a\n") {
        return Err("an HDF5 file without MATLAB's 512-byte v7.3 header (written by another program, its dimensions' order is unknown); save it from MATLAB with -v7.3, -v7 or -v6".into());
    }
    if length < HEADER {
        return Err(format!(
            "not a level-5 MAT file: {length} bytes, shorter than the {HEADER}-byte header; {v4}"
        ));
    }
    let mark = &bytes[126..128];
    if mark != b"IM" && mark != b"MI" {
        return Err(format!(
            "not a level-5 MAT file: bytes 127–128 are not the endianness mark 'IM' or 'MI'; {v4}"
        ));
    }
    let little = mark == b"IM";
    let word = |at: usize| {
        let quad = [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]];
        if little {
            u32::from_le_bytes(quad)
        } else {
            u32::from_be_bytes(quad)
        }
    };
    let (mut offset, mut element) = (HEADER, 1);
    while offset < length {
        if length - offset < 8 {
            return Err(format!(
                "the MAT file is truncated: it ends inside the tag of data element {element} (variable {element}), at byte {length}"
            ));
        }
        let tag = word(offset);
        let next = if tag >> 16 != 0 {
            offset + 8
        } else {
            let size = word(offset + 4) as usize;
            let padded = if tag == COMPRESSED {
                size
            } else {
                size.div_ceil(8) * 8
            };
            // An unpadded last element is accepted: some writers omit its padding.
            let end = offset.saturating_add(8).saturating_add(size);
            if end > length {
                return Err(format!(
                    "the MAT file is truncated: data element {element} (variable {element}) needs {} bytes from byte {offset}, the file has {}; the variable would be lost",
                    8 + size,
                    length - offset
                ));
            }
            offset
                .saturating_add(8)
                .saturating_add(padded)
                .min(length.max(end))
        };
        offset = next;
        element += 1;
    }
    Ok(element - 1)
}

/// What a MAT file holds, for messages and `dampid init`: one line per variable,
/// struct and leaf field, by path.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// `FRdata.ResponseControl(3).amplitude`.
    pub path: String,
    /// `41×1 double`, `1×8 struct`, `1×4 char`.
    pub description: String,
    /// The text of a char array.
    pub text: Option<String>,
    /// Whether it can be table columns (a real numeric 1-D or 2-D array).
    pub columns: bool,
}

/// The variables of a MAT file by path, and what it holds.
pub(crate) struct MatVariables {
    /// The numeric leaves, usable or with the reason they are not.
    pub variables: Vec<Variable>,
    /// Everything, in file order (module doc).
    pub contents: Vec<Entry>,
}

/// What the MAT reader reads, for messages that say what a file holds instead.
pub(crate) const SUPPORTED: &str = "read are real numeric 1-D or 2-D arrays (double, single, integer), at the top level or in structs and struct arrays, named by path (s.a, s(2).b); not read are cell, sparse, logical, complex and N-D arrays, objects and function handles; level-5 (-v6, -v7) and v7.3 (HDF5) files are read";

/// A one-line list of what a file holds: `a (41×1 double), s (1×8 struct), …`.
pub(crate) fn holds(contents: &[Entry]) -> String {
    const SHOWN: usize = 12;
    let mut list: Vec<String> = contents
        .iter()
        .take(SHOWN)
        .map(|e| format!("{} ({})", e.path, e.description))
        .collect();
    if contents.len() > SHOWN {
        list.push(format!("{} more", contents.len() - SHOWN));
    }
    if list.is_empty() {
        "no variables".into()
    } else {
        list.join(", ")
    }
}

/// The path of element `e` (0-based) of a struct array of `count` elements at `path`.
pub(crate) fn element_path(path: &str, e: usize, count: usize) -> String {
    if count == 1 {
        path.to_string()
    } else {
        format!("{path}({})", e + 1)
    }
}

/// Flattens `value` at `path` into leaves and entries (module doc).
fn flatten(path: String, value: Value, variables: &mut Vec<Variable>, contents: &mut Vec<Entry>) {
    let description = value.describe();
    let entry = |text: Option<String>, columns: bool| Entry {
        path: path.clone(),
        description: description.clone(),
        text,
        columns,
    };
    match value {
        Value::Struct {
            fields, elements, ..
        } => {
            contents.push(entry(None, false));
            let count = elements.len();
            for (e, element) in elements.into_iter().enumerate() {
                let at = element_path(&path, e, count);
                for (field, value) in fields.iter().zip(element) {
                    flatten(format!("{at}.{field}"), value, variables, contents);
                }
            }
        }
        Value::Char { text, .. } => contents.push(entry(Some(text), false)),
        Value::Numeric { dims, values, .. } => {
            let usable = dims.len() == 2;
            contents.push(entry(None, usable));
            variables.push(Variable {
                name: path.clone(),
                values: match dims.as_slice() {
                    [r, c] => Ok((*r, *c, values)),
                    size => Err(format!("size {size:?}: expected one or two dimensions")),
                },
            });
        }
        Value::Complex { .. } => {
            contents.push(entry(None, false));
            variables.push(Variable {
                name: path.clone(),
                values: Err("complex values: only real variables are read".to_string()),
            });
        }
        Value::Other { class, .. } => {
            contents.push(entry(None, false));
            variables.push(Variable {
                name: path.clone(),
                values: Err(format!(
                    "a {class} array ({description}), not read: only real numeric 1-D or 2-D arrays are"
                )),
            });
        }
    }
}

/// The variables of the MAT file at `path`, parsed: a v7.3 file (its header says so)
/// by [`v73::parse`], a level-5 file checked whole ([`complete`]) by [`element::parse`].
pub(crate) fn parsed(path: &Path) -> Result<Vec<element::Variable>> {
    let file = path.display().to_string();
    let error = |message: String| Error::Data {
        file: file.clone(),
        row: 0,
        column: String::new(),
        message,
    };
    super::require_data_file(path)?;
    let bytes = std::fs::read(path).map_err(|e| error(e.to_string()))?;
    if v73::is_v73(&bytes) {
        return v73::parse(bytes)
            .map_err(|e| error(format!("not a readable MAT v7.3 (HDF5) file: {e}")));
    }
    complete(&bytes).map_err(error)?;
    element::parse(&bytes).map_err(|e| error(format!("not a readable level-5 MAT file: {e}")))
}

/// Reads the variables of a `.mat` file, flattened by path.
pub(crate) fn variables(path: &Path) -> Result<MatVariables> {
    let mut variables = Vec::new();
    let mut contents = Vec::new();
    // A top-level array without a name is MATLAB's subsystem data (the storage of
    // objects such as strings and tables), not a variable.
    for v in parsed(path)?.into_iter().filter(|v| !v.name.is_empty()) {
        flatten(v.name, v.value, &mut variables, &mut contents);
    }
    Ok(MatVariables {
        variables,
        contents,
    })
}

/// What the MAT file at `path` holds (every variable, struct and field by path), for
/// `dampid init`.
pub fn contents(path: &Path) -> Result<Vec<Entry>> {
    variables(path).map(|v| v.contents)
}
