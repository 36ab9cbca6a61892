//! Proper orthogonal decomposition (POD) of a record's displacements, and the
//! reduced-order records it gives (Feeny 2009, section 3).
//!
//! With X the N × n ensemble of displacement samples (one row per time sample, optionally
//! with the column means x̄ removed; the paper removes none), the correlation matrix
//!
//! ```text
//!   R = Xᵀ X / N = U Λ Uᵀ,     Λ = diag(λ_1 ≥ λ_2 ≥ … ≥ λ_n ≥ 0)
//! ```
//!
//! gives the proper orthogonal modes (POMs, the orthonormal columns u_k of U) and values
//! (POVs λ_k, the mean square of the modal coordinate y_k = u_kᵀ x, clamped at 0 against
//! round-off). Mode k carries the energy share λ_k / Σ_j λ_j. Each mode is scaled to unit
//! length and signed so that its largest-magnitude component (the first one, on a tie)
//! is positive.
//!
//! Retaining the m leading modes U_m (a count, or the fewest whose cumulative share
//! reaches an energy threshold such as 99.9%) gives the approximation
//!
//! ```text
//!   x ≈ x̄ + U_m U_mᵀ (x − x̄),    ẋ ≈ U_m U_mᵀ ẋ,    y = U_mᵀ (x − x̄).
//! ```
//!
//! A projected record holds these reconstructed displacements (and measured velocities,
//! if any) with the forces unchanged. Reduced identification is the ordinary regressor on
//! projected records: every term is evaluated in physical coordinates from U y and U ẏ,
//! and since ẏᵀ U_mᵀ g = (U_m ẏ)ᵀ g for any force vector g, its columns are the paper's
//! reduced integrals (eqs. 8, 9, 14–16, 19):
//!
//! ```text
//!   ∮ ẏᵀ U_mᵀ C₀ U_m ẏ dt,   ∮ ẏᵀ U_mᵀ f(U_m y, U_m ẏ) dt,   ∮ ẏᵀ U_mᵀ r dt.
//! ```
//!
//! One basis per record follows the paper; one basis shared by all records (from their
//! stacked displacements) is an option.

use faer::linalg::matmul::triangular::{BlockStructure, matmul};
use faer::{Accum, Mat, MatRef, Par, Side};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, check_finite};
use crate::record::{Record, RecordParts};

/// Relative tolerance under which two components tie for the largest magnitude in the
/// sign convention.
const SIGN_TIE: f64 = 1e-9;

/// Slack, relative to 1, allowed on a cumulative energy share when it is compared with a
/// threshold: Σ_k λ_k/Σ_j λ_j may fall short of 1 by round-off.
const SHARE_SLACK: f64 = 1e-12;

/// How many modes to retain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Retain {
    /// Exactly this many leading modes (1 ≤ m ≤ n).
    Count(usize),
    /// The fewest leading modes whose cumulative energy share reaches this fraction,
    /// in (0, 1] (e.g. 0.999 for 99.9%).
    Energy(f64),
}

impl Default for Retain {
    /// 99.9% of the signal energy, the paper's example criterion.
    fn default() -> Self {
        Retain::Energy(0.999)
    }
}

impl Retain {
    /// Checks the criterion for a system of `dofs` DOFs.
    pub fn validate(&self, dofs: usize) -> Result<()> {
        match *self {
            Retain::Count(m) if m == 0 || m > dofs => Err(Error::invalid(
                "retained modes",
                m as f64,
                &format!("must be between 1 and the number of DOFs, {dofs}"),
            )),
            Retain::Energy(share) if !(share > 0.0 && share <= 1.0) => Err(Error::invalid(
                "retained energy share",
                share,
                "must be in (0, 1]",
            )),
            _ => Ok(()),
        }
    }
}

/// Which displacements a basis is computed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PodBasis {
    /// One basis per record, from that record's samples (the paper's choice).
    #[default]
    PerRecord,
    /// One basis for all records, from their stacked samples.
    Shared,
}

