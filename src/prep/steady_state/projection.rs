//! The denoised states the steady-state check compares: each channel projected on the
//! harmonics of ω = 2π/T that stand above its record's noise, separately over single
//! periods of a compared span.
//!
//! Over a span of k' whole periods starting at the (fractional) sample position u₀:
//!
//! 1. the harmonic orders S and the per-sample noise σ̂_j of every channel j are the
//!    record's (`prep/fourier/record_noise.rs`: selected on a few spans spread over the
//!    record, σ̂_j the median of their out-of-band estimates), the same for every span;
//! 2. each period [u₀ + pL, u₀ + (p + 1)L), L = T/h, is projected over the samples
//!    inside it (half open, so neighbouring periods share none), t measured from the
//!    period's first sample:
//!
//!    ```text
//!      x̂(t) = bᵀ(t) c_x,   b(t) = [1, cos q₁ωt, sin q₁ωt, …],   c_x = (BᵀB)⁻¹ Bᵀ x,
//!      v̂(t) = bᵀ(t) c_v,   c_v = J c_x,   (c_v)_{cos q} = qω (c_x)_{sin q},
//!                                          (c_v)_{sin q} = −qω (c_x)_{cos q},
//!      Cov [c_x; c_v] = σ̂_j² [I; J] (RᵀR)⁻¹ [I; J]ᵀ        (B = QR, white noise);
//!    ```
//!
//! 3. the whole span's fit on S measures what no harmonic of ω explains: the
//!    non-harmonic RMS per channel, r_j = √max(0, RSS_j/(m − p) − σ̂_j²), and its
//!    significance RSS_j / ((m − p) σ̂_j²) (≈ 1 for white noise alone).
//!
//! Every channel is described by displacement and velocity coefficients in one basis
//! with their joint covariance. A channel measured as velocity or acceleration
//! ([`crate::record::Sensor`]) is projected as measured, where its noise is white, and
//! mapped per kept harmonic into that form, c_x = S c_m:
//!
//! ```text
//!   velocity:      (c_x)_{cos q} = −(c_m)_{sin q}/(qω),   (c_x)_{sin q} = (c_m)_{cos q}/(qω),
//!   acceleration:  (c_x)_{cos q} = −(c_m)_{cos q}/(qω)²,  (c_x)_{sin q} = −(c_m)_{sin q}/(qω)²,
//! ```
//!
//! the constant term set to zero (a mean position cannot be known from them), and
//! Cov [c_x; c_v] = σ̂_j² [I; J] S (RᵀR)⁻¹ Sᵀ [I; J]ᵀ. Their non-harmonic RMS is given
//! as the displacement it would be at the drive frequency, r_j/ω^d (d = 1 for velocity,
//! 2 for acceleration), which overstates content above ω and understates it below.
//!
//! **The span's residual from its periods.** Where a period holds a whole number
//! N = T/h of samples, every period of a span has the same design B (the basis is
//! T-periodic), so the span's design is P copies of it and its fit is the mean of the
//! periods' fits, c̄ = (1/P) Σ_p c_p. Its residual splits into the periods' own
//! residuals and the spread of their fits about the mean,
//!
//! ```text
//!   RSS = Σ_p RSS_p + Σ_p ‖R (c_p − c̄)‖²,   RSS_p = ‖x_p − s_p 1‖² − ‖R (c_p − s_p e₀)‖²,
//! ```
//!
//! (RᵀR = BᵀB, s_p the period's first sample, which keeps an offset out of the
//! difference of sums of squares), so the span is never read again: each period is read
//! once for Bᵀx and ‖x − s 1‖², whichever spans it is in. Otherwise the span is fitted
//! whole on its own table (`table.rs`) for its residual.
//!
//! **Cost.** O(m p) per channel and period, on a table of the basis shared by every
//! period of a record (t measured from a period's first sample): no transform, no
//! selection per span. The half ranges of x̂ and v̂ over each period (the amplitudes
//! the mismatches are relative to: only the largest over the channels is used) cost
//! O(N p) per channel, for the channels whose bounds (by amplitudes, then from a grid
//! of every eighth sample) can reach the largest (usually one or two: the others are
//! skipped, `table.rs`, `range_grid.rs`). A period's covariance per sensor kind (σ̂_j²
//! times a unit covariance shared by the channels of that kind) depends on its length
//! and harmonics only (`PeriodBasis`). A period's channels are made once, side by side
//! ([`PeriodChannels`]), and shared by the spans it is in.

use std::sync::Arc;

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::fourier::{HarmonicBasis, RecordNoise, whole_samples};
use crate::record::{Record, Sensor, col};

use super::range_grid::RangeGrid;
use super::table::HarmonicTable;

