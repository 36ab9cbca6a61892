//! NumPy `.npy` files (one array, named after the file stem): a header, a Python dict
//! literal with the dtype, the order and the shape (parsed by npyz), then the raw
//! elements. The elements are read in one pass, in blocks of about 1 MiB straight from
//! the file (no per-element reader), converted to f64 (f8, f4, i8, i4, little or big
//! endian) and appended to their columns in file order; C and Fortran order and the
//! orientation rule are `Layout`'s (io/arrays.rs). The bytes the header's shape needs are checked
//! against the bytes the file holds after it before anything of that size is
//! allocated, so a header that claims more data than there is is an error, never a read
//! past the end or an allocation of the claimed size. `.npz` archives: `io/npz.rs`.

use std::io::{BufReader, Read, Seek};
use std::path::Path;

use npyz::{DType, Endianness, NpyHeader, Order, TypeChar};

use crate::error::{Error, Result};
use crate::io::arrays::{Layout, NamedArray, table_from_arrays};
use crate::io::table::Table;

/// Elements converted per block (8 MiB of f64 at most per block of values).
const BLOCK: usize = 1 << 17;

pub(crate) fn data_error(file: &str, column: &str, message: impl std::fmt::Display) -> Error {
    Error::Data {
        file: file.to_string(),
        row: 0,
        column: column.to_string(),
        message: message.to_string(),
    }
}

/// A stored element type read as f64.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    F64,
    F32,
    I64,
    I32,
}

/// What an NPY header says about an array that can be table columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Header {
    pub layout: Layout,
    kind: Kind,
    big_endian: bool,
    /// The dtype as written (`<f8`), for messages.
    dtype: String,
}

impl Header {
    pub(crate) fn element_size(&self) -> usize {
        match self.kind {
            Kind::F64 | Kind::I64 => 8,
            Kind::F32 | Kind::I32 => 4,
        }
    }

    /// The bytes of data the header's shape needs (`None`: more than a `u64` holds).
    pub fn data_bytes(&self) -> Option<u64> {
        (self.layout.elements() as u64).checked_mul(self.element_size() as u64)
    }
}

/// Reads an NPY header from `reader`, leaving it at the first data byte. `Err` is what
/// makes the array unusable as columns (a malformed header, a shape of other than one
/// or two dimensions, a dtype that is not f8, f4, i8 or i4), in words.
pub(crate) fn read_header<R: Read>(reader: R) -> std::result::Result<Header, String> {
    // npyz multiplies the shape's dimensions unchecked: with overflow checks on (tests,
    // fuzzing) a huge shape panics inside it, which is the same bad header.
    let parsed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        NpyHeader::from_reader(reader)
    }))
    .map_err(|_| "the NPY header's shape overflows".to_string())?;
    let header = parsed.map_err(|e| format!("not an NPY array: {e}"))?;
    let DType::Plain(type_str) = header.dtype() else {
        return Err("structured arrays are not supported".into());
    };
    let kind = match (type_str.type_char(), type_str.size_field()) {
        (TypeChar::Float, 8) => Kind::F64,
        (TypeChar::Float, 4) => Kind::F32,
        (TypeChar::Int, 8) => Kind::I64,
        (TypeChar::Int, 4) => Kind::I32,
        _ => {
            return Err(format!(
                "dtype {type_str} is not a supported real type (f8, f4, i8, i4)"
            ));
        }
    };
    let shape = header.shape();
    let dims: Option<Vec<usize>> = shape.iter().map(|&d| usize::try_from(d).ok()).collect();
    let (rows, cols) = match dims.as_deref() {
        Some([n]) => (*n, 1),
        Some([r, c]) => (*r, *c),
        _ => {
            return Err(format!("shape {shape:?}: expected one or two dimensions"));
        }
    };
    let layout = Layout::new(rows, cols, header.order() == Order::C)
        .ok_or_else(|| format!("shape {shape:?} overflows"))?;
    Ok(Header {
        layout,
        kind,
        big_endian: type_str.endianness() == Endianness::Big,
        dtype: type_str.to_string(),
    })
}

/// Converts whole elements of `bytes` into `values` (as many as `values` holds).
fn convert(header: &Header, bytes: &[u8], values: &mut [f64]) {
    macro_rules! each {
        ($t:ty, $n:literal) => {{
            let chunks = bytes.chunks_exact($n);
            if header.big_endian {
                for (v, b) in values.iter_mut().zip(chunks) {
                    // cannot fail: chunks_exact($n) yields slices of exactly $n bytes
                    *v = <$t>::from_be_bytes(b.try_into().expect("chunk of the size")) as f64;
                }
            } else {
                for (v, b) in values.iter_mut().zip(chunks) {
                    // cannot fail: chunks_exact($n) yields slices of exactly $n bytes
                    *v = <$t>::from_le_bytes(b.try_into().expect("chunk of the size")) as f64;
                }
            }
        }};
    }
    match header.kind {
        Kind::F64 => each!(f64, 8),
        Kind::F32 => each!(f32, 4),
        Kind::I64 => each!(i64, 8),
        Kind::I32 => each!(i32, 4),
    }
}

