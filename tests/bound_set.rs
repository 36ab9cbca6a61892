//! A coefficient that noise puts on its bound, and the free coefficients it pulls
//! (`analysis::bound_set`, `Warning::BoundSetsCoefficients`): by hand on two columns,
//! and on the physics fuzz target's finding (a 3-DOF chain whose records repeat one
//! forcing point and mode, 10⁻⁴ sensor noise, nonnegative coefficients).

use dampid::analysis::diagnostics::diagnose;
use dampid::fit::{self, BoundSide, SolverSettings};
use dampid::prelude::*;
use dampid::regressor::{NoiseTreatment, RegressorSettings, Windows};
use dampid::report::Warning;
use faer::Mat;

mod support;
use support::regressors::row_labels;

/// b = A θ_u + e with e orthogonal to both columns, so that θ_u is the least-squares
/// solution: column a all ones, column b = `second`.
fn two_columns(second: [f64; 6], theta_u: [f64; 2], e: [f64; 6]) -> Regressor {
    let a = [1.0; 6];
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    // Gram–Schmidt: e less its projection on span(a, second).
    let q1: Vec<f64> = a.iter().map(|v| v / dot(&a, &a).sqrt()).collect();
    let mut q2: Vec<f64> = second.to_vec();
    let c = dot(&q2, &q1);
    q2.iter_mut().zip(&q1).for_each(|(v, q)| *v -= c * q);
    let n2 = dot(&q2, &q2).sqrt();
    q2.iter_mut().for_each(|v| *v /= n2);
    let (c1, c2) = (dot(&e, &q1), dot(&e, &q2));
    let e: Vec<f64> = (0..6).map(|i| e[i] - c1 * q1[i] - c2 * q2[i]).collect();
    let b: Vec<f64> = (0..6)
        .map(|i| a[i] * theta_u[0] + second[i] * theta_u[1] + e[i])
        .collect();
    Regressor::from_parts(
        Mat::from_fn(6, 2, |i, j| if j == 0 { a[i] } else { second[i] }),
        b,
        vec!["a".into(), "b".into()],
        row_labels(6),
    )
    .unwrap()
}

fn nonnegative_report(regressor: &Regressor) -> FitReport {
    let fit = fit::constrained(
        regressor,
        &Constraints::nonnegative(),
        &SolverSettings::default(),
    )
    .unwrap();
    let diagnostics = diagnose(regressor, &fit, 1e-10);
    FitReport::new(regressor, fit, diagnostics)
}

fn bound_warnings(report: &FitReport) -> Vec<&Warning> {
    report
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::BoundSetsCoefficients { .. }))
        .collect()
}

