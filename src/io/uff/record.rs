//! One dataset 58 (or 58b) after its header line: records 1–11, the data (fixed-width
//! text or raw IEEE bytes) and the time axis, with the exact step h = 1/f for the one
//! whole sample rate f that the six written digits fit (see the parent module).

use crate::error::{Error, Result};

use super::FunctionRecord;
use super::fields::{Cursor, characteristics, data_error, fields, integer, integers, number};

/// The binary `58b` header: byte order (true = little endian) and the byte count.
pub(super) fn binary_header(cursor: &Cursor, rest: &str) -> Result<(bool, usize)> {
    let tokens: Vec<&str> = rest.split_whitespace().collect();
    let field = |k: usize, name: &str| {
        tokens.get(k).and_then(|t| integer(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                cursor.line,
                &format!("58b header field {} ({name})", k + 2),
                format!("expected an integer, found {:?}", tokens.get(k)),
            )
        })
    };
    let order = field(0, "byte order")?;
    let format = field(1, "floating-point format")?;
    let lines = field(2, "number of ASCII lines")?;
    let bytes = field(3, "number of bytes")?;
    let bad = |k: usize, message: String| {
        Err(data_error(
            cursor.file,
            cursor.line,
            &format!("58b header field {k}"),
            message,
        ))
    };
    if order != 1 && order != 2 {
        return bad(
            2,
            format!("byte order {order}: expected 1 (little) or 2 (big endian)"),
        );
    }
    if format != 2 {
        return bad(
            3,
            format!("floating-point format {format}: only 2 (IEEE 754) is read"),
        );
    }
    if lines != 11 {
        return bad(4, format!("{lines} ASCII lines: dataset 58b has 11"));
    }
    match usize::try_from(bytes) {
        Ok(bytes) => Ok((order == 1, bytes)),
        Err(_) => bad(5, format!("byte count {bytes}")),
    }
}

/// The abscissa of one record: start, step, the precision they were written to, and
/// the line of record 7.
pub(super) struct Abscissa {
    pub(super) start: f64,
    pub(super) step: f64,
    pub(super) tolerance: f64,
    pub(super) line: usize,
}

/// Half a unit of the sixth significant digit of `value` (E13.5 rounding).
pub(super) fn half_unit(value: f64) -> f64 {
    if value == 0.0 {
        return 0.0;
    }
    0.5 * 10f64.powi(value.abs().log10().floor() as i32 - 5) * (1.0 + 1e-9)
}

/// The exact step 1/f for the one whole sample rate f within `tolerance` of `step`.
pub fn exact_step(step: f64, tolerance: f64) -> f64 {
    let rate = (1.0 / step).round();
    let fits = |f: f64| f >= 1.0 && (1.0 / f - step).abs() <= tolerance;
    if fits(rate) && !fits(rate - 1.0) && !fits(rate + 1.0) {
        1.0 / rate
    } else {
        step
    }
}

