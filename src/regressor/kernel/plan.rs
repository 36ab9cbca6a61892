//! The plan of one record's window sums: which weighted sums one pass computes, in
//! which order, and how they combine into the regressor row.
//!
//! Every column of the row and the input work are linear combinations of sums
//! S = Σ_i w_i g_i over the window's samples:
//!
//! ```text
//!   element e of a law:      S_e   = Σ_i w_i v_e f(x_e, v_e)     (relative motion on a dashpot)
//!   matrix entry (j ≤ k):    S_jk  = Σ_i w_i v_j v_k = G_jk      (sparse path)
//!   force channel c on j:    S_cj  = Σ_i w_i s_c v_j
//!
//!   per-element column e:    A_e = ω_e S_e
//!   shared column:           A   = Σ_e ω_e S_e
//!   matrix column:           A   = Σ_j C_jj G_jj + Σ_{j<k} (C_jk + C_kj) G_jk
//!   input work:              b   = Σ_c Σ_j D_jc S_cj
//! ```
//!
//! The sums are ordered by the last (highest) velocity column they read, so that a pass
//! over a block of samples brings each column in from memory once and every other sum
//! that reads it finds it in cache (on a chain: the dashpot (j−1, j), the damper on j
//! and the force on j all run while v_j is fresh). The sums of one last column form a
//! group, whose sums with a closed form run in one loop (`fused.rs`); consecutive runs
//! of groups form the segments that are evaluated as separate tasks.
//!
//! Matrix terms whose combined pattern is dense use the Gram matrix instead: G = Vᵀ W V
//! by one matrix product per window (see `gram.rs`), then A = tr(C₀ᵀ G). The choice is
//! made once per plan from the number of distinct entries (j ≤ k) of C₀ + C₀ᵀ.

use crate::terms::OnElements;
use std::collections::HashMap;
use std::ops::Range;

use faer::Mat;

use crate::model::DampingModel;
use crate::record::{LoadDistribution, Record};
use crate::terms::{Coefficients, Law, Term};

/// Matrix terms use the Gram matrix G when their distinct entries (j ≤ k) exceed this
/// fraction of the n(n+1)/2 entries of G (and n is at least [`GRAM_MIN_DOFS`]). One
/// entry summed on its own costs about as much as 1/[`GRAM_DENSITY`] of the entries in
/// a blocked matrix product that forms all of G.
pub(crate) const GRAM_DENSITY: f64 = 0.1;

/// Below this many DOFs the entries are always summed one by one (G would be tiny).
pub(crate) const GRAM_MIN_DOFS: usize = 32;

/// A segment closes at the first change of column after this many sums.
const SEGMENT_SUMS: usize = 96;

/// One weighted sum over a window's samples.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Sum<'m> {
    /// Σ w v f(x, v) of `law` on DOF `a` (to ground) or on the relative motion a − b.
    Power {
        law: &'m dyn Law,
        a: usize,
        b: Option<usize>,
    },
    /// Σ w v_j v_k: the Gram entry G_jk.
    Product { j: usize, k: usize },
    /// Σ w s_c v_j: the input work of force channel c on DOF j (before its load factor).
    Work { channel: usize, dof: usize },
}

impl Sum<'_> {
    /// The highest velocity column the sum reads: its place in the pass.
    fn last_column(&self) -> usize {
        match *self {
            Sum::Power { a, b, .. } => b.map_or(a, |b| a.max(b)),
            Sum::Product { j, k } => j.max(k),
            Sum::Work { dof, .. } => dof,
        }
    }

    /// Whether the sum can run in the fused loop of its group (`fused.rs`): a law with a
    /// closed power form in the velocity alone, a Gram entry or a force channel's work.
    pub(crate) fn fusable(&self) -> bool {
        match self {
            Sum::Power { law, .. } => law.power_form().is_some() && !law.uses_displacement(),
            Sum::Product { .. } | Sum::Work { .. } => true,
        }
    }
}

/// The sums of one velocity column: every sum whose last column is `column`, the
/// [`Sum::fusable`] ones first.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    /// The group's slots.
    pub(crate) slots: Range<usize>,
    /// How many of them, from the first, run in one fused loop.
    pub(crate) fused: usize,
    /// The column that the group brings in.
    pub(crate) column: usize,
}

