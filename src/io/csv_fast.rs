//! The fast path of the CSV reader: plain numeric CSV parsed straight from its bytes,
//! with no allocation per field (memchr finds the line and field ends, fast-float2
//! parses each cell's bytes to f64), and in parallel by blocks of whole lines when the
//! file is large (rayon; the blocks' columns are joined in order). A file is streamed
//! through one buffer ([`read_file`]): its text is never held whole, and the memory it
//! takes is the columns'.
//!
//! It never decides an error. [`read`] gives `None` whenever anything is unusual: a
//! quote character, a byte outside printable ASCII in the header, a header that names
//! a column twice or not at all, a row with another number of fields, a cell that is
//! not a finite number, no data rows. The caller then reads the file with the csv
//! crate ([`super::csv`]), which gives the same table or the error naming the row,
//! column and value. On the files it accepts it gives what that general path gives:
//! - the same records: a line ends at `\n` and a `\r` before it is dropped; empty lines
//!   and lines whose first byte is `#` are skipped (the csv crate's comment setting);
//!   a lone `\r` (the csv crate's other line end) stays in a cell and fails its parse;
//! - the same fields: split at commas, with spaces, tabs and `\r` trimmed at both ends
//!   (`str::trim`, which the general path applies, removes these and more; whatever
//!   else is left fails the number parse);
//! - the same values: fast-float2 reads the syntax of `str::parse::<f64>` and rounds
//!   correctly, as it does.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use memchr::{memchr, memchr_iter, memrchr};
use rayon::prelude::*;

/// A header's names and their columns.
pub(crate) type Parsed = (Vec<String>, Vec<Vec<f64>>);

/// The header and the columns of a plain numeric CSV text, or `None` (module doc).
/// Texts of at least two blocks of `block` bytes are parsed in parallel.
pub(crate) fn read(bytes: &[u8], block: usize) -> Option<Parsed> {
    let (headers, body) = header(bytes)?;
    let mut columns = vec![Vec::new(); headers.len()];
    append(body, block, &mut columns)?;
    finish(headers, columns)
}

/// [`read`] of the file at `path`, streamed through a buffer of `buffer` bytes (a line
/// longer than it is left to the general path), so that the file's text is never held
/// whole: `Ok(None)` when the general path must read it.
pub(crate) fn read_file(
    path: &Path,
    buffer: usize,
    block: usize,
) -> std::io::Result<Option<Parsed>> {
    let mut file = File::open(path)?;
    let mut text = vec![0u8; buffer.max(1)];
    let (mut filled, mut end_of_file) = fill(&mut file, &mut text, 0)?;
    // The header's line must end inside the first buffer.
    let whole = if end_of_file {
        filled
    } else {
        match memrchr(b'\n', &text[..filled]) {
            Some(i) => i + 1,
            None => return Ok(None),
        }
    };
    let Some((headers, body)) = header(&text[..whole]) else {
        return Ok(None);
    };
    let mut start = whole - body.len();
    let mut columns = vec![Vec::new(); headers.len()];
    loop {
        let end = if end_of_file {
            filled
        } else {
            match memrchr(b'\n', &text[start..filled]) {
                Some(i) => start + i + 1,
                None => return Ok(None),
            }
        };
        if append(&text[start..end], block, &mut columns).is_none() {
            return Ok(None);
        }
        if end_of_file {
            break;
        }
        text.copy_within(end..filled, 0);
        (filled, end_of_file) = fill(&mut file, &mut text, filled - end)?;
        start = 0;
    }
    Ok(finish(headers, columns))
}

