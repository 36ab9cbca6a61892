//! The weights w_i of one window's quadrature rule, held compactly.
//!
//! The rectangular and trapezoid rules give the same weight h to every sample but a
//! few at the ends,
//!
//! ```text
//!   w = [ head_0 … head_{a−1} | h h … h | tail_0 … tail_{c−1} ],    len = a + (interior) + c,
//! ```
//!
//! so they are stored as the two short ends and the one interior value: no vector of
//! N samples is made, filled or read (on a record of 1e6 samples that vector was 8 MB of
//! fresh pages per build). The spectral rule's weights differ at every sample and are
//! kept as they are.

use std::ops::Range;

use crate::terms::Weights;

/// A window's quadrature weights, w_i for i in 0..len.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum WindowWeights {
    /// One weight per sample.
    PerSample(Vec<f64>),
    /// `head`, then `interior` repeated, then `tail`: `len` weights in all.
    Banded {
        head: Vec<f64>,
        interior: f64,
        tail: Vec<f64>,
        len: usize,
    },
}

impl WindowWeights {
    /// Weights that are `interior` everywhere but `head` (first) and `tail` (last).
    pub(crate) fn banded(head: Vec<f64>, interior: f64, tail: Vec<f64>, len: usize) -> Self {
        debug_assert!(head.len() + tail.len() <= len);
        WindowWeights::Banded {
            head,
            interior,
            tail,
            len,
        }
    }

    /// How many samples the weights cover.
    pub(crate) fn len(&self) -> usize {
        match self {
            WindowWeights::PerSample(w) => w.len(),
            WindowWeights::Banded { len, .. } => *len,
        }
    }

    /// The same weights followed by zeros up to `len` samples (a window that reads
    /// samples its rule does not weigh).
    pub(crate) fn padded_to(self, len: usize) -> Self {
        match self {
            WindowWeights::PerSample(mut w) => {
                if w.len() < len {
                    w.resize(len, 0.0);
                }
                WindowWeights::PerSample(w)
            }
            WindowWeights::Banded {
                head,
                interior,
                mut tail,
                len: old,
            } => {
                if old < len {
                    tail.resize(tail.len() + len - old, 0.0);
                }
                WindowWeights::banded(head, interior, tail, len.max(old))
            }
        }
    }

    /// The samples `rows` cut into runs that each carry their weights: at most one run
    /// of the interior (one value, never read per sample) between the explicit ends.
    pub(crate) fn pieces(&self, rows: Range<usize>) -> impl Iterator<Item = Piece<'_>> {
        let mut pieces: [Option<Piece<'_>>; 3] = [None, None, None];
        match self {
            WindowWeights::PerSample(w) => {
                pieces[0] = Some(Piece {
                    weights: Weights::PerSample(&w[rows.clone()]),
                    rows,
                });
            }
            WindowWeights::Banded {
                head,
                interior,
                tail,
                len,
            } => {
                let interior_rows = head.len()..len - tail.len();
                let clamp = |i: usize| i.clamp(rows.start, rows.end);
                let before = rows.start..clamp(interior_rows.start);
                let inside = clamp(interior_rows.start)..clamp(interior_rows.end);
                let after = clamp(interior_rows.end)..rows.end;
                if !before.is_empty() {
                    pieces[0] = Some(Piece {
                        weights: Weights::PerSample(&head[before.clone()]),
                        rows: before,
                    });
                }
                if !inside.is_empty() {
                    pieces[1] = Some(Piece {
                        weights: Weights::Uniform(*interior),
                        rows: inside,
                    });
                }
                if !after.is_empty() {
                    let offset = interior_rows.end;
                    pieces[2] = Some(Piece {
                        weights: Weights::PerSample(
                            &tail[after.start - offset..after.end - offset],
                        ),
                        rows: after,
                    });
                }
            }
        }
        pieces.into_iter().flatten()
    }

    /// Every weight, one per sample.
    pub(crate) fn to_vec(&self) -> Vec<f64> {
        match self {
            WindowWeights::PerSample(w) => w.clone(),
            WindowWeights::Banded {
                head,
                interior,
                tail,
                len,
            } => {
                let mut w = Vec::with_capacity(*len);
                w.extend_from_slice(head);
                w.resize(len - tail.len(), *interior);
                w.extend_from_slice(tail);
                w
            }
        }
    }
}

/// Consecutive samples of a window and their weights.
#[derive(Debug, Clone)]
pub(crate) struct Piece<'a> {
    /// The samples, as indices into the window.
    pub(crate) rows: Range<usize>,
    /// Their weights: one value for all, or one per sample of `rows`.
    pub(crate) weights: Weights<'a>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pieces of any block of samples, expanded, are exactly that block of the full
    /// vector: head, interior and tail meet without gap or overlap.
    #[test]
    fn pieces_cover_every_block_with_the_right_weights() {
        let weights = WindowWeights::banded(vec![0.5, 0.7], 1.0, vec![0.3, 0.2, 0.1], 12);
        let full = weights.to_vec();
        assert_eq!(full.len(), 12);
        assert_eq!(&full[..2], &[0.5, 0.7]);
        assert_eq!(&full[9..], &[0.3, 0.2, 0.1]);
        for start in 0..12 {
            for end in start..=12 {
                let mut expanded = Vec::new();
                let mut next = start;
                for piece in weights.pieces(start..end) {
                    assert_eq!(piece.rows.start, next, "gap or overlap at {start}..{end}");
                    next = piece.rows.end;
                    match piece.weights {
                        Weights::Uniform(w) => expanded.extend(piece.rows.map(|_| w)),
                        Weights::PerSample(w) => {
                            assert_eq!(w.len(), piece.rows.len());
                            expanded.extend_from_slice(w);
                        }
                    }
                }
                assert_eq!(next.max(start), end);
                assert_eq!(expanded, full[start..end], "block {start}..{end}");
            }
        }
    }

    /// Padding appends zeros at the end, for both representations.
    #[test]
    fn padding_appends_zeros() {
        let banded = WindowWeights::banded(vec![], 2.0, vec![1.0], 4).padded_to(6);
        assert_eq!(banded.to_vec(), vec![2.0, 2.0, 2.0, 1.0, 0.0, 0.0]);
        let explicit = WindowWeights::PerSample(vec![1.0, 2.0]).padded_to(3);
        assert_eq!(explicit.to_vec(), vec![1.0, 2.0, 0.0]);
        assert_eq!(explicit.len(), 3);
    }
}