/// One channel over one period: coefficients of x̂ and v̂ in the basis b(t), and their
/// joint covariance (a view of its period's [`PeriodChannels`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelProjection<'a> {
    /// c_x: [a₀, a_q, b_q, …] of the displacement (p = 2|S| + 1).
    pub displacement: &'a [f64],
    /// c_v: the velocity's coefficients in the same basis (its a₀ is 0).
    pub velocity: &'a [f64],
    /// Cov [c_x; c_v] / σ̂_j² (2p × 2p), shared by the period's channels of one sensor
    /// kind.
    pub unit_covariance: &'a Mat<f64>,
    /// σ̂_j², the channel's noise variance per sample.
    pub noise_variance: f64,
}

impl ChannelProjection<'_> {
    /// The variance of g_xᵀ c_x + g_vᵀ c_v.
    pub fn variance(&self, g_x: &[f64], g_v: &[f64]) -> f64 {
        self.scaled(self.unit_variance(g_x, g_v))
    }

    /// gᵀ (Cov / σ̂_j²) g for g = [g_x; g_v]: the same for every channel that shares the
    /// unit covariance.
    pub fn unit_variance(&self, g_x: &[f64], g_v: &[f64]) -> f64 {
        let p = g_x.len();
        let g = |k: usize| if k < p { g_x[k] } else { g_v[k - p] };
        let unit = self.unit_covariance;
        let mut sum = 0.0;
        for a in 0..2 * p {
            let ga = g(a);
            if ga != 0.0 {
                for b in 0..2 * p {
                    sum += ga * unit[(a, b)] * g(b);
                }
            }
        }
        sum
    }

    /// The variance from its [`ChannelProjection::unit_variance`].
    pub fn scaled(&self, unit_variance: f64) -> f64 {
        (self.noise_variance * unit_variance).max(0.0)
    }
}

/// Every channel of one period, their coefficients side by side: made once per period
/// and shared by every span the period is in.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodChannels {
    /// p, the coefficients per channel.
    columns: usize,
    /// c_x of every channel, channel j's at j p..(j + 1) p.
    displacement: Vec<f64>,
    /// c_v of every channel, as `displacement`.
    velocity: Vec<f64>,
    /// Per channel, the unit covariance of its sensor kind.
    units: Arc<[Arc<Mat<f64>>]>,
    /// Per channel, σ̂_j².
    noise_variance: Arc<[f64]>,
}

impl PeriodChannels {
    /// The number of channels.
    pub fn len(&self) -> usize {
        self.units.len()
    }

    /// Whether the period has no channel.
    pub fn is_empty(&self) -> bool {
        self.units.is_empty()
    }

    /// Channel `j` (0-based).
    pub fn channel(&self, j: usize) -> ChannelProjection<'_> {
        let at = j * self.columns..(j + 1) * self.columns;
        ChannelProjection {
            displacement: &self.displacement[at.clone()],
            velocity: &self.velocity[at],
            unit_covariance: &self.units[j],
            noise_variance: self.noise_variance[j],
        }
    }

    /// Per channel, Cov [c_x; c_v] / σ̂_j² (shared by the channels of a sensor kind).
    pub fn unit_covariances(&self) -> &[Arc<Mat<f64>>] {
        &self.units
    }

    /// Per channel, σ̂_j².
    pub fn noise_variances(&self) -> &[f64] {
        &self.noise_variance
    }

    /// Every channel, in order.
    pub fn iter(&self) -> impl Iterator<Item = ChannelProjection<'_>> {
        (0..self.len()).map(|j| self.channel(j))
    }

    /// c_x of every channel, in order.
    pub fn displacements(&self) -> std::slice::ChunksExact<'_, f64> {
        self.displacement.chunks_exact(self.columns)
    }

    /// c_v of every channel, in order.
    pub fn velocities(&self) -> std::slice::ChunksExact<'_, f64> {
        self.velocity.chunks_exact(self.columns)
    }
}

/// The projection of one period of the span.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodProjection {
    /// First sample fitted (record index).
    pub first: usize,
    /// Samples fitted.
    pub samples: usize,
    /// Every channel (DOF), shared by every span the period is in.
    pub channels: Arc<PeriodChannels>,
    /// The largest ½ range of x̂ over the period's samples among its channels.
    pub half_range_displacement: f64,
    /// The largest ½ range of v̂ over the period's samples among its channels.
    pub half_range_velocity: f64,
}