/// Two nearly collinear columns (r ≈ 0.99) and an unconstrained optimum with a < 0: the
/// nonnegative fit puts a on 0 and moves b. Freeing a alone is the unconstrained fit,
/// so the warning's free estimate is θ_u(a) exactly, its standard error
/// √(s² [(AᵀA)⁻¹]_aa) with the constrained fit's s² = ‖e‖²/(m − 1), and b moves by
/// |h| Δ, h = a_bᵀa_a / a_bᵀa_b the regression of column a on column b, over
/// Δ = θ_u(a) + 1.96 se.
#[test]
fn the_warning_is_the_unconstrained_fit_of_the_coefficient_at_its_bound() {
    let second = [1.0, 1.1, 0.9, 1.05, 0.95, 1.0];
    let theta_u = [-0.05, 1.25];
    let r = two_columns(second, theta_u, [0.02, -0.01, 0.015, -0.02, 0.01, -0.005]);
    let report = nonnegative_report(&r);
    assert_eq!(report.coefficients[0].value, 0.0, "{report}");
    let found = bound_warnings(&report);
    assert_eq!(found.len(), 1, "{report}");
    let Warning::BoundSetsCoefficients {
        coefficient,
        side,
        bound,
        free_estimate,
        free_std_error,
        allowed,
        moved,
    } = found[0]
    else {
        unreachable!()
    };
    assert_eq!(
        (coefficient.as_str(), *side, *bound),
        ("a", BoundSide::Lower, 0.0)
    );
    assert!(
        (free_estimate - theta_u[0]).abs() < 1e-10,
        "{free_estimate}"
    );

    // By hand: AᵀA, its inverse, the constrained fit's residual variance.
    let (saa, sab, sbb) = (
        6.0,
        second.iter().sum::<f64>(),
        second.iter().map(|v| v * v).sum::<f64>(),
    );
    let det = saa * sbb - sab * sab;
    let inverse_aa = sbb / det;
    let b_c = report.coefficients[1].value;
    let rss: f64 = (0..6).map(|i| (r.rhs()[i] - second[i] * b_c).powi(2)).sum();
    let s2 = rss / 5.0;
    assert!(
        (b_c - r.rhs().iter().zip(&second).map(|(y, x)| y * x).sum::<f64>() / sbb).abs() < 1e-12
    );
    let se = (s2 * inverse_aa).sqrt();
    assert!(
        (free_std_error / se - 1.0).abs() < 1e-9,
        "{free_std_error} vs {se}"
    );
    let span = theta_u[0] + 1.959_963_984_540_054 * se;
    let allowed = allowed.expect("the data allow a > 0");
    assert!((allowed - span).abs() < 1e-9 * span.abs().max(1.0));
    let h = sab / sbb;
    let se_b = (s2 / sbb).sqrt();
    assert_eq!(moved.len(), 1, "{moved:?}");
    let (name, shift, sigmas) = &moved[0];
    assert_eq!(name, "b");
    assert!(
        (shift / (h * span) - 1.0).abs() < 1e-9,
        "{shift} vs {}",
        h * span
    );
    assert!((sigmas / (h * span / se_b) - 1.0).abs() < 1e-9);
    // The reported b is that many of its standard errors from the unconstrained one.
    assert!(*sigmas > 3.0);
    let text = report.to_string();
    assert!(
        text.contains("a sits at its lower bound") && text.contains("b moves by"),
        "{text}"
    );
    // It does not fail --strict: a bound that is exact leaves the values right.
    assert!(!found[0].fails_strict());
}

/// Nearly orthogonal columns: a on its bound hardly moves b, and nothing is said.
#[test]
fn a_bound_that_moves_nothing_is_not_named() {
    let second = [1.0, -1.0, 1.0, -1.0, 1.2, -0.8];
    let r = two_columns(
        second,
        [-0.01, 1.0],
        [0.02, 0.01, -0.015, -0.02, 0.01, 0.005],
    );
    let report = nonnegative_report(&r);
    assert_eq!(report.coefficients[0].value, 0.0, "{report}");
    assert!(bound_warnings(&report).is_empty(), "{report}");
}

/// The data put a far below its bound (θ_u(a) = −0.5, many standard errors): the bound
/// holds a where the data do not put it, b compensates by −h·0.5, and the warning says
/// that the data contradict the bound (no "allowed" range).
#[test]
fn a_bound_the_data_contradict_is_named_with_what_it_moves() {
    let second = [1.0, 1.1, 0.9, 1.05, 0.95, 1.0];
    let theta_u = [-0.5, 1.25];
    let r = two_columns(
        second,
        theta_u,
        [0.002, -0.001, 0.0015, -0.002, 0.001, -0.0005],
    );
    let report = nonnegative_report(&r);
    let found = bound_warnings(&report);
    assert_eq!(found.len(), 1, "{report}");
    let Warning::BoundSetsCoefficients {
        free_estimate,
        allowed,
        moved,
        ..
    } = found[0]
    else {
        unreachable!()
    };
    assert_eq!(*allowed, None);
    assert!((free_estimate - theta_u[0]).abs() < 1e-10);
    let (sab, sbb) = (
        second.iter().sum::<f64>(),
        second.iter().map(|v| v * v).sum::<f64>(),
    );
    let h = sab / sbb;
    assert!((moved[0].1 / (h * 0.5) - 1.0).abs() < 1e-9, "{moved:?}");
    // The constrained b is the unconstrained one plus what it compensates.
    assert!((report.coefficients[1].value - (theta_u[1] - h * 0.5)).abs() < 1e-9);
    let text = report.to_string();
    assert!(text.contains("the data contradict the bound"), "{text}");
}

