//! A record's matrix allocated without being zeroed first, for a reader that writes
//! every element of it exactly once (`model_file/measured.rs`: each column from the
//! file in place, [`super::in_place`], or from a table's column).
//!
//! `Mat::zeros` writes N·k zeros that the reader then overwrites: for the 2·10⁵ × 100
//! matrices of a 323 MB record, two passes of 160 MB each on the calling thread, the
//! first of which also takes every page fault of the fresh memory. Here the memory is
//! only reserved ([`Fresh::new`]), the columns are handed out as uninitialised slices
//! ([`Fresh::columns`]), and the matrix takes its shape only when the caller vouches
//! that every column was written ([`Fresh::assume_written`]), so that nothing can read
//! an element before it holds a value. The pages are then first touched by the reader,
//! on the threads that read the file.

use std::mem::MaybeUninit;

use faer::Mat;

/// An N × k matrix whose elements are not written yet (module doc).
pub(crate) struct Fresh {
    /// Room for N × k, shaped 0 × 0 until every column is written.
    mat: Mat<f64>,
    rows: usize,
    cols: usize,
}

impl Fresh {
    /// Room for `rows` × `cols` values, none of them written.
    pub fn new(rows: usize, cols: usize) -> Fresh {
        Fresh {
            mat: Mat::with_capacity(rows, cols),
            rows,
            cols,
        }
    }

    /// The k columns, N uninitialised values each, not overlapping.
    pub fn columns(&mut self) -> Vec<&mut [MaybeUninit<f64>]> {
        // The matrix's columns lie `col_stride` ≥ N elements apart in one allocation of
        // at least col_stride × k elements (faer's `with_capacity`), so the k slices of N
        // are inside it and disjoint.
        let stride = self.mat.col_stride().unsigned_abs();
        let base = self.mat.as_ptr_mut().cast::<MaybeUninit<f64>>();
        (0..self.cols)
            .map(|j| {
                // SAFETY: column j is elements j·stride .. j·stride + N of the allocation
                // (above), borrowed mutably from `self` for the slices' lifetime, and
                // MaybeUninit may hold anything.
                unsafe { std::slice::from_raw_parts_mut(base.add(j * stride), self.rows) }
            })
            .collect()
    }

    /// The N × k matrix.
    ///
    /// # Safety
    /// Every element of every column that [`Fresh::columns`] handed out must have been
    /// written.
    pub unsafe fn assume_written(mut self) -> Mat<f64> {
        // SAFETY: N and k are within the capacity reserved in `new`, and the caller
        // vouches that the elements now in bounds were written.
        unsafe { self.mat.set_dims(self.rows, self.cols) };
        self.mat
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns written one by one give the matrix with those columns, whatever the
    /// shape (an odd number of rows, one column, none).
    #[test]
    fn written_columns_are_the_matrix() {
        for (rows, cols) in [(7, 3), (1, 1), (0, 2), (5, 0), (1001, 4)] {
            let mut fresh = Fresh::new(rows, cols);
            for (j, column) in fresh.columns().into_iter().enumerate() {
                for (i, v) in column.iter_mut().enumerate() {
                    v.write((i * 10 + j) as f64);
                }
            }
            // SAFETY: every element was written just above.
            let mat = unsafe { fresh.assume_written() };
            assert_eq!(mat.shape(), (rows, cols));
            for j in 0..cols {
                for i in 0..rows {
                    assert_eq!(mat[(i, j)], (i * 10 + j) as f64);
                }
            }
        }
    }
}
