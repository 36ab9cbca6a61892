//! Trials of a stepped-sine table with per-sweep residual unknowns, rebuilt one sweep
//! at a time.
//!
//! With η = (η_law, ρ₁, …, ρ_S), ρ_s the residual unknowns of sweep s (r_k, or r_k and
//! r_m), point p of sweep s has the equation of its mode's response
//! Z_mode = Z_p − R_p(ρ_s) a_p ([`crate::prep::harmonic::residual`]):
//!
//! ```text
//!   A_p(η) θ = b_p,   A_p = A(η_law; X_mode,p(ρ_s), φ_mode,p(ρ_s)),   b_p = π a_p X_p sin φ_p,
//! ```
//!
//! so the rows of sweep s (with the forward-difference rows of their noise model) are a
//! function of (η_law, ρ_s) alone: the regressor is block structured, each ρ_s touching
//! only its sweep's rows. A trial at η therefore reuses every sweep whose (η_law, ρ_s)
//! was built before (compared bit for bit) and synthesizes only the others: a forward
//! difference in ρ_s rebuilds one sweep instead of the table (1/S of a build), and a
//! trial whose η_law did not move (the nested searches of the law parameters' profile
//! intervals, the joint covariance's differences in ρ) only the sweeps whose ρ_s moved.
//! A point's rows depend on that point alone (one synthesized period each), so the
//! assembled regressor is the one a whole build at η gives, to the last bit
//! (tests/varpro_sweep_blocks.rs); the estimates and intervals do not change.
//!
//! Each sweep keeps its [`CAPACITY`] most recent blocks (a Levenberg–Marquardt
//! iteration asks for the base point, one difference per parameter and a step).

use std::sync::{Arc, Mutex};

use crate::error::Result;
use crate::model::DampingModel;
use crate::regressor::stepped_sine::{PointRows, assemble, point_rows, row_labels};
use crate::regressor::{ParametricRegressor, Regressor, RowLabel, SteppedSineSource};

/// Blocks kept per sweep.
const CAPACITY: usize = 8;

/// The key of a sweep's block: the bits of η_law then of the sweep's unknowns.
type Key = Vec<u64>;

/// The rows of one sweep's points, in the sweep's order.
type Block = Arc<Vec<PointRows>>;

/// ∂A/∂η_j on the rows it touches: (table row, ∂A_p/∂η_j per column).
pub(super) type RowDerivatives = Vec<(usize, Vec<f64>)>;

/// The trial builder of a table with residual unknowns (module doc).
pub(super) struct SweepBlocks<'a> {
    problem: &'a ParametricRegressor<'a>,
    source: &'a SteppedSineSource,
    /// Law parameters (the first of η).
    law: usize,
    /// Residual unknowns per sweep.
    per_sweep: usize,
    /// The points of each sweep, in table order.
    members: Vec<Vec<usize>>,
    /// Each point's place in its sweep.
    places: Vec<usize>,
    /// The row labels of every trial (the same for all: made once, shared).
    labels: Arc<[RowLabel]>,
    /// Per sweep: the most recent blocks, newest last.
    cache: Mutex<Vec<Vec<(Key, Block)>>>,
}

impl<'a> SweepBlocks<'a> {
    /// The builder of `problem` when its source is a table with residual unknowns per
    /// sweep, else `None`.
    pub fn of(problem: &'a ParametricRegressor<'a>) -> Option<Self> {
        let source = problem.source().stepped_sine()?;
        let sweeps = source.table.sweep_names.len();
        let per_sweep = source.residual.per_sweep();
        if per_sweep == 0 || source.residual_parameters.len() != per_sweep * sweeps {
            return None;
        }
        let mut members = vec![Vec::new(); sweeps];
        let mut places = Vec::with_capacity(source.table.sweeps.len());
        for (p, &s) in source.table.sweeps.iter().enumerate() {
            places.push(members[s].len());
            members[s].push(p);
        }
        Some(SweepBlocks {
            problem,
            source,
            law: problem.law().parameters().len(),
            per_sweep,
            members,
            places,
            labels: row_labels(source).into(),
            cache: Mutex::new(vec![Vec::new(); sweeps]),
        })
    }

    /// The regressor at `eta` (every parameter), as
    /// [`ParametricRegressor::regressor`] builds it.
    pub fn regressor(&self, eta: &[f64]) -> Result<Regressor> {
        self.assembled(eta, true)
    }

    /// [`SweepBlocks::regressor`] without its noise model (the same matrix, b, labels
    /// and work scale): for fits that read none (ordinary weighting).
    pub fn regressor_without_noise(&self, eta: &[f64]) -> Result<Regressor> {
        self.assembled(eta, false)
    }

