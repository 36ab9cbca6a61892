//! MAT v7.3 files (MATLAB's `save -v7.3`: HDF5) as the same tree of [`Value`]s as the
//! level-5 reader (`element.rs`), so that paths, struct arrays, sweeps, gains and
//! `dampid init` read them alike. HDF5 is read by the `hdf5-reader` crate (pure Rust).
//!
//! Layout (as MATLAB writes it): a 512-byte user block whose first 128 bytes are the
//! level-5 header (text `MATLAB 7.3 MAT-file…`), then HDF5. Each top-level variable is a
//! dataset, or a group for a struct, named by the variable, with a string attribute
//! `MATLAB_class` (`double`, `single`, `int8`…`uint64`, `char`, `logical`, `struct`,
//! `cell`, `function_handle`, an object's class). Dimensions are stored reversed: an
//! r × c array is a dataset of shape (c, r) whose data are MATLAB's column-major order,
//! so the MATLAB dimensions are the shape reversed and the data are read as they lie.
//! `char` is uint16 (UTF-16 code units); `logical` is uint8; complex numbers are a
//! compound (real, imag); an empty array holds its dimensions, marked `MATLAB_empty`.
//! A 1 × 1 struct is a group whose members are its fields (their order in the attribute
//! `MATLAB_fields` when it can be read, else by name); a struct *array* is a group whose
//! fields are datasets of object references, one per element (column-major), to values
//! in the group `#refs#`; a cell is such a dataset with `MATLAB_class = "cell"`. A sparse
//! array is a group with `MATLAB_sparse`. Top-level names starting with `#` (`#refs#`,
//! `#subsystem#`) are MATLAB's storage, not variables, and are skipped; variables are
//! listed by name (HDF5's order).
//!
//! What can be columns is what the level-5 reader reads: real numeric arrays (values as
//! f64) and structs of them; chars are text; complex, logical, cell, sparse, object and
//! function-handle values are kept by class and size. Every read is bounded: references
//! nest at most [`MAX_DEPTH`] levels (a crafted file may point a reference at its own
//! ancestor), one dataset's bytes and the values held count against the memory budget,
//! and any malformation is an `Err` with the variable's path.

use std::collections::HashMap;

use hdf5_reader::group::Group;
use hdf5_reader::{Attribute, Dataset, Datatype, Hdf5File, OpenOptions};

use super::element::{Value, Variable};

/// References nested deeper than this are refused (as the level-5 reader's structs).
const MAX_DEPTH: usize = 64;

/// The memory one value takes beside its data, for the budget check of many small values
/// (as the level-5 reader counts).
const NODE_BYTES: u128 = 256;

/// The most a deflate stream expands (zlib's limit is about 1032:1), which bounds the
/// values a chunked dataset of a file of n bytes can hold (MATLAB writes every chunk).
const MAX_EXPANSION: u64 = 1100;

/// The text a v7.3 file's header starts with.
const SIGNATURE: &[u8] = b"MATLAB 7.3";

/// Whether `bytes` start with a MAT v7.3 header (the level-5 header's text says
/// `MATLAB 7.3`; HDF5 follows at byte 512).
pub(crate) fn is_v73(bytes: &[u8]) -> bool {
    bytes.len() >= 128
        && bytes[..116]
            .windows(SIGNATURE.len())
            .any(|w| w == SIGNATURE)
}

/// An object a reference points to.
enum Object {
    Group(Group),
    Dataset(Box<Dataset>),
}

/// What the walk needs: the objects of `#refs#` by address, the size of an address,
/// and the count of values made (for the budget).
struct Walk {
    refs: HashMap<u64, Object>,
    offset_size: u8,
    nodes: usize,
    /// The file's length in bytes.
    length: u64,
}