/// A linear combination Σ factor · S[slot].
type Combination = Vec<(usize, f64)>;

/// The entries (j, k, factor) of a matrix term, j ≤ k: vᵀC₀v = Σ factor v_j v_k.
type MatrixEntries = Vec<(usize, usize, f64)>;

/// The sums of one record's windows and how they make a row.
#[derive(Debug)]
pub(crate) struct Plan<'m> {
    /// The sums, in pass order; a sum's index is its slot.
    pub(crate) sums: Vec<Sum<'m>>,
    /// The sums cut by last column, in pass order.
    pub(crate) groups: Vec<Group>,
    /// Consecutive ranges of groups, each evaluated as one task per block of samples.
    pub(crate) segments: Vec<Range<usize>>,
    /// Per regressor column, its combination of sums (empty for Gram columns).
    columns: Vec<Combination>,
    /// Matrix terms on the Gram path: (column, entries (j, k, factor) of C₀ + C₀ᵀ).
    gram_terms: Vec<(usize, MatrixEntries)>,
    /// The input work's combination of sums.
    input: Combination,
}

impl<'m> Plan<'m> {
    /// The plan of `model` on the windows of `record` (already validated together).
    pub(crate) fn new(model: &'m DampingModel, record: &Record) -> Self {
        let dofs = record.dofs();
        let mut sums: Vec<Sum<'m>> = Vec::new();
        let mut columns: Vec<Combination> = vec![Vec::new(); model.coefficient_count()];
        let mut gram_terms = Vec::new();
        let mut input = Vec::new();

        let matrix_entries: Vec<MatrixEntries> = model
            .terms()
            .iter()
            .filter_map(|t| match t {
                Term::Matrix(m) => Some(symmetric_entries(m.matrix())),
                Term::Elements(_) | Term::History(_) | Term::Structural(_) => None,
            })
            .collect();
        let use_gram = use_gram(dofs, &matrix_entries);
        let mut matrix_entries = matrix_entries.into_iter();
        let mut product_slot: HashMap<(usize, usize), usize> = HashMap::new();

        for (term, range) in model.term_columns() {
            match term {
                Term::Matrix(_) => {
                    // cannot fail: matrix_entries holds one list per matrix term of
                    // this same model, in term order.
                    let entries = matrix_entries
                        .next()
                        .expect("one entry list per matrix term");
                    if use_gram {
                        gram_terms.push((range.start, entries));
                        continue;
                    }
                    for (j, k, factor) in entries {
                        let slot = *product_slot.entry((j, k)).or_insert_with(|| {
                            sums.push(Sum::Product { j, k });
                            sums.len() - 1
                        });
                        columns[range.start].push((slot, factor));
                    }
                }
                Term::Elements(t) => {
                    let weights = t.weights();
                    for (index, element) in t.elements().iter().enumerate() {
                        sums.push(Sum::Power {
                            law: t.law(),
                            a: element.a,
                            b: element.b,
                        });
                        let column = match t.coefficients() {
                            Coefficients::Shared(_) => range.start,
                            Coefficients::PerElement(_) => range.start + index,
                        };
                        let weight = weights.map_or(1.0, |w| w[index]);
                        columns[column].push((sums.len() - 1, weight));
                    }
                }
                // Computed per window on the periodic orbit or by the window's
                // Hilbert transform (regressor/history.rs), then added to the row: no
                // sum here.
                Term::History(_) | Term::Structural(_) => {}
            }
        }

        let forcing = record.forcing();
        for &channel in record.active_channels() {
            match &forcing.distribution {
                LoadDistribution::Dofs(dofs) => {
                    sums.push(Sum::Work {
                        channel,
                        dof: dofs[channel],
                    });
                    input.push((sums.len() - 1, 1.0));
                }
                LoadDistribution::Matrix(d) => {
                    for dof in (0..d.nrows()).filter(|&i| d[(i, channel)] != 0.0) {
                        sums.push(Sum::Work { channel, dof });
                        input.push((sums.len() - 1, d[(dof, channel)]));
                    }
                }
            }
        }

        // Pass order: by last column read, the fusable sums of a column first, ties in
        // the order made (stable sort).
        let mut order: Vec<usize> = (0..sums.len()).collect();
        order.sort_by_key(|&s| (sums[s].last_column(), !sums[s].fusable()));
        let mut slot_of = vec![0; sums.len()];
        for (slot, &made) in order.iter().enumerate() {
            slot_of[made] = slot;
        }
        let sums: Vec<Sum<'m>> = order.iter().map(|&made| sums[made]).collect();
        for (slot, _) in columns.iter_mut().flatten().chain(input.iter_mut()) {
            *slot = slot_of[*slot];
        }
        let groups = groups(&sums);
        let segments = segments(&groups);
        Plan {
            sums,
            groups,
            segments,
            columns,
            gram_terms,
            input,
        }
    }