/// POD settings.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PodSettings {
    /// Remove the column means before forming R (the paper does not).
    pub remove_mean: bool,
    /// How many modes to retain.
    pub retain: Retain,
    /// One basis per record or one shared.
    pub basis: PodBasis,
}

/// A proper orthogonal decomposition: all n modes and values, and how many are retained.
#[derive(Debug, Clone)]
pub struct Pod {
    modes: Mat<f64>,
    values: Vec<f64>,
    mean: Vec<f64>,
    mean_removed: bool,
    retained: usize,
    samples: usize,
}

impl Pod {
    /// The POD of the displacements (N × n, one row per sample).
    pub fn from_displacements(x: MatRef<'_, f64>, settings: &PodSettings) -> Result<Self> {
        Self::from_blocks(&[x], settings)
    }

    /// The POD of one record's displacements (all its samples).
    pub fn from_record(record: &Record, settings: &PodSettings) -> Result<Self> {
        Self::from_blocks(&[record.displacements()], settings)
    }

    /// One POD of the stacked displacements of every record (a shared basis).
    pub fn from_records(records: &[Record], settings: &PodSettings) -> Result<Self> {
        let blocks: Vec<MatRef<'_, f64>> = records.iter().map(Record::displacements).collect();
        Self::from_blocks(&blocks, settings)
    }

