//! The gradients of one noise-robust row in the projection coefficients of each
//! channel, u_j = ∂(·)/∂c_j, gathered for the input work and every column: sums over
//! samples u = Σ_i g_i d_i (+ Σ_i g'_i b_i) become one product Dᵀ G (and Bᵀ G') per
//! window, then whitened to z = σ_j R⁻ᵀ u_j ([`ChannelSensitivity`]). Shared by the
//! row (`row.rs`) and the structural-damping column (`structural.rs`).

use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

use faer::Mat;

use crate::io::fresh::Fresh;
use crate::record::col;

use crate::regressor::robust::projected::ProjectedWindow;
use crate::regressor::robust::sensitivity::ChannelSensitivity;

/// Gradients ∂(·)/∂c_j in the projection coefficients of each channel j, collected for
/// the input work (slot 0) and each column k (slot k + 1).
///
/// Most contributions are sums over samples, u = Σ_i g_i d_i (+ Σ_i g'_i b_i) with d_i,
/// b_i the derivative and design rows: those are gathered per (channel, slot) as sample
/// vectors g and turned into coefficient gradients at the end by one product Dᵀ G (and
/// Bᵀ G'), a matrix product over every channel and slot at once rather than a pass over
/// the window's rows per element (on a 100-DOF chain, 200 elements: the rows were read
/// 200 times).
pub(super) struct Gradients {
    p: usize,
    count: usize,
    by_channel: BTreeMap<usize, BTreeMap<usize, Vec<f64>>>,
    /// Σ of sample-space gradients on the derivative rows, per (channel, slot).
    on_derivative: BTreeMap<(usize, usize), Vec<f64>>,
    /// The same on the design rows.
    on_design: BTreeMap<(usize, usize), Vec<f64>>,
}

impl Gradients {
    pub(super) fn new(p: usize, count: usize) -> Self {
        Gradients {
            p,
            count,
            by_channel: BTreeMap::new(),
            on_derivative: BTreeMap::new(),
            on_design: BTreeMap::new(),
        }
    }

    /// Adds `scale` Σ_i g_i d_i (d_i the derivative rows) to the gradient of (`channel`,
    /// `slot`); `g` holds the window's `count` samples.
    pub(super) fn add_on_derivative(&mut self, channel: usize, slot: usize, g: &[f64], scale: f64) {
        let count = self.count;
        accumulate(&mut self.on_derivative, count, (channel, slot), g, scale);
    }

    /// Adds `scale` Σ_i g_i b_i (b_i the design rows) to the gradient of (`channel`, `slot`).
    pub(super) fn add_on_design(&mut self, channel: usize, slot: usize, g: &[f64], scale: f64) {
        let count = self.count;
        accumulate(&mut self.on_design, count, (channel, slot), g, scale);
    }

    /// Adds `scale` u (a gradient in the coefficients) to (`channel`, `slot`).
    pub(super) fn add(&mut self, channel: usize, slot: usize, u: &[f64], scale: f64) {
        let slots = self.by_channel.entry(channel).or_default();
        add_scaled(slots.entry(slot), self.p, u, scale);
    }

    /// Turns the sample-space gradients into coefficient gradients: Dᵀ G and Bᵀ G'.
    pub(super) fn gather(&mut self, projected: &ProjectedWindow) {
        for (sampled, rows) in [
            (
                std::mem::take(&mut self.on_derivative),
                &projected.derivative,
            ),
            (std::mem::take(&mut self.on_design), &projected.design),
        ] {
            if sampled.is_empty() {
                continue;
            }
            let keys: Vec<(usize, usize)> = sampled.keys().copied().collect();
            let g = sampled_matrix(&sampled, self.count);
            // sequential: windows already run in parallel, and a split product's sums
            // would depend on the thread count
            let mut u = Mat::<f64>::zeros(self.p, keys.len());
            faer::linalg::matmul::matmul(
                u.as_mut(),
                faer::Accum::Replace,
                rows.as_ref().subrows(0, self.count).transpose(),
                g.as_ref(),
                1.0,
                faer::Par::Seq,
            );
            for (k, (channel, slot)) in keys.into_iter().enumerate() {
                self.add(channel, slot, col(u.as_ref(), k), 1.0);
            }
        }
    }