/// Parses the variables of a MAT v7.3 file (module doc); `Err` says why it cannot be read.
pub(crate) fn parse(bytes: Vec<u8>) -> Result<Vec<Variable>, String> {
    let length = bytes.len() as u64;
    let mut options = OpenOptions::default();
    if let Some(limit) = crate::budget::limit() {
        options.max_read_bytes = usize::try_from(limit).unwrap_or(usize::MAX);
    }
    let file = Hdf5File::from_vec_with_options(bytes, options)
        .map_err(|e| format!("its HDF5 part does not open: {e}"))?;
    let root = file
        .root_group()
        .map_err(|e| format!("no root group: {e}"))?;
    let (groups, datasets) = root
        .members()
        .map_err(|e| format!("its variables cannot be listed: {e}"))?;
    let mut walk = Walk {
        refs: HashMap::new(),
        offset_size: root.offset_size(),
        nodes: 0,
        length,
    };
    let mut top: Vec<(String, Object)> = Vec::new();
    for g in groups {
        if g.name() == "#refs#" {
            let (gs, ds) = g
                .members()
                .map_err(|e| format!("MATLAB's #refs# group cannot be listed: {e}"))?;
            walk.refs
                .extend(gs.into_iter().map(|g| (g.address(), Object::Group(g))));
            walk.refs.extend(
                ds.into_iter()
                    .map(|d| (d.address(), Object::Dataset(Box::new(d)))),
            );
        } else if !g.name().starts_with('#') {
            top.push((g.name().to_string(), Object::Group(g)));
        }
    }
    for d in datasets {
        if !d.name().starts_with('#') {
            top.push((d.name().to_string(), Object::Dataset(Box::new(d))));
        }
    }
    top.sort_by(|a, b| a.0.cmp(&b.0));
    top.into_iter()
        .map(|(name, object)| {
            let value = walk.value(&object, &name, 0)?;
            Ok(Variable { name, value })
        })
        .collect()
}

/// The string attribute `name` of a list of attributes, if there.
fn text(attributes: &[Attribute], name: &str) -> Option<String> {
    let a = attributes.iter().find(|a| a.name == name)?;
    a.read_string()
        .ok()
        .map(|s| s.trim_end_matches(['\0', ' ']).to_string())
}

/// Whether the attribute `name` is there and not zero (`MATLAB_empty`).
fn flag(attributes: &[Attribute], name: &str) -> bool {
    attributes
        .iter()
        .find(|a| a.name == name)
        .is_some_and(|a| a.read_as_f64().map_or(true, |v| v != 0.0))
}

/// MATLAB's dimensions of a dataset of HDF5 shape `shape`: reversed, at least two.
fn matlab_dims(shape: &[u64]) -> Result<Vec<usize>, String> {
    let mut dims = shape
        .iter()
        .rev()
        .map(|&d| usize::try_from(d).map_err(|_| format!("dimension {d} too large")))
        .collect::<Result<Vec<usize>, String>>()?;
    while dims.len() < 2 {
        dims.push(1);
    }
    Ok(dims)
}

/// The number of elements of `dims`.
fn count(dims: &[usize]) -> Result<usize, String> {
    dims.iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| format!("dimensions {dims:?} overflow"))
}

/// The MATLAB class of a numeric HDF5 type, for datasets without `MATLAB_class`.
fn numeric_class(dtype: &Datatype) -> Option<&'static str> {
    Some(match dtype {
        Datatype::FloatingPoint { size: 8, .. } => "double",
        Datatype::FloatingPoint { size: 4, .. } => "single",
        Datatype::FixedPoint { size, signed, .. } => match (size, signed) {
            (1, true) => "int8",
            (1, false) => "uint8",
            (2, true) => "int16",
            (2, false) => "uint16",
            (4, true) => "int32",
            (4, false) => "uint32",
            (8, true) => "int64",
            (8, false) => "uint64",
            _ => return None,
        },
        _ => return None,
    })
}

/// The `&'static` name of a numeric MATLAB class named in a file.
fn static_class(class: &str) -> Option<&'static str> {
    [
        "double", "single", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
        "uint64",
    ]
    .into_iter()
    .find(|c| *c == class)
}