    /// R = Σ_b X̃_bᵀ X̃_b / Σ_b N_b over the blocks, with X̃ = X − 1 x̄ᵀ.
    fn from_blocks(blocks: &[MatRef<'_, f64>], settings: &PodSettings) -> Result<Self> {
        let Some(first) = blocks.first() else {
            return Err(Error::Empty {
                what: "record list for the POD".into(),
            });
        };
        let n = first.ncols();
        if n == 0 {
            return Err(Error::Empty {
                what: "displacement DOFs for the POD".into(),
            });
        }
        for block in blocks {
            if block.ncols() != n {
                return Err(Error::mismatch(
                    "DOFs of stacked records for a shared POD basis",
                    n,
                    block.ncols(),
                ));
            }
            check_finite("displacements for the POD", *block)?;
        }
        let samples: usize = blocks.iter().map(|b| b.nrows()).sum();
        if samples == 0 {
            return Err(Error::Empty {
                what: "displacement samples for the POD".into(),
            });
        }
        settings.retain.validate(n)?;
        // R, its symmetric copy, the eigenvectors and the eigensolver's workspace (about
        // 4 n × n), the parallel partial sums (up to MAX_CHUNKS n × n), and the centred
        // rows of a chunk (CENTRED_ROWS × n): checked before any of them is allocated.
        let n2 = (n as u128).saturating_mul(n as u128);
        crate::budget::require(
            &format!("a POD of {n} sensors (its {n} × {n} correlation matrix)"),
            crate::budget::f64s(
                n2.saturating_mul(MAX_CHUNKS as u128 + 4)
                    .saturating_add((CENTRED_ROWS as u128).saturating_mul(n as u128)),
            ),
            "use fewer sensors (displacement columns) for the POD",
        )?;
        let mut mean = vec![0.0; n];
        if settings.remove_mean {
            for block in blocks {
                for (j, m) in mean.iter_mut().enumerate() {
                    *m += block.col(j).iter().sum::<f64>();
                }
            }
            mean.iter_mut().for_each(|m| *m /= samples as f64);
        }
        let mut r = Mat::<f64>::zeros(n, n);
        for block in blocks {
            add_correlation(&mut r, *block, settings.remove_mean.then_some(&mean[..]));
        }
        // The product filled (at least) the lower triangle; R is read from it.
        let r = Mat::from_fn(n, n, |i, j| r[(i.max(j), i.min(j))] / samples as f64);
        let eigen = r
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Numerical {
                stage: "POD".into(),
                detail: format!("eigendecomposition of the correlation matrix failed: {e:?}"),
            })?;
        // faer returns ascending eigenvalues: reverse to descending.
        let order: Vec<usize> = (0..n).rev().collect();
        let values: Vec<f64> = order.iter().map(|&k| eigen.S()[k].max(0.0)).collect();
        let total: f64 = values.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Err(Error::invalid(
                "POD signal energy",
                total,
                "the displacements (after any mean removal) carry no energy: there is nothing to decompose",
            ));
        }
        let u = eigen.U();
        let mut modes = Mat::from_fn(n, n, |i, k| u[(i, order[k])]);
        for k in 0..n {
            orient(modes.col_as_slice_mut(k));
        }
        let mut pod = Pod {
            modes,
            values,
            mean,
            mean_removed: settings.remove_mean,
            retained: n,
            samples,
        };
        pod.retained = pod.count_for(settings.retain)?;
        Ok(pod)
    }

    /// The number of modes `retain` selects.
    pub fn count_for(&self, retain: Retain) -> Result<usize> {
        let n = self.dofs();
        retain.validate(n)?;
        Ok(match retain {
            Retain::Count(m) => m,
            Retain::Energy(share) => self
                .cumulative_shares()
                .iter()
                .position(|&c| c >= share - SHARE_SLACK)
                .map_or(n, |k| k + 1),
        })
    }

    /// The same decomposition retaining the modes `retain` selects.
    pub fn retaining(&self, retain: Retain) -> Result<Self> {
        let retained = self.count_for(retain)?;
        Ok(Pod {
            retained,
            ..self.clone()
        })
    }

    /// Number of DOFs n.
    pub fn dofs(&self) -> usize {
        self.values.len()
    }
    /// Number of samples the decomposition was computed from.
    pub fn samples(&self) -> usize {
        self.samples
    }
    /// Number of retained modes m.
    pub fn retained(&self) -> usize {
        self.retained
    }
    /// Whether the column means were removed.
    pub fn mean_removed(&self) -> bool {
        self.mean_removed
    }
    /// The removed column means x̄ (zeros when none were removed).
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }
    /// The POVs λ_k, descending and nonnegative.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
    /// Σ_k λ_k, the mean squared norm of the (centred) displacement.
    pub fn total_energy(&self) -> f64 {
        self.values.iter().sum()
    }
    /// All n modes, as the columns of an n × n orthogonal matrix, in value order.
    pub fn modes(&self) -> MatRef<'_, f64> {
        self.modes.as_ref()
    }
    /// Mode k (0-based), unit length, largest-magnitude component positive.
    pub fn mode(&self, k: usize) -> Option<&[f64]> {
        (k < self.dofs()).then(|| self.modes.col_as_slice(k))
    }
    /// The retained modes U_m (n × m).
    pub fn retained_modes(&self) -> MatRef<'_, f64> {
        self.modes.as_ref().subcols(0, self.retained)
    }
    /// Energy share λ_k / Σ_j λ_j of every mode.
    pub fn energy_shares(&self) -> Vec<f64> {
        let total = self.total_energy();
        self.values.iter().map(|v| v / total).collect()
    }
    /// Cumulative energy share of the k + 1 leading modes, for every k.
    pub fn cumulative_shares(&self) -> Vec<f64> {
        let mut sum = 0.0;
        self.energy_shares()
            .into_iter()
            .map(|s| {
                sum += s;
                sum
            })
            .collect()
    }

    /// The retained modal coordinates y = U_mᵀ (x − x̄) of displacements `x` (N × n),
    /// one row per sample (N × m).
    pub fn coordinates(&self, x: MatRef<'_, f64>) -> Result<Mat<f64>> {
        self.check_dofs(x.ncols(), "columns of displacements vs POD DOFs")?;
        let centred = Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)] - self.mean[j]);
        Ok(centred * self.retained_modes())
    }

    /// The record reconstructed from the retained modes: displacements x̄ + U_m U_mᵀ(x − x̄),
    /// measured velocities (if any) U_m U_mᵀ ẋ, forces, step and period unchanged. The
    /// label gains " [m POMs]".
    pub fn project(&self, record: &Record) -> Result<Record> {
        self.check_dofs(record.dofs(), "DOFs of the record vs the POD basis")?;
        // The projector (n × n), the centred and projected displacements (2 N × n) and
        // the projected velocities (N × n).
        let (samples, n) = (record.samples() as u128, self.dofs() as u128);
        crate::budget::require(
            &format!(
                "the POD projection of {} samples × {} sensors",
                record.samples(),
                self.dofs()
            ),
            crate::budget::f64s(
                n.saturating_mul(n)
                    .saturating_add(samples.saturating_mul(n).saturating_mul(3)),
            ),
            "use fewer samples (a shorter record) or fewer sensors",
        )?;
        let u = self.retained_modes();
        let projector = u * u.transpose();
        let x = record.displacements();
        let centred = Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)] - self.mean[j]);
        let mut displacements = centred * &projector;
        for j in 0..self.dofs() {
            displacements
                .col_as_slice_mut(j)
                .iter_mut()
                .for_each(|value| *value += self.mean[j]);
        }
        let velocities = record.velocities().map(|v| v * &projector);
        let parts = record.parts();
        Record::new(RecordParts {
            label: format!("{} [{} POMs]", parts.label, self.retained),
            step: parts.step,
            start_time: parts.start_time,
            displacements,
            velocities,
            forcing: parts.forcing.clone(),
            period: parts.period,
        })?
        .with_channel_names(record.channel_names().to_vec())
    }

    /// A serializable summary: values, shares, cumulative shares and shapes.
    pub fn report(&self) -> PodReport {
        let shares = self.energy_shares();
        let cumulative = self.cumulative_shares();
        PodReport {
            dofs: self.dofs(),
            samples: self.samples,
            mean_removed: self.mean_removed,
            total_energy: self.total_energy(),
            retained: self.retained,
            retained_share: cumulative[self.retained - 1],
            modes: (0..self.dofs())
                .map(|k| PodModeReport {
                    index: k + 1,
                    value: self.values[k],
                    energy_share: shares[k],
                    cumulative_share: cumulative[k],
                    shape: self.modes.col_as_slice(k).to_vec(),
                })
                .collect(),
        }
    }

    fn check_dofs(&self, found: usize, what: &str) -> Result<()> {
        if found != self.dofs() {
            return Err(Error::mismatch(what, self.dofs(), found));
        }
        Ok(())
    }
}

