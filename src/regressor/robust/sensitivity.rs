//! First-order noise sensitivity of one equation. With whitened vectors
//! z_{j,0} = σ_j R⁻ᵀ ∂b/∂c_j and z_{j,k} = σ_j R⁻ᵀ ∂A_k/∂c_j for channel j,
//!
//! ```text
//!   Var e(θ) = Σ_j ‖z_{j,0} − Σ_k θ_k z_{j,k}‖² + (force noise term),
//! ```
//!
//! with e = b − Σ θ_k A_k the equation's residual.
//!
//! **Scale.** Every entry of a whitened vector is of the size of (noise of x) × (force),
//! s_x s_f, so their squares are of size (s_x s_f)²: data in units that put s_x s_f near
//! 1e-160 (a force and a displacement of 1e-80 each) would square to below the smallest
//! f64 and the variance would read 0, and above 1e154 to infinity. The force term is kept
//! as a standard deviation and [`RowNoise::std`] forms the norm after dividing by the
//! largest entry (as `hypot` does), so the standard deviation of a residual is right
//! wherever it is itself a finite f64: the weighted fit, its χ² and its standard errors
//! are then the same at any data scale.

use serde::{Deserialize, Serialize};

/// The whitened sensitivities of one equation to the noise of one displacement channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelSensitivity {
    /// The displacement channel (DOF).
    pub channel: usize,
    /// σ_j R⁻ᵀ ∂b/∂c_j (empty when the input work does not read this channel).
    pub input: Vec<f64>,
    /// (column k, σ_j R⁻ᵀ ∂A_k/∂c_j) for the columns that read this channel.
    pub columns: Vec<(usize, Vec<f64>)>,
}

/// First-order noise sensitivity of one equation's residual.
///
/// **Storage.** A campaign holds one per row (tens of thousands), so the channels'
/// vectors are kept flat: one array of numbers and one of their layout, instead of a
/// vector per channel and per column (two allocations per row instead of about
/// seventeen; about 40 % of the bytes for four channels of two columns). Serialised as
/// the channels ([`ChannelSensitivity`]) they were made from.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(from = "Channels", into = "Channels")]
pub struct RowNoise {
    /// Per channel: the channel, p (the length of its combined vector), the length of
    /// its input vector (0 or p) and its column count, then (column k, length) per
    /// column.
    layout: Vec<u32>,
    /// The vectors in layout order: per channel its input vector, then each column's.
    values: Vec<f64>,
    /// Standard deviation of the input work from force-channel noise.
    pub force_std: f64,
}

/// [`RowNoise`] as channels, its serialised form.
#[derive(Serialize, Deserialize)]
struct Channels {
    /// Per displacement channel.
    channels: Vec<ChannelSensitivity>,
    /// Standard deviation of the input work from force-channel noise.
    force_std: f64,
}

impl From<Channels> for RowNoise {
    fn from(c: Channels) -> Self {
        RowNoise::new(&c.channels, c.force_std)
    }
}

impl From<RowNoise> for Channels {
    fn from(row: RowNoise) -> Self {
        Channels {
            channels: row.channels(),
            force_std: row.force_std,
        }
    }
}

/// A count or index of the layout: channels, columns and harmonic dimensions are far
/// below 2³² (a matrix with that many would not fit in memory).
fn entry(value: usize) -> u32 {
    // cannot fail: channels, columns and vector lengths are far below 2^32 (above)
    u32::try_from(value).expect("layout entry below 2^32")
}

impl RowNoise {
    /// The sensitivities of one equation to the noise of each displacement channel it
    /// reads, and the standard deviation of its input work from force noise.
    pub fn new(channels: &[ChannelSensitivity], force_std: f64) -> Self {
        let numbers = channels
            .iter()
            .map(|c| c.input.len() + c.columns.iter().map(|(_, z)| z.len()).sum::<usize>())
            .sum();
        let entries = channels.iter().map(|c| 4 + 2 * c.columns.len()).sum();
        let mut layout = Vec::with_capacity(entries);
        let mut values = Vec::with_capacity(numbers);
        for channel in channels {
            let p = channel
                .input
                .len()
                .max(channel.columns.first().map_or(0, |(_, z)| z.len()));
            layout.extend(
                [
                    channel.channel,
                    p,
                    channel.input.len(),
                    channel.columns.len(),
                ]
                .map(entry),
            );
            values.extend_from_slice(&channel.input);
            for (k, z) in &channel.columns {
                layout.extend([entry(*k), entry(z.len())]);
                values.extend_from_slice(z);
            }
        }
        RowNoise {
            layout,
            values,
            force_std,
        }
    }

    /// The sensitivities per channel, as given to [`RowNoise::new`].
    pub fn channels(&self) -> Vec<ChannelSensitivity> {
        let mut channels = Vec::new();
        self.each_channel(|channel, _, input, columns| {
            channels.push(ChannelSensitivity {
                channel,
                input: input.to_vec(),
                columns: columns.map(|(k, z)| (k, z.to_vec())).collect(),
            })
        });
        channels
    }

