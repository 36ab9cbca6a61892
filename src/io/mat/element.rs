//! The data elements of a level-5 MAT file (MATLAB v5 to v7; MathWorks' "MAT-File
//! Format", chapter 1) as a tree of [`Value`]s: numeric and char arrays, and structs and
//! struct arrays nested to any depth; cells, sparse arrays, objects and function handles
//! are kept by class and size only (skipped by their byte count, never parsed).
//!
//! Written here rather than taken from a crate: matfile 0.5 reads numeric arrays only
//! (structs were silently absent) and panicked on sizes near `u32::MAX`; matrw 0.1
//! (young, binrw-based) allocates from untrusted counts. This parser reads every size
//! checked (`checked_*`, counts bounded by the bytes that are there), decompresses
//! `miCOMPRESSED` elements (zlib, flate2) within the memory budget, and limits nesting.
//!
//! Layout: a 128-byte header (text, subsystem offset, version, endianness mark `IM`
//! little / `MI` big endian), then data elements, each an 8-byte tag (type, byte count)
//! and its data padded to 8 bytes, or a small element (count < 5 bytes) packed as
//! (count << 16 | type) and 4 data bytes. A variable is an `miMATRIX` element (14),
//! possibly inside an `miCOMPRESSED` one (15), holding sub-elements: array flags
//! (`miUINT32` ×2: class in the low byte, complex 0x800, logical 0x200), dimensions
//! (`miINT32`), name (`miINT8`), then by class: the real and imaginary parts (numeric),
//! the characters (char), or for a struct the field-name length (`miINT32`), the names
//! (`miINT8`, fixed width, NUL padded) and one `miMATRIX` per field per element, the
//! elements in column-major order.

use std::io::Read;

/// Nesting deeper than this is refused (a struct in a struct … 64 levels down is no
/// measurement file; a crafted file could otherwise exhaust the stack).
const MAX_DEPTH: usize = 64;

/// The memory one parsed value takes at most beside its data (the enum, its dimensions
/// and field list), for the budget check of files of many small values.
const NODE_BYTES: u128 = 256;

/// What a MAT variable (or a struct field's value) holds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    /// A real numeric array, column-major, with its class name (`double`, `int16`).
    Numeric {
        class: &'static str,
        dims: Vec<usize>,
        values: Vec<f64>,
    },
    /// A numeric array with an imaginary part.
    Complex {
        class: &'static str,
        dims: Vec<usize>,
    },
    /// A char array, as text (rows joined by newlines when it has several).
    Char { dims: Vec<usize>, text: String },
    /// A struct or struct array: field names, and per element (column-major) one value
    /// per field.
    Struct {
        dims: Vec<usize>,
        fields: Vec<String>,
        elements: Vec<Vec<Value>>,
    },
    /// Anything else (cell, sparse, object, logical, function handle), by class.
    Other { class: String, dims: Vec<usize> },
}

impl Value {
    /// The dimensions.
    pub fn dims(&self) -> &[usize] {
        match self {
            Value::Numeric { dims, .. }
            | Value::Complex { dims, .. }
            | Value::Char { dims, .. }
            | Value::Struct { dims, .. }
            | Value::Other { dims, .. } => dims,
        }
    }

    /// The MATLAB class name.
    pub fn class(&self) -> &str {
        match self {
            Value::Numeric { class, .. } => class,
            Value::Complex { class, .. } => class,
            Value::Char { .. } => "char",
            Value::Struct { .. } => "struct",
            Value::Other { class, .. } => class,
        }
    }

    /// `2×41 double`, `1×1 struct`, `complex 3×1 double`.
    pub fn describe(&self) -> String {
        let size = self
            .dims()
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join("×");
        match self {
            Value::Complex { class, .. } => format!("{size} complex {class}"),
            _ => format!("{size} {}", self.class()),
        }
    }
}

/// One variable: its name and value.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Variable {
    pub name: String,
    pub value: Value,
}

/// Reads `u32`/`i32` words in the file's byte order.
#[derive(Clone, Copy)]
struct Order {
    little: bool,
}

impl Order {
    fn u32(self, b: &[u8]) -> u32 {
        let q = [b[0], b[1], b[2], b[3]];
        if self.little {
            u32::from_le_bytes(q)
        } else {
            u32::from_be_bytes(q)
        }
    }
}