/// The physics fuzz target's records: a chain of `n` unit masses and unit springs
/// between walls, dashpots `c` on its n + 1 links, driven on DOF `dof` (0-based) at
/// ω with amplitude `a`; the exact steady state sampled 48 times per period over 4
/// periods, with noise of `noise` times each channel's amplitude (and of the force).
mod chain {
    use dampid::prelude::*;
    use faer::Mat;
    use realfft::num_complex::Complex64;

    pub const PER_PERIOD: usize = 48;
    pub const PERIODS: usize = 4;

    /// The fuzz target's generator: an LCG, normals as a centred sum of 4 uniforms.
    pub struct Noise(pub u64);

    impl Noise {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn normal(&mut self) -> f64 {
            ((0..4).map(|_| self.uniform()).sum::<f64>() - 2.0) * 3f64.sqrt()
        }
    }

    /// X of (K − ω²I + iωC) X = a e_dof, by complex Gaussian elimination.
    fn response(n: usize, c: &[f64], omega: f64, dof: usize, a: f64) -> Vec<Complex64> {
        let mut z = vec![vec![Complex64::new(0.0, 0.0); n + 1]; n];
        for i in 0..n {
            z[i][i] = Complex64::new(2.0 - omega * omega, omega * (c[i] + c[i + 1]));
            if i + 1 < n {
                z[i][i + 1] = Complex64::new(-1.0, -omega * c[i + 1]);
                z[i + 1][i] = Complex64::new(-1.0, -omega * c[i + 1]);
            }
        }
        z[dof][n] = Complex64::new(a, 0.0);
        for k in 0..n {
            let pivot = (k..n)
                .max_by(|&i, &j| z[i][k].norm().total_cmp(&z[j][k].norm()))
                .unwrap();
            z.swap(k, pivot);
            let pivot_row = z[k].clone();
            for row in z.iter_mut().skip(k + 1) {
                let f = row[k] / pivot_row[k];
                for (entry, p) in row.iter_mut().zip(&pivot_row).skip(k) {
                    *entry -= f * p;
                }
            }
        }
        let mut x = vec![Complex64::new(0.0, 0.0); n];
        for i in (0..n).rev() {
            let mut s = z[i][n];
            for j in i + 1..n {
                s -= z[i][j] * x[j];
            }
            x[i] = s / z[i][i];
        }
        x
    }

    /// One record: drive on `dof` near `mode` (1-based) at `detune` (0.7 … 1.3 of its
    /// frequency, as the fuzz target's byte / 255), amplitude `a`.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        label: &str,
        n: usize,
        c: &[f64],
        dof: usize,
        mode: usize,
        detune: f64,
        a: f64,
        noise: f64,
        rng: &mut Noise,
    ) -> Record {
        let natural = 2.0 * (mode as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin();
        let omega = natural * (0.7 + 0.6 * detune);
        let x_hat = response(n, c, omega, dof, a);
        let samples = PER_PERIOD * PERIODS + 1;
        let h = 2.0 * std::f64::consts::PI / omega / PER_PERIOD as f64;
        let level: Vec<f64> = x_hat.iter().map(|p| noise * p.norm()).collect();
        let mut x = Mat::zeros(samples, n);
        let mut v = Mat::zeros(samples, n);
        for i in 0..samples {
            let (cos, sin) = ((omega * i as f64 * h).cos(), (omega * i as f64 * h).sin());
            for j in 0..n {
                let (re, im) = (x_hat[j].re, x_hat[j].im);
                x[(i, j)] = re * cos - im * sin + level[j] * rng.normal();
                v[(i, j)] = omega * (-re * sin - im * cos) + omega * level[j] * rng.normal();
            }
        }
        let force: Vec<f64> = (0..samples)
            .map(|i| a * (omega * i as f64 * h).cos() * (1.0 + noise * rng.normal()))
            .collect();
        Record::new(RecordParts {
            label: label.into(),
            step: h,
            start_time: 0.0,
            displacements: x,
            velocities: Some(v),
            forcing: Forcing::on_dofs(Mat::from_fn(samples, 1, |i, _| force[i]), vec![dof]),
            period: 2.0 * std::f64::consts::PI / omega,
        })
        .unwrap()
    }
}