    pub(super) fn whiten(
        mut self,
        projected: &ProjectedWindow,
        sigma: &[f64],
    ) -> Vec<ChannelSensitivity> {
        self.gather(projected);
        self.by_channel
            .into_iter()
            .map(|(channel, slots)| {
                let mut input = Vec::new();
                let mut columns = Vec::new();
                for (slot, u) in slots {
                    let z = projected.whiten(&u, sigma[channel], channel);
                    if slot == 0 {
                        input = z;
                    } else {
                        columns.push((slot - 1, z));
                    }
                }
                ChannelSensitivity {
                    channel,
                    input,
                    columns,
                }
            })
            .collect()
    }
}

/// Adds `scale` g to the sample vector of `key` in `sampled` (absent: zeros).
fn accumulate(
    sampled: &mut BTreeMap<(usize, usize), Vec<f64>>,
    count: usize,
    key: (usize, usize),
    g: &[f64],
    scale: f64,
) {
    add_scaled(sampled.entry(key), count, g, scale);
}

/// Adds `scale` g to the vector of `entry`, of length `len`. An absent vector is made
/// as the zeros it stands for plus `scale` g, 0 + s·g (so −0 becomes +0, as in a zeroed
/// vector added to), in one pass without zero-filling it first; past the end of g it
/// is 0.
fn add_scaled<K: Ord>(entry: Entry<'_, K, Vec<f64>>, len: usize, g: &[f64], scale: f64) {
    match entry {
        Entry::Occupied(mut target) => {
            for (t, g) in target.get_mut().iter_mut().zip(g) {
                *t += scale * g;
            }
        }
        Entry::Vacant(target) => {
            let mut values: Vec<f64> = Vec::with_capacity(len);
            values.extend(g.iter().take(len).map(|g| 0.0 + scale * g));
            values.resize(len, 0.0);
            target.insert(values);
        }
    }
}

