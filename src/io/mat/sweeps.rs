//! A stepped-sine table from struct arrays of a MAT file: `sweeps = "FRdata.ResponseControl"`
//! makes each element of that struct array one sweep, labelled by its path
//! (`FRdata.ResponseControl(3)`), its rows the values of its fields, the table's columns
//! named by field (`frequency`, `force`, `amplitude`, `phase`).
//!
//! Rule: a path names a struct, a struct array or one element of one; the sweeps under
//! it are the struct elements at or below it that hold no struct (leaf structs), in file
//! order. So `"FRdata.ResponseControl"` is that array's elements, and `"FRdata"` (a
//! 1 × 1 struct of struct arrays) is every element of every struct array in it. Each
//! field a table column names must be a real vector (1 × N or N × 1, either orientation)
//! of the length N of the sweep's frequency field, or a scalar (one value for the whole
//! sweep: a force level); other fields (a `units` text) are not read.

use std::path::Path;

use super::element::Value;
use crate::error::{Error, Result};
use crate::io::Table;

/// A leaf struct element: its path, field names and values.
struct Sweep<'a> {
    path: String,
    fields: &'a [String],
    values: &'a [Value],
}

/// Every struct element at or below `value` (at `path`) that is selected (its path or
/// one of its ancestors' is `root`) and holds no struct, in file order.
fn collect<'a>(path: &str, value: &'a Value, root: &str, selected: bool, out: &mut Vec<Sweep<'a>>) {
    let Value::Struct {
        fields, elements, ..
    } = value
    else {
        return;
    };
    let selected = selected || path == root;
    for (e, element) in elements.iter().enumerate() {
        let at = super::element_path(path, e, elements.len());
        let chosen = selected || at == root;
        let leaf = !element.iter().any(|v| matches!(v, Value::Struct { .. }));
        if leaf {
            if chosen {
                out.push(Sweep {
                    path: at,
                    fields,
                    values: element,
                });
            }
        } else {
            for (field, v) in fields.iter().zip(element) {
                collect(&format!("{at}.{field}"), v, root, chosen, out);
            }
        }
    }
}

/// The table of the sweeps under `roots` in the MAT file at `path` (module doc): the
/// columns `columns` (field names; `columns[0]` the frequency, whose length is the
/// sweep's), and each row's sweep label. A root with no struct under it, a missing
/// field, a field that is not a real vector or scalar, of another length, or a
/// non-finite value is [`Error::Data`] naming the file, the element path and the field.
pub(crate) fn sweep_table(
    path: &Path,
    roots: &[String],
    columns: &[&str],
) -> Result<(Table, Vec<String>)> {
    let file = path.display().to_string();
    let error = |column: String, row: usize, message: String| Error::Data {
        file: file.clone(),
        row,
        column,
        message,
    };
    let tree = super::parsed(path)?;
    let mut sweeps: Vec<Sweep> = Vec::new();
    for root in roots {
        let mut found = Vec::new();
        for v in &tree {
            collect(&v.name, &v.value, root, false, &mut found);
        }
        if found.is_empty() {
            let structs: Vec<String> = super::variables(path)?
                .contents
                .into_iter()
                .filter(|e| e.description.ends_with(" struct"))
                .map(|e| format!("{} ({})", e.path, e.description))
                .collect();
            return Err(error(
                root.clone(),
                0,
                format!(
                    "no struct or struct array '{root}' with fields to read as sweeps; the file's structs: {}",
                    if structs.is_empty() {
                        "none".to_string()
                    } else {
                        structs.join(", ")
                    }
                ),
            ));
        }
        for sweep in found {
            if !sweeps.iter().any(|s| s.path == sweep.path) {
                sweeps.push(sweep);
            }
        }
    }
    let mut table_columns: Vec<Vec<f64>> = vec![Vec::new(); columns.len()];
    let mut labels = Vec::new();
    for sweep in &sweeps {
        let mut length = None;
        for (k, &name) in columns.iter().enumerate() {
            let at = format!("{}.{name}", sweep.path);
            let Some(f) = sweep.fields.iter().position(|f| f == name) else {
                return Err(error(
                    at,
                    0,
                    format!(
                        "sweep '{}' has no field '{name}' (its fields: {})",
                        sweep.path,
                        sweep.fields.join(", ")
                    ),
                ));
            };
            let value = &sweep.values[f];
            let values = match value {
                Value::Numeric { dims, values, .. }
                    if dims.len() == 2 && (dims[0] == 1 || dims[1] == 1) && !values.is_empty() =>
                {
                    values
                }
                other => {
                    return Err(error(
                        at,
                        0,
                        format!(
                            "is {}: a sweep's field must be a real vector (1×N or N×1) or a scalar",
                            other.describe()
                        ),
                    ));
                }
            };
            let n = *length.get_or_insert(values.len());
            if values.len() != n && values.len() != 1 {
                return Err(error(
                    at,
                    0,
                    format!(
                        "{} values, but the sweep's '{}' has {n} (a field holds one value per point, or one for the whole sweep)",
                        values.len(),
                        columns[0]
                    ),
                ));
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(error(at, i + 1, format!("non-finite value {}", values[i])));
            }
            if values.len() == n {
                table_columns[k].extend_from_slice(values);
            } else {
                table_columns[k].extend(std::iter::repeat_n(values[0], n));
            }
        }
        labels.extend(std::iter::repeat_n(sweep.path.clone(), length.unwrap_or(0)));
    }
    Ok((
        Table {
            file,
            headers: columns.iter().map(|c| c.to_string()).collect(),
            columns: table_columns,
        },
        labels,
    ))
}