/// Refuses a dataset whose size cannot be what a file of `length` bytes holds (a damaged
/// dimension would otherwise read as gigabytes of fill values): its dimensions within
/// their stored maxima, and its `n` values of `width` bytes within the file's bytes, or
/// within [`MAX_EXPANSION`] times them when chunked (compressed).
fn plausible(d: &Dataset, n: usize, width: usize, length: u64) -> Result<(), String> {
    if let Some(max) = d.max_dims()
        && let Some((k, (size, most))) = d
            .shape()
            .iter()
            .zip(max)
            .enumerate()
            .find(|(_, (size, most))| size > most)
    {
        return Err(format!(
            "dimension {} is {size}, more than its stored maximum {most}: a damaged file",
            k + 1
        ));
    }
    let bytes = (n as u64).saturating_mul(width as u64);
    let room = if d.chunks().is_some() {
        length.saturating_mul(MAX_EXPANSION)
    } else {
        length
    };
    if bytes > room {
        return Err(format!(
            "{n} values of {width} bytes, more than a file of {length} bytes holds: a damaged file"
        ));
    }
    Ok(())
}

/// The values of a numeric dataset as f64, in the order they lie (MATLAB's column-major),
/// for a file of `length` bytes ([`plausible`]).
fn numbers(d: &Dataset, n: usize, length: u64) -> Result<Vec<f64>, String> {
    let width = d.raw_element_size().map_err(|e| e.to_string())?;
    plausible(d, n, width, length)?;
    crate::budget::require(
        "reading a MAT variable",
        crate::budget::f64s(n as u128),
        "read a smaller file, or raise --max-memory",
    )
    .map_err(|e| e.to_string())?;
    let dtype = d.dtype().clone();
    if let Datatype::FloatingPoint { size: 8, .. } = dtype {
        // The library copies native doubles straight into the buffer.
        let mut values = vec![0.0; n];
        d.read_into::<f64>(&mut values).map_err(|e| e.to_string())?;
        return Ok(values);
    }
    let raw = d.read_native_bytes().map_err(|e| e.to_string())?;
    let (width, read): (usize, fn(&[u8]) -> f64) = match dtype {
        Datatype::FloatingPoint { size: 4, .. } => (4, |b| {
            f64::from(f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
        }),
        Datatype::FixedPoint { size, signed, .. } => match (size, signed) {
            (1, true) => (1, |b| f64::from(b[0] as i8)),
            (1, false) => (1, |b| f64::from(b[0])),
            (2, true) => (2, |b| f64::from(i16::from_ne_bytes([b[0], b[1]]))),
            (2, false) => (2, |b| f64::from(u16::from_ne_bytes([b[0], b[1]]))),
            (4, true) => (4, |b| {
                f64::from(i32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
            }),
            (4, false) => (4, |b| {
                f64::from(u32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
            }),
            (8, true) => (8, |b| {
                i64::from_ne_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) as f64
            }),
            (8, false) => (8, |b| {
                u64::from_ne_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) as f64
            }),
            _ => return Err(format!("{size}-byte integers")),
        },
        other => return Err(format!("numbers of HDF5 type {other:?}")),
    };
    if raw.len() != n * width {
        return Err(format!(
            "{} bytes for {n} values of {width} bytes",
            raw.len()
        ));
    }
    Ok(raw.chunks_exact(width).map(read).collect())
}

/// The text of a char array of MATLAB dimensions `dims` from its UTF-16 code units
/// (column-major; rows joined by newlines, as the level-5 reader does).
fn char_text(units: &[u16], dims: &[usize]) -> String {
    let r = dims.first().copied().unwrap_or(1).max(1);
    let c = units.len() / r;
    (0..r)
        .map(|i| {
            char::decode_utf16((0..c).map(|j| units[i + j * r]))
                .map(|u| u.unwrap_or(char::REPLACEMENT_CHARACTER))
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

impl Walk {
    /// The value of `object` at MATLAB path `path`, `depth` references down.
    fn value(&mut self, object: &Object, path: &str, depth: usize) -> Result<Value, String> {
        self.nodes += 1;
        if self.nodes.is_multiple_of(4096) {
            crate::budget::require(
                "the variables and struct fields of a MAT file",
                (self.nodes as u128).saturating_mul(NODE_BYTES),
                "read a smaller file, or raise --max-memory",
            )
            .map_err(|e| e.to_string())?;
        }
        if depth > MAX_DEPTH {
            return Err(format!(
                "{path}: references nested deeper than {MAX_DEPTH} levels"
            ));
        }
        match object {
            Object::Dataset(d) => Self::dataset(d, self.length),
            Object::Group(g) => self.group(g, path, depth),
        }
        .map_err(|e| {
            if e.starts_with(path) {
                e
            } else {
                format!("{path}: {e}")
            }
        })
    }

    /// A dataset's value (module doc).
    fn dataset(d: &Dataset, length: u64) -> Result<Value, String> {
        let attributes = d.attributes();
        let dtype = d.dtype();
        let class = text(&attributes, "MATLAB_class")
            .or_else(|| numeric_class(dtype).map(str::to_string))
            .unwrap_or_else(|| "unknown class".into());
        let mut dims = matlab_dims(d.shape())?;
        if flag(&attributes, "MATLAB_empty") {
            // The data are the dimensions of the empty array.
            let n = usize::try_from(d.num_elements().map_err(|e| e.to_string())?)
                .map_err(|_| "too many dimensions".to_string())?;
            if n > 64 {
                return Err(format!("an empty array of {n} dimensions"));
            }
            dims = numbers(d, n, length)?
                .into_iter()
                .map(|v| v as usize)
                .collect();
            if count(&dims)? != 0 {
                dims = vec![0, 0];
            }
            return Ok(match (class.as_str(), static_class(&class)) {
                ("char", _) => Value::Char {
                    dims,
                    text: String::new(),
                },
                ("struct", _) => Value::Struct {
                    dims,
                    fields: Vec::new(),
                    elements: Vec::new(),
                },
                (_, Some(class)) => Value::Numeric {
                    class,
                    dims,
                    values: Vec::new(),
                },
                (class, None) => Value::Other {
                    class: class.to_string(),
                    dims,
                },
            });
        }
        let n = count(&dims)?;
        if class == "char" {
            let values = numbers(d, n, length)?;
            let units: Vec<u16> = values.iter().map(|&v| v as u16).collect();
            return Ok(Value::Char {
                text: char_text(&units, &dims),
                dims,
            });
        }
        if let Datatype::Reference { .. } = dtype
            && class == "struct"
        {
            return Err("a struct stored as references outside a struct group".into());
        }
        match (static_class(&class), dtype) {
            (Some(class), Datatype::Compound { .. }) => Ok(Value::Complex { class, dims }),
            (Some(class), Datatype::FloatingPoint { .. } | Datatype::FixedPoint { .. }) => {
                let values = numbers(d, n, length)?;
                Ok(Value::Numeric {
                    class,
                    dims,
                    values,
                })
            }
            _ => Ok(Value::Other {
                class: if class == "function_handle" {
                    "function handle".into()
                } else {
                    class
                },
                dims,
            }),
        }
    }

    /// The field names of a struct group: `MATLAB_fields` when it can be read and names
    /// exactly its members, else the members by name.
    fn field_order(g: &Group, attributes: &[Attribute], members: &[String]) -> Vec<String> {
        let from_attribute = || -> Option<Vec<String>> {
            let a = attributes.iter().find(|a| a.name == "MATLAB_fields")?;
            let names = match a.read_strings() {
                Ok(names) => names,
                Err(_) => {
                    // A vlen sequence of 1-byte characters per field: each element is
                    // (length u32, heap address, index u32).
                    let width = 8 + usize::from(g.offset_size());
                    a.raw_data
                        .chunks_exact(width)
                        .map(|e| {
                            g.resolve_vlen_reference_bytes(e, 1)
                                .ok()
                                .map(|b| String::from_utf8_lossy(&b).into_owned())
                        })
                        .collect::<Option<Vec<String>>>()?
                }
            };
            let mut sorted = names.clone();
            sorted.sort();
            let mut given = members.to_vec();
            given.sort();
            (sorted == given).then_some(names)
        };
        from_attribute().unwrap_or_else(|| {
            let mut names = members.to_vec();
            names.sort();
            names
        })
    }

    /// A group's value: a struct or struct array (module doc), or a sparse array or an
    /// object by class.
    fn group(&mut self, g: &Group, path: &str, depth: usize) -> Result<Value, String> {
        let attributes = g.attributes().map_err(|e| e.to_string())?;
        let class = text(&attributes, "MATLAB_class").unwrap_or_else(|| "struct".into());
        if attributes.iter().any(|a| a.name == "MATLAB_sparse") {
            return Ok(Value::Other {
                class: "sparse".into(),
                dims: vec![0, 0],
            });
        }
        if class != "struct" {
            return Ok(Value::Other {
                class,
                dims: vec![1, 1],
            });
        }
        let (groups, datasets) = g.members().map_err(|e| e.to_string())?;
        let mut members: HashMap<String, Object> = HashMap::new();
        let mut references: Option<Vec<usize>> = None;
        for d in datasets {
            let plain_refs = matches!(d.dtype(), Datatype::Reference { .. })
                && !d.attributes().iter().any(|a| a.name == "MATLAB_class");
            if plain_refs {
                references = Some(matlab_dims(d.shape())?);
            }
            members.insert(d.name().to_string(), Object::Dataset(Box::new(d)));
        }
        for sub in groups {
            members.insert(sub.name().to_string(), Object::Group(sub));
        }
        let names: Vec<String> = members.keys().cloned().collect();
        let fields = Self::field_order(g, &attributes, &names);
        let Some(dims) = references else {
            // A 1 × 1 struct: each member is a field.
            let mut element = Vec::with_capacity(fields.len());
            for field in &fields {
                let object = members
                    .get(field)
                    .ok_or_else(|| format!("no member for field '{field}'"))?;
                element.push(self.value(object, &format!("{path}.{field}"), depth + 1)?);
            }
            return Ok(Value::Struct {
                dims: vec![1, 1],
                fields,
                elements: vec![element],
            });
        };
        // A struct array: each field a dataset of one reference per element.
        let n = count(&dims)?;
        let mut columns: Vec<Vec<u64>> = Vec::with_capacity(fields.len());
        for field in &fields {
            let Some(Object::Dataset(d)) = members.get(field) else {
                return Err(format!(
                    "field '{field}' of a struct array is a group, not references"
                ));
            };
            if !matches!(d.dtype(), Datatype::Reference { .. }) {
                return Err(format!(
                    "field '{field}' of a struct array holds no references"
                ));
            }
            plausible(d, n, usize::from(self.offset_size), self.length)?;
            let raw = d.read_raw_bytes().map_err(|e| e.to_string())?;
            let refs = hdf5_reader::reference::read_object_references(&raw, self.offset_size)
                .map_err(|e| e.to_string())?;
            if refs.len() != n {
                return Err(format!(
                    "field '{field}' has {} references for {n} elements",
                    refs.len()
                ));
            }
            columns.push(refs);
        }
        let mut elements = Vec::with_capacity(n);
        for e in 0..n {
            let at = super::element_path(path, e, n);
            let mut element = Vec::with_capacity(fields.len());
            for (field, refs) in fields.iter().zip(&columns) {
                let field_path = format!("{at}.{field}");
                let object = self.refs.remove(&refs[e]).ok_or_else(|| {
                    format!(
                        "{field_path}: a reference to byte {} which is no value in #refs#",
                        refs[e]
                    )
                })?;
                let value = self.value(&object, &field_path, depth + 1);
                self.refs.insert(refs[e], object);
                element.push(value?);
            }
            elements.push(element);
        }
        Ok(Value::Struct {
            dims,
            fields,
            elements,
        })
    }
}