/// G (`count` × keys): the sample vectors of `sampled` as columns, in key order, each
/// written once into memory that is not zeroed first (`Fresh`); the same shape and
/// column stride as `Mat::zeros(count, keys)` (faer's capacity rounding), so the
/// product Dᵀ G sees the same matrix.
fn sampled_matrix(sampled: &BTreeMap<(usize, usize), Vec<f64>>, count: usize) -> Mat<f64> {
    let mut fresh = Fresh::new(count, sampled.len());
    for (column, values) in fresh.columns().into_iter().zip(sampled.values()) {
        let written = values.len().min(count);
        for (target, value) in column.iter_mut().zip(values) {
            target.write(*value);
        }
        // none: every vector has `count` values (`add_scaled`)
        for target in &mut column[written..] {
            target.write(0.0);
        }
    }
    // SAFETY: `Fresh::columns` handed out one column per vector of `sampled` (it has
    // `sampled.len()` columns), and every element of each was written just above.
    unsafe { fresh.assume_written() }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bookkeeping before `add_scaled` and `sampled_matrix`: a zeroed vector per
    /// key, added to, then copied into a zeroed G.
    fn reference(adds: &[((usize, usize), Vec<f64>, f64)], count: usize) -> Mat<f64> {
        let mut sampled: BTreeMap<(usize, usize), Vec<f64>> = BTreeMap::new();
        for (key, g, scale) in adds {
            let target = sampled.entry(*key).or_insert_with(|| vec![0.0; count]);
            for (t, g) in target.iter_mut().zip(g) {
                *t += scale * g;
            }
        }
        let mut g = Mat::<f64>::zeros(count, sampled.len());
        for (k, values) in sampled.values().enumerate() {
            g.col_as_slice_mut(k).copy_from_slice(values);
        }
        g
    }

    /// G is bitwise the zeroed layout's (shape, column stride, every bit): three
    /// channels, keys added out of order, one key three times, −0 samples (a first
    /// −0 must become +0, as 0 + (−0) does), row counts on and off faer's rounding.
    #[test]
    fn sampled_matrix_is_the_zeroed_layout() {
        for count in [1, 7, 8, 203] {
            let sample = |seed: f64| -> Vec<f64> {
                (0..count)
                    .map(|i| match i % 5 {
                        0 => -0.0,
                        1 => 0.0,
                        _ => (seed * (i as f64 + 1.0)).sin() * 1e3,
                    })
                    .collect()
            };
            let adds = vec![
                ((2, 3), sample(0.3), 1.0),
                ((0, 1), sample(0.7), -2.5),
                ((1, 0), sample(1.1), 1.0),
                ((2, 3), sample(1.3), -1.0),
                ((0, 0), sample(0.0), 1.0),
                ((0, 1), sample(1.7), 1e-300),
                ((2, 3), sample(2.9), 3.0),
                ((1, 4), sample(0.9), -0.0),
            ];
            let expected = reference(&adds, count);
            let mut sampled = BTreeMap::new();
            for (key, g, scale) in &adds {
                accumulate(&mut sampled, count, *key, g, *scale);
            }
            let ours = sampled_matrix(&sampled, count);
            assert_eq!(ours.shape(), expected.shape(), "rows {count}");
            assert_eq!(ours.col_stride(), expected.col_stride(), "rows {count}");
            assert_eq!(ours.row_stride(), expected.row_stride(), "rows {count}");
            for k in 0..ours.ncols() {
                for i in 0..count {
                    assert_eq!(
                        ours[(i, k)].to_bits(),
                        expected[(i, k)].to_bits(),
                        "rows {count}, column {k}, sample {i}"
                    );
                }
            }
            // the first add of a −0 sample: +0 in both
            assert_eq!(ours[(0, 0)].to_bits(), 0.0f64.to_bits());
        }
    }

    /// A coefficient gradient added to an absent slot is 0 + s·u, and to a present one
    /// adds s·u, as a zeroed vector of p did.
    #[test]
    fn added_gradients_are_the_zeroed_ones() {
        let p = 5;
        let mut gradients = Gradients::new(p, 3);
        let u = [-0.0, 1.5, -2.25, 0.0, 1e-310];
        let w = [3.0, -0.0, 0.5, -1.0, 2.0];
        gradients.add(4, 2, &u, 1.0);
        gradients.add(1, 0, &w, -0.5);
        gradients.add(4, 2, &w, 2.0);
        gradients.add(4, 1, &u[..3], 1.0);
        let mut expected: BTreeMap<(usize, usize), Vec<f64>> = BTreeMap::new();
        for (key, g, scale) in [
            ((4, 2), &u[..], 1.0),
            ((1, 0), &w[..], -0.5),
            ((4, 2), &w[..], 2.0),
            ((4, 1), &u[..3], 1.0),
        ] {
            let target = expected.entry(key).or_insert_with(|| vec![0.0; p]);
            for (t, g) in target.iter_mut().zip(g) {
                *t += scale * g;
            }
        }
        let ours: Vec<((usize, usize), Vec<u64>)> = gradients
            .by_channel
            .iter()
            .flat_map(|(c, slots)| {
                slots
                    .iter()
                    .map(move |(s, u)| ((*c, *s), u.iter().map(|v| v.to_bits()).collect()))
            })
            .collect();
        let theirs: Vec<((usize, usize), Vec<u64>)> = expected
            .into_iter()
            .map(|(k, u)| (k, u.iter().map(|v| v.to_bits()).collect()))
            .collect();
        assert_eq!(ours, theirs);
    }
}