    /// The slots of the groups `segment`.
    pub(crate) fn segment_slots(&self, segment: &Range<usize>) -> Range<usize> {
        if segment.is_empty() {
            return 0..0;
        }
        self.groups[segment.start].slots.start..self.groups[segment.end - 1].slots.end
    }

    /// Whether some matrix term reads the Gram matrix.
    pub(crate) fn needs_gram(&self) -> bool {
        !self.gram_terms.is_empty()
    }

    /// The row and the input work from the window's sums (and its Gram matrix, lower
    /// triangle, when [`Plan::needs_gram`]).
    pub(crate) fn combine(&self, sums: &[f64], gram: Option<&Mat<f64>>) -> (Vec<f64>, f64) {
        let combination = |terms: &Combination| {
            terms
                .iter()
                .fold(0.0, |total, &(slot, factor)| total + factor * sums[slot])
        };
        let mut row: Vec<f64> = self.columns.iter().map(combination).collect();
        if let Some(gram) = gram {
            for (column, entries) in &self.gram_terms {
                row[*column] = entries
                    .iter()
                    .fold(0.0, |total, &(j, k, factor)| total + factor * gram[(k, j)]);
            }
        }
        (row, combination(&self.input))
    }
}

/// The entries (j ≤ k) of C₀ + C₀ᵀ that are not zero, as (j, k, factor) with factor
/// C_jj on the diagonal and C_jk + C_kj above it, column by column: vᵀC₀v = Σ factor v_j v_k.
fn symmetric_entries(c0: &Mat<f64>) -> MatrixEntries {
    let mut entries = Vec::new();
    for k in 0..c0.ncols() {
        for j in 0..=k {
            let factor = if j == k {
                c0[(j, j)]
            } else {
                c0[(j, k)] + c0[(k, j)]
            };
            if factor != 0.0 {
                entries.push((j, k, factor));
            }
        }
    }
    entries
}

/// Whether the matrix terms' distinct entries make the Gram matrix the cheaper path.
fn use_gram(dofs: usize, entries: &[MatrixEntries]) -> bool {
    if entries.is_empty() || dofs < GRAM_MIN_DOFS {
        return false;
    }
    let mut distinct: Vec<(usize, usize)> =
        entries.iter().flatten().map(|&(j, k, _)| (j, k)).collect();
    distinct.sort_unstable();
    distinct.dedup();
    let all = dofs * (dofs + 1) / 2;
    distinct.len() as f64 > GRAM_DENSITY * all as f64
}

/// Cuts the sums (in pass order) where the last column changes.
fn groups(sums: &[Sum<'_>]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for (slot, sum) in sums.iter().enumerate() {
        let column = sum.last_column();
        match groups.last_mut() {
            Some(group) if group.column == column => group.slots.end = slot + 1,
            _ => groups.push(Group {
                slots: slot..slot + 1,
                fused: 0,
                column,
            }),
        }
    }
    for group in &mut groups {
        group.fused = sums[group.slots.clone()]
            .iter()
            .take_while(|sum| sum.fusable())
            .count();
    }
    groups
}

/// Cuts the groups into runs of at least [`SEGMENT_SUMS`] sums.
fn segments(groups: &[Group]) -> Vec<Range<usize>> {
    let mut segments = Vec::new();
    let mut start = 0;
    for g in 1..groups.len() {
        if groups[g].slots.start - groups[start].slots.start >= SEGMENT_SUMS {
            segments.push(start..g);
            start = g;
        }
    }
    if start < groups.len() {
        segments.push(start..groups.len());
    }
    segments
}