    /// Calls `f(channel, p, input, columns)` for each channel in order, `columns`
    /// yielding (k, vector).
    fn each_channel<'a>(&'a self, mut f: impl FnMut(usize, usize, &'a [f64], ColumnVectors<'a>)) {
        let (mut at, mut from) = (0, 0);
        while at + 4 <= self.layout.len() {
            let [channel, p, input, count] = [0, 1, 2, 3].map(|i| self.layout[at + i] as usize);
            let pairs = &self.layout[at + 4..at + 4 + 2 * count];
            let length: usize = pairs.chunks_exact(2).map(|c| c[1] as usize).sum();
            let own = &self.values[from..from + input + length];
            f(
                channel,
                p,
                &own[..input],
                ColumnVectors {
                    pairs,
                    values: &own[input..],
                },
            );
            at += 4 + 2 * count;
            from += input + length;
        }
    }

    /// √Var e(θ), the residual's standard deviation at coefficients `theta`, formed
    /// without squaring an entry of the data's size (module doc).
    pub fn std(&self, theta: &[f64]) -> f64 {
        self.std_with(theta, &mut Vec::new())
    }

    /// [`RowNoise::std`] with `buffer` as its scratch (cleared first): the same numbers,
    /// in the same order, without an allocation per row when one buffer serves many rows
    /// ([`crate::regressor::robust::NoiseModel::residual_std`]).
    pub(crate) fn std_with(&self, theta: &[f64], buffer: &mut Vec<f64>) -> f64 {
        buffer.clear();
        self.each_channel(|_, p, input, columns| {
            let start = buffer.len();
            buffer.resize(start + p, 0.0);
            let acc = &mut buffer[start..];
            for (a, z) in acc.iter_mut().zip(input) {
                *a += z;
            }
            for (k, z) in columns {
                for (a, z) in acc.iter_mut().zip(z) {
                    *a -= theta[k] * z;
                }
            }
        });
        buffer.push(self.force_std);
        norm(buffer)
    }

    /// Var e(θ) = [`RowNoise::std`]², for sums of variances over rows of one size.
    pub fn variance(&self, theta: &[f64]) -> f64 {
        self.std(theta).powi(2)
    }
}

/// The (column k, vector) of one channel of a [`RowNoise`], in order.
struct ColumnVectors<'a> {
    /// (k, length) per column.
    pairs: &'a [u32],
    /// The columns' vectors, one after the other.
    values: &'a [f64],
}

impl<'a> Iterator for ColumnVectors<'a> {
    type Item = (usize, &'a [f64]);

    fn next(&mut self) -> Option<Self::Item> {
        let (pair, rest) = self.pairs.split_first_chunk::<2>()?;
        let (z, values) = self.values.split_at(pair[1] as usize);
        (self.pairs, self.values) = (rest, values);
        Some((pair[0] as usize, z))
    }
}

/// ‖values‖₂ without overflow or underflow of the squares: the largest magnitude m
/// times √Σ (v/m)².
pub(crate) fn norm(values: &[f64]) -> f64 {
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest
        * values
            .iter()
            .map(|v| (v / largest).powi(2))
            .sum::<f64>()
            .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One channel, b-sensitivity (1, 0), column 0 sensitivity (0, 2), column 1 (1, 1):
    /// at θ = (0.5, 2), the residual's whitened vector is (1 − 2, 0 − 1 − 2) = (−1, −3).
    #[test]
    fn variance_is_the_squared_norm_of_the_combined_sensitivity() {
        let row = RowNoise::new(
            &[ChannelSensitivity {
                channel: 0,
                input: vec![1.0, 0.0],
                columns: vec![(0, vec![0.0, 2.0]), (1, vec![1.0, 1.0])],
            }],
            0.5,
        );
        assert!((row.variance(&[0.5, 2.0]) - (1.0 + 9.0 + 0.25)).abs() < 1e-14);
        // The same row at the data scales 1e-160 and 1e160: its standard deviation
        // scales exactly where the squares would underflow or overflow.
        for scale in [1e-160, 1e160] {
            let scaled = RowNoise::new(
                &[ChannelSensitivity {
                    channel: 0,
                    input: vec![scale, 0.0],
                    columns: vec![(0, vec![0.0, 2.0 * scale]), (1, vec![scale, scale])],
                }],
                0.5 * scale,
            );
            let std = scaled.std(&[0.5, 2.0]) / scale;
            assert!((std - 10.25f64.sqrt()).abs() < 1e-14, "{scale}: {std}");
        }
    }

    /// The flat storage gives the channels back as given, survives serialisation in the
    /// channels' form, and its standard deviation equals, bit for bit, the one formed
    /// from the channels' own vectors (channels with and without an input vector).
    #[test]
    fn flat_storage_is_the_channels() {
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let channels: Vec<ChannelSensitivity> = (0..4)
            .map(|j| ChannelSensitivity {
                channel: 3 * j,
                input: if j == 2 {
                    (0..5).map(|_| next()).collect()
                } else {
                    Vec::new()
                },
                columns: (0..2)
                    .map(|k| (k + j % 2, (0..5).map(|_| next()).collect()))
                    .collect(),
            })
            .collect();
        let row = RowNoise::new(&channels, 0.125);
        assert_eq!(row.channels(), channels);
        let bytes = serde_json::to_string(&row).unwrap();
        assert!(
            bytes.starts_with(r#"{"channels":[{"channel":0,"#),
            "{bytes}"
        );
        assert_eq!(serde_json::from_str::<RowNoise>(&bytes).unwrap(), row);
        let theta = [0.75, -1.5, 2.25];
        // the nested vectors' own arithmetic, in the same order
        let mut nested = Vec::new();
        for c in &channels {
            let p = c.input.len().max(c.columns[0].1.len());
            let mut acc = vec![0.0; p];
            for (a, z) in acc.iter_mut().zip(&c.input) {
                *a += z;
            }
            for (k, z) in &c.columns {
                for (a, z) in acc.iter_mut().zip(z) {
                    *a -= theta[*k] * z;
                }
            }
            nested.extend(acc);
        }
        nested.push(0.125);
        assert_eq!(row.std(&theta).to_bits(), norm(&nested).to_bits());
    }
}