/// The projections of a compared span.
#[derive(Debug, Clone, PartialEq)]
pub struct StateProjection {
    /// ω = 2π/T.
    pub omega: f64,
    /// Sampling step h.
    pub step: f64,
    /// Harmonic orders S kept (ascending, starting with 1).
    pub orders: Vec<usize>,
    /// σ̂_j, the noise standard deviation per sample of each channel.
    pub noise_std: Vec<f64>,
    /// The requested periods, in the order asked.
    pub periods: Vec<PeriodProjection>,
    /// r_j, the non-harmonic RMS of each channel over the whole span.
    pub non_harmonic: Vec<f64>,
    /// RSS_j / ((m − p) σ̂_j²) of each channel over the whole span.
    pub residual_ratio: Vec<f64>,
    /// m − p, the residual degrees of freedom of the whole-span fit.
    pub residual_dof: usize,
}

impl StateProjection {
    /// b(t) = [1, cos q₁ωt, sin q₁ωt, …].
    pub fn row(&self, t: f64) -> Vec<f64> {
        let mut row = Vec::with_capacity(2 * self.orders.len() + 1);
        row.push(1.0);
        for &q in &self.orders {
            let (s, c) = (q as f64 * self.omega * t).sin_cos();
            row.push(c);
            row.push(s);
        }
        row
    }

    /// b(t) at the fractional sample position `at` for a period fitted from sample
    /// `first` (t = (at − first) h, negative before it: the series is periodic).
    pub fn row_at_sample(&self, first: usize, at: f64) -> Vec<f64> {
        self.row((at - first as f64) * self.step)
    }

    /// Half the range of x̂ (and of v̂) over the samples of every projected period, the
    /// largest over the channels.
    pub fn amplitudes(&self) -> (f64, f64) {
        self.periods.iter().fold((0.0f64, 0.0f64), |(ax, av), p| {
            (
                ax.max(p.half_range_displacement),
                av.max(p.half_range_velocity),
            )
        })
    }
}

/// A sample position within round-off of a whole number is that number.
pub(super) fn snap(position: f64) -> f64 {
    let whole = position.round();
    if (position - whole).abs() <= 1e-9 * position.abs().max(1.0) {
        whole
    } else {
        position
    }
}

/// The samples of [u, u + length) (half open, positions in samples), clamped to the
/// record's `available` samples.
fn samples_in(u: f64, length: f64, available: usize) -> (usize, usize) {
    let first = snap(u).ceil().max(0.0) as usize;
    let end = (snap(u + length).ceil().max(0.0) as usize).min(available);
    (first.min(end), end)
}

/// The measured signals of `record` and their sensors, where the noise is white
/// (module doc).
fn signals(record: &Record) -> (faer::MatRef<'_, f64>, Vec<Sensor>) {
    match record.measured_motion() {
        Some(m) => (m.signals.as_ref(), m.sensors.clone()),
        None => (
            record.displacements(),
            vec![Sensor::Displacement; record.dofs()],
        ),
    }
}

/// Steps 1 and 3 of the module doc over a compared span: the harmonics kept, the noise,
/// and what no harmonic explains.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SpanFit {
    /// Harmonic orders S kept.
    pub(super) orders: Vec<usize>,
    /// σ̂_j per channel.
    noise_std: Vec<f64>,
    /// r_j per channel.
    non_harmonic: Vec<f64>,
    /// RSS_j / ((m − p) σ̂_j²) per channel.
    residual_ratio: Vec<f64>,
    /// m − p.
    residual_dof: usize,
}

/// The samples (first, count) of period `k` of the span from the sample position
/// `origin` of `record`.
pub(super) fn period_samples(record: &Record, origin: f64, k: usize) -> (usize, usize) {
    let length = record.period() / record.step();
    let (first, end) = samples_in(origin + k as f64 * length, length, record.samples());
    (first, end - first)
}

/// Whether the span of `periods` periods from the sample position `origin` of `record`
/// is made of periods of N = T/h whole samples, each with the same design, so that its
/// residual comes from its periods' fits (module doc): N whole and the span exactly P N
/// samples from a whole sample. Otherwise the span is fitted whole.
pub(super) fn from_periods(record: &Record, origin: f64, periods: usize) -> bool {
    let Some(n) = whole_samples(record.step(), record.period()) else {
        return false;
    };
    let length = record.period() / record.step();
    let (first, end) = samples_in(origin, periods as f64 * length, record.samples());
    end - first == periods * n
}

/// The harmonic orders of `record`'s `noise` that a period of `rows` samples holds.
pub(super) fn period_orders(
    record: &Record,
    noise: &RecordNoise,
    rows: usize,
) -> Result<Vec<usize>> {
    noise.orders_for(rows, record.step(), record.period(), None)
}

