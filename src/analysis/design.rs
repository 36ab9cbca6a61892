//! Experiment design: from candidate experiments (driving frequency, amplitude, forcing
//! DOF), choose a small set whose equations make the model's coefficients identifiable.
//!
//! Each candidate is simulated on a nominal system (M, K and a guess of the damping)
//! with [`simulate`] and turned into its regressor rows (all its windows). Starting from
//! the `start` set, the greedy step adds the candidate that most improves the stacked
//! rows' column-scaled regressor A_s = U Σ Vᵀ (unit-norm columns, so the criterion does
//! not depend on the coefficients' units):
//!
//! ```text
//!   D-optimal:          log det(A_sᵀ A_s) = 2 Σ_i ln σ_i        (maximise)
//!   minimum condition:  κ = σ_1/σ_p                           (minimise)
//! ```
//!
//! Candidates are compared first by practical rank (σ_i ≥ max(tol, ε)·σ_1 with the
//! identifiability analysis's precision ε = 1e-6: the simulations are noise-free, and a
//! direction below ε·σ_1 is not determined by any real record; a set that determines
//! more directions always wins), then by the criterion over the numerically nonzero σ_i
//! (σ_i > tol·σ_1); ties go to the lower index. The search stops after `picks` additions, as soon as the
//! condition number falls below `target_condition`, or when the candidates run out. The
//! report lists the condition number and log det after each addition. The design is
//! only as good as the nominal damping: it uses noise-free simulations of the guess.

use std::fmt;

use faer::Mat;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};
use crate::fit::svd::{numerical_rank, scaled_singular_values};
use crate::model::DampingModel;
use crate::progress::Progress;
use crate::record::Record;
use crate::regressor::{Regressor, RegressorSettings};
use crate::simulate::{HarmonicForce, SimSettings, System, simulate};

/// What the greedy search optimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Maximise log det(A_sᵀA_s).
    #[default]
    DOptimal,
    /// Minimise the condition number of A_s.
    Condition,
}

/// Settings of the greedy search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignSettings {
    /// The criterion (default D-optimal).
    pub criterion: Criterion,
    /// Most candidates to add (default 3).
    pub picks: usize,
    /// Candidates always included (0-based indices), e.g. the experiments already run.
    pub start: Vec<usize>,
    /// Stop once the column-scaled condition number is below this (default none).
    pub target_condition: Option<f64>,
    /// Numerical rank tolerance relative to σ_1 (default 1e-10).
    pub rank_tolerance: f64,
    /// ε: singular values below ε·σ_1 do not count towards the practical rank
    /// (default 1e-6, as in [`crate::analysis::identifiability::IdentifiabilitySettings`]).
    pub precision: f64,
}

impl Default for DesignSettings {
    fn default() -> Self {
        DesignSettings {
            criterion: Criterion::DOptimal,
            picks: 3,
            start: Vec::new(),
            target_condition: None,
            rank_tolerance: 1e-10,
            precision: 1e-6,
        }
    }
}

impl DesignSettings {
    /// Checks the settings against `candidates` candidates.
    pub fn validate(&self, candidates: usize) -> Result<()> {
        if candidates == 0 {
            return Err(Error::Empty {
                what: "candidate experiments".into(),
            });
        }
        for (k, &s) in self.start.iter().enumerate() {
            if s >= candidates {
                return Err(Error::invalid(
                    "start experiment",
                    s as f64,
                    &format!("there are {candidates} candidates (0-based indices)"),
                ));
            }
            if self.start[..k].contains(&s) {
                return Err(Error::invalid(
                    "start experiment",
                    s as f64,
                    "is listed twice",
                ));
            }
        }
        if let Some(t) = self.target_condition
            && !(t.is_finite() && t > 1.0)
        {
            return Err(Error::invalid(
                "target_condition",
                t,
                "must be finite and above 1",
            ));
        }
        if !(self.rank_tolerance > 0.0 && self.rank_tolerance < 1.0) {
            return Err(Error::invalid(
                "rank_tolerance",
                self.rank_tolerance,
                "must be in (0, 1)",
            ));
        }
        if !(self.precision >= 0.0 && self.precision < 1.0) {
            return Err(Error::invalid(
                "precision",
                self.precision,
                "must be in [0, 1)",
            ));
        }
        Ok(())
    }
}