/// A fuzz case: the records of `experiments` ((force DOF 0-based, mode, detune, amplitude)
/// as the fuzz input decodes) on an `n`-DOF chain with dashpots `truth`, identified with
/// `regressor` settings and nonnegative coefficients. Returns the report and the free,
/// determined coefficients that are more than 6 standard errors and 5 % of the largest
/// dashpot off their truth (the fuzz target's "wrong").
fn fuzz_case(
    n: usize,
    truth: &[f64],
    experiments: &[(usize, usize, f64, f64)],
    noise: f64,
    seed: u64,
    regressor: RegressorSettings,
) -> (FitReport, Vec<String>) {
    let mut rng = chain::Noise(seed);
    let records: Vec<Record> = experiments
        .iter()
        .enumerate()
        .map(|(k, &(dof, mode, detune, a))| {
            chain::record(
                &format!("r{}", k + 1),
                n,
                truth,
                dof,
                mode,
                detune,
                a,
                noise,
                &mut rng,
            )
        })
        .collect();
    let model = DampingModel::new().with(Term::on_elements(
        Linear,
        Element::chain_fixed_both_ends(n),
        Coefficients::PerElement("c".into()),
    ));
    let mut settings = IdentifySettings {
        regressor,
        ..IdentifySettings::default()
    };
    settings.fit.constraints = Constraints::nonnegative();
    let report = identify(
        &ParametricRegressor::linear(&model, &records),
        &settings,
        &silent,
    )
    .unwrap()
    .report;
    let largest = truth.iter().copied().fold(0.0, f64::max);
    let off = report
        .coefficients
        .iter()
        .zip(truth)
        .filter(|(c, t)| {
            let se = c.std_error.unwrap_or(f64::INFINITY);
            !report.active_constraints.iter().any(|a| a.name == c.name)
                && c.determined
                && (c.value - *t).abs() > 0.05 * largest
                && (c.value - *t).abs() > 6.0 * se
        })
        .map(|(c, _)| c.name.clone())
        .collect();
    (report, off)
}

/// Every coefficient in `off` is named by a `BoundSetsCoefficients` warning of `report`,
/// whose coefficient is at its bound; returns those warnings.
fn named<'a>(report: &'a FitReport, off: &[String]) -> Vec<&'a Warning> {
    assert!(!off.is_empty(), "the case no longer reproduces:\n{report}");
    let found = bound_warnings(report);
    for name in off {
        assert!(
            found.iter().any(|w| matches!(w,
                Warning::BoundSetsCoefficients { moved, .. }
                    if moved.iter().any(|(m, _, _)| m == name))),
            "{name} is off its truth but not named:\n{report}"
        );
    }
    for w in &found {
        let Warning::BoundSetsCoefficients { coefficient, .. } = w else {
            unreachable!()
        };
        assert!(
            report
                .active_constraints
                .iter()
                .any(|a| &a.name == coefficient)
        );
    }
    found
}

/// The fuzz input's byte for detune as a share of 0.7 … 1.3.
fn detune(byte: f64) -> f64 {
    byte / 255.0
}

