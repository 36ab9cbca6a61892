//! The gradients of one noise-robust row in the projection coefficients of each
//! channel, u_j = ∂(·)/∂c_j, gathered for the input work and every column: sums over
//! samples u = Σ_i g_i d_i (+ Σ_i g'_i b_i) become one product Dᵀ G (and Bᵀ G') per
//! window, then whitened to z = σ_j R⁻ᵀ u_j ([`ChannelSensitivity`]). Shared by the
//! row (`row.rs`) and the structural-damping column (`structural.rs`).

use std::collections::BTreeMap;

use faer::Mat;

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

    fn slot(&mut self, channel: usize, slot: usize) -> &mut Vec<f64> {
        let p = self.p;
        self.by_channel
            .entry(channel)
            .or_default()
            .entry(slot)
            .or_insert_with(|| vec![0.0; p])
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
        for (t, u) in self.slot(channel, slot).iter_mut().zip(u) {
            *t += scale * u;
        }
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
            let mut g = Mat::<f64>::zeros(self.count, keys.len());
            for (k, values) in sampled.values().enumerate() {
                g.col_as_slice_mut(k).copy_from_slice(values);
            }
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

/// Adds `scale` g to the sample vector of `key` in `sampled` (created as zeros).
fn accumulate(
    sampled: &mut BTreeMap<(usize, usize), Vec<f64>>,
    count: usize,
    key: (usize, usize),
    g: &[f64],
    scale: f64,
) {
    let target = sampled.entry(key).or_insert_with(|| vec![0.0; count]);
    for (t, g) in target.iter_mut().zip(g) {
        *t += scale * g;
    }
}