/// The state of the selection after one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignStep {
    /// The candidate added (`None` for the start set).
    pub candidate: Option<usize>,
    /// What was added, in words.
    pub label: String,
    /// Equations so far.
    pub equations: usize,
    /// Practical rank so far (σ_i ≥ max(tol, ε)·σ_1).
    pub rank: usize,
    /// Condition number of the column-scaled regressor (`None`: numerically rank
    /// deficient).
    pub condition_number: Option<f64>,
    /// log det(A_sᵀA_s) (`None`: numerically rank deficient).
    pub log_det: Option<f64>,
    /// Singular values of the column-scaled regressor.
    pub singular_values: Vec<f64>,
}

/// The chosen experiments and how the conditioning improved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignReport {
    /// The criterion used.
    pub criterion: Criterion,
    /// Names of the regressor's columns: the model's coefficients, then (in the
    /// non-periodic mode) its nuisance unknowns.
    pub coefficients: Vec<String>,
    /// Labels of all candidates, by index.
    pub candidates: Vec<String>,
    /// The start set.
    pub start: Vec<usize>,
    /// Candidates added, in order.
    pub chosen: Vec<usize>,
    /// The state after the start set (if any) and after each addition.
    pub steps: Vec<DesignStep>,
    /// The target condition number, if one was set.
    pub target_condition: Option<f64>,
}

impl DesignReport {
    /// The start set followed by the chosen candidates.
    pub fn selected(&self) -> Vec<usize> {
        self.start.iter().chain(&self.chosen).copied().collect()
    }

    /// The last step (none when nothing was selected).
    pub fn last(&self) -> Option<&DesignStep> {
        self.steps.last()
    }

    /// True when the final set has full rank and meets the target condition, if any.
    pub fn succeeded(&self) -> bool {
        self.last().is_some_and(|s| {
            s.rank == self.coefficients.len()
                && match (self.target_condition, s.condition_number) {
                    (Some(t), Some(k)) => k < t,
                    (Some(_), None) => false,
                    (None, _) => true,
                }
        })
    }
}

/// One label per candidate: "a=1 ω=0.4450 on DOF 3" (DOFs 1-based, as in model files).
pub fn candidate_label(force: &HarmonicForce) -> String {
    format!(
        "a={} ω={:.4} on DOF {}",
        force.amplitude,
        force.frequency,
        force.dof + 1
    )
}

/// Simulates `system` once per candidate forcing (replacing its `forcing`), in
/// parallel; records are labelled with [`candidate_label`].
pub fn simulate_candidates(
    system: &System,
    candidates: &[HarmonicForce],
    simulation: &SimSettings,
) -> Result<Vec<Record>> {
    // Every candidate's record is held at once: x and v (N × n) and its one force
    // channel (N × 1), N recorded steps.
    let values = (candidates.len() as u128)
        .saturating_mul(simulation.recorded_steps as u128)
        .saturating_mul(2 * system.dofs() as u128 + 1);
    crate::budget::require(
        &format!(
            "{} design candidates of {} recorded steps × {} DOFs",
            candidates.len(),
            simulation.recorded_steps,
            system.dofs()
        ),
        crate::budget::f64s(values),
        "reduce the candidates or `recorded_steps`",
    )?;
    candidates
        .par_iter()
        .map(|force| {
            crate::cancel::check("simulating the design candidates")?;
            let mut one = system.clone();
            one.forcing = vec![*force];
            let simulated = simulate(&one, simulation, &crate::progress::silent);
            let mut parts =
                crate::cancel::within("simulating the design candidates", simulated)?.into_parts();
            parts.label = candidate_label(force);
            Record::new(parts)
        })
        .collect()
}

/// Simulates every candidate on the `nominal` system and selects a set for `model`.
pub fn design(
    nominal: &System,
    model: &DampingModel,
    candidates: &[HarmonicForce],
    simulation: &SimSettings,
    regressor: &RegressorSettings,
    settings: &DesignSettings,
) -> Result<DesignReport> {
    settings.validate(candidates.len())?;
    let records = simulate_candidates(nominal, candidates, simulation)?;
    select(
        model,
        &records,
        regressor,
        settings,
        &crate::progress::silent,
    )
}

/// The units of work of a selection: one regressor block per candidate, then one
/// evaluation per remaining candidate at each of the (at most) `picks` steps,
/// Σ_{i<q} (c − s − i) with c candidates, s started with and q = min(picks, c − s).
fn work_units(candidates: usize, started: usize, picks: usize) -> u64 {
    let left = candidates.saturating_sub(started);
    let steps = picks.min(left);
    (0..steps).map(|i| (left - i) as u64).sum::<u64>() + candidates as u64
}