/// Step 3 over a span of P periods of N whole samples from their fits (in time order,
/// on one [`PeriodBasis`]): RSS = Σ_p RSS_p + Σ_p ‖R (c_p − c̄)‖² (module doc).
pub(super) fn fit_span_from(
    record: &Record,
    noise: &RecordNoise,
    basis: &PeriodBasis,
    periods: &[&PeriodFit],
) -> SpanFit {
    let p = basis.table.columns();
    let channels = noise.motion_std.len();
    // c̄ of every channel, side by side as the periods' coefficients
    let mut mean = vec![0.0; channels * p];
    for fit in periods {
        for (m, c) in mean.iter_mut().zip(&fit.measured) {
            *m += c;
        }
    }
    let count = periods.len() as f64;
    mean.iter_mut().for_each(|m| *m /= count);
    // per channel, Σ_p (RSS_p + ‖R (c_p − c̄)‖²) in the order of the periods
    let mut residuals = vec![0.0; channels];
    let mut spread = vec![0.0; p];
    for fit in periods {
        let coefficients = fit.measured.chunks_exact(p).zip(mean.chunks_exact(p));
        for ((residual, within), (c, m)) in residuals.iter_mut().zip(&fit.within).zip(coefficients)
        {
            for ((s, c), m) in spread.iter_mut().zip(c).zip(m) {
                *s = c - m;
            }
            *residual += within + basis.table.norm_squared(&spread);
        }
    }
    let samples = periods.iter().map(|fit| fit.samples).sum();
    span_fit(record, noise, basis.orders.clone(), samples, residuals)
}

/// Step 3 over the span of `periods` whole periods from the sample position `origin` of
/// `record`, fitted whole on its own table (N = T/h not whole).
pub(super) fn fit_span(
    record: &Record,
    noise: &RecordNoise,
    origin: f64,
    periods: usize,
) -> Result<SpanFit> {
    let (step, period) = (record.step(), record.period());
    let length = period / step;
    let (x, _) = signals(record);
    let (first, end) = samples_in(origin, periods as f64 * length, record.samples());
    let m = end - first;
    let orders = period_orders(record, noise, period_samples(record, origin, 0).1)?;
    let omega = 2.0 * std::f64::consts::PI / period;
    let basis = HarmonicBasis::with_orders(omega, orders.clone(), step, m)?;
    let table = HarmonicTable::new(&basis, m);
    let residuals = (0..x.ncols())
        .map(|j| {
            let samples = &col(x, j)[first..end];
            table.residual_sum_of_squares(&table.fit(samples), samples)
        })
        .collect();
    Ok(span_fit(record, noise, orders, m, residuals))
}

/// A span's [`SpanFit`] on `orders` with the record's noise, from its residual sums of
/// squares over its m = `samples` samples, per channel.
fn span_fit(
    record: &Record,
    noise: &RecordNoise,
    orders: Vec<usize>,
    samples: usize,
    residuals: Vec<f64>,
) -> SpanFit {
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let (_, sensors) = signals(record);
    let sigma = noise.motion_std.clone();
    let p = 2 * orders.len() + 1;
    let dof = samples.saturating_sub(p).max(1);
    let mut non_harmonic = Vec::with_capacity(residuals.len());
    let mut residual_ratio = Vec::with_capacity(residuals.len());
    for (j, rss) in residuals.into_iter().enumerate() {
        let mean_square = rss / dof as f64;
        let as_displacement = omega.powi(sensors[j].order() as i32);
        non_harmonic.push((mean_square - sigma[j] * sigma[j]).max(0.0).sqrt() / as_displacement);
        residual_ratio.push(if mean_square == 0.0 {
            0.0
        } else {
            mean_square / (sigma[j] * sigma[j])
        });
    }
    SpanFit {
        orders,
        noise_std: sigma,
        non_harmonic,
        residual_ratio,
        residual_dof: dof,
    }
}

/// Step 2 for one period: what it gives every span it is in (a one-period window's
/// period is compared with the previous one and with the next, so it is fitted once for
/// both, and its channels' projections are shared by both).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PeriodFit {
    /// First sample fitted (record index).
    first: usize,
    /// Samples fitted.
    samples: usize,
    /// Per channel: c_x, c_v, the unit covariance and the record's σ̂_j².
    channels: Arc<PeriodChannels>,
    /// c of the signal as measured (before the map to displacements), channel j's p
    /// coefficients at j p.
    measured: Vec<f64>,
    /// Per channel, RSS_p of the period's own fit (module doc).
    within: Vec<f64>,
    /// The largest ½ ranges of x̂ and of v̂ over the period's samples among the channels.
    half_ranges: (f64, f64),
}

