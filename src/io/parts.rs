//! A stored array read straight into its destinations by several threads at once, each
//! from its own part of the file ([`read_parts`]), and the CRC-32 of the bytes read
//! ([`Crc`]).
//!
//! The flat data of an N × k array ([`Layout`]) are cut at whole units, rows of k
//! interleaved values or columns of N contiguous ones, into P parts of about equal size:
//!
//! ```text
//!   part i = flat elements [u_i·w, u_{i+1}·w),   w = k (rows) or N (columns),
//!   u_i = ⌊i·U/P⌋,   U = N (rows) or k (columns),
//!   P = min(threads, bytes / 8 MiB, U), at least 1,
//!   threads = the member's share of the pool by its bytes (`io/in_place.rs`),
//! ```
//!
//! so a part writes samples u_i..u_{i+1} of every column (rows), or whole columns
//! (columns): the destinations split into disjoint slices, one set per part. Each part
//! is read in order by its own file handle, exactly as one pass over the whole array
//! would read it (the same blocks from the part's first row, the same conversion, the
//! same finiteness check), so the values written are the same bit for bit. The fresh
//! pages of the destination are then first touched by every thread, not one.
//!
//! The CRC-32 of the whole member is the combination of the parts' in file order,
//! crc(a ‖ b) = combine(crc(a), crc(b), |b|) (crc32fast's `Hasher::combine`), and an
//! error is the first in file order: the one a single pass would have met first.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::mem::MaybeUninit;
use std::path::Path;

use rayon::prelude::*;

use crate::error::Result;
use crate::io::arrays::Layout;
use crate::io::npy::{Header, data_error, read_range};
use crate::io::scatter::Target;

/// Fewest bytes of data worth a part of their own: below this one thread reads the
/// whole array (a part costs a file handle and its buffers).
const PART_BYTES: u64 = 8 << 20;

/// A reader that computes the CRC-32 of the bytes it passes on.
pub(crate) struct Crc<R> {
    pub inner: R,
    pub hasher: crc32fast::Hasher,
}

impl<R: Read> Read for Crc<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hasher.update(&buf[..n]);
        Ok(n)
    }
}

/// One part: its flat elements and the destinations' slices it writes.
struct Part<'a> {
    elements: std::ops::Range<usize>,
    /// The flat index of the part's sample 0 in its targets' slices (0 for columns).
    rebase: usize,
    targets: Vec<Target<'a>>,
}

/// Cuts `targets` (each N samples) into the parts' disjoint slices (module doc).
fn parts<'a>(
    layout: Layout,
    bytes: u64,
    threads: usize,
    targets: &mut [Target<'a>],
) -> Vec<Part<'a>> {
    let (width, units) = if layout.interleaved {
        (layout.columns, layout.samples)
    } else {
        (layout.samples, layout.columns)
    };
    let count = (bytes / PART_BYTES)
        .min(threads as u64)
        .min(units as u64)
        .max(1) as usize;
    let bounds: Vec<usize> = (0..=count).map(|i| i * units / count).collect();
    let mut parts: Vec<Part<'a>> = bounds
        .windows(2)
        .map(|b| Part {
            elements: b[0] * width..b[1] * width,
            rebase: if layout.interleaved { b[0] * width } else { 0 },
            targets: Vec::new(),
        })
        .collect();
    for t in targets.iter_mut() {
        let mut rest: &'a mut [MaybeUninit<f64>] = std::mem::take(&mut t.into);
        if layout.interleaved {
            for (part, b) in parts.iter_mut().zip(bounds.windows(2)) {
                let (head, tail) = rest.split_at_mut(b[1] - b[0]);
                part.targets.push(Target {
                    column: t.column,
                    into: head,
                    gain: t.gain,
                });
                rest = tail;
            }
        } else {
            // The part whose columns hold the target's: bounds[0] = 0 ≤ column < k.
            let i = bounds.partition_point(|&u| u <= t.column) - 1;
            parts[i].targets.push(Target {
                column: t.column,
                into: rest,
                gain: t.gain,
            });
        }
    }
    parts
}