/// One dataset 58 after its header line.
pub(super) fn function_record(
    cursor: &mut Cursor,
    header_line: usize,
    binary: Option<(bool, usize)>,
) -> Result<(FunctionRecord, Abscissa)> {
    let id = cursor.expect("record 1 (ID line 1)")?.trim().to_string();
    for record in 2..=5 {
        cursor.expect(&format!("record {record} (ID line {record})"))?;
    }
    let r6 = cursor.expect("record 6")?;
    let w6 = [5, 10, 5, 10, 11, 10, 4, 11, 10, 4];
    let t6 = fields(r6, &w6);
    let int6 = |k: usize, name: &str| {
        t6.get(k).and_then(|t| integer(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                cursor.line,
                &format!("record 6 field {} ({name})", k + 1),
                format!("expected an integer, found {:?}", t6.get(k).unwrap_or(&"")),
            )
        })
    };
    let function_type = int6(0, "function type")?;
    let node = int6(5, "response node")?;
    let direction = int6(6, "response direction")?;
    if function_type != 0 && function_type != 1 {
        return Err(data_error(
            cursor.file,
            cursor.line,
            "record 6 field 1 (function type)",
            format!(
                "function type {function_type} is not a time response: dampid reads type 1 (or 0, general)"
            ),
        ));
    }
    let r7 = cursor.expect("record 7")?;
    let line7 = cursor.line;
    let i7 = integers(cursor, r7, 7, &[10, 10, 10])?;
    let t7 = fields(r7, &[10, 10, 10, 13, 13, 13]);
    let real7 = |k: usize, name: &str| {
        t7.get(k).and_then(|t| number(t)).ok_or_else(|| {
            data_error(
                cursor.file,
                line7,
                &format!("record 7 field {} ({name})", k + 1),
                format!("expected a number, found {:?}", t7.get(k).unwrap_or(&"")),
            )
        })
    };
    let (kind, count, spacing) = (i7[0], i7[1], i7[2]);
    let size = match kind {
        2 => 4,
        4 => 8,
        5 | 6 => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 1 (ordinate data type)",
                format!("ordinate type {kind} is complex: dampid reads real time histories (2, 4)"),
            ));
        }
        _ => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 1 (ordinate data type)",
                format!("ordinate type {kind}: expected 2 (real single) or 4 (real double)"),
            ));
        }
    };
    let even = match spacing {
        1 => true,
        0 => false,
        _ => {
            return Err(data_error(
                cursor.file,
                line7,
                "record 7 field 3 (abscissa spacing)",
                format!("{spacing}: expected 1 (even) or 0 (uneven)"),
            ));
        }
    };
    let count = usize::try_from(count)
        .ok()
        .filter(|&n| n >= 2)
        .ok_or_else(|| {
            data_error(
                cursor.file,
                line7,
                "record 7 field 2 (number of values)",
                format!("{count}: a time history needs at least two values"),
            )
        })?;
    let (start, increment) = if even {
        (
            real7(3, "abscissa minimum")?,
            real7(4, "abscissa increment")?,
        )
    } else {
        (0.0, 0.0)
    };
    let abscissa = characteristics(cursor, 8)?;
    if abscissa.data_type != 0 && abscissa.data_type != 17 {
        return Err(data_error(
            cursor.file,
            cursor.line,
            "record 8 field 1 (abscissa data type)",
            format!(
                "abscissa type {} ({}): a time history has 17 (time) or 0",
                abscissa.data_type,
                abscissa.quantity()
            ),
        ));
    }
    let ordinate = characteristics(cursor, 9)?;
    characteristics(cursor, 10)?;
    characteristics(cursor, 11)?;
    let per_sample = if even { 1 } else { 2 };
    let total = count.saturating_mul(per_sample);
    let (pairs, data_line) = match binary {
        Some((little, declared)) => {
            let bytes = total.saturating_mul(size);
            // pyuff 2.5 declares N·size bytes for uneven records that hold 2N values.
            if declared != bytes && declared != count.saturating_mul(size) {
                return Err(data_error(
                    cursor.file,
                    header_line,
                    "58b header field 5 (number of bytes)",
                    format!(
                        "{declared} bytes, but record 7 describes {total} values of {size} bytes ({bytes})"
                    ),
                ));
            }
            let line = cursor.line + 1;
            let raw = cursor.take(bytes).ok_or_else(|| {
                data_error(
                    cursor.file,
                    line,
                    "record 12 (data)",
                    format!("the file ends inside the {bytes} data bytes (truncated dataset)"),
                )
            })?;
            let values = raw
                .chunks_exact(size)
                .map(|c| match (size, little) {
                    (4, true) => f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                    (4, false) => f64::from(f32::from_be_bytes([c[0], c[1], c[2], c[3]])),
                    (_, true) => f64::from_le_bytes(c.try_into().unwrap_or([0; 8])),
                    (_, false) => f64::from_be_bytes(c.try_into().unwrap_or([0; 8])),
                })
                .collect::<Vec<_>>();
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(data_error(
                    cursor.file,
                    line,
                    "record 12 (data)",
                    format!("value {} is {}", k + 1, values[k]),
                ));
            }
            (values, line)
        }
        None => ascii_values(cursor, total, size == 8, even)?,
    };
    let line = cursor.line;
    match cursor.next_line() {
        Some(Ok(l)) if l.trim() == "-1" => {}
        // Binary data may be followed by a line end before the delimiter.
        Some(Ok(l)) if binary.is_some() && l.trim().is_empty() => {
            let after = cursor.expect("the delimiter -1")?;
            if after.trim() != "-1" {
                return Err(too_many(cursor, count));
            }
        }
        Some(Ok(_)) => return Err(too_many(cursor, count)),
        Some(Err(e)) => return Err(e),
        None => {
            return Err(data_error(
                cursor.file,
                line,
                "delimiter",
                "the file ends before the dataset's closing -1 (truncated dataset)",
            ));
        }
    }
    let (values, abscissa) = if even {
        let tolerance = half_unit(increment);
        (
            pairs,
            Abscissa {
                start,
                step: increment,
                tolerance,
                line: line7,
            },
        )
    } else {
        uneven(cursor.file, pairs, data_line, binary.is_none(), line7)?
    };
    let record = FunctionRecord {
        line: header_line,
        id,
        function_type,
        node,
        direction,
        ordinate,
        values,
    };
    Ok((record, abscissa))
}

