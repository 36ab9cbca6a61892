//! The denoised states the steady-state check compares: each channel projected on the
//! harmonics of ω = 2π/T that stand above the noise floor, separately over single
//! periods of a compared span.
//!
//! Over a span of k' whole periods starting at the (fractional) sample position u₀,
//! [`project_periods`]
//!
//! 1. selects the harmonic orders S and the per-sample noise σ̂_j of every channel j from
//!    the samples of the whole span (`prep::fourier`: out-of-band median,
//!    harmonics above 3.5 σ̂_A; with k' ≥ 2 the bins between harmonics, or with whole
//!    samples per period the contrasts between the periods, are available);
//! 2. projects each requested period [u₀ + pL, u₀ + (p + 1)L), L = T/h, over the samples
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
//! 3. fits the whole span at once on S and measures what no harmonic of ω explains: the
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
//! **Cost.** Where a period holds a whole number N = T/h of samples (and the span P N
//! of them), each period is transformed once, by one real FFT per channel
//! (`prep::fourier::periods`), and everything else is read off the periods' spectra:
//! the span's harmonic amplitudes are the sums of its periods' bins; its noise floor
//! reads the contrasts between its periods' bins in place of the bins between the
//! harmonics (the same distribution on noise, the same count; `periods.rs` derives
//! both); its residual on S is the power of every other bin (Parseval); and each
//! period's coefficients on S are its own bins. A period in two spans is transformed
//! once for both (`span_periods`, `spans.rs`). Otherwise step 1 fits the span by one
//! FFT or by least squares (`prep::fourier::noise_floor`) and steps 2 and 3 are
//! least-squares passes over a channel's samples against a table of the basis
//! (`table.rs`). Either way the half ranges of x̂ and v̂ over each period (the
//! amplitudes the mismatches are relative to: only the largest over the channels is
//! used) cost O(N p) per channel on the table, for the channels whose bound
//! Σ_q |c_q| can reach the largest (usually a few: the others are skipped, `table.rs`). A
//! period's table and its covariance per sensor kind (σ̂_j² times a unit covariance
//! shared by the channels of that kind) depend on its length and harmonics only, t
//! being measured from its first sample (`PeriodBasis`). Steps 1 and 3 (`fit_span`)
//! and step 2 (`fit_period`) are separate so that a period compared in two spans on
//! the same harmonics is fitted once (`spans.rs`); [`project_periods`] is the two for
//! one span.

use std::sync::Arc;

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::fourier::{
    HarmonicBasis, HarmonicSelection, PeriodSpectrum, WindowFit, select_from_periods,
    select_with_residuals, span_harmonics, whole_samples,
};
use crate::record::{Record, Sensor, col};

use super::table::HarmonicTable;

/// One channel over one period: coefficients of x̂ and v̂ in the basis b(t), and their
/// joint covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelProjection {
    /// c_x: [a₀, a_q, b_q, …] of the displacement (p = 2|S| + 1).
    pub displacement: Vec<f64>,
    /// c_v: the velocity's coefficients in the same basis (its a₀ is 0).
    pub velocity: Vec<f64>,
    /// Cov [c_x; c_v] / σ̂_j² (2p × 2p), shared by the period's channels of one sensor
    /// kind.
    pub unit_covariance: Arc<Mat<f64>>,
    /// σ̂_j², the channel's noise variance per sample.
    pub noise_variance: f64,
}

impl ChannelProjection {
    /// The variance of g_xᵀ c_x + g_vᵀ c_v.
    pub fn variance(&self, g_x: &[f64], g_v: &[f64]) -> f64 {
        self.scaled(self.unit_variance(g_x, g_v))
    }