/// The map of one sensor kind's coefficients to [c_x; c_v] and their unit covariance.
struct SensorKind {
    sensor: Sensor,
    /// F = [I; J] S (2p × p).
    full: Mat<f64>,
    /// Per row i of F, its nonzero entries (k, F_ik) in the order of k, padded to two
    /// with (k, 0): [I; J] S is a 2 × 2 block per harmonic, so a row holds one or two.
    /// `None` when a row holds more, or an entry is not finite.
    pairs: Option<Vec<[(usize, f64); 2]>>,
    /// F (RᵀR)⁻¹ Fᵀ.
    unit: Arc<Mat<f64>>,
}

impl SensorKind {
    /// [c_x; c_v] = F c into `c_x` and `c_v` (zeroed), each entry Σ_k F_ik c_k added to
    /// 0.0 in the order of k over the c_k ≠ 0. Where F's entries and every c_k are
    /// finite, a term F_ik c_k with F_ik = 0 or c_k = 0 is a zero, which added to a sum
    /// that starts at +0.0 changes nothing (the sum is never −0.0): so each entry is its
    /// two terms of [`SensorKind::pairs`]. Otherwise every column is used (0 · ∞ is NaN).
    fn map(&self, c: &[f64], c_x: &mut [f64], c_v: &mut [f64]) {
        if let Some(pairs) = self
            .pairs
            .as_ref()
            .filter(|_| c.iter().all(|c| c.is_finite()))
        {
            let (top, bottom) = pairs.split_at(c_x.len());
            for (pairs, out) in [(top, c_x), (bottom, c_v)] {
                for (pair, out) in pairs.iter().zip(out) {
                    let mut sum = 0.0;
                    sum += pair[0].1 * c[pair[0].0];
                    sum += pair[1].1 * c[pair[1].0];
                    *out = sum;
                }
            }
            return;
        }
        let p = c.len();
        for (k, &ck) in c.iter().enumerate() {
            if ck != 0.0 {
                let (top, bottom) = self.full.col_as_slice(k).split_at(p);
                for (s, f) in c_x.iter_mut().zip(top) {
                    *s += f * ck;
                }
                for (s, f) in c_v.iter_mut().zip(bottom) {
                    *s += f * ck;
                }
            }
        }
    }
}

/// What step 2 needs for periods of `rows` samples projected on `orders`, the same for
/// every such period of a record (t is measured from a period's first sample, so the
/// basis values do not depend on where it starts): the table of the basis, [I; J] S and
/// the unit covariance per sensor kind, and the record's sensors.
pub(super) struct PeriodBasis {
    table: HarmonicTable,
    /// The harmonic orders S of the basis.
    orders: Vec<usize>,
    /// Whether (BᵀB)⁻¹ is finite.
    regular: bool,
    /// Per sensor kind present: [I; J] S and its unit covariance.
    kinds: Vec<SensorKind>,
    /// The sensor kind of each channel (its index in `kinds`; empty when not `regular`).
    kind_of: Vec<usize>,
    /// Per channel, the unit covariance of its sensor kind (empty when not `regular`).
    units: Arc<[Arc<Mat<f64>>]>,
    /// Per channel, the record's σ̂_j².
    noise_variance: Arc<[f64]>,
    /// The table on a coarse grid, for the half ranges.
    grid: RangeGrid,
}

/// The [`PeriodBasis`] of `record` for periods of `rows` samples on `orders`, with the
/// record's `noise`.
pub(super) fn period_basis(
    record: &Record,
    noise: &RecordNoise,
    rows: usize,
    orders: &[usize],
) -> Result<PeriodBasis> {
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let (_, sensors) = signals(record);
    let basis = HarmonicBasis::with_orders(omega, orders.to_vec(), record.step(), rows)?;
    let table = HarmonicTable::new(&basis, rows);
    let grid = RangeGrid::new(&basis, table.design());
    let p = table.columns();
    let gram_inverse = table.gram_inverse();
    let regular = (0..p).all(|k| gram_inverse[(k, k)].is_finite());
    // [I; J]: rows 0..p give c_x, rows p..2p give c_v = J c_x.
    let mut map = Mat::<f64>::zeros(2 * p, p);
    for k in 0..p {
        map[(k, k)] = 1.0;
    }
    for (q, &order) in orders.iter().enumerate() {
        let qw = order as f64 * omega;
        map[(p + 2 * q + 1, 2 * q + 2)] = qw;
        map[(p + 2 * q + 2, 2 * q + 1)] = -qw;
    }
    // [I; J] S and its unit covariance [I; J] S (RᵀR)⁻¹ Sᵀ [I; J]ᵀ, once per sensor
    // kind present.
    let mut kinds: Vec<SensorKind> = Vec::new();
    let (mut kind_of, mut units) = (Vec::new(), Vec::new());
    if regular {
        for &sensor in &sensors {
            let kind = match kinds.iter().position(|kind| kind.sensor == sensor) {
                Some(kind) => kind,
                None => {
                    let full = &map * to_displacement(sensor, orders, omega);
                    let unit = &full * &gram_inverse * full.transpose();
                    let pairs = (0..2 * p)
                        .map(|i| {
                            let nonzero: Vec<(usize, f64)> = (0..p)
                                .filter(|&k| full[(i, k)] != 0.0)
                                .map(|k| (k, full[(i, k)]))
                                .collect();
                            let finite = nonzero.iter().all(|(_, f)| f.is_finite());
                            match nonzero[..] {
                                [] if finite => Some([(0, 0.0), (0, 0.0)]),
                                [one] if finite => Some([one, (one.0, 0.0)]),
                                [one, two] if finite => Some([one, two]),
                                _ => None,
                            }
                        })
                        .collect();
                    kinds.push(SensorKind {
                        sensor,
                        full,
                        pairs,
                        unit: Arc::new(unit),
                    });
                    kinds.len() - 1
                }
            };
            kind_of.push(kind);
            units.push(Arc::clone(&kinds[kind].unit));
        }
    }
    let noise_variance = noise.motion_std.iter().map(|s| s * s).collect();
    Ok(PeriodBasis {
        table,
        orders: orders.to_vec(),
        regular,
        kinds,
        kind_of,
        units: units.into(),
        noise_variance,
        grid,
    })
}

