//! Properties of the energy balance and of the numerical stages, checked with proptest on
//! small synthetic systems: pure harmonic motion x_j = X_j cos(ωt + φ_j) with exact
//! velocities (tests/support), 2 or 3 DOFs, a few records, 32 cases per property.
//!
//! - scaling the forces by k scales every coefficient by k (least squares, any k ≠ 0;
//!   nonnegative fit, k > 0);
//! - permuting the DOFs together with the model's connectivity (elements and matrices)
//!   leaves every coefficient unchanged;
//! - adding a conservative force (K₂x with K₂ symmetric, and a cubic spring) to the
//!   recorded generalized force leaves them unchanged: its work over a period is zero;
//! - splitting a record into its cycles (as windows, or as separate records) gives the
//!   same answer as one window over the whole record;
//! - the POD reconstructs its input: all modes retained, or m modes of rank-m data;
//! - the constrained fit with bounds that do not bind equals least squares.
//!
//! Tolerances scale with the condition number κ of the column-scaled regressor: a
//! perturbation of relative size ε in b moves the coefficients by up to κε.

mod support;

use std::f64::consts::PI;

use dampid::fit::{self, SolverSettings};
use dampid::prelude::*;
use faer::Mat;
use proptest::prelude::*;
use support::Harmonic;
use support::regressors::row_labels;

const CASES: u32 = 32;

/// One harmonic record's parameters (tests/support's `Harmonic` is not `Debug`).
#[derive(Debug, Clone)]
struct Motion {
    amplitudes: Vec<f64>,
    phases: Vec<f64>,
    omega: f64,
    per_period: f64,
    force: f64,
    force_phase: f64,
    force_dof: usize,
}

impl Motion {
    fn harmonic(&self, periods: f64) -> Harmonic {
        Harmonic {
            amplitudes: self.amplitudes.clone(),
            phases: self.phases.clone(),
            omega: self.omega,
            per_period: self.per_period,
            periods,
            force: self.force,
            force_phase: self.force_phase,
            force_dof: self.force_dof,
        }
    }

    fn record(&self) -> Record {
        self.harmonic(1.0).record()
    }
}

/// Harmonic motion on `n` DOFs with `per_period` samples per period drawn by `samples`.
fn motion(n: usize, samples: impl Strategy<Value = f64>) -> impl Strategy<Value = Motion> {
    (
        prop::collection::vec(0.2..2.0f64, n),
        prop::collection::vec(0.0..2.0 * PI, n),
        0.5..2.0f64,
        samples,
        0.5..2.0f64,
        0.0..2.0 * PI,
        0..n,
    )
        .prop_map(
            |(amplitudes, phases, omega, per_period, force, force_phase, force_dof)| Motion {
                amplitudes,
                phases,
                omega,
                per_period,
                force,
                force_phase,
                force_dof,
            },
        )
}

fn motions(n: usize, count: usize) -> impl Strategy<Value = Vec<Motion>> {
    prop::collection::vec(motion(n, 24.0..64.0f64), count)
}

fn settings(
    quadrature: Quadrature,
    cycles: usize,
    count: usize,
    constraints: Constraints,
) -> IdentifySettings {
    let mut settings = support::identify_settings(
        WindowSpec::cycles(cycles).first(count),
        quadrature,
        VelocitySource::Measured,
    );
    settings.fit.constraints = constraints;
    // The records' force phases are arbitrary, so their input work may be negative:
    // these properties are of the algebra of the fit, not of a passive structure.
    settings.fit.accept_negative_work = true;
    settings
}

fn least_squares() -> IdentifySettings {
    settings(Quadrature::Trapezoid, 1, 1, Constraints::default())
}

/// Linear damping per DOF to ground (`c[1]`, `c[2]`, …) and shared quadratic `d`.
fn per_dof_model(n: usize) -> DampingModel {
    DampingModel::new()
        .with(Term::per_dof(
            Linear,
            n,
            Coefficients::PerElement("c".into()),
        ))
        .with(Term::per_dof(
            Quadratic,
            n,
            Coefficients::Shared("d".into()),
        ))
}

fn values(report: &FitReport) -> Vec<f64> {
    report.coefficients.iter().map(|c| c.value).collect()
}

/// κ of the column-scaled regressor, infinite when rank deficient.
fn kappa(report: &FitReport) -> f64 {
    report.condition_number.unwrap_or(f64::INFINITY)
}

