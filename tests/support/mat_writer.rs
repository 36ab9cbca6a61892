//! A small writer of level-5 MAT files (uncompressed, little endian) for tests: double
//! and char arrays, structs and struct arrays nested to any depth, as MATLAB's `save -v6`
//! lays them out (MathWorks' "MAT-File Format": each variable an miMATRIX element of
//! array flags, dimensions, name, then the data; a struct's field-name width and names,
//! then one miMATRIX per field per element, elements column-major). Files it writes were
//! checked once against SciPy's `scipy.io.loadmat`.

#![allow(dead_code)]

/// A MATLAB value.
pub enum Mat {
    /// An r × c double array, column-major.
    Double(usize, usize, Vec<f64>),
    /// A 1 × n char array.
    Char(String),
    /// A 1 × n struct array: field names, and per element one value per field.
    Struct(Vec<String>, Vec<Vec<Mat>>),
    /// A 1 × n cell array (for the unsupported-contents errors).
    Cell(Vec<Mat>),
}

impl Mat {
    /// A 1 × n row vector.
    pub fn row(values: &[f64]) -> Mat {
        Mat::Double(1, values.len(), values.to_vec())
    }
    /// An n × 1 column vector.
    pub fn column(values: &[f64]) -> Mat {
        Mat::Double(values.len(), 1, values.to_vec())
    }
    /// A 1 × 1 struct.
    pub fn fields(fields: Vec<(&str, Mat)>) -> Mat {
        let (names, values): (Vec<String>, Vec<Mat>) =
            fields.into_iter().map(|(n, v)| (n.to_string(), v)).unzip();
        Mat::Struct(names, vec![values])
    }
}

fn element(kind: u32, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend(kind.to_le_bytes());
    out.extend((data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    while out.len() % 8 != 0 {
        out.push(0);
    }
    out
}

fn matrix(name: &str, value: &Mat) -> Vec<u8> {
    let (class, dims): (u32, [usize; 2]) = match value {
        Mat::Double(r, c, _) => (6, [*r, *c]),
        Mat::Char(s) => (4, [1, s.chars().count()]),
        Mat::Struct(_, elements) => (2, [1, elements.len()]),
        Mat::Cell(items) => (1, [1, items.len()]),
    };
    let mut body = Vec::new();
    body.extend(element(
        6,
        &[class.to_le_bytes(), 0u32.to_le_bytes()].concat(),
    ));
    let dims: Vec<u8> = dims
        .iter()
        .flat_map(|d| (*d as i32).to_le_bytes())
        .collect();
    body.extend(element(5, &dims));
    body.extend(element(1, name.as_bytes()));
    match value {
        Mat::Double(_, _, values) => {
            let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
            body.extend(element(9, &data));
        }
        Mat::Char(s) => {
            let data: Vec<u8> = s.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
            body.extend(element(4, &data));
        }
        Mat::Struct(fields, elements) => {
            let width = fields.iter().map(|f| f.len()).max().unwrap_or(0) + 1;
            body.extend(element(5, &(width as i32).to_le_bytes()));
            let mut names = Vec::new();
            for f in fields {
                let mut n = f.as_bytes().to_vec();
                n.resize(width, 0);
                names.extend(n);
            }
            body.extend(element(1, &names));
            for values in elements {
                for v in values {
                    body.extend(matrix("", v));
                }
            }
        }
        Mat::Cell(items) => {
            for v in items {
                body.extend(matrix("", v));
            }
        }
    }
    element(14, &body)
}

/// The bytes of a level-5 MAT file holding `variables`.
pub fn mat_bytes(variables: &[(&str, Mat)]) -> Vec<u8> {
    let mut header = b"MATLAB 5.0 MAT-file, written by dampid's tests".to_vec();
    header.resize(116, b' ');
    header.extend([0u8; 8]);
    header.extend([0x00, 0x01]);
    header.extend(b"IM");
    for (name, value) in variables {
        header.extend(matrix(name, value));
    }
    header
}

/// Writes a level-5 MAT file holding `variables` to `path`.
pub fn write_mat(path: &std::path::Path, variables: &[(&str, Mat)]) {
    std::fs::write(path, mat_bytes(variables)).unwrap();
}