/// Step 2 for the period of `record` from sample `first`, with its [`PeriodBasis`], by
/// least squares on the basis' table, and the period's own residual RSS_p.
pub(super) fn fit_period(record: &Record, basis: &PeriodBasis, first: usize) -> Result<PeriodFit> {
    let (x, _) = signals(record);
    let table = &basis.table;
    let (rows, p) = (table.rows(), table.columns());
    if !basis.regular {
        return Err(Error::Numerical {
            stage: "steady-state check".into(),
            detail: format!(
                "the harmonic projection of the {rows} samples from sample {first} is singular"
            ),
        });
    }
    let channels = x.ncols();
    let mut measured = vec![0.0; channels * p];
    let within = measured
        .chunks_exact_mut(p)
        .enumerate()
        .map(|(j, c)| table.fit_and_residual(&col(x, j)[first..first + rows], c))
        .collect();
    let (mut displacement, mut velocity) = (vec![0.0; channels * p], vec![0.0; channels * p]);
    let states = displacement
        .chunks_exact_mut(p)
        .zip(velocity.chunks_exact_mut(p));
    for ((c, &kind), (c_x, c_v)) in measured.chunks_exact(p).zip(&basis.kind_of).zip(states) {
        basis.kinds[kind].map(c, c_x, c_v);
    }
    // the largest half ranges of x̂ and v̂ over the period's samples (evaluated on the
    // channels that can hold them, `table.rs`)
    let states: Vec<(&[f64], &[f64])> = displacement
        .chunks_exact(p)
        .zip(velocity.chunks_exact(p))
        .collect();
    let half_ranges = table.largest_half_ranges(&states, rows, Some(&basis.grid));
    let channels = Arc::new(PeriodChannels {
        columns: p,
        displacement,
        velocity,
        units: Arc::clone(&basis.units),
        noise_variance: Arc::clone(&basis.noise_variance),
    });
    Ok(PeriodFit {
        first,
        samples: rows,
        channels,
        measured,
        within,
        half_ranges,
    })
}