/// One data element: its type and its data bytes.
struct Element<'a> {
    kind: u32,
    data: &'a [u8],
}

/// The next sub-element of an array, which must be there (`what` it is).
fn take<'a>(order: Order, rest: &mut &'a [u8], what: &str) -> Result<Element<'a>, String> {
    next(order, rest)?.ok_or_else(|| format!("an array ends before its {what}"))
}

/// Splits the next data element off `bytes` (its tag and padded data); `Ok(None)` at the
/// end. Every element but an miCOMPRESSED one is padded to 8 bytes (an unpadded last
/// element is accepted).
fn next<'a>(order: Order, bytes: &mut &'a [u8]) -> Result<Option<Element<'a>>, String> {
    if bytes.is_empty() {
        return Ok(None);
    }
    if bytes.len() < 8 {
        return Err(format!(
            "truncated: {} bytes left, less than a data element's 8-byte tag",
            bytes.len()
        ));
    }
    let word = order.u32(&bytes[..4]);
    if word >> 16 != 0 {
        // Small element: count in the upper half, type in the lower, data in 4 bytes.
        let count = (word >> 16) as usize;
        if count > 4 {
            return Err(format!(
                "a small data element claims {count} bytes (at most 4)"
            ));
        }
        let element = Element {
            kind: word & 0xFFFF,
            data: &bytes[4..4 + count],
        };
        *bytes = &bytes[8..];
        return Ok(Some(element));
    }
    let size = order.u32(&bytes[4..8]) as usize;
    let rest = &bytes[8..];
    if size > rest.len() {
        return Err(format!(
            "truncated: a data element needs {size} bytes, {} are left",
            rest.len()
        ));
    }
    let padded = if word == COMPRESSED {
        size
    } else {
        size.div_ceil(8).saturating_mul(8).min(rest.len())
    };
    let element = Element {
        kind: word,
        data: &rest[..size],
    };
    *bytes = &rest[padded..];
    Ok(Some(element))
}

const MATRIX: u32 = 14;
const COMPRESSED: u32 = 15;

/// The bytes each value of a numeric data type takes, and its name.
fn numeric_type(kind: u32) -> Option<usize> {
    Some(match kind {
        1 | 2 => 1,       // miINT8, miUINT8
        3 | 4 => 2,       // miINT16, miUINT16
        5..=7 => 4,       // miINT32, miUINT32, miSINGLE
        9 | 12 | 13 => 8, // miDOUBLE, miINT64, miUINT64
        _ => return None,
    })
}

/// The values of a numeric data element as f64.
fn numbers(order: Order, element: &Element) -> Result<Vec<f64>, String> {
    let width = numeric_type(element.kind)
        .ok_or_else(|| format!("data of type {} where numbers were expected", element.kind))?;
    let data = element.data;
    if !data.len().is_multiple_of(width) {
        return Err(format!("{} bytes of {width}-byte numbers", data.len()));
    }
    crate::budget::require(
        "reading a MAT variable",
        crate::budget::f64s((data.len() / width) as u128),
        "read a smaller file, or raise --max-memory",
    )
    .map_err(|e| e.to_string())?;
    let word = |c: &[u8]| -> [u8; 8] {
        let mut b = [0u8; 8];
        if order.little {
            b[..c.len()].copy_from_slice(c);
        } else {
            b[8 - c.len()..].copy_from_slice(c);
        }
        b
    };
    let read = |c: &[u8]| -> f64 {
        let b = word(c);
        let (lo4, lo2) = if order.little {
            ([b[0], b[1], b[2], b[3]], [b[0], b[1]])
        } else {
            ([b[4], b[5], b[6], b[7]], [b[6], b[7]])
        };
        let u64v = if order.little {
            u64::from_le_bytes(b)
        } else {
            u64::from_be_bytes(b)
        };
        let u32v = if order.little {
            u32::from_le_bytes(lo4)
        } else {
            u32::from_be_bytes(lo4)
        };
        let u16v = if order.little {
            u16::from_le_bytes(lo2)
        } else {
            u16::from_be_bytes(lo2)
        };
        match element.kind {
            1 => c[0] as i8 as f64,
            2 => c[0] as f64,
            3 => u16v as i16 as f64,
            4 => u16v as f64,
            5 => u32v as i32 as f64,
            6 => u32v as f64,
            7 => f32::from_bits(u32v) as f64,
            9 => f64::from_bits(u64v),
            12 => u64v as i64 as f64,
            _ => u64v as f64,
        }
    };
    Ok(data.chunks_exact(width).map(read).collect())
}