/// Where an array's data lie: the file at `path`, already open (`opened`, which the
/// first part reads), from byte `start`.
pub(crate) struct Source<'p> {
    pub opened: File,
    pub path: &'p Path,
    pub start: u64,
}

/// Reads the data of the array of `header` at `source` into `targets` (every sample of
/// every target written when it returns `Ok`), in blocks of about `block` elements and
/// at most `threads` parts read in parallel (module doc); returns the CRC-32 state of the
/// data bytes. `name` and `file` name the array in errors.
pub(crate) fn read_parts(
    source: Source<'_>,
    header: &Header,
    block: usize,
    threads: usize,
    targets: &mut [Target<'_>],
    name: &str,
    file: &str,
) -> Result<crc32fast::Hasher> {
    let layout = header.layout;
    let size = header.element_size();
    let bytes = (layout.elements() as u64).saturating_mul(size as u64);
    let Source {
        opened,
        path,
        start,
    } = source;
    let read = |mut handle: File, part: &mut Part<'_>| -> Result<crc32fast::Hasher> {
        let error = |e: &dyn std::fmt::Display| data_error(file, name, e);
        let offset = start + (part.elements.start as u64) * size as u64;
        handle
            .seek(SeekFrom::Start(offset))
            .map_err(|e| error(&e))?;
        let length = (part.elements.len() as u64) * size as u64;
        let mut reader = BufReader::with_capacity(
            1 << 16,
            Crc {
                inner: handle.take(length),
                hasher: crc32fast::Hasher::new(),
            },
        );
        let (rebase, targets) = (part.rebase, &mut part.targets);
        read_range(
            &mut reader,
            header,
            block,
            part.elements.clone(),
            name,
            file,
            |done, values| layout.scatter(done - rebase, values, targets),
        )?;
        // Every byte of the part was handed out, so the hasher has seen exactly them.
        Ok(reader.into_inner().hasher)
    };
    let mut parts = parts(layout, bytes, threads, targets);
    if parts.len() == 1 {
        return read(opened, &mut parts[0]);
    }
    let mut handles = vec![Some(opened)];
    handles.resize_with(parts.len(), || None);
    let hashers: Vec<Result<crc32fast::Hasher>> = parts
        .par_iter_mut()
        .zip(handles)
        .map(|(part, handle)| {
            let handle = match handle {
                Some(handle) => handle,
                None => File::open(path).map_err(|e| data_error(file, name, e))?,
            };
            read(handle, part)
        })
        .collect();
    let mut whole = crc32fast::Hasher::new();
    for hasher in hashers {
        whole.combine(&hasher?);
    }
    Ok(whole)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parts cover the flat elements once, in order, at whole rows or columns, and
    /// each target's slices add up to its N samples.
    #[test]
    fn parts_cover_every_element_once_at_whole_units() {
        for interleaved in [true, false] {
            let layout = Layout {
                samples: 1000,
                columns: 7,
                interleaved,
            };
            let mut out = vec![vec![MaybeUninit::new(0.0); 1000]; 9];
            let mut targets: Vec<Target<'_>> = out
                .iter_mut()
                .enumerate()
                .map(|(j, into)| Target {
                    column: j % 7,
                    into,
                    gain: (1.0, 0.0),
                })
                .collect();
            let cut = parts(layout, 3 * PART_BYTES, 3, &mut targets);
            assert_eq!(cut.len(), 3);
            let width = if interleaved { 7 } else { 1000 };
            let mut next = 0;
            for part in &cut {
                assert_eq!(part.elements.start, next);
                assert!(part.elements.start.is_multiple_of(width));
                next = part.elements.end;
            }
            assert_eq!(next, 7000);
            let mut samples = [0usize; 7];
            for part in &cut {
                for t in &part.targets {
                    samples[t.column] += t.into.len();
                }
            }
            // Columns 0 and 1 have two targets each.
            assert_eq!(samples, [2000, 2000, 1000, 1000, 1000, 1000, 1000]);
            // Fewer threads, fewer parts; a small array, one.
            assert_eq!(parts(layout, 3 * PART_BYTES, 2, &mut []).len(), 2);
            assert_eq!(parts(layout, PART_BYTES - 1, 3, &mut []).len(), 1);
        }
    }
}