/// Greedy selection among candidates already simulated (or measured): one record each.
/// `progress(done, total)` counts in units of `work_units` (blocks built, then
/// candidate evaluations; the count jumps to the end when the target condition number
/// stops the selection early); [`crate::cancel::check`] runs before each unit.
pub fn select(
    model: &DampingModel,
    records: &[Record],
    regressor: &RegressorSettings,
    settings: &DesignSettings,
    progress: Progress<'_>,
) -> Result<DesignReport> {
    settings.validate(records.len())?;
    let total = work_units(records.len(), settings.start.len(), settings.picks);
    let done = AtomicU64::new(0);
    let tick = || progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
    let blocks: Vec<Regressor> = records
        .par_iter()
        .map(|r| {
            crate::cancel::check("the design")?;
            let block = crate::cancel::within(
                "the design",
                Regressor::build(model, std::slice::from_ref(r), regressor),
            );
            tick();
            block
        })
        .collect::<Result<_>>()?;
    // Every column of the regressor: the damping coefficients, and in the non-periodic
    // mode the stored-energy and offset unknowns, which compete with them for the data.
    let columns = blocks
        .first()
        .map_or_else(|| model.coefficient_names(), |b| b.columns().to_vec());
    let p = columns.len();
    require_stacks(&blocks, settings, p)?;
    let labels: Vec<String> = records.iter().map(|r| r.label().to_string()).collect();
    let mut selected: Vec<usize> = settings.start.clone();
    let mut steps = Vec::new();
    if !selected.is_empty() {
        let state = evaluate(&blocks, &selected, p, settings);
        steps.push(step(
            None,
            format!(
                "start: {}",
                selected
                    .iter()
                    .map(|&k| labels[k].as_str())
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
            state,
        ));
    }
    let mut chosen = Vec::new();
    let reached = |steps: &[DesignStep]| match (settings.target_condition, steps.last()) {
        (Some(t), Some(s)) => s.condition_number.is_some_and(|k| k < t),
        _ => false,
    };
    while chosen.len() < settings.picks && !reached(&steps) {
        let remaining: Vec<usize> = (0..records.len())
            .filter(|k| !selected.contains(k))
            .collect();
        if remaining.is_empty() {
            break;
        }
        let scored: Vec<(usize, State)> = remaining
            .par_iter()
            .map(|&k| {
                crate::cancel::check("the design")?;
                let mut trial = selected.clone();
                trial.push(k);
                let state = evaluate(&blocks, &trial, p, settings);
                tick();
                Ok((k, state))
            })
            .collect::<Result<_>>()?;
        let mut best: Option<&(usize, State)> = None;
        for candidate in &scored {
            let better = match best {
                None => true,
                Some((_, b)) => better(&candidate.1, b, settings.criterion),
            };
            if better {
                best = Some(candidate);
            }
        }
        let Some((k, state)) = best.cloned() else {
            break;
        };
        selected.push(k);
        chosen.push(k);
        steps.push(step(Some(k), labels[k].clone(), state));
    }
    progress(total, total);
    Ok(DesignReport {
        criterion: settings.criterion,
        coefficients: columns,
        candidates: labels,
        start: settings.start.clone(),
        chosen,
        steps,
        target_condition: settings.target_condition,
    })
}

/// Checks the memory of the candidate evaluations before any: each evaluation stacks
/// its selection's rows, at most the start blocks and the `picks` largest others, R
/// rows × p columns, and its SVD holds about 3 such matrices (the stack, its scaled
/// copy, the factor's workspace); up to T evaluations (the rayon threads) run at once:
/// 8 · 3 · T · R · p bytes.
fn require_stacks(blocks: &[Regressor], settings: &DesignSettings, p: usize) -> Result<()> {
    let mut others: Vec<u128> = (0..blocks.len())
        .filter(|k| !settings.start.contains(k))
        .map(|k| blocks[k].equations() as u128)
        .collect();
    others.sort_unstable_by_key(|&rows| std::cmp::Reverse(rows));
    let rows: u128 = settings
        .start
        .iter()
        .map(|&k| blocks[k].equations() as u128)
        .chain(others.into_iter().take(settings.picks))
        .sum::<u128>()
        .max(p as u128);
    let threads = rayon::current_num_threads().min(blocks.len()).max(1) as u128;
    crate::budget::require(
        &format!("evaluating designs of up to {rows} equations × {p} columns"),
        crate::budget::f64s(rows.saturating_mul(p as u128).saturating_mul(3 * threads)),
        "reduce the picks, the candidates' windows, or the model's coefficients",
    )
}

/// Rank, condition number and log det of a stacked selection.
#[derive(Debug, Clone)]
struct State {
    equations: usize,
    /// Practical rank.
    rank: usize,
    /// Numerical rank.
    numerical_rank: usize,
    singular_values: Vec<f64>,
    /// Σ ln σ_i and ln(σ_1/σ_r) over the numerically nonzero σ_i.
    log_sum: f64,
    log_condition: f64,
}

fn evaluate(
    blocks: &[Regressor],
    selection: &[usize],
    p: usize,
    settings: &DesignSettings,
) -> State {
    let m: usize = selection.iter().map(|&k| blocks[k].equations()).sum();
    let mut a = Mat::<f64>::zeros(m.max(p), p);
    let mut b = vec![0.0; m.max(p)];
    let mut row = 0;
    for &k in selection {
        let block = blocks[k].matrix();
        for i in 0..block.nrows() {
            for j in 0..p {
                a[(row, j)] = block[(i, j)];
            }
            b[row] = blocks[k].rhs()[i];
            row += 1;
        }
    }
    // Zero rows below a short stack keep p singular values (the missing ones are 0).
    let mut s = scaled_singular_values(&a, &b);
    if s.is_empty() {
        s = vec![0.0; p];
    }
    let largest = s.first().copied().unwrap_or(0.0);
    let nonzero: Vec<f64> = s[..numerical_rank(&s, settings.rank_tolerance)].to_vec();
    let floor = settings.rank_tolerance.max(settings.precision) * largest;
    State {
        equations: m,
        rank: nonzero.iter().filter(|v| **v >= floor).count(),
        numerical_rank: nonzero.len(),
        log_sum: nonzero.iter().map(|v| v.ln()).sum(),
        log_condition: match nonzero.last() {
            Some(last) => (largest / last).ln(),
            None => f64::INFINITY,
        },
        singular_values: s,
    }
}

fn better(x: &State, y: &State, criterion: Criterion) -> bool {
    if x.rank != y.rank {
        return x.rank > y.rank;
    }
    match criterion {
        Criterion::DOptimal => x.log_sum > y.log_sum,
        Criterion::Condition => x.log_condition < y.log_condition,
    }
}

fn step(candidate: Option<usize>, label: String, state: State) -> DesignStep {
    let full = state.numerical_rank == state.singular_values.len();
    DesignStep {
        candidate,
        label,
        equations: state.equations,
        rank: state.rank,
        condition_number: full.then(|| state.log_condition.exp()),
        log_det: full.then_some(2.0 * state.log_sum),
        singular_values: state.singular_values,
    }
}

impl fmt::Display for DesignReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "experiment design ({}), {} coefficients: {}",
            match self.criterion {
                Criterion::DOptimal => "greedy D-optimal",
                Criterion::Condition => "greedy minimum condition number",
            },
            self.coefficients.len(),
            self.coefficients.join(", ")
        )?;
        writeln!(
            f,
            "{:>5}  {:<44} {:>9} {:>5} {:>14} {:>12}",
            "added", "experiment", "equations", "rank", "condition no.", "log det"
        )?;
        for s in &self.steps {
            let condition = s
                .condition_number
                .map_or("infinite".to_string(), |c| format!("{c:.4e}"));
            let log_det = s.log_det.map_or("-".to_string(), |d| format!("{d:.4}"));
            let index = match s.candidate {
                Some(c) => format!("#{}", c + 1),
                None => "start".to_string(),
            };
            writeln!(
                f,
                "{:>5}  {:<44} {:>9} {:>5} {:>14} {:>12}",
                index, s.label, s.equations, s.rank, condition, log_det
            )?;
        }
        if let Some(t) = self.target_condition {
            writeln!(
                f,
                "target condition number {t}: {}",
                if self.succeeded() {
                    "reached"
                } else {
                    "not reached"
                }
            )?;
        } else if !self.succeeded() {
            writeln!(
                f,
                "the selected experiments do not determine every coefficient: add candidates"
            )?;
        }
        Ok(())
    }
}