/// The class name of an mxCLASS number.
fn class_name(class: u32) -> &'static str {
    match class {
        1 => "cell",
        2 => "struct",
        3 => "object",
        4 => "char",
        5 => "sparse",
        6 => "double",
        7 => "single",
        8 => "int8",
        9 => "uint8",
        10 => "int16",
        11 => "uint16",
        12 => "int32",
        13 => "uint32",
        14 => "int64",
        15 => "uint64",
        16 => "function handle",
        17 => "opaque (MATLAB object: string, table, datetime …)",
        _ => "unknown class",
    }
}

/// Parses a level-5 MAT file's variables (module doc).
pub(crate) fn parse(bytes: &[u8]) -> Result<Vec<Variable>, String> {
    const HEADER: usize = 128;
    if bytes.len() < HEADER {
        return Err(format!(
            "{} bytes, shorter than the 128-byte header",
            bytes.len()
        ));
    }
    let order = match &bytes[126..128] {
        b"IM" => Order { little: true },
        b"MI" => Order { little: false },
        _ => return Err("no endianness mark 'IM' or 'MI' at bytes 127–128".into()),
    };
    let mut rest = &bytes[HEADER..];
    let mut variables = Vec::new();
    let mut index = 0;
    let mut nodes = 0;
    while let Some(element) =
        next(order, &mut rest).map_err(|e| format!("variable {}: {e}", index + 1))?
    {
        index += 1;
        let at = |e: String| format!("variable {index}: {e}");
        match element.kind {
            MATRIX => variables.push(matrix(order, element.data, 0, &mut nodes).map_err(at)?),
            COMPRESSED => {
                let inflated = inflate(element.data).map_err(at)?;
                let mut inner: &[u8] = &inflated;
                // One miMATRIX per compressed element (MATLAB's and SciPy's writers).
                while let Some(e) = next(order, &mut inner).map_err(at)? {
                    if e.kind == MATRIX {
                        variables.push(matrix(order, e.data, 0, &mut nodes).map_err(at)?);
                    }
                }
            }
            // Other top-level elements (none are written by MATLAB) are skipped.
            _ => {}
        }
    }
    Ok(variables)
}

/// Inflates a zlib stream within the memory budget.
fn inflate(data: &[u8]) -> Result<Vec<u8>, String> {
    let limit = crate::budget::limit().unwrap_or(u64::MAX);
    let mut out = Vec::new();
    flate2::read::ZlibDecoder::new(data)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| format!("a compressed element does not inflate: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "a compressed element inflates to more than the memory limit ({limit} bytes); raise --max-memory"
        ));
    }
    Ok(out)
}