/// Rows per block when the mean is removed: the centred copy of a block stays small.
const CENTRED_ROWS: usize = 4096;

/// Least rows in a chunk of the correlation product (see [`add_correlation`]).
const CHUNK_ROWS: usize = 8192;

/// Most chunks of the correlation product, each with an n × n partial sum.
const MAX_CHUNKS: usize = 16;

/// DOFs from which R is formed on its lower triangle only (below, the triangular
/// product's recursion costs more than the half of the work it saves).
const TRIANGLE_DOFS: usize = 64;

/// r += X̃ᵀ X̃ on (at least) the lower triangle (row ≥ column), with X̃ = X − 1 x̄ᵀ when
/// `mean` is given (centred block by block) and X̃ = X otherwise (no copy). Matrix
/// products on the triangle only for many DOFs: half the work of the full product.
///
/// Rows are cut into chunks whose count depends on the sizes only (at least
/// [`CHUNK_ROWS`] and n rows each, at most [`MAX_CHUNKS`], so the partial sums take no
/// more memory than X); chunks run in parallel, each product sequential, and their sums
/// are added in row order: the same bits on any number of threads.
fn add_correlation(r: &mut Mat<f64>, x: MatRef<'_, f64>, mean: Option<&[f64]>) {
    let (m, n) = x.shape();
    let chunks = (m / CHUNK_ROWS.max(n)).clamp(1, MAX_CHUNKS);
    if chunks == 1 {
        return add_chunk(r, x, mean);
    }
    let rows = m.div_ceil(chunks);
    let partials: Vec<Mat<f64>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let start = c * rows;
            let mut partial = Mat::<f64>::zeros(n, n);
            add_chunk(&mut partial, x.subrows(start, rows.min(m - start)), mean);
            partial
        })
        .collect();
    for partial in &partials {
        for j in 0..n {
            for (t, p) in r
                .col_as_slice_mut(j)
                .iter_mut()
                .zip(partial.col_as_slice(j))
            {
                *t += p;
            }
        }
    }
}