    /// The regressor at `eta`, with its noise model when `with_noise`.
    fn assembled(&self, eta: &[f64], with_noise: bool) -> Result<Regressor> {
        let (model, blocks) = self.blocks(eta, with_noise)?;
        let rows: Vec<&PointRows> = self
            .source
            .table
            .sweeps
            .iter()
            .zip(&self.places)
            .map(|(&s, &place)| &blocks[s][place])
            .collect();
        assemble(&model, self.source, &rows, with_noise, Some(&self.labels))
    }

    /// ∂A/∂η_j at `eta` for a residual unknown j (`None` for a law parameter): the
    /// rows of its sweep (table row, ∂A_p/∂η_j) alone, every other row's being zero,
    ///
    /// ```text
    ///   ∂A_p/∂η_j = (∂R_p/∂η_j) ∂A_p/∂R,   ∂R_p/∂r_k = 1,   ∂R_p/∂r_m = −1/ω_p²,
    /// ```
    ///
    /// ∂A_p/∂R in closed form where the point's rows have one, else from its forward
    /// differences in X and φ ([`PointRows::residual_derivative`]); b does not depend
    /// on R.
    pub fn derivative(&self, eta: &[f64], j: usize) -> Result<Option<RowDerivatives>> {
        if j < self.law || j >= eta.len() {
            return Ok(None);
        }
        let (s, which) = (
            (j - self.law) / self.per_sweep,
            (j - self.law) % self.per_sweep,
        );
        // the sweep's block as kept (a Levenberg–Marquardt iteration asks for it right
        // after the residual at η), else every sweep's as a trial builds them
        let block = match self.kept(eta, s) {
            Some(block) => block,
            None => Arc::clone(&self.blocks(eta, false)?.1[s]),
        };
        let points = self.source.table.table.points();
        Ok(Some(
            self.members[s]
                .iter()
                .enumerate()
                .map(|(place, &p)| {
                    let point = &points[p];
                    let factor = if which == 0 {
                        1.0
                    } else {
                        -1.0 / (point.frequency * point.frequency)
                    };
                    let mut d = block[place].residual_derivative(point);
                    for x in &mut d {
                        *x *= factor;
                    }
                    (p, d)
                })
                .collect(),
        ))
    }

    /// The kept block of sweep `s` at `eta` (any, with or without the noise model's
    /// rows), when `eta` has the problem's length.
    fn kept(&self, eta: &[f64], s: usize) -> Option<Block> {
        if eta.len() != self.law + self.per_sweep * self.members.len() {
            return None;
        }
        let key = self.key(eta, s);
        // cannot fail: no code panics while holding the lock.
        let cache = self.cache.lock().expect("cache lock");
        cache[s]
            .iter()
            .rev()
            .find(|(at, _)| *at == key)
            .map(|(_, b)| Arc::clone(b))
    }

    /// The key of sweep `s`'s block at `eta`: the bits of η_law, then of the sweep's
    /// unknowns.
    fn key(&self, eta: &[f64], s: usize) -> Key {
        eta[..self.law]
            .iter()
            .chain(&eta[self.law + s * self.per_sweep..self.law + (s + 1) * self.per_sweep])
            .map(|v| v.to_bits())
            .collect()
    }