pub(super) fn too_many(cursor: &Cursor, count: usize) -> Error {
    data_error(
        cursor.file,
        cursor.line,
        "record 7 field 2 (number of values)",
        format!("record 7 announces {count} values, but the data go on past them (expected -1)"),
    )
}

/// `total` values in fixed-width fields: 6E13.5 single, 4E20.12 double, and double
/// uneven pairs E13.5,E20.12. Returns them and the first data line.
pub(super) fn ascii_values(
    cursor: &mut Cursor,
    total: usize,
    double: bool,
    even: bool,
) -> Result<(Vec<f64>, usize)> {
    let widths: &[usize] = match (double, even) {
        (false, _) => &[13; 6],
        (true, true) => &[20; 4],
        (true, false) => &[13, 20, 13, 20],
    };
    // Never reserve more than the file can hold (a field takes at least 2 bytes).
    let mut values = Vec::with_capacity(total.min(cursor.bytes.len() / 2));
    let first = cursor.line + 1;
    while values.len() < total {
        let line = cursor.expect("record 12 (data)")?;
        if line.trim() == "-1" {
            return Err(data_error(
                cursor.file,
                cursor.line,
                "record 7 field 2 (number of values)",
                format!(
                    "record 7 announces {total} values, the data hold {} (truncated dataset)",
                    values.len()
                ),
            ));
        }
        let need = (total - values.len()).min(widths.len());
        let fixed = fields(line, &widths[..need]);
        let parsed: Option<Vec<f64>> = fixed.iter().map(|f| number(f)).collect();
        let parsed = parsed.filter(|p| !p.is_empty()).or_else(|| {
            let free: Option<Vec<f64>> = line.split_whitespace().map(number).collect();
            free.filter(|p| !p.is_empty() && p.len() <= need)
        });
        match parsed {
            Some(p) => values.extend(p),
            None => {
                let k = fixed.iter().position(|f| number(f).is_none()).unwrap_or(0);
                return Err(data_error(
                    cursor.file,
                    cursor.line,
                    &format!("record 12 field {}", k + 1),
                    format!(
                        "expected a finite number, found {:?}",
                        fixed.get(k).unwrap_or(&"")
                    ),
                ));
            }
        }
    }
    Ok((values, first))
}

/// Splits x,y pairs and checks the x are uniform to the precision written.
pub(super) fn uneven(
    file: &str,
    pairs: Vec<f64>,
    first: usize,
    ascii: bool,
    line7: usize,
) -> Result<(Vec<f64>, Abscissa)> {
    let x: Vec<f64> = pairs.iter().step_by(2).copied().collect();
    let y: Vec<f64> = pairs.iter().skip(1).step_by(2).copied().collect();
    let n = x.len();
    let step = (x[n - 1] - x[0]) / (n - 1) as f64;
    let precision = |v: f64| {
        if ascii {
            half_unit(v)
        } else {
            4.0 * f64::EPSILON * v.abs()
        }
    };
    let values_per_line = if ascii { 2 } else { usize::MAX };
    if step.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(data_error(
            file,
            first,
            "record 12 (abscissa)",
            format!("the abscissa does not increase: mean step {step}"),
        ));
    }
    for (i, &xi) in x.iter().enumerate() {
        let expected = x[0] + i as f64 * step;
        if (xi - expected).abs()
            > precision(xi) + precision(x[0]) + precision(x[n - 1]) + 1e-9 * step
        {
            return Err(data_error(
                file,
                first + i / values_per_line.max(1),
                "record 12 (abscissa)",
                format!(
                    "the abscissa is not uniform: x[{}] = {xi}, a uniform step {step} gives {expected}",
                    i + 1
                ),
            ));
        }
    }
    let tolerance = (precision(x[0]) + precision(x[n - 1])) / (n - 1) as f64;
    Ok((
        y,
        Abscissa {
            start: x[0],
            step,
            tolerance,
            line: line7,
        },
    ))
}
