//! Flat values of a stored array written straight into the columns that want them
//! ([`Layout::scatter`]): each destination column p gets, at sample s,
//!
//!   into[s] = scale · value(s, p) + offset
//!
//! where value(s, p) lies at the flat index of the [`Layout`] table (io/arrays.rs).
//! Contiguous runs (Fortran order, or a transposed C-order array) are copied run by
//! run. Interleaved rows (C order, N × k with N ≥ k) are a transpose: sample s of
//! column p sits at s·k + p, so each column takes its samples of a block of whole rows
//! (about 128 KiB, in cache) by a stride of k, and writes them as one contiguous run.
//!
//! Cutting the block into tiles of a few rows that stay in L1 (each column then writes
//! runs of 16–20 samples, revisited per tile) was measured slower, not faster, on the
//! project's machine: 2·10⁵ × 100 into fresh memory, best of 5 in one sitting, 0.19–0.25 s
//! with tiles of 400–2048 values against 0.11–0.14 s for the whole block (BENCHMARKS.md
//! §13, branch `read2`): strided reads from L2 are cheap, and long runs of writes are
//! what the destination's cache lines want.

use std::mem::MaybeUninit;

use crate::io::arrays::Layout;

/// Where one column of an array read straight into place goes: column `column` of the
/// oriented array (0-based), written from sample 0 as scale × value + offset. The
/// destination need not hold values yet ([`super::fresh`]): once every flat index of
/// the array has been scattered, each of its N samples has been written.
pub(crate) struct Target<'a> {
    /// The column of the oriented array.
    pub column: usize,
    /// Its destination, N samples.
    pub into: &'a mut [MaybeUninit<f64>],
    /// (scale, offset).
    pub gain: (f64, f64),
}

/// Writes scale × value + offset of `values` into `into`.
pub(crate) fn put<'v>(
    into: &mut [MaybeUninit<f64>],
    values: impl Iterator<Item = &'v f64>,
    (scale, offset): (f64, f64),
) {
    for (out, &v) in into.iter_mut().zip(values) {
        out.write(scale * v + offset);
    }
}

impl Layout {
    /// [`Layout::place`] into `targets` instead of growing columns: the flat values
    /// `values`, which start at flat index `start`, each written with its target's gain
    /// at its sample (columns no target names are skipped).
    pub fn scatter(&self, start: usize, values: &[f64], targets: &mut [Target<'_>]) {
        let k = self.columns;
        if self.interleaved {
            if start.is_multiple_of(k) && values.len().is_multiple_of(k) {
                let (first, rows) = (start / k, values.len() / k);
                for t in targets.iter_mut() {
                    let into = &mut t.into[first..first + rows];
                    put(into, values[t.column..].iter().step_by(k), t.gain);
                }
            } else {
                for (offset, v) in values.iter().enumerate() {
                    let (s, p) = self.position(start + offset);
                    for t in targets.iter_mut().filter(|t| t.column == p) {
                        put(&mut t.into[s..=s], std::iter::once(v), t.gain);
                    }
                }
            }
        } else {
            let n = self.samples;
            let mut f = start;
            let mut rest = values;
            while !rest.is_empty() {
                let (s, p) = (f % n, f / n);
                let run = (n - s).min(rest.len());
                for t in targets.iter_mut().filter(|t| t.column == p) {
                    put(&mut t.into[s..s + run], rest[..run].iter(), t.gain);
                }
                rest = &rest[run..];
                f += run;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scatter` writes what `place` appends, with each target's gain, bit for bit, in
    /// every order and orientation and at any block boundary (whole rows or not), and a
    /// column read by two targets is written into both.
    #[test]
    fn scatter_writes_what_place_appends_with_the_gain() {
        for (r, c) in [(5, 3), (3, 5), (4, 1), (1, 4), (4, 4), (37, 5), (6, 29)] {
            for row_major in [true, false] {
                let layout = Layout::new(r, c, row_major).unwrap();
                let k = layout.columns;
                let flat: Vec<f64> = (0..r * c).map(|f| 0.1 * f as f64 - 0.7).collect();
                let mut placed = layout.allocate();
                layout.place(0, &flat, &mut placed);
                let gains = [(1.0, 0.0), (1e-3, 5e-3), (-2.5, 0.25)];
                for block in [1, 2, 3, k, 3 * k, r * c] {
                    let n = layout.samples;
                    let mut out = vec![vec![MaybeUninit::new(f64::NAN); n]; 2 * k];
                    let mut targets: Vec<Target<'_>> = out
                        .iter_mut()
                        .enumerate()
                        .map(|(j, into)| Target {
                            column: j % k,
                            into,
                            gain: gains[j % 3],
                        })
                        .collect();
                    for start in (0..r * c).step_by(block) {
                        let end = (start + block).min(r * c);
                        layout.scatter(start, &flat[start..end], &mut targets);
                    }
                    for (j, column) in out.iter().enumerate() {
                        let (scale, offset) = gains[j % 3];
                        let expected: Vec<u64> = placed[j % k]
                            .iter()
                            .map(|v| (scale * v + offset).to_bits())
                            .collect();
                        // SAFETY: initialised to NaN above.
                        let got: Vec<u64> = column
                            .iter()
                            .map(|v| unsafe { v.assume_init() }.to_bits())
                            .collect();
                        assert_eq!(got, expected, "{r}x{c} {row_major} {block} {j}");
                    }
                }
            }
        }
    }

    /// Targets that name a subset of the columns, in any order, get exactly their
    /// columns; the others are left as they were.
    #[test]
    fn scatter_fills_only_the_columns_named() {
        let layout = Layout::new(50, 7, true).unwrap();
        let flat: Vec<f64> = (0..350).map(|f| f as f64).collect();
        let mut out = vec![vec![MaybeUninit::new(-1.0); 50]; 3];
        let mut targets: Vec<Target<'_>> = out
            .iter_mut()
            .zip([6, 0, 3])
            .map(|(into, column)| Target {
                column,
                into,
                gain: (1.0, 0.0),
            })
            .collect();
        for start in (0..350).step_by(70) {
            layout.scatter(start, &flat[start..start + 70], &mut targets);
        }
        for (column, got) in [6, 0, 3].into_iter().zip(&out) {
            let expected: Vec<f64> = (0..50).map(|s| (s * 7 + column) as f64).collect();
            // SAFETY: initialised to −1 above.
            let got: Vec<f64> = got.iter().map(|v| unsafe { v.assume_init() }).collect();
            assert_eq!(got, expected);
        }
    }
}