/// Reads the data of the array `name` described by `header` from `reader`, which holds
/// `available` bytes after the header: one pass, block by block (module doc).
pub(crate) fn read_data<R: Read>(
    reader: &mut R,
    header: &Header,
    available: u64,
    name: &str,
    file: &str,
) -> Result<NamedArray> {
    require_data(header, available, name, file)?;
    let layout = header.layout;
    let mut columns = layout.allocate();
    read_values(reader, header, BLOCK, name, file, |done, values| {
        layout.place(done, values, &mut columns)
    })?;
    Ok(NamedArray {
        name: name.to_string(),
        columns,
    })
}

/// Checks, before anything of the header's size is allocated, that the `available`
/// bytes after the header hold the data it claims, and that the data as f64 fit the
/// memory budget.
pub(crate) fn require_data(header: &Header, available: u64, name: &str, file: &str) -> Result<()> {
    let layout = header.layout;
    let needed = header.data_bytes();
    if needed.is_none_or(|n| n > available) {
        return Err(data_error(
            file,
            name,
            format!(
                "the header says {} × {} elements of {} ({} bytes), but the file holds {available} bytes of data: it is truncated or its header is wrong",
                layout.samples,
                layout.columns,
                header.dtype,
                needed.map_or("more than 2^64".to_string(), |n| n.to_string()),
            ),
        ));
    }
    // The columns hold every element as f64, whatever the stored type: checked before
    // they are allocated (a deflated archive member can claim far more than its file).
    crate::budget::require(
        &format!(
            "reading the array '{name}' of {file} ({} × {} values)",
            crate::format::integer(layout.samples as u128),
            crate::format::integer(layout.columns as u128)
        ),
        crate::budget::f64s(layout.elements() as u128),
        "read a file with fewer samples or channels, or raise --max-memory",
    )
}

/// Reads every element of the array described by `header` from `reader` (whose data
/// were checked by [`require_data`]) in blocks of about `block` elements, converted to
/// f64 and checked finite, and hands each block to `place` with the flat index of its
/// first element. A non-finite value is [`Error::Data`] at its sample and column.
pub(crate) fn read_values<R: Read>(
    reader: &mut R,
    header: &Header,
    block: usize,
    name: &str,
    file: &str,
    place: impl FnMut(usize, &[f64]),
) -> Result<()> {
    let all = 0..header.layout.elements();
    read_range(reader, header, block, all, name, file, place)
}

/// [`read_values`] of the flat elements `range` only, `reader` at the first of them:
/// blocks from `range.start` (whole rows when interleaved, if `range.start` is a row's
/// first element), each handed to `place` with its flat index in the whole array, and a
/// non-finite value named at its sample and column in the whole array.
pub(crate) fn read_range<R: Read>(
    reader: &mut R,
    header: &Header,
    block: usize,
    range: std::ops::Range<usize>,
    name: &str,
    file: &str,
    mut place: impl FnMut(usize, &[f64]),
) -> Result<()> {
    let layout = header.layout;
    let size = header.element_size();
    let block = layout.block(block).min(range.len().max(1));
    let mut bytes = vec![0u8; block * size];
    let mut values = vec![0.0; block];
    let mut done = range.start;
    while done < range.end {
        let m = block.min(range.end - done);
        reader
            .read_exact(&mut bytes[..m * size])
            .map_err(|e| data_error(file, name, format!("reading its data: {e}")))?;
        let values = &mut values[..m];
        convert(header, &bytes[..m * size], values);
        if !values.iter().fold(true, |ok, v| ok & v.is_finite()) {
            let at = values.iter().position(|v| !v.is_finite()).unwrap_or(0);
            let (s, p) = layout.position(done + at);
            return Err(Error::Data {
                file: file.to_string(),
                row: s + 1,
                column: layout.headers(name)[p].clone(),
                message: format!("non-finite value {}", values[at]),
            });
        }
        place(done, values);
        done += m;
    }
    Ok(())
}

/// Reads a `.npy` file; its array is named after the file stem.
pub fn read_npy(path: &Path) -> Result<Table> {
    let file = path.display().to_string();
    let name = path
        .file_stem()
        .map_or("x".into(), |s| s.to_string_lossy().into_owned());
    super::require_data_file(path)?;
    let opened = std::fs::File::open(path).map_err(|e| data_error(&file, "", e))?;
    let length = opened
        .metadata()
        .map_err(|e| data_error(&file, "", e))?
        .len();
    let mut reader = BufReader::new(opened);
    let header = read_header(&mut reader).map_err(|e| data_error(&file, &name, e))?;
    let start = reader
        .stream_position()
        .map_err(|e| data_error(&file, "", e))?;
    let array = read_data(
        &mut reader,
        &header,
        length.saturating_sub(start),
        &name,
        &file,
    )?;
    table_from_arrays(&file, vec![array])
}
