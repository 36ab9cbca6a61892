//! MATLAB `.mat` files, level 5 (MATLAB v5 to v7, compressed or not; v7.3 is HDF5 and is
//! not read), with the matfile crate. Every real numeric 1-D or 2-D variable can become
//! columns (as for NPY arrays: `x[1]`…`x[k]` for N × k); complex and other variables are
//! kept with the reason they cannot, an error only when a record names them, and
//! skipped by the whole-file read. A file cut short inside a data element is an error,
//! not a table without that variable.

use std::path::Path;

use matfile::{MatFile, NumericData};

use crate::error::{Error, Result};

/// One variable of a MAT file: its name and its values column-major with its
/// dimensions (r, c), or why it cannot be table columns.
pub(crate) struct Variable {
    pub name: String,
    pub values: std::result::Result<(usize, usize, Vec<f64>), String>,
}

fn real_values(data: &NumericData) -> Option<Vec<f64>> {
    macro_rules! convert {
        ($real:expr, $imag:expr) => {
            if $imag.is_some() {
                None
            } else {
                Some($real.iter().map(|&v| v as f64).collect())
            }
        };
    }
    match data {
        NumericData::Double { real, imag } => convert!(real, imag),
        NumericData::Single { real, imag } => convert!(real, imag),
        NumericData::Int8 { real, imag } => convert!(real, imag),
        NumericData::UInt8 { real, imag } => convert!(real, imag),
        NumericData::Int16 { real, imag } => convert!(real, imag),
        NumericData::UInt16 { real, imag } => convert!(real, imag),
        NumericData::Int32 { real, imag } => convert!(real, imag),
        NumericData::UInt32 { real, imag } => convert!(real, imag),
        NumericData::Int64 { real, imag } => convert!(real, imag),
        NumericData::UInt64 { real, imag } => convert!(real, imag),
    }
}

/// The file holds whole data elements: matfile 0.5 stops quietly at a data element cut
/// short (a file copied or written incompletely), so that variable would vanish from the
/// table. Each element is an 8-byte tag (type, byte count; a small element packs both
/// and its data into 8 bytes) followed by its data, padded to 8 bytes unless compressed.
/// Returns the number of data elements (variables) the file holds.
fn complete(bytes: &[u8]) -> std::result::Result<usize, String> {
    const HEADER: usize = 128;
    const COMPRESSED: u32 = 15;
    let length = bytes.len();
    let v4 = "a MAT v4 file (MATLAB's save -v4: no 128-byte text header, which level-5 files start with) is not read; save the variables with -v7 or -v6";
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
    if bytes[..116].windows(10).any(|w| w == b"MATLAB 7.3") {
        return Err(
            "a MAT v7.3 file (HDF5) is not read; save the variables with -v7 or -v6".into(),
        );
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

/// The numeric variables of a MAT file, and how many variables of other kinds it holds.
pub(crate) struct MatVariables {
    /// The numeric arrays (matfile's), usable or with the reason they are not.
    pub variables: Vec<Variable>,
    /// Data elements that are not numeric arrays (structs, cells, sparse, char or
    /// logical arrays, function handles), which are not read.
    pub unread: usize,
}

/// Reads the variables of a `.mat` file.
pub(crate) fn variables(path: &Path) -> Result<MatVariables> {
    let file = path.display().to_string();
    let error = |message: String| Error::Data {
        file: file.clone(),
        row: 0,
        column: String::new(),
        message,
    };
    super::require_data_file(path)?;
    let bytes = std::fs::read(path).map_err(|e| error(e.to_string()))?;
    let elements = complete(&bytes).map_err(error)?;
    // matfile 0.5 panics on some malformed files (a data element whose size is within 8
    // of u32::MAX overflows its padding arithmetic; found by the `mat` fuzz target), so
    // a panic in the parser is turned into the same typed error as a parse failure.
    let parsed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        MatFile::parse(bytes.as_slice())
    }))
    .map_err(|_| error("not a level-5 MAT file: the MAT parser failed on it".into()))?;
    let mat =
        parsed.map_err(|e| error(format!("not a level-5 MAT file (v7.3 files are HDF5): {e}")))?;
    let arrays = mat.arrays();
    Ok(MatVariables {
        unread: elements.saturating_sub(arrays.len()),
        variables: arrays
            .iter()
            .map(|a| {
                let size = a.size();
                let values = match (size.as_slice(), real_values(a.data())) {
                    (_, None) => Err("complex values: only real variables are read".to_string()),
                    ([r, c], Some(values)) => Ok((*r, *c, values)),
                    (size, Some(_)) => {
                        Err(format!("size {size:?}: expected one or two dimensions"))
                    }
                };
                Variable {
                    name: a.name().to_string(),
                    values,
                }
            })
            .collect(),
    })
}