    /// The model at `eta` and the rows of every sweep, built where not kept; with the
    /// rows of the noise model when `noise` (a kept block without them serves a request
    /// without `noise` only).
    fn blocks(&self, eta: &[f64], noise: bool) -> Result<(DampingModel, Vec<Block>)> {
        let model = self.problem.model(eta)?;
        // cannot fail: `model` checked the length of `eta`.
        let residual = self
            .source
            .per_point(&eta[self.law..])?
            .expect("a table with residual unknowns");
        let sweeps = self.members.len();
        let keys: Vec<Key> = (0..sweeps).map(|s| self.key(eta, s)).collect();
        let mut blocks: Vec<Option<Block>> = {
            // cannot fail: no code panics while holding the lock.
            let cache = self.cache.lock().expect("cache lock");
            keys.iter()
                .zip(cache.iter())
                .map(|(k, kept)| {
                    kept.iter()
                        .rev()
                        .find(|(at, b)| at == k && (!noise || b.iter().all(PointRows::complete)))
                        .map(|(_, b)| Arc::clone(b))
                })
                .collect()
        };
        let missing: Vec<usize> = (0..sweeps).filter(|&s| blocks[s].is_none()).collect();
        if !missing.is_empty() {
            let indices: Vec<usize> = missing
                .iter()
                .flat_map(|&s| self.members[s].iter().copied())
                .collect();
            let r: Vec<f64> = indices.iter().map(|&p| residual[p]).collect();
            let mut built = point_rows(&model, self.source, &indices, Some(&r), noise)?.into_iter();
            // cannot fail: no code panics while holding the lock.
            let mut cache = self.cache.lock().expect("cache lock");
            for &s in &missing {
                let block = Arc::new(built.by_ref().take(self.members[s].len()).collect());
                let kept = &mut cache[s];
                if kept.len() >= CAPACITY {
                    kept.remove(0);
                }
                kept.push((keys[s].clone(), Arc::clone(&block)));
                blocks[s] = Some(block);
            }
        }
        // cannot fail: every sweep's block was found or built above.
        let blocks = blocks
            .into_iter()
            .map(|b| b.expect("every sweep built"))
            .collect();
        Ok((model, blocks))
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::model_file::{Job, parse};

    /// The shipped residual example (7 sweeps, R = −2e-6 m/N) with its power law's
    /// exponent estimated too.
    fn job() -> Job {
        let text = std::fs::read_to_string("models/bolted_joint_stepped_sine_residual.toml")
            .unwrap()
            .replace(
                "exponent = 1.5 ",
                "exponent = { estimate = true, initial = 1.4, lower = 0.5, upper = 3.0 } ",
            );
        assert!(text.contains("estimate = true"));
        parse(
            &text,
            "residual.toml",
            Path::new("models"),
            Default::default(),
        )
        .unwrap()
    }

    fn same(a: &Regressor, b: &Regressor) {
        let (ma, mb) = (a.matrix(), b.matrix());
        assert_eq!((ma.nrows(), ma.ncols()), (mb.nrows(), mb.ncols()));
        for r in 0..ma.nrows() {
            for k in 0..ma.ncols() {
                assert_eq!(ma[(r, k)].to_bits(), mb[(r, k)].to_bits(), "A[{r}, {k}]");
            }
        }
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a.rhs()), bits(b.rhs()));
        assert_eq!(format!("{:?}", a.noise()), format!("{:?}", b.noise()));
        assert_eq!(a.rows(), b.rows());
    }

    /// A trial assembled from cached and rebuilt sweeps is the whole build, bit for
    /// bit, along a sequence that moves one sweep's r_k, the exponent, then comes back.
    #[test]
    fn blocks_equal_whole_builds() {
        let job = job();
        let problem = job.problem();
        let blocks = SweepBlocks::of(&problem).unwrap();
        let settings = &job.settings.regressor;
        let mut eta = problem.initial_values();
        assert_eq!(eta.len(), 1 + 7);
        for (s, v) in eta[1..].iter_mut().enumerate() {
            *v = -2e-6 + 1e-7 * s as f64;
        }
        let mut moved = eta.clone();
        moved[3] += 3e-7;
        let mut exponent = moved.clone();
        exponent[0] = 1.55;
        for at in [&eta, &moved, &exponent, &eta, &moved] {
            same(
                &blocks.regressor(at).unwrap(),
                &problem.regressor(at, settings).unwrap(),
            );
        }
    }

    /// Trials without the noise model (ordinary weighting) have the whole build's A, b,
    /// labels and work scale, bit for bit, and no noise model; a trial with it at an η
    /// first built without is the whole build (its sweeps computed again, with the rows
    /// of a + h), and so is ∂A/∂r_k read from either.
    #[test]
    fn trials_without_noise_equal_whole_builds_but_the_noise_model() {
        let job = job();
        let problem = job.problem();
        let blocks = SweepBlocks::of(&problem).unwrap();
        let settings = &job.settings.regressor;
        let mut eta = problem.initial_values();
        for (s, v) in eta[1..].iter_mut().enumerate() {
            *v = -2e-6 + 1e-7 * s as f64;
        }
        let mut moved = eta.clone();
        moved[2] -= 4e-7;
        moved[0] = 1.45;
        for at in [&eta, &moved] {
            let whole = problem.regressor(at, settings).unwrap();
            assert!(whole.noise().is_some());
            let bare = blocks.regressor_without_noise(at).unwrap();
            assert!(bare.noise().is_none());
            let derivative_bare = blocks.derivative(at, 3).unwrap().unwrap();
            let bits = |m: &faer::Mat<f64>| {
                (0..m.nrows())
                    .flat_map(|r| (0..m.ncols()).map(move |k| m[(r, k)].to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(bare.matrix()), bits(whole.matrix()));
            assert_eq!(
                bare.rhs().iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                whole.rhs().iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
            assert_eq!(bare.rows(), whole.rows());
            assert_eq!(
                format!("{:?}", bare.work_scale()),
                format!("{:?}", whole.work_scale())
            );
            same(&blocks.regressor(at).unwrap(), &whole);
            let derivative_full = blocks.derivative(at, 3).unwrap().unwrap();
            assert_eq!(
                format!("{derivative_bare:?}"),
                format!("{derivative_full:?}")
            );
        }
    }

    /// ∂A/∂r_k in closed form against central differences of whole builds: the rows of
    /// sweep k to 10⁻⁵ of their largest entry, every other row exactly zero.
    #[test]
    fn residual_derivative_matches_central_differences() {
        let job = job();
        let problem = job.problem();
        let blocks = SweepBlocks::of(&problem).unwrap();
        let settings = &job.settings.regressor;
        let mut eta = problem.initial_values();
        eta[0] = 1.5;
        for v in &mut eta[1..] {
            *v = -2e-6;
        }
        for j in [1, 4, 7] {
            let derivative = blocks.derivative(&eta, j).unwrap().unwrap();
            let h = 1e-9;
            let at = |d: f64| {
                let mut e = eta.clone();
                e[j] += d;
                problem.regressor(&e, settings).unwrap()
            };
            let (up, down) = (at(h), at(-h));
            let m = up.matrix().nrows();
            let p = up.matrix().ncols();
            let mut closed = vec![vec![0.0; p]; m];
            for (row, d) in &derivative {
                closed[*row] = d.clone();
            }
            let sweep = j - 1;
            assert_eq!(
                derivative.len(),
                job.stepped_sine
                    .as_ref()
                    .unwrap()
                    .table
                    .sweeps
                    .iter()
                    .filter(|&&s| s == sweep)
                    .count()
            );
            for k in 0..p {
                let largest = closed.iter().map(|d| d[k].abs()).fold(0.0, f64::max);
                assert!(largest > 0.0);
                for (r, d) in closed.iter().enumerate() {
                    let central = (up.matrix()[(r, k)] - down.matrix()[(r, k)]) / (2.0 * h);
                    if derivative.iter().all(|(row, _)| *row != r) {
                        assert_eq!(central, 0.0, "row {r} outside sweep {sweep}");
                    } else {
                        assert!(
                            (d[k] - central).abs() <= 1e-5 * largest,
                            "row {r} column {k}: {} vs {central}",
                            d[k]
                        );
                    }
                }
            }
            assert!(blocks.derivative(&eta, 0).unwrap().is_none());
        }
    }

    /// The rows of every point in closed form without a point per perturbed copy are
    /// the rows through one copied point each (labels and all), bit for bit, with the
    /// noise model's copies (the equation's row alone without them, when ∂A/∂R is in
    /// closed form), and ∂A/∂R in closed form is the copies' differences; a residual receptance that cancels a response
    /// (here an infinite one) is still the error naming the point.
    #[test]
    fn closed_rows_in_place_equal_the_copied_rows() {
        use crate::regressor::stepped_sine::copied_point_rows;
        let job = job();
        let problem = job.problem();
        let source = problem.source().stepped_sine().unwrap();
        let mut eta = problem.initial_values();
        eta[0] = 1.55;
        for (s, v) in eta[1..].iter_mut().enumerate() {
            *v = -2e-6 + 3e-7 * s as f64;
        }
        let model = problem.model(&eta).unwrap();
        assert!(model.terms().iter().all(|t| t.has_harmonic_work()));
        let residual = source.per_point(&eta[1..]).unwrap().unwrap();
        let indices: Vec<usize> = (0..residual.len()).rev().collect();
        let r: Vec<f64> = indices.iter().map(|&p| residual[p]).collect();
        let points = source.table.table.points();
        for noise in [true, false] {
            for r in [None, Some(r.as_slice())] {
                let fast = point_rows(&model, source, &indices, r, noise).unwrap();
                let copied = copied_point_rows(&model, source, &indices, r, noise).unwrap();
                // ∂A/∂R in closed form with residual unknowns, against the forward
                // differences of the copied rows (to 10⁻⁵ of the largest entry)
                for ((f, c), &p) in fast.iter().zip(&copied).zip(&indices) {
                    assert_eq!(f.equation(), c.equation());
                    assert!(c.slope().is_none());
                    let Some(slope) = f.slope() else {
                        assert!(r.is_none());
                        continue;
                    };
                    let differenced = c.residual_derivative(&points[p]);
                    let largest = differenced.iter().fold(0.0f64, |m, d| m.max(d.abs()));
                    for (a, d) in slope.iter().zip(&differenced) {
                        assert!((a - d).abs() <= 1e-5 * largest, "{a} vs {d}");
                    }
                }
                // with the noise model, every row the same to the last bit
                let fast: Vec<_> = fast.into_iter().map(PointRows::without_slope).collect();
                if noise {
                    assert_eq!(format!("{fast:?}"), format!("{copied:?}"));
                }
            }
        }
        let cancel = vec![f64::INFINITY; indices.len()];
        let error = point_rows(&model, source, &indices, Some(&cancel), false)
            .unwrap_err()
            .to_string();
        let copied = copied_point_rows(&model, source, &indices, Some(&cancel), false)
            .unwrap_err()
            .to_string();
        assert_eq!(error, copied);
        let label = &source.table.table.points()[indices[0]].label;
        assert!(error.contains(&format!("'{label}'")), "{error}");
    }
}