/// Reads from `file` into `text` after its first `from` bytes until it is full or the
/// file ends: the bytes now in `text`, and whether the file ended.
fn fill(file: &mut File, text: &mut [u8], from: usize) -> std::io::Result<(usize, bool)> {
    let mut filled = from;
    while filled < text.len() {
        match file.read(&mut text[filled..]) {
            Ok(0) => return Ok((filled, true)),
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok((filled, false))
}

/// The table, when it has data rows.
fn finish(headers: Vec<String>, columns: Vec<Vec<f64>>) -> Option<Parsed> {
    if columns.first().is_none_or(Vec::is_empty) {
        return None;
    }
    Some((headers, columns))
}

/// Parses the whole lines of `text` (in parallel when it is two blocks or more) and
/// appends their cells to `columns`.
fn append(text: &[u8], block: usize, columns: &mut [Vec<f64>]) -> Option<()> {
    if memchr(b'"', text).is_some() {
        return None;
    }
    let k = columns.len();
    let pieces = split(text, block);
    let parsed: Vec<Vec<Vec<f64>>> = if pieces.len() == 1 {
        vec![parse_block(text, k)?]
    } else {
        pieces
            .par_iter()
            .map(|piece| parse_block(piece, k))
            .collect::<Option<Vec<_>>>()?
    };
    columns.par_iter_mut().enumerate().for_each(|(j, column)| {
        column.reserve(parsed.iter().map(|p| p[j].len()).sum());
        for p in &parsed {
            column.extend_from_slice(&p[j]);
        }
    });
    Some(())
}

/// The header's names and the text after the header line; `None` for a header the
/// general path must judge.
fn header(bytes: &[u8]) -> Option<(Vec<String>, &[u8])> {
    let mut rest = bytes;
    loop {
        let end = memchr(b'\n', rest).unwrap_or(rest.len());
        let line = strip_cr(&rest[..end]);
        let after = &rest[(end + 1).min(rest.len())..];
        if line.is_empty() || line[0] == b'#' {
            if after.is_empty() {
                return None;
            }
            rest = after;
            continue;
        }
        if !line
            .iter()
            .all(|&b| b == b'\t' || (b' '..=b'~').contains(&b))
            || line.contains(&b'"')
        {
            return None;
        }
        let text = std::str::from_utf8(line).ok()?;
        let headers: Vec<String> = text.split(',').map(|h| h.trim().to_string()).collect();
        // One hash set: a header of 300,000 names is checked in linear time.
        let mut seen = std::collections::HashSet::with_capacity(headers.len());
        let unique = headers
            .iter()
            .all(|h| !h.is_empty() && seen.insert(h.as_str()));
        return unique.then_some((headers, after));
    }
}

fn strip_cr(line: &[u8]) -> &[u8] {
    line.strip_suffix(b"\r").unwrap_or(line)
}

/// `body` cut after line ends into pieces of about `block` bytes (one piece when it is
/// shorter than two).
fn split(body: &[u8], block: usize) -> Vec<&[u8]> {
    let block = block.max(1);
    if body.len() < 2 * block {
        return vec![body];
    }
    let mut pieces = Vec::with_capacity(body.len() / block + 1);
    let mut rest = body;
    while rest.len() >= 2 * block {
        let cut = match memchr(b'\n', &rest[block..]) {
            Some(i) => block + i + 1,
            None => rest.len(),
        };
        pieces.push(&rest[..cut]);
        rest = &rest[cut..];
    }
    if !rest.is_empty() {
        pieces.push(rest);
    }
    pieces
}

/// The cell's value, when it is a finite number once trimmed.
fn cell(field: &[u8]) -> Option<f64> {
    let trimmed = field.trim_ascii_start();
    let trimmed = trimmed
        .iter()
        .rposition(|b| !matches!(b, b' ' | b'\t' | b'\r'))
        .map_or(&trimmed[..0], |last| &trimmed[..=last]);
    fast_float2::parse::<f64, _>(trimmed)
        .ok()
        .filter(|v| v.is_finite())
}

/// The columns of the whole lines in `text`, each with `k` numeric cells.
fn parse_block(text: &[u8], k: usize) -> Option<Vec<Vec<f64>>> {
    let lines = memchr_iter(b'\n', text).count() + 1;
    let mut columns: Vec<Vec<f64>> = (0..k).map(|_| Vec::with_capacity(lines)).collect();
    let mut start = 0;
    while start < text.len() {
        let end = memchr(b'\n', &text[start..]).map_or(text.len(), |i| start + i);
        let line = strip_cr(&text[start..end]);
        start = end + 1;
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let mut rest = line;
        for (j, column) in columns.iter_mut().enumerate() {
            let field = match memchr(b',', rest) {
                Some(i) if j + 1 < k => {
                    let field = &rest[..i];
                    rest = &rest[i + 1..];
                    field
                }
                None if j + 1 == k => rest,
                _ => return None,
            };
            column.push(cell(field)?);
        }
    }
    Some(columns)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Streaming through the read buffer, and the agreement of this path with the csv
    // crate's: tests/formats.rs (csv_file_larger_than_the_read_buffer,
    // csv_fast_and_general_paths_agree).

    #[test]
    fn plain_text_is_read_and_anything_unusual_is_left_to_the_csv_crate() {
        let (headers, columns) =
            read(b"# c\n\nt, x\r\n0,1.5\r\n# mid\n\n 1e-3 ,\t-2\n", 4).unwrap();
        assert_eq!(headers, ["t", "x"]);
        assert_eq!(columns, [vec![0.0, 1e-3], vec![1.5, -2.0]]);
        for unusual in [
            &b"t,x\n0,\"1\"\n"[..],
            b"\"t\",x\n0,1\n",
            b"t,x\n0,1,2\n",
            b"t,x\n0\n",
            b"t,x\n0,abc\n",
            b"t,x\n0,inf\n",
            b"t,x\n0,NaN\n",
            b"t,x\n0,\n",
            b"t,t\n0,1\n",
            b"t,,x\n0,1,2\n",
            b"t,x\n",
            b"t,x\n0,1\r2,3\n",
            "t,\u{e9}\n0,1\n".as_bytes(),
        ] {
            assert!(
                read(unusual, 4).is_none(),
                "{}",
                String::from_utf8_lossy(unusual)
            );
        }
    }

    /// Blocks cut anywhere give the same columns as one block.
    #[test]
    fn blocks_join_in_order() {
        let mut text = String::from("a,b,c\n");
        for i in 0..997 {
            text.push_str(&format!("{i},{}.25,{:e}\n", i * 2, i as f64 * 1e-7));
            if i % 101 == 0 {
                text.push_str("# note\n\n");
            }
        }
        let (_, one) = read(text.as_bytes(), usize::MAX / 4).unwrap();
        assert_eq!(one[0].len(), 997);
        for block in [1, 7, 64, 1000] {
            let (_, many) = read(text.as_bytes(), block).unwrap();
            assert_eq!(many, one, "block {block}");
        }
    }
}