/// The projection of a span from its steps 1 and 3 and its periods' fits (in the order
/// asked): the first error of the span, else of its periods, in order.
pub(super) fn assemble(
    record: &Record,
    span: &Result<SpanFit>,
    periods: &[&Result<PeriodFit>],
) -> Result<StateProjection> {
    let span = span.as_ref().map_err(Clone::clone)?;
    let periods = periods
        .iter()
        .map(|fit| {
            let fit = fit.as_ref().map_err(Clone::clone)?;
            Ok(PeriodProjection {
                first: fit.first,
                samples: fit.samples,
                channels: Arc::clone(&fit.channels),
                half_range_displacement: fit.half_ranges.0,
                half_range_velocity: fit.half_ranges.1,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(StateProjection {
        omega: 2.0 * std::f64::consts::PI / record.period(),
        step: record.step(),
        orders: span.orders.clone(),
        noise_std: span.noise_std.clone(),
        periods,
        non_harmonic: span.non_harmonic.clone(),
        residual_ratio: span.residual_ratio.clone(),
        residual_dof: span.residual_dof,
    })
}

/// Projects the span of `periods` whole periods from the sample position `origin` of
/// `record` (steps 1–3 of the module doc, on the record's noise estimated here), and
/// the periods `which` (0-based, each < `periods`) one by one.
pub fn project_periods(
    record: &Record,
    origin: f64,
    periods: usize,
    which: &[usize],
) -> Result<StateProjection> {
    let noise = RecordNoise::of(record)?;
    let fit = |k: usize| {
        let (first, rows) = period_samples(record, origin, k);
        let basis = period_basis(record, &noise, rows, &period_orders(record, &noise, rows)?)?;
        fit_period(record, &basis, first).map(|fit| (fit, basis))
    };
    let span = if from_periods(record, origin, periods) {
        let fits = (0..periods).map(fit).collect::<Result<Vec<_>>>()?;
        let all: Vec<&PeriodFit> = fits.iter().map(|(fit, _)| fit).collect();
        fit_span_from(record, &noise, &fits[0].1, &all)
    } else {
        fit_span(record, &noise, origin, periods)?
    };
    let fits: Vec<Result<PeriodFit>> = which.iter().map(|&k| fit(k).map(|(f, _)| f)).collect();
    assemble(record, &Ok(span), &fits.iter().collect::<Vec<_>>())
}

/// S: the displacement coefficients [a₀, a_q, b_q, …] of a channel measured by `sensor`
/// from its own (module doc).
fn to_displacement(sensor: Sensor, orders: &[usize], omega: f64) -> Mat<f64> {
    let p = 2 * orders.len() + 1;
    let mut s = Mat::<f64>::zeros(p, p);
    match sensor {
        Sensor::Displacement => {
            for k in 0..p {
                s[(k, k)] = 1.0;
            }
        }
        Sensor::Velocity => {
            for (q, &order) in orders.iter().enumerate() {
                let qw = order as f64 * omega;
                s[(2 * q + 1, 2 * q + 2)] = -1.0 / qw;
                s[(2 * q + 2, 2 * q + 1)] = 1.0 / qw;
            }
        }
        Sensor::Acceleration => {
            for (q, &order) in orders.iter().enumerate() {
                let qw2 = (order as f64 * omega).powi(2);
                s[(2 * q + 1, 2 * q + 1)] = -1.0 / qw2;
                s[(2 * q + 2, 2 * q + 2)] = -1.0 / qw2;
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::MeasuredMotion;
    use crate::reference::{four_mass_records_with, with_displacement_noise};
    use crate::simulate::SimSettings;

    /// A sensor of each kind on the four masses (velocity twice).
    const MIXED: [Sensor; 4] = [
        Sensor::Displacement,
        Sensor::Velocity,
        Sensor::Acceleration,
        Sensor::Velocity,
    ];

    /// The noise-free four-mass records with N = `n` samples per period, after
    /// `transient` steps, over `periods` periods and one sample.
    fn whole_sample_records(n: usize, transient: usize, periods: usize) -> Vec<Record> {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let settings = SimSettings {
            step: period / n as f64,
            transient_steps: transient,
            recorded_steps: periods * n + 1,
            ..SimSettings::default()
        };
        four_mass_records_with(false, &settings).unwrap()
    }

    /// The map to [c_x; c_v] on F's nonzero entries is bit for bit the sum over every
    /// column of F: for each sensor kind, coefficients with zeros, signed zeros, values
    /// over forty decades, and a non-finite one (where every column is used).
    #[test]
    fn the_sparse_map_is_the_dense_one() {
        let n = 64;
        let clean = whole_sample_records(n, 200, 2);
        let x = clean[0].displacements();
        let sensors = MIXED.to_vec();
        let motion = Mat::from_fn(clean[0].samples(), 4, |i, j| x[(i, j)]);
        let record = clean[0]
            .clone()
            .with_measured_motion(MeasuredMotion {
                sensors,
                signals: motion,
            })
            .unwrap();
        let noise = RecordNoise::of(&record).unwrap();
        let orders = [1, 2, 3, 5];
        let basis = period_basis(&record, &noise, n, &orders).unwrap();
        let p = basis.table.columns();
        assert_eq!(basis.kinds.len(), 3);
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        for kind in &basis.kinds {
            for trial in 0..200 {
                let mut c: Vec<f64> = (0..p)
                    .map(|_| {
                        let value = 10f64.powf(rng.random_range(-20.0..20.0));
                        match rng.random_range(0..7) {
                            0 => 0.0,
                            1 => -0.0,
                            2 => -value,
                            _ => value,
                        }
                    })
                    .collect();
                if trial % 50 == 49 {
                    c[(trial / 50) % p] =
                        [f64::INFINITY, f64::NAN, f64::NEG_INFINITY, f64::NAN][trial / 50];
                }
                let (mut c_x, mut c_v) = (vec![0.0; p], vec![0.0; p]);
                kind.map(&c, &mut c_x, &mut c_v);
                let (mut d_x, mut d_v) = (vec![0.0f64; p], vec![0.0f64; p]);
                for (k, &ck) in c.iter().enumerate() {
                    if ck != 0.0 {
                        for i in 0..p {
                            d_x[i] += kind.full[(i, k)] * ck;
                            d_v[i] += kind.full[(p + i, k)] * ck;
                        }
                    }
                }
                let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&c_x), bits(&d_x), "{:?} {c:?}", kind.sensor);
                assert_eq!(bits(&c_v), bits(&d_v), "{:?} {c:?}", kind.sensor);
            }
        }
    }

    /// A span's residual from its periods' fits (RSS = Σ_p RSS_p + Σ_p ‖R (c_p − c̄)‖²)
    /// is the residual of the span's own fit on its table, to round-off: the same
    /// non-harmonic RMS and residual ratio, for spans of 2 and 3 periods of N = 64 whole
    /// samples, noise-free and noisy, for displacement channels and for channels
    /// measured as velocities and accelerations; and each period's coefficients are
    /// its own least-squares fit on the basis.
    #[test]
    fn a_spans_residual_from_its_periods_is_its_own_fits() {
        let n = 64;
        let clean = whole_sample_records(n, 2000, 8);
        let noisy = with_displacement_noise(&clean, 0.01, 3).unwrap().remove(0);
        let (x, v) = (noisy.displacements(), clean[0].velocities().unwrap());
        let sensors = MIXED.to_vec();
        let motion = Mat::from_fn(noisy.samples(), 4, |i, j| match sensors[j] {
            Sensor::Displacement => x[(i, j)],
            Sensor::Velocity => v[(i, j)],
            Sensor::Acceleration => 0.3 * v[(i, j)] - x[(i, j)],
        });
        let measured = noisy
            .clone()
            .with_measured_motion(MeasuredMotion {
                sensors,
                signals: motion,
            })
            .unwrap();
        for (record, with_noise) in [(&clean[0], false), (&noisy, true), (&measured, true)] {
            let noise = RecordNoise::of(record).unwrap();
            for (origin, periods) in [(0.0, 2), (64.0, 2), (128.0, 3)] {
                assert!(from_periods(record, origin, periods));
                let orders = period_orders(record, &noise, n).unwrap();
                let basis = period_basis(record, &noise, n, &orders).unwrap();
                let fits: Vec<PeriodFit> = (0..periods)
                    .map(|k| {
                        let (first, rows) = period_samples(record, origin, k);
                        assert_eq!(rows, n);
                        fit_period(record, &basis, first).unwrap()
                    })
                    .collect();
                let from = fit_span_from(record, &noise, &basis, &fits.iter().collect::<Vec<_>>());
                let whole = fit_span(record, &noise, origin, periods).unwrap();
                assert_eq!(from.orders, whole.orders);
                assert_eq!(from.residual_dof, whole.residual_dof);
                // to 10⁻⁶ of the value, or within round-off of the signal's size (the
                // difference of sums of squares loses the digits a noise-free record's
                // residual would need)
                let (motion, _) = signals(record);
                let size = (0..motion.ncols())
                    .flat_map(|j| col(motion, j).iter())
                    .fold(0.0f64, |m, x| m.max(x.abs()));
                let close = |a: &[f64], b: &[f64], what: &str| {
                    for (p, q) in a.iter().zip(b) {
                        let tolerance = 1e-6 * q.abs() + 1e-7 * size;
                        assert!((p - q).abs() <= tolerance, "{what}: {p} vs {q}");
                    }
                };
                // (on a channel without noise the ratio is round-off over round-off: the
                // clean record, and the measured one's velocity channels)
                for (p, q) in from.residual_ratio.iter().zip(&whole.residual_ratio) {
                    if with_noise && *q < 1e3 {
                        assert!((p - q).abs() <= 1e-6 * q, "ratio: {p} vs {q}");
                    }
                }
                close(&from.non_harmonic, &whole.non_harmonic, "non-harmonic RMS");
                // each period's coefficients: its own fit on the basis
                let (signals, _) = signals(record);
                let table = &basis.table;
                for fit in &fits {
                    for (j, c) in fit.measured.chunks_exact(basis.table.columns()).enumerate() {
                        let samples = &col(signals, j)[fit.first..fit.first + n];
                        let own = table.fit(samples);
                        assert_eq!(c, own.as_slice());
                        let direct = table.residual_sum_of_squares(&own, samples);
                        let total: f64 = samples.iter().map(|x| (x - samples[0]).powi(2)).sum();
                        let tolerance = 1e-6 * direct + 1e-12 * total;
                        assert!((fit.within[j] - direct).abs() <= tolerance, "{j}");
                    }
                }
            }
        }
    }
}