/// Parses the body of an miMATRIX element, `depth` levels down.
fn matrix(order: Order, body: &[u8], depth: usize, nodes: &mut usize) -> Result<Variable, String> {
    // Each value (a struct field's, however empty) is held in memory: a file of many
    // empty fields holds more than its bytes, so their number is checked too.
    *nodes += 1;
    if nodes.is_multiple_of(4096) {
        crate::budget::require(
            "the variables and struct fields of a MAT file",
            (*nodes as u128).saturating_mul(NODE_BYTES),
            "read a smaller file, or raise --max-memory",
        )
        .map_err(|e| e.to_string())?;
    }
    if depth > MAX_DEPTH {
        return Err(format!("structs nested deeper than {MAX_DEPTH} levels"));
    }
    if body.is_empty() {
        // MATLAB writes an empty field value ([]) as an miMATRIX of no bytes.
        return Ok(Variable {
            name: String::new(),
            value: Value::Numeric {
                class: "double",
                dims: vec![0, 0],
                values: Vec::new(),
            },
        });
    }
    let mut rest = body;
    let mut sub = |what: &str| take(order, &mut rest, what);
    let flags = sub("array flags")?;
    if flags.data.len() < 8 {
        return Err("array flags shorter than 8 bytes".into());
    }
    let word = order.u32(&flags.data[..4]);
    let class = word & 0xFF;
    let complex = word & 0x0800 != 0;
    let logical = word & 0x0200 != 0;
    let dims_element = sub("dimensions")?;
    if dims_element.kind != 5 || !dims_element.data.len().is_multiple_of(4) {
        return Err("dimensions are not 32-bit integers".into());
    }
    let dims = dims_element
        .data
        .chunks_exact(4)
        .map(|c| {
            let d = order.u32(c) as i32;
            usize::try_from(d).map_err(|_| format!("negative dimension {d}"))
        })
        .collect::<Result<Vec<usize>, String>>()?;
    let count = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| format!("dimensions {dims:?} overflow"))?;
    let name_element = sub("name")?;
    let name = String::from_utf8_lossy(name_element.data).into_owned();
    let other = |class: &str| Value::Other {
        class: class.to_string(),
        dims: dims.clone(),
    };
    let value = match class {
        6..=15 if logical => other("logical"),
        6..=15 if complex => Value::Complex {
            class: class_name(class),
            dims: dims.clone(),
        },
        6..=15 => {
            let real = sub("real part")?;
            let values = numbers(order, &real)?;
            if values.len() != count {
                return Err(format!(
                    "'{name}': {} values for dimensions {dims:?}",
                    values.len()
                ));
            }
            Value::Numeric {
                class: class_name(class),
                dims: dims.clone(),
                values,
            }
        }
        4 => {
            let data = sub("characters")?;
            let units: Vec<u32> = match data.kind {
                16 | 1 | 2 => data.data.iter().map(|&b| u32::from(b)).collect(),
                17 | 3 | 4 => data
                    .data
                    .chunks_exact(2)
                    .map(|c| {
                        u32::from(if order.little {
                            u16::from_le_bytes([c[0], c[1]])
                        } else {
                            u16::from_be_bytes([c[0], c[1]])
                        })
                    })
                    .collect(),
                _ => Vec::new(),
            };
            let text = if data.kind == 16 {
                String::from_utf8_lossy(data.data).into_owned()
            } else {
                // Column-major rows of characters: row i is units[i], units[i + r], …
                let r = dims.first().copied().unwrap_or(1).max(1);
                let c = units.len() / r;
                (0..r)
                    .map(|i| {
                        (0..c)
                            .filter_map(|j| char::from_u32(units[i + j * r]))
                            .collect::<String>()
                    })
                    .collect::<Vec<_>>()
                    .join("\n")
            };
            Value::Char {
                dims: dims.clone(),
                text,
            }
        }
        2 => {
            let length = sub("field-name length")?;
            let width = if length.data.len() >= 4 {
                order.u32(&length.data[..4]) as usize
            } else {
                0
            };
            let names = sub("field names")?;
            if width == 0 || !names.data.len().is_multiple_of(width) {
                return Err(format!(
                    "'{name}': {} bytes of field names {width} wide",
                    names.data.len()
                ));
            }
            let fields: Vec<String> = names
                .data
                .chunks_exact(width)
                .map(|c| {
                    let end = c.iter().position(|&b| b == 0).unwrap_or(c.len());
                    String::from_utf8_lossy(&c[..end]).into_owned()
                })
                .collect();
            let mut elements = Vec::new();
            // No fields: no data to bound the count by, and nothing to read.
            let count = if fields.is_empty() { 0 } else { count };
            for e in 0..count {
                let mut element = Vec::with_capacity(fields.len());
                for field in &fields {
                    let value = match next(order, &mut rest)? {
                        Some(m) if m.kind == MATRIX => {
                            matrix(order, m.data, depth + 1, nodes)
                                .map_err(|x| format!("'{name}'({}).", e + 1) + field + ": " + &x)?
                                .value
                        }
                        _ => {
                            return Err(format!(
                                "'{name}': element {} has no value for field '{field}'",
                                e + 1
                            ));
                        }
                    };
                    element.push(value);
                }
                elements.push(element);
            }
            Value::Struct {
                dims: dims.clone(),
                fields,
                elements,
            }
        }
        _ => other(class_name(class)),
    };
    Ok(Variable { name, value })
}