    /// gᵀ (Cov / σ̂_j²) g for g = [g_x; g_v]: the same for every channel that shares the
    /// unit covariance.
    pub fn unit_variance(&self, g_x: &[f64], g_v: &[f64]) -> f64 {
        let p = g_x.len();
        let g = |k: usize| if k < p { g_x[k] } else { g_v[k - p] };
        let unit = &*self.unit_covariance;
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

/// The projection of one period of the span.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodProjection {
    /// First sample fitted (record index).
    pub first: usize,
    /// Samples fitted.
    pub samples: usize,
    /// One entry per channel (DOF).
    pub channels: Vec<ChannelProjection>,
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

/// The first sample of each period of the span of `periods` periods from the sample
/// position `origin` of `record`, and N, when the span's step 1 and 3 read off its
/// periods' spectra (`prep::fourier::periods`): N = T/h whole and the span exactly P N
/// samples from a whole sample. `None` otherwise, where the span is fitted as a whole.
pub(super) fn span_periods(
    record: &Record,
    origin: f64,
    periods: usize,
) -> Option<(Vec<usize>, usize)> {
    let n = whole_samples(record.step(), record.period())?;
    let length = record.period() / record.step();
    let (first, end) = samples_in(origin, periods as f64 * length, record.samples());
    (end - first == periods * n).then(|| ((0..periods).map(|i| first + i * n).collect(), n))
}

/// The spectrum of the period of `length` samples from sample `first` of `record`'s
/// signals, with the bins a span of its periods reads.
pub(super) fn period_spectrum(record: &Record, first: usize, length: usize) -> PeriodSpectrum {
    let (x, _) = signals(record);
    let most = span_harmonics(length, record.step(), record.period());
    PeriodSpectrum::new(x.subrows(first, length), most)
}

/// The harmonic fit the noise-robust rows make of the one-period window of `m` samples
/// from sample `first` of `record` (`prep/fourier/window_fit.rs`), read off its
/// period's `spectrum`; `None` where the rows must make it themselves.
pub(super) fn window_fit(
    record: &Record,
    spectrum: &PeriodSpectrum,
    first: usize,
    m: usize,
    harmonics: Option<usize>,
) -> Option<WindowFit> {
    if first.checked_add(m)? > record.samples() {
        return None;
    }
    let (x, _) = signals(record);
    let (step, period) = (record.step(), record.period());
    WindowFit::from_period(spectrum, x.subrows(first, m), step, period, harmonics)
}

/// Steps 1 and 3 over the span of `periods` whole periods from the sample position
/// `origin` of `record`: from its periods' spectra where [`span_periods`] allows, else
/// over the whole span.
pub(super) fn fit_span(record: &Record, origin: f64, periods: usize) -> Result<SpanFit> {
    if let Some((firsts, n)) = span_periods(record, origin, periods) {
        let spectra: Vec<PeriodSpectrum> = firsts
            .iter()
            .map(|&first| period_spectrum(record, first, n))
            .collect();
        return fit_span_from(record, &spectra.iter().collect::<Vec<_>>());
    }
    let (step, period) = (record.step(), record.period());
    let length = period / step;
    let (x, _) = signals(record);
    let (first, end) = samples_in(origin, periods as f64 * length, record.samples());
    let whole = x.subrows(first, end - first);
    let (selection, spectrum) = select_with_residuals(whole, step, period, periods)?;
    let omega = 2.0 * std::f64::consts::PI / period;
    let orders = &selection.kept;
    // Step 3: the whole span's residual on S, from the spectrum when the span holds
    // whole samples per period (Parseval), else one pass per channel for the fit and
    // one for its residual.
    let m = whole.nrows();
    let from_spectrum: Option<Vec<f64>> = spectrum.as_ref().and_then(|s| {
        (0..x.ncols())
            .map(|j| s.residual_sum_of_squares(orders, j))
            .collect()
    });
    let residuals = match from_spectrum {
        Some(rss) => rss,
        None => {
            let basis = HarmonicBasis::with_orders(omega, orders.clone(), step, m)?;
            let table = HarmonicTable::new(&basis, m);
            (0..x.ncols())
                .map(|j| {
                    let samples = &col(x, j)[first..end];
                    table.residual_sum_of_squares(&table.fit(samples), samples)
                })
                .collect()
        }
    };
    Ok(span_fit(record, selection, residuals))
}

/// Steps 1 and 3 over the span made of the periods `spectra` of `record` (in time
/// order, from [`period_spectrum`]).
pub(super) fn fit_span_from(record: &Record, spectra: &[&PeriodSpectrum]) -> Result<SpanFit> {
    let (selection, span) = select_from_periods(spectra, record.step(), record.period())?;
    let residuals = (0..selection.noise_std.len())
        .map(|j| span.residual_sum_of_squares(&selection.kept, j))
        .collect();
    Ok(span_fit(record, selection, residuals))
}

/// A span's [`SpanFit`] from its selection (over m samples) and its residual sums of
/// squares on the kept harmonics, per channel.
fn span_fit(record: &Record, selection: HarmonicSelection, residuals: Vec<f64>) -> SpanFit {
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let (_, sensors) = signals(record);
    let orders = selection.kept;
    let sigma = selection.noise_std;
    let p = 2 * orders.len() + 1;
    let dof = selection.samples.saturating_sub(p).max(1);
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

/// One channel's fit over one period: c_x, c_v and the unit covariance.
type ChannelFit = (Vec<f64>, Vec<f64>, Arc<Mat<f64>>);

/// Step 2 for one period: what it gives every span that projects it on the same
/// harmonics (a one-period window's period is compared with the previous one and with
/// the next, so it is fitted once for both), all but the noise of the span.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PeriodFit {
    /// First sample fitted (record index).
    first: usize,
    /// Samples fitted.
    samples: usize,
    /// Per channel: c_x, c_v and the unit covariance.
    channels: Vec<ChannelFit>,
    /// The largest ½ ranges of x̂ and of v̂ over the period's samples among the channels.
    half_ranges: (f64, f64),
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
    kinds: Vec<(Sensor, Mat<f64>, Arc<Mat<f64>>)>,
    /// The sensor of each channel.
    sensors: Vec<Sensor>,
}

/// The [`PeriodBasis`] of `record` for periods of `rows` samples on `orders`.
pub(super) fn period_basis(record: &Record, rows: usize, orders: &[usize]) -> Result<PeriodBasis> {
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let (_, sensors) = signals(record);
    let basis = HarmonicBasis::with_orders(omega, orders.to_vec(), record.step(), rows)?;
    let table = HarmonicTable::new(&basis, rows);
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
    let mut kinds: Vec<(Sensor, Mat<f64>, Arc<Mat<f64>>)> = Vec::new();
    if regular {
        for &sensor in &sensors {
            if !kinds.iter().any(|(s, _, _)| *s == sensor) {
                let full = &map * to_displacement(sensor, orders, omega);
                let unit = &full * &gram_inverse * full.transpose();
                kinds.push((sensor, full, Arc::new(unit)));
            }
        }
    }
    Ok(PeriodBasis {
        table,
        orders: orders.to_vec(),
        regular,
        kinds,
        sensors,
    })
}

/// Step 2 for the `rows` samples of `record` from sample `first`, projected on `orders`:
/// read off the period's spectrum when it is one period of N = T/h whole samples, as in
/// a check (`spans.rs`), else by least squares.
pub(super) fn fit_period(
    record: &Record,
    first: usize,
    rows: usize,
    orders: &[usize],
) -> Result<PeriodFit> {
    let basis = period_basis(record, rows, orders)?;
    if whole_period(record, rows) {
        fit_period_from(record, &basis, first, &period_spectrum(record, first, rows))
    } else {
        fit_period_with(record, &basis, first)
    }
}

/// Whether `rows` samples of `record` are one period of N = T/h whole samples, whose
/// step 2 reads off its spectrum.
pub(super) fn whole_period(record: &Record, rows: usize) -> bool {
    whole_samples(record.step(), record.period()) == Some(rows)
}

/// Step 2 for the period of `record` from sample `first`, with its [`PeriodBasis`], by
/// least squares on the basis' table.
pub(super) fn fit_period_with(
    record: &Record,
    basis: &PeriodBasis,
    first: usize,
) -> Result<PeriodFit> {
    let (x, _) = signals(record);
    let rows = basis.table.rows();
    period_fit(basis, first, |j| {
        basis.table.fit(&col(x, j)[first..first + rows])
    })
}

/// Step 2 for the period of `record` from sample `first`, with its [`PeriodBasis`] and
/// its spectrum (`spectrum` of the same samples): the coefficients read off the bins
/// (`prep::fourier::dft`: the least-squares ones on whole samples per period), by least
/// squares where the spectrum does not hold an order.
pub(super) fn fit_period_from(
    record: &Record,
    basis: &PeriodBasis,
    first: usize,
    spectrum: &PeriodSpectrum,
) -> Result<PeriodFit> {
    let (x, _) = signals(record);
    let rows = basis.table.rows();
    period_fit(basis, first, |j| {
        spectrum
            .coefficients(j, &basis.orders)
            .unwrap_or_else(|| basis.table.fit(&col(x, j)[first..first + rows]))
    })
}

/// Step 2 from each channel's coefficients c on the basis: c_x and c_v through [I; J] S,
/// the unit covariance, and the largest half ranges of x̂ and v̂ over the period's
/// samples (evaluated on the channels that can hold them, `table.rs`).
fn period_fit(
    basis: &PeriodBasis,
    first: usize,
    coefficients: impl Fn(usize) -> Vec<f64>,
) -> Result<PeriodFit> {
    let table = &basis.table;
    let rows = table.rows();
    if !basis.regular {
        return Err(Error::Numerical {
            stage: "steady-state check".into(),
            detail: format!(
                "the harmonic projection of the {rows} samples from sample {first} is singular"
            ),
        });
    }
    let p = table.columns();
    let channels: Vec<ChannelFit> = (0..basis.sensors.len())
        .map(|j| {
            // cannot fail: every sensor of `sensors` was added to `kinds` by period_basis
            let (_, full, unit) = basis
                .kinds
                .iter()
                .find(|(s, _, _)| *s == basis.sensors[j])
                .expect("each sensor kind has its map");
            let c = coefficients(j);
            let stacked: Vec<f64> = (0..2 * p)
                .map(|a| (0..p).map(|k| full[(a, k)] * c[k]).sum())
                .collect();
            let (displacement, velocity) = (stacked[..p].to_vec(), stacked[p..].to_vec());
            (displacement, velocity, Arc::clone(unit))
        })
        .collect();
    let states: Vec<(&[f64], &[f64])> = channels
        .iter()
        .map(|(x, v, _)| (x.as_slice(), v.as_slice()))
        .collect();
    let half_ranges = table.largest_half_ranges(&states, rows);
    Ok(PeriodFit {
        first,
        samples: rows,
        channels,
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
                channels: fit
                    .channels
                    .iter()
                    .zip(&span.noise_std)
                    .map(
                        |((displacement, velocity, unit), sigma)| ChannelProjection {
                            displacement: displacement.clone(),
                            velocity: velocity.clone(),
                            unit_covariance: Arc::clone(unit),
                            noise_variance: sigma * sigma,
                        },
                    )
                    .collect(),
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
/// `record` (steps 1–3 of the module doc), and the periods `which` (0-based, each
/// < `periods`) one by one.
pub fn project_periods(
    record: &Record,
    origin: f64,
    periods: usize,
    which: &[usize],
) -> Result<StateProjection> {
    let span = fit_span(record, origin, periods)?;
    let fits = which
        .iter()
        .map(|&k| {
            let (first, rows) = period_samples(record, origin, k);
            fit_period(record, first, rows, &span.orders)
        })
        .collect::<Vec<_>>();
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

    /// A period of N whole samples read off its spectrum (`fit_period_from`) gives the
    /// least-squares fit on the table (`fit_period_with`) to round-off: the same c_x,
    /// c_v and half ranges, the same unit covariance, for displacement channels and for
    /// channels measured as velocities and accelerations (mapped per harmonic), with
    /// noise, on one harmonic and on several.
    #[test]
    fn period_fits_read_off_the_spectrum_are_the_least_squares_ones() {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let n = 64;
        let settings = SimSettings {
            step: period / n as f64,
            transient_steps: 2000,
            recorded_steps: 4 * n + 1,
            ..SimSettings::default()
        };
        let clean = four_mass_records_with(false, &settings).unwrap();
        let record = with_displacement_noise(&clean, 0.01, 3).unwrap().remove(0);
        let (x, v) = (record.displacements(), clean[0].velocities().unwrap());
        let sensors = vec![
            Sensor::Displacement,
            Sensor::Velocity,
            Sensor::Acceleration,
            Sensor::Velocity,
        ];
        // any signal serves: both fits read the same one
        let signals = Mat::from_fn(record.samples(), 4, |i, j| match sensors[j] {
            Sensor::Displacement => x[(i, j)],
            Sensor::Velocity => v[(i, j)],
            Sensor::Acceleration => 0.3 * v[(i, j)] - x[(i, j)],
        });
        let measured = record
            .clone()
            .with_measured_motion(MeasuredMotion { sensors, signals })
            .unwrap();
        assert!(whole_period(&record, n));
        for record in [&record, &measured] {
            for orders in [vec![1], vec![1, 2, 3, 5]] {
                let basis = period_basis(record, n, &orders).unwrap();
                for first in [0, n, 2 * n + 1] {
                    let spectrum = period_spectrum(record, first, n);
                    let ours = fit_period_from(record, &basis, first, &spectrum).unwrap();
                    let table = fit_period_with(record, &basis, first).unwrap();
                    for (a, b) in ours.channels.iter().zip(&table.channels) {
                        let scale =
                            b.0.iter()
                                .chain(&b.1)
                                .fold(1e-300f64, |m, c| m.max(c.abs()));
                        for (p, q) in a.0.iter().chain(&a.1).zip(b.0.iter().chain(&b.1)) {
                            assert!(
                                (p - q).abs() <= 1e-12 * scale,
                                "{orders:?} from {first}: {p} vs {q}"
                            );
                        }
                        assert!(Arc::ptr_eq(&a.2, &b.2));
                    }
                    let ((ax, av), (bx, bv)) = (ours.half_ranges, table.half_ranges);
                    assert!((ax - bx).abs() <= 1e-12 * bx.max(1e-300));
                    assert!((av - bv).abs() <= 1e-12 * bv.max(1e-300));
                }
            }
        }
    }
}