/// The fuzz input's byte for a force amplitude.
fn amplitude(byte: f64) -> f64 {
    0.25 + byte / 64.0
}

/// The fuzz finding 13f68…: a 3-DOF chain, dashpots (1, 1, 1, 2)/64; five records driven
/// on DOF 2 near mode 2 (its node) and two on DOF 1 near mode 1, 10⁻⁴ noise, the default
/// pipeline, nonnegative. Noise puts c[0-1] on 0, and c[2-3] comes out 22 of its standard
/// errors from the truth, "determined", with the χ² check passing. The report must say
/// that the bound sets it, and the truth of c[0-1] lies within what the data allow.
#[test]
fn a_coefficient_that_noise_puts_on_its_bound_is_said_to_set_the_others() {
    let truth = [1.0 / 64.0, 1.0 / 64.0, 1.0 / 64.0, 2.0 / 64.0];
    let experiments = [
        (1, 2, detune(253.0), amplitude(253.0)),
        (1, 2, detune(253.0), amplitude(253.0)),
        (1, 2, detune(253.0), amplitude(253.0)),
        (1, 2, detune(253.0), amplitude(253.0)),
        (1, 2, detune(253.0), amplitude(101.0)),
        (0, 1, detune(254.0), amplitude(106.0)),
        (0, 1, detune(255.0), amplitude(101.0)),
    ];
    let regressor = RegressorSettings {
        windows: Windows::Cycles(WindowSpec::cycles(1)),
        ..RegressorSettings::default()
    };
    let (report, off) = fuzz_case(3, &truth, &experiments, 1e-4, 0, regressor);
    for w in named(&report, &off) {
        let Warning::BoundSetsCoefficients {
            coefficient,
            allowed,
            ..
        } = w
        else {
            unreachable!()
        };
        let t = truth[report
            .coefficients
            .iter()
            .position(|c| &c.name == coefficient)
            .unwrap()];
        let allowed = allowed.expect("the data allow values above the bound");
        assert!(
            t <= allowed,
            "{coefficient}: truth {t}, allowed up to {allowed}"
        );
    }
}

/// The fuzz finding 18351…: a 2-DOF chain, dashpots (6, 16, 16)/64, six records driven
/// on DOF 2 near mode 2, 10⁻³ noise, measured velocities with ordinary least squares
/// (no noise treatment: the noise of v biases the damping columns upwards), nonnegative.
/// The data put c[0-1] far below 0; held there, c[1-2] = 0.064 for 0.25 with a 0.26 %
/// standard error, and no warning. The report must say that the data contradict the
/// bound and name what it moves.
#[test]
fn a_bound_that_the_data_contradict_is_said_to_move_the_others() {
    let truth = [6.0 / 64.0, 16.0 / 64.0, 16.0 / 64.0];
    let experiments = [
        (1, 2, detune(0.0), amplitude(255.0)),
        (1, 2, detune(255.0), amplitude(255.0)),
        (1, 2, detune(255.0), amplitude(255.0)),
        (1, 2, detune(255.0), amplitude(255.0)),
        (1, 2, detune(255.0), amplitude(46.0)),
        (1, 2, detune(0.0), amplitude(255.0)),
    ];
    let regressor = RegressorSettings {
        windows: Windows::Cycles(WindowSpec::cycles(1)),
        quadrature: Quadrature::Trapezoid,
        velocity: VelocitySource::Measured,
        noise: NoiseTreatment::Ignore,
        ..RegressorSettings::default()
    };
    let (report, off) = fuzz_case(
        2,
        &truth,
        &experiments,
        1e-3,
        18446463148488706559,
        regressor,
    );
    let found = named(&report, &off);
    assert!(
        found
            .iter()
            .any(|w| matches!(w, Warning::BoundSetsCoefficients { allowed: None, .. })),
        "{report}"
    );
    assert!(report.to_string().contains("the data contradict the bound"));
}