/// max_j |a_j − b_j| / max(max_j |b_j|, floor).
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Records with their force channels multiplied by `k`.
fn scaled_forces(records: &[Record], k: f64) -> Vec<Record> {
    records
        .iter()
        .map(|r| {
            let mut parts = r.parts().clone();
            let s = &parts.forcing.signals;
            parts.forcing.signals = Mat::from_fn(s.nrows(), s.ncols(), |i, j| k * s[(i, j)]);
            Record::new(parts).unwrap()
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    /// b scales by k and A does not, so least squares gives kθ (the minimum-norm
    /// solution too, were the regressor rank deficient).
    #[test]
    fn scaling_forces_scales_least_squares_coefficients(
        data in motions(2, 4),
        k in prop_oneof![0.1..10.0f64, -10.0..-0.1f64],
    ) {
        let model = per_dof_model(2);
        let records: Vec<Record> = data.iter().map(Motion::record).collect();
        let base = identify(&ParametricRegressor::linear(&model, &records), &least_squares(), &silent).unwrap().report;
        prop_assume!(kappa(&base) < 1e8);
        let scaled = identify(&ParametricRegressor::linear(&model, &scaled_forces(&records, k)), &least_squares(), &silent).unwrap().report;
        let expected: Vec<f64> = values(&base).iter().map(|v| k * v).collect();
        let error = relative_difference(&values(&scaled), &expected);
        prop_assert!(error < 1e-12 * kappa(&base).max(1.0), "error {error:e}, κ {:e}", kappa(&base));
    }

    /// Under θ ≥ 0 the feasible set is a cone, so k > 0 scales the solution as well,
    /// coefficients held at zero included.
    #[test]
    fn scaling_forces_scales_nonnegative_coefficients(
        data in motions(2, 4),
        k in 0.1..10.0f64,
    ) {
        let model = per_dof_model(2);
        let records: Vec<Record> = data.iter().map(Motion::record).collect();
        let nonnegative = settings(Quadrature::Trapezoid, 1, 1, Constraints::nonnegative());
        let base = identify(&ParametricRegressor::linear(&model, &records), &nonnegative, &silent).unwrap().report;
        prop_assume!(base.status == FitStatus::Solved && kappa(&base) < 1e6);
        let scaled = identify(&ParametricRegressor::linear(&model, &scaled_forces(&records, k)), &nonnegative, &silent).unwrap().report;
        prop_assert_eq!(scaled.status, FitStatus::Solved);
        let expected: Vec<f64> = values(&base).iter().map(|v| k * v).collect();
        let error = relative_difference(&values(&scaled), &expected);
        prop_assert!(error < 1e-7, "error {error:e}: {:?} vs {expected:?}", values(&scaled));
        let zeros = |r: &FitReport| -> Vec<bool> { values(r).iter().map(|v| *v == 0.0).collect() };
        prop_assert_eq!(zeros(&base), zeros(&scaled));
    }

    /// DOF i of the original is DOF perm[i] of the permuted system: displacements,
    /// velocities, force DOFs, element ends and matrix entries all follow. Elements keep
    /// their labels, so the coefficient names are the same.
    #[test]
    fn permuting_dofs_with_the_connectivity_leaves_coefficients_unchanged(
        data in motions(3, 7),
        perm in Just(vec![0usize, 1, 2]).prop_shuffle(),
        c0 in prop::collection::vec(-1.0..1.0f64, 6),
    ) {
        let n = 3;
        // A symmetric C₀ from its upper triangle.
        let upper = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
        let mut matrix = Mat::<f64>::zeros(n, n);
        for (&(i, j), v) in upper.iter().zip(&c0) {
            matrix[(i, j)] = *v;
            matrix[(j, i)] = *v;
        }
        let elements = |p: &dyn Fn(usize) -> usize| {
            vec![
                Element::to_ground(p(0)).labelled("g"),
                Element::between(p(0), p(1)).labelled("a"),
                Element::between(p(1), p(2)).labelled("b"),
            ]
        };
        let model = |p: &dyn Fn(usize) -> usize, c: Mat<f64>| {
            DampingModel::new()
                .with(Term::viscous("c0", c))
                .with(Term::on_elements(Linear, elements(p), Coefficients::PerElement("k".into())))
                .with(Term::on_elements(
                    Quadratic,
                    vec![Element::to_ground(p(2))],
                    Coefficients::Shared("q".into()),
                ))
        };
        let identity = |i: usize| i;
        let moved = |i: usize| perm[i];
        let mut permuted_matrix = Mat::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                permuted_matrix[(perm[i], perm[j])] = matrix[(i, j)];
            }
        }
        let records: Vec<Record> = data.iter().map(Motion::record).collect();
        let permuted: Vec<Record> = records
            .iter()
            .map(|r| {
                let parts = r.parts().clone();
                let permute = |m: &Mat<f64>| {
                    let mut out = Mat::<f64>::zeros(m.nrows(), n);
                    for i in 0..n {
                        for t in 0..m.nrows() {
                            out[(t, perm[i])] = m[(t, i)];
                        }
                    }
                    out
                };
                let dofs = match &parts.forcing.distribution {
                    dampid::record::LoadDistribution::Dofs(d) => d.iter().map(|&i| perm[i]).collect(),
                    other => panic!("fixture forcing is per DOF: {other:?}"),
                };
                Record::new(RecordParts {
                    displacements: permute(&parts.displacements),
                    velocities: parts.velocities.as_ref().map(permute),
                    forcing: Forcing::on_dofs(parts.forcing.signals.clone(), dofs),
                    ..parts
                })
                .unwrap()
            })
            .collect();
        let base = identify(&ParametricRegressor::linear(&model(&identity, matrix), &records), &least_squares(), &silent).unwrap().report;
        prop_assume!(kappa(&base) < 1e8);
        let other = identify(&ParametricRegressor::linear(&model(&moved, permuted_matrix), &permuted), &least_squares(), &silent).unwrap().report;
        let names: Vec<&str> = base.coefficients.iter().map(|c| c.name.as_str()).collect();
        let by_name: Vec<f64> = names.iter().map(|name| other.coefficient(name).unwrap()).collect();
        let error = relative_difference(&by_name, &values(&base));
        prop_assert!(error < 1e-12 * kappa(&base).max(1.0), "error {error:e}, κ {:e}", kappa(&base));
    }

    /// r + K₂x + κ₃ x_j³ e_j: the added work is ∮ d/dt(½xᵀK₂x + ¼κ₃x_j⁴) dt = 0 over a
    /// period. Its integrand is a trigonometric polynomial, which the spectral rule
    /// integrates exactly on any grid.
    #[test]
    fn adding_a_conservative_force_leaves_coefficients_unchanged(
        data in motions(2, 4),
        k2 in prop::collection::vec(-3.0..3.0f64, 3),
        cubic in -2.0..2.0f64,
        cubic_dof in 0..2usize,
    ) {
        let n = 2;
        let stiffness = Mat::from_fn(n, n, |i, j| k2[i + j]);
        let model = per_dof_model(n);
        let spectral = settings(Quadrature::Spectral, 1, 1, Constraints::default());
        let records: Vec<Record> = data.iter().map(Motion::record).collect();
        let with_spring: Vec<Record> = records
            .iter()
            .map(|r| {
                let parts = r.parts().clone();
                let x = &parts.displacements;
                let samples = x.nrows();
                let dofs = match &parts.forcing.distribution {
                    dampid::record::LoadDistribution::Dofs(d) => d.clone(),
                    other => panic!("fixture forcing is per DOF: {other:?}"),
                };
                let generalized = Mat::from_fn(samples, n, |t, i| {
                    let applied: f64 = dofs
                        .iter()
                        .enumerate()
                        .filter(|(_, d)| **d == i)
                        .map(|(k, _)| parts.forcing.signals[(t, k)])
                        .sum();
                    let spring: f64 = (0..n).map(|j| stiffness[(i, j)] * x[(t, j)]).sum();
                    let cubic_force = if i == cubic_dof { cubic * x[(t, i)].powi(3) } else { 0.0 };
                    applied + spring + cubic_force
                });
                Record::new(RecordParts {
                    forcing: Forcing::generalized(generalized),
                    ..parts
                })
                .unwrap()
            })
            .collect();
        let base = identify(&ParametricRegressor::linear(&model, &records), &spectral, &silent).unwrap().report;
        prop_assume!(kappa(&base) < 1e8);
        let other = identify(&ParametricRegressor::linear(&model, &with_spring), &spectral, &silent).unwrap().report;
        // The added work cancels to round-off of the spring's own work, which can be
        // larger than the damping work: measure against both.
        let error = relative_difference(&values(&other), &values(&base));
        prop_assert!(error < 1e-9 * kappa(&base).max(1.0), "error {error:e}, κ {:e}", kappa(&base));
    }

    /// With a whole number P of samples per period every cycle reads the same samples of
    /// a periodic signal, so one window over k cycles, k windows of one cycle, and k
    /// separate one-cycle records all give the same least-squares answer.
    #[test]
    fn splitting_a_record_into_cycles_gives_the_same_answer(
        data in prop::collection::vec(motion(2, (16u32..48).prop_map(f64::from)), 4),
        cycles in 2usize..=4,
    ) {
        let model = per_dof_model(2);
        let whole_records: Vec<Record> = data
            .iter()
            .map(|m| m.harmonic(cycles as f64).record())
            .collect();
        let whole = identify(&ParametricRegressor::linear(&model, &whole_records), &settings(Quadrature::Trapezoid, cycles, 1, Constraints::default()), &silent)
        .unwrap().report;
        prop_assume!(kappa(&whole) < 1e8);
        let tolerance = 1e-11 * kappa(&whole).max(1.0);

        let windows = identify(&ParametricRegressor::linear(&model, &whole_records), &settings(Quadrature::Trapezoid, 1, cycles, Constraints::default()), &silent)
        .unwrap().report;
        prop_assert_eq!(windows.residuals.len(), 4 * cycles);
        let error = relative_difference(&values(&windows), &values(&whole));
        prop_assert!(error < tolerance, "windows: error {error:e}, κ {:e}", kappa(&whole));

        // Cycle j of each record as its own record: samples jP ..= jP + P.
        let pieces: Vec<Record> = whole_records
            .iter()
            .zip(&data)
            .flat_map(|(record, m)| {
                let p = m.per_period.round() as usize;
                (0..cycles).map(move |j| {
                    let parts = record.parts();
                    let rows = |a: &Mat<f64>| a.as_ref().subrows(j * p, p + 1).to_owned();
                    Record::new(RecordParts {
                        label: format!("{} cycle {j}", parts.label),
                        step: parts.step,
                        start_time: parts.start_time + (j * p) as f64 * parts.step,
                        displacements: rows(&parts.displacements),
                        velocities: parts.velocities.as_ref().map(rows),
                        forcing: Forcing {
                            signals: rows(&parts.forcing.signals),
                            distribution: parts.forcing.distribution.clone(),
                        },
                        period: parts.period,
                    })
                    .unwrap()
                })
            })
            .collect();
        let split = identify(&ParametricRegressor::linear(&model, &pieces), &least_squares(), &silent).unwrap().report;
        prop_assert_eq!(split.residuals.len(), 4 * cycles);
        let error = relative_difference(&values(&split), &values(&whole));
        prop_assert!(error < tolerance, "records: error {error:e}, κ {:e}", kappa(&whole));
    }

    /// With every mode retained U Uᵀ = I: the projected record is the input.
    #[test]
    fn pod_with_every_mode_reconstructs_its_input(
        (n, x) in (1usize..=5, 4usize..=40).prop_flat_map(|(n, samples)| {
            (Just(n), prop::collection::vec(-2.0..2.0f64, n * samples))
        }),
        remove_mean in any::<bool>(),
    ) {
        let samples = x.len() / n;
        let x = Mat::from_fn(samples, n, |i, j| x[i * n + j]);
        let pod_settings = PodSettings {
            remove_mean,
            retain: Retain::Count(n),
            basis: PodBasis::PerRecord,
        };
        let scale = x.norm_max();
        prop_assume!(scale > 1e-3);
        let pod = match Pod::from_displacements(x.as_ref(), &pod_settings) {
            Ok(pod) => pod,
            // Constant columns with the mean removed carry no energy: a typed error.
            Err(Error::InvalidParameter { ref name, .. }) if remove_mean && name == "POD signal energy" => {
                return Ok(());
            }
            Err(e) => panic!("{e}"),
        };
        let projected = pod.project(&pod_record(&x)).unwrap();
        let error = (projected.displacements() - &x).norm_max();
        prop_assert!(error < 1e-12 * scale, "error {error:e}");
        // The same through the modal coordinates: x = x̄ + U_m y.
        let y = pod.coordinates(x.as_ref()).unwrap();
        let back = &y * pod.retained_modes().transpose();
        let back = Mat::from_fn(samples, n, |i, j| back[(i, j)] + pod.mean()[j]);
        prop_assert!((&back - &x).norm_max() < 1e-12 * scale);
    }

    /// Data of rank m (x = Y Φᵀ): the m leading modes span them, and reconstruct them.
    #[test]
    fn pod_with_m_modes_reconstructs_rank_m_data(
        (n, m, samples, y, phi) in (2usize..=5, 10usize..=40).prop_flat_map(|(n, samples)| {
            (1..n).prop_flat_map(move |m| {
                (
                    Just(n),
                    Just(m),
                    Just(samples),
                    prop::collection::vec(-2.0..2.0f64, samples * m),
                    prop::collection::vec(-1.0..1.0f64, n * m),
                )
            })
        }),
        remove_mean in any::<bool>(),
    ) {
        let y = Mat::from_fn(samples, m, |i, k| y[i * m + k]);
        let phi = Mat::from_fn(n, m, |j, k| phi[j * m + k]);
        let x = &y * phi.transpose();
        let scale = x.norm_max();
        prop_assume!(scale > 1e-3);
        let pod_settings = PodSettings {
            remove_mean,
            retain: Retain::Count(m),
            basis: PodBasis::PerRecord,
        };
        let pod = Pod::from_displacements(x.as_ref(), &pod_settings).unwrap();
        prop_assert_eq!(pod.retained(), m);
        let projected = pod.project(&pod_record(&x)).unwrap();
        let error = (projected.displacements() - &x).norm_max();
        prop_assert!(error < 1e-9 * scale, "error {error:e}");
        // The discarded values are round-off.
        let values = pod.values();
        prop_assert!(values[m..].iter().all(|v| *v <= 1e-12 * values[0]), "{values:?}");
    }

    /// Bounds at least half of |θ|+1 away from the least-squares solution do not bind:
    /// the constrained fit (clarabel, then the polish) is the least-squares solution.
    #[test]
    fn constrained_fit_with_inactive_bounds_equals_least_squares(
        (rows, cols, a, b) in (1usize..=4).prop_flat_map(|p| (p + 1..=p + 6).prop_flat_map(move |m| {
            (
                Just(m),
                Just(p),
                prop::collection::vec(-1.0..1.0f64, m * p),
                prop::collection::vec(-1.0..1.0f64, m),
            )
        })),
        margins in prop::collection::vec((0.5..5.0f64, 0.5..5.0f64, 0u8..4), 4),
    ) {
        let matrix = Mat::from_fn(rows, cols, |i, j| a[i * cols + j]);
        let names: Vec<String> = (0..cols).map(|j| format!("t{j}")).collect();
        let labels = row_labels(rows);
        let regressor = Regressor::from_parts(matrix, b, names.clone(), labels).unwrap();
        let ls = fit::least_squares(&regressor, 1e-10).unwrap();
        let ls_report = FitReport::new(
            &regressor,
            ls.clone(),
            dampid::analysis::diagnostics::diagnose(&regressor, &ls, 1e-10),
        );
        prop_assume!(kappa(&ls_report) < 1e6);
        let bounds = names
            .iter()
            .zip(&ls.coefficients)
            .zip(&margins)
            .map(|((name, &theta), &(below, above, sides))| Bound {
                name: name.clone(),
                // sides: 0 both, 1 lower only, 2 upper only, 3 both again
                lower: (sides != 2).then(|| theta - below * (theta.abs() + 1.0)),
                upper: (sides != 1).then(|| theta + above * (theta.abs() + 1.0)),
            })
            .collect();
        let constraints = Constraints {
            bounds,
            ..Constraints::default()
        };
        let fit = fit::constrained(&regressor, &constraints, &SolverSettings::default()).unwrap();
        prop_assert_eq!(fit.status, FitStatus::Solved);
        prop_assert!(fit.active.is_empty(), "{:?}", fit.active);
        let error = relative_difference(&fit.coefficients, &ls.coefficients);
        prop_assert!(error < 1e-9 * kappa(&ls_report).max(1.0), "error {error:e}: {:?} vs {:?}", fit.coefficients, ls.coefficients);
    }
}

/// A record holding displacements `x` (for `Pod::project`), with zero forces.
fn pod_record(x: &Mat<f64>) -> Record {
    Record::new(RecordParts {
        label: "pod".into(),
        step: 0.1,
        start_time: 0.0,
        displacements: x.clone(),
        velocities: None,
        forcing: Forcing::generalized(Mat::zeros(x.nrows(), x.ncols())),
        period: 1.0,
    })
    .unwrap()
}