/// `add_correlation` on one chunk of rows, by one sequential product.
fn add_chunk(r: &mut Mat<f64>, x: MatRef<'_, f64>, mean: Option<&[f64]>) {
    let structure = if x.ncols() >= TRIANGLE_DOFS {
        BlockStructure::TriangularLower
    } else {
        BlockStructure::Rectangular
    };
    let product = |r: &mut Mat<f64>, block: MatRef<'_, f64>| {
        matmul(
            r.as_mut(),
            structure,
            Accum::Add,
            block.transpose(),
            BlockStructure::Rectangular,
            block,
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        )
    };
    match mean {
        None => product(r, x),
        Some(mean) => {
            for start in (0..x.nrows()).step_by(CENTRED_ROWS) {
                let rows = CENTRED_ROWS.min(x.nrows() - start);
                let centred = Mat::from_fn(rows, x.ncols(), |i, j| x[(start + i, j)] - mean[j]);
                product(r, centred.as_ref());
            }
        }
    }
}

/// Signs a unit vector so that its largest-magnitude component (the first within a
/// relative [`SIGN_TIE`] of the largest) is positive.
fn orient(mode: &mut [f64]) {
    let largest = mode.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if let Some(lead) = mode.iter().find(|v| v.abs() >= largest * (1.0 - SIGN_TIE))
        && *lead < 0.0
    {
        mode.iter_mut().for_each(|v| *v = -*v);
    }
}

/// One mode of a [`PodReport`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PodModeReport {
    /// 1-based mode number, in value order.
    pub index: usize,
    /// POV λ_k (mean squared modal coordinate).
    pub value: f64,
    /// λ_k / Σ λ.
    pub energy_share: f64,
    /// Share of modes 1..=k.
    pub cumulative_share: f64,
    /// The unit mode shape u_k.
    pub shape: Vec<f64>,
}

/// What a POD found, for reports and JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PodReport {
    /// Number of DOFs (sensors) n.
    pub dofs: usize,
    /// Samples used.
    pub samples: usize,
    /// Whether the column means were removed.
    pub mean_removed: bool,
    /// Σ λ.
    pub total_energy: f64,
    /// Retained modes m.
    pub retained: usize,
    /// Cumulative energy share of the retained modes.
    pub retained_share: f64,
    /// Every mode, in value order.
    pub modes: Vec<PodModeReport>,
}

/// Records projected onto POD bases, with the bases.
#[derive(Debug, Clone)]
pub struct Reduction {
    /// The projected records, in the order given.
    pub records: Vec<Record>,
    /// One basis per record ([`PodBasis::PerRecord`]) or a single shared one.
    pub bases: Vec<Pod>,
}

impl Reduction {
    /// The basis used for record `index`.
    pub fn basis_for(&self, index: usize) -> Option<&Pod> {
        match self.bases.len() {
            1 => (index < self.records.len()).then(|| &self.bases[0]),
            _ => self.bases.get(index),
        }
    }

    /// The report of every basis, in order.
    pub fn reports(&self) -> Vec<PodReport> {
        self.bases.iter().map(Pod::report).collect()
    }
}

/// Computes the POD bases `settings` asks for and projects every record onto its basis.
/// Identify on [`Reduction::records`] with the full model for the reduced-order fit.
pub fn reduce(records: &[Record], settings: &PodSettings) -> Result<Reduction> {
    if records.is_empty() {
        return Err(Error::Empty {
            what: "record list for the POD".into(),
        });
    }
    let bases = match settings.basis {
        PodBasis::PerRecord => records
            .iter()
            .map(|r| Pod::from_record(r, settings))
            .collect::<Result<Vec<_>>>()?,
        PodBasis::Shared => vec![Pod::from_records(records, settings)?],
    };
    let records = records
        .iter()
        .enumerate()
        .map(|(k, r)| bases[if bases.len() == 1 { 0 } else { k }].project(r))
        .collect::<Result<_>>()?;
    Ok(Reduction { records, bases })
}
