//! History terms (src/terms/history/): forces with memory identified on simulated
//! single-DOF oscillators,
//!
//! ```text
//!   m ẍ + c ẋ + k x + F_h = F₀ cos ωt,
//! ```
//!
//! F_h a Bouc–Wen element, a four-parameter Iwan joint or a Dahl element, harmonically
//! forced at several levels and two frequencies. The records come from this file's own
//! integrator (classical RK4 in time on a step 4–10 times finer than the records',
//! the hysteretic state carried in time: ż for Bouc–Wen and Dahl, and for the Iwan
//! joint its own equal-mass discretisation of Segalman's density with 400 sliders),
//! never from the identification's state update (rate-independent steps in x along the
//! recorded samples, a geometric 120-slider discretisation).

use std::f64::consts::PI;
use std::sync::OnceLock;

use dampid::prelude::*;
use dampid::regressor::NoiseTreatment;
use dampid::report::FitReport;
use dampid::terms::history::{BoucWen, Dahl, Iwan};
use dampid::varpro::{NonlinearParameter, ParametricModel, VarProSettings};

/// `law` identified on `records` by the one `identify`, its outer loop under `varpro`.
fn identify_varpro(
    law: &ParametricModel,
    records: &[Record],
    settings: &IdentifySettings,
    varpro: &VarProSettings,
) -> dampid::Result<FitReport> {
    let settings = IdentifySettings {
        estimation: *varpro,
        ..settings.clone()
    };
    identify(
        &ParametricRegressor::new(law.clone(), records),
        &settings,
        &silent,
    )
    .map(|i| i.report)
}
use faer::Mat;

const MASS: f64 = 1.0;
/// Samples per forcing period in the records.
const SAMPLES: usize = 200;
/// Whole periods recorded after the transient.
const RECORDED: usize = 6;

/// The hysteretic force of the simulated oscillator: its state, advanced in time.
trait Simulated {
    /// State length.
    fn state_len(&self) -> usize;
    /// The force at displacement x in `state`.
    fn force(&self, state: &[f64], x: f64) -> f64;
    /// d(state)/dt at (x, v) (for the ODE kinds).
    fn rate(&self, state: &[f64], x: f64, v: f64, out: &mut [f64]);
    /// Commits the state after a step to displacement x (for the slider kinds, which
    /// have no rate: their state is the clipping of the sliders, done once per step).
    fn commit(&self, _state: &mut [f64], _x: f64) {}
    /// The virgin state at x (zero for the ODE kinds).
    fn start(&self, _state: &mut [f64], _x: f64) {}
    /// The force at x if the sliders moved to x from `state` (slider kinds).
    fn trial_force(&self, state: &[f64], x: f64) -> f64 {
        self.force(state, x)
    }
}

/// ż = v − β|v||z|^{n−1}z − γ v|z|ⁿ, F = α z.
struct SimBoucWen {
    alpha: f64,
    beta: f64,
    gamma: f64,
    n: f64,
}

impl Simulated for SimBoucWen {
    fn state_len(&self) -> usize {
        1
    }
    fn force(&self, state: &[f64], _x: f64) -> f64 {
        self.alpha * state[0]
    }
    fn rate(&self, state: &[f64], _x: f64, v: f64, out: &mut [f64]) {
        let z = state[0];
        out[0] = v
            - self.beta * v.abs() * z.abs().powf(self.n - 1.0) * z
            - self.gamma * v * z.abs().powf(self.n);
    }
}

/// dF/dt = σ v (1 − (F/F_c) sgn v), F_c = the Coulomb level, σ = F_c/x_c.
struct SimDahl {
    f_c: f64,
    x_c: f64,
}

impl Simulated for SimDahl {
    fn state_len(&self) -> usize {
        1
    }
    fn force(&self, state: &[f64], _x: f64) -> f64 {
        state[0]
    }
    fn rate(&self, state: &[f64], _x: f64, v: f64, out: &mut [f64]) {
        let sigma = self.f_c / self.x_c;
        out[0] = sigma * v * (1.0 - state[0] / self.f_c * v.signum());
    }
}

/// Segalman's density R φ^χ on [0, φ_max] + S δ(φ − φ_max), as 400 sliders of equal
/// mass (the k-th at the centroid of the k-th equal-mass slice of t^{χ+1}), plus S.
struct SimIwan {
    strengths: Vec<f64>,
    masses: Vec<f64>,
}

impl SimIwan {
    fn new(k_t: f64, phi_max: f64, chi: f64, beta: f64) -> Self {
        const SLIDERS: usize = 400;
        let continuous = k_t / (1.0 + beta);
        let (c1, c2) = (chi + 1.0, chi + 2.0);
        let mut strengths = Vec::new();
        let mut masses = Vec::new();
        for k in 0..SLIDERS {
            // slice [a, b] of t = φ/φ_max with equal t^{χ+1} increments
            let a = (k as f64 / SLIDERS as f64).powf(1.0 / c1);
            let b = ((k + 1) as f64 / SLIDERS as f64).powf(1.0 / c1);
            let mass = b.powf(c1) - a.powf(c1);
            let moment = c1 / c2 * (b.powf(c2) - a.powf(c2));
            strengths.push(phi_max * moment / mass);
            masses.push(continuous * mass);
        }
        strengths.push(phi_max);
        masses.push(k_t * beta / (1.0 + beta));
        SimIwan { strengths, masses }
    }
}

impl Simulated for SimIwan {
    fn state_len(&self) -> usize {
        self.strengths.len()
    }
    fn force(&self, state: &[f64], x: f64) -> f64 {
        state
            .iter()
            .zip(&self.masses)
            .map(|(p, m)| m * (x - p))
            .sum()
    }
    fn rate(&self, _state: &[f64], _x: f64, _v: f64, out: &mut [f64]) {
        out.fill(0.0);
    }
    fn start(&self, state: &mut [f64], x: f64) {
        state.fill(x);
    }
    fn commit(&self, state: &mut [f64], x: f64) {
        for (p, phi) in state.iter_mut().zip(&self.strengths) {
            *p = p.clamp(x - phi, x + phi);
        }
    }
    fn trial_force(&self, state: &[f64], x: f64) -> f64 {
        state
            .iter()
            .zip(&self.masses)
            .zip(&self.strengths)
            .map(|((p, m), phi)| m * (x - p.clamp(x - phi, x + phi)))
            .sum()
    }
}

/// The oscillator's linear part and drive.
#[derive(Clone, Copy)]
struct Drive {
    stiffness: f64,
    viscous: f64,
    force: f64,
    omega: f64,
}

/// RK4 on (x, v, state) with `fine` sub-steps per record sample; `transient` periods
/// discarded, `RECORDED` periods kept (SAMPLES per period). The record's force is the
/// drive times `force_scale` (the invariance test's scaled force).
fn simulate(
    element: &dyn Simulated,
    drive: Drive,
    transient: usize,
    fine: usize,
    label: &str,
) -> (Vec<f64>, Vec<f64>, Vec<f64>, f64) {
    let period = 2.0 * PI / drive.omega;
    let h = period / SAMPLES as f64 / fine as f64;
    let n = element.state_len();
    // start on the linear steady state of the spring alone
    let k_dyn = drive.stiffness - MASS * drive.omega * drive.omega;
    let amplitude = drive.force / k_dyn;
    let (mut x, mut v) = (amplitude, 0.0);
    let mut state = vec![0.0; n];
    element.start(&mut state, x);
    let accel = |t: f64, x: f64, v: f64, state: &[f64]| {
        (drive.force * (drive.omega * t).cos()
            - drive.viscous * v
            - drive.stiffness * x
            - element.trial_force(state, x))
            / MASS
    };
    let (mut xs, mut vs, mut fs) = (Vec::new(), Vec::new(), Vec::new());
    let total = (transient + RECORDED) * SAMPLES * fine;
    let keep_from = transient * SAMPLES * fine;
    let mut t = 0.0;
    let mut k1s = vec![0.0; n];
    let mut k2s = vec![0.0; n];
    let mut k3s = vec![0.0; n];
    let mut k4s = vec![0.0; n];
    let mut tmp = vec![0.0; n];
    for step in 0..total {
        if step >= keep_from && (step - keep_from).is_multiple_of(fine) {
            xs.push(x);
            vs.push(v);
            fs.push(drive.force * (drive.omega * t).cos());
        }
        let a1 = accel(t, x, v, &state);
        element.rate(&state, x, v, &mut k1s);
        let (x2, v2) = (x + 0.5 * h * v, v + 0.5 * h * a1);
        tmp.iter_mut()
            .zip(state.iter().zip(&k1s))
            .for_each(|(o, (s, k))| *o = s + 0.5 * h * k);
        let a2 = accel(t + 0.5 * h, x2, v2, &tmp);
        element.rate(&tmp, x2, v2, &mut k2s);
        let (x3, v3) = (x + 0.5 * h * v2, v + 0.5 * h * a2);
        tmp.iter_mut()
            .zip(state.iter().zip(&k2s))
            .for_each(|(o, (s, k))| *o = s + 0.5 * h * k);
        let a3 = accel(t + 0.5 * h, x3, v3, &tmp);
        element.rate(&tmp, x3, v3, &mut k3s);
        let (x4, v4) = (x + h * v3, v + h * a3);
        tmp.iter_mut()
            .zip(state.iter().zip(&k3s))
            .for_each(|(o, (s, k))| *o = s + h * k);
        let a4 = accel(t + h, x4, v4, &tmp);
        element.rate(&tmp, x4, v4, &mut k4s);
        x += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        for (j, s) in state.iter_mut().enumerate() {
            *s += h / 6.0 * (k1s[j] + 2.0 * k2s[j] + 2.0 * k3s[j] + k4s[j]);
        }
        element.commit(&mut state, x);
        t += h;
    }
    assert!(x.is_finite(), "{label}: simulation diverged");
    (xs, vs, fs, period)
}

/// A record of the simulated oscillator, the force multiplied by `force_scale`.
fn record(
    element: &dyn Simulated,
    drive: Drive,
    transient: usize,
    fine: usize,
    force_scale: f64,
) -> Record {
    let label = format!("F={:.3},w={:.2}", drive.force, drive.omega);
    let (xs, vs, fs, period) = simulate(element, drive, transient, fine, &label);
    let m = xs.len();
    Record::new(RecordParts {
        label,
        step: period / SAMPLES as f64,
        start_time: 0.0,
        displacements: Mat::from_fn(m, 1, |i, _| xs[i]),
        velocities: Some(Mat::from_fn(m, 1, |i, _| vs[i])),
        forcing: Forcing::on_dofs(Mat::from_fn(m, 1, |i, _| force_scale * fs[i]), vec![0]),
        period,
    })
    .unwrap()
}

/// Plain rows (measured velocities, no noise model), one equation per period.
fn settings() -> IdentifySettings {
    let mut settings = IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(1).into();
    settings.regressor.velocity = VelocitySource::Measured;
    settings.regressor.noise = NoiseTreatment::Ignore;
    settings
}

fn relative(found: f64, truth: f64) -> f64 {
    (found - truth).abs() / truth.abs()
}

fn ground() -> Vec<Element> {
    vec![Element::to_ground(0)]
}

fn viscous() -> Term {
    Term::viscous("c", Mat::identity(1, 1))
}

// ---------------------------------------------------------------- Bouc–Wen

const BW_K: f64 = 4.0 * PI * PI;
const BW_C: f64 = 0.2;
const BW_ALPHA: f64 = 8.0;
const BW_BETA: f64 = 60.0;
const BW_GAMMA: f64 = 20.0;
const BW_N: f64 = 1.5;

fn bouc_wen_records(force_scale: f64) -> Vec<Record> {
    let element = SimBoucWen {
        alpha: BW_ALPHA,
        beta: BW_BETA,
        gamma: BW_GAMMA,
        n: BW_N,
    };
    let wn = ((BW_K + BW_ALPHA) / MASS).sqrt();
    let mut records = Vec::new();
    for ratio in [0.7, 1.4] {
        let omega = ratio * wn;
        let k_dyn = (BW_K - MASS * omega * omega).abs();
        for x in [0.005, 0.015, 0.03, 0.06, 0.12] {
            let drive = Drive {
                stiffness: BW_K,
                viscous: BW_C,
                force: k_dyn * x,
                omega,
            };
            records.push(record(&element, drive, 80, 10, force_scale));
        }
    }
    records
}

fn bouc_wen_clean() -> &'static [Record] {
    static RECORDS: OnceLock<Vec<Record>> = OnceLock::new();
    RECORDS.get_or_init(|| bouc_wen_records(1.0))
}

fn bouc_wen_model(beta: f64, gamma: f64, n: f64) -> dampid::Result<DampingModel> {
    Ok(DampingModel::new().with(viscous()).with(Term::history(
        BoucWen::new(beta, gamma, n)?,
        ground(),
        Coefficients::Shared("alpha".into()),
    )))
}

#[test]
fn bouc_wen_with_known_shape_gives_its_coefficients() {
    let report = identify(
        &ParametricRegressor::linear(
            &bouc_wen_model(BW_BETA, BW_GAMMA, BW_N).unwrap(),
            bouc_wen_clean(),
        ),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    let c = report.coefficient("c").unwrap();
    let alpha = report.coefficient("alpha").unwrap();
    assert!(relative(c, BW_C) < 0.01, "c = {c}");
    assert!(relative(alpha, BW_ALPHA) < 0.01, "alpha = {alpha}");
}

#[test]
fn bouc_wen_every_parameter_within_5_percent() {
    let parametric = ParametricModel::new(
        vec![
            NonlinearParameter::new("beta", 30.0, 5.0, 200.0),
            NonlinearParameter::new("gamma", 5.0, 0.0, 100.0),
            NonlinearParameter::new("n", 1.2, 1.0, 3.0),
        ],
        |eta| bouc_wen_model(eta[0], eta[1], eta[2]),
    )
    .unwrap();
    let varpro = VarProSettings {
        profile: false,
        ..VarProSettings::default()
    };
    let report = identify_varpro(&parametric, bouc_wen_clean(), &settings(), &varpro).unwrap();
    assert!(report.is_estimate(), "{report}");
    let found = [
        ("c", report.coefficient("c").unwrap(), BW_C),
        ("alpha", report.coefficient("alpha").unwrap(), BW_ALPHA),
        ("beta", report.parameter("beta").unwrap(), BW_BETA),
        ("gamma", report.parameter("gamma").unwrap(), BW_GAMMA),
        ("n", report.parameter("n").unwrap(), BW_N),
    ];
    for (name, value, truth) in found {
        eprintln!(
            "{name} = {value:.6e} (truth {truth}, {:+.3} %)",
            100.0 * (value - truth) / truth
        );
    }
    eprintln!(
        "{} iterations, {} trials",
        report.estimation.as_ref().unwrap().status.iterations,
        report.estimation.as_ref().unwrap().status.evaluations
    );
    for (name, value, truth) in found {
        assert!(
            relative(value, truth) < 0.05,
            "{name} = {value}, truth {truth}\n{report}"
        );
    }
}

// ---------------------------------------------------------------- Iwan

const IW_K: f64 = 30.0;
const IW_C: f64 = 0.3;
const IW_KT: f64 = 10.0;
const IW_PHI_MAX: f64 = 0.05;
const IW_CHI: f64 = -0.5;
const IW_BETA: f64 = 0.5;

fn iwan_clean() -> &'static [Record] {
    static RECORDS: OnceLock<Vec<Record>> = OnceLock::new();
    RECORDS.get_or_init(|| {
        let element = SimIwan::new(IW_KT, IW_PHI_MAX, IW_CHI, IW_BETA);
        let wn = ((IW_K + IW_KT) / MASS).sqrt();
        let mut records = Vec::new();
        for ratio in [0.7, 1.4] {
            let omega = ratio * wn;
            let k_dyn = (IW_K + IW_KT - MASS * omega * omega).abs();
            for x in [0.01, 0.02, 0.035, 0.06, 0.1] {
                let drive = Drive {
                    stiffness: IW_K,
                    viscous: IW_C,
                    force: k_dyn * x,
                    omega,
                };
                records.push(record(&element, drive, 150, 3, 1.0));
            }
        }
        records
    })
}

fn iwan_model(phi_max: f64, chi: f64, beta: f64) -> dampid::Result<DampingModel> {
    Ok(DampingModel::new().with(viscous()).with(Term::history(
        Iwan::new(phi_max, chi, beta)?,
        ground(),
        Coefficients::Shared("k_t".into()),
    )))
}

/// The discrete joint's loop area under a symmetric sine of amplitude A (on its
/// periodic orbit, the loop integral ∮ s dx by the trapezoid rule on 8000 samples)
/// against Segalman's closed form D(A) (module doc of terms/history/iwan.rs), in
/// microslip and beyond macroslip.
#[test]
fn iwan_discretisation_dissipates_as_the_closed_form() {
    let joint = Iwan::new(IW_PHI_MAX, IW_CHI, IW_BETA).unwrap();
    for fraction in [0.02, 0.1, 0.5, 0.9, 1.0, 2.0, 5.0] {
        let amplitude = fraction * IW_PHI_MAX;
        let samples = 8000;
        let path: Vec<f64> = (0..samples)
            .map(|i| amplitude * (2.0 * PI * i as f64 / samples as f64).sin())
            .collect();
        let s = dampid::terms::history::orbit::periodic_force(&joint, &path).unwrap();
        let area: f64 = (0..samples)
            .map(|i| {
                let j = (i + 1) % samples;
                0.5 * (s[i] + s[j]) * (path[j] - path[i])
            })
            .sum();
        let exact = joint.dissipation(1.0, amplitude);
        assert!(
            relative(area, exact) < 0.01,
            "A = {fraction} φ_max: loop {area:e}, closed form {exact:e}"
        );
    }
}

#[test]
fn iwan_every_parameter_within_5_percent() {
    let parametric = ParametricModel::new(
        vec![
            NonlinearParameter::new("phi_max", 0.03, 0.01, 0.2),
            NonlinearParameter::new("chi", -0.2, -0.9, 0.5),
            NonlinearParameter::new("beta", 1.0, 0.0, 3.0),
        ],
        |eta| iwan_model(eta[0], eta[1], eta[2]),
    )
    .unwrap();
    let varpro = VarProSettings {
        profile: false,
        ..VarProSettings::default()
    };
    let report = identify_varpro(&parametric, iwan_clean(), &settings(), &varpro).unwrap();
    assert!(report.is_estimate(), "{report}");
    let k_t = report.coefficient("k_t").unwrap();
    let (phi_max, chi, beta) = (
        report.parameter("phi_max").unwrap(),
        report.parameter("chi").unwrap(),
        report.parameter("beta").unwrap(),
    );
    let f_s = Iwan::new(phi_max, chi, beta).unwrap().slip_force(k_t);
    let f_s_truth = Iwan::new(IW_PHI_MAX, IW_CHI, IW_BETA)
        .unwrap()
        .slip_force(IW_KT);
    let found = [
        ("c", report.coefficient("c").unwrap(), IW_C),
        ("K_T", k_t, IW_KT),
        ("F_S", f_s, f_s_truth),
        ("chi", chi, IW_CHI),
        ("beta", beta, IW_BETA),
        ("phi_max", phi_max, IW_PHI_MAX),
    ];
    for (name, value, truth) in found {
        eprintln!(
            "{name} = {value:.6e} (truth {truth}, {:+.3} %)",
            100.0 * (value - truth) / truth
        );
    }
    eprintln!(
        "{} iterations, {} trials",
        report.estimation.as_ref().unwrap().status.iterations,
        report.estimation.as_ref().unwrap().status.evaluations
    );
    for (name, value, truth) in found {
        assert!(
            relative(value, truth) < 0.05,
            "{name} = {value}, truth {truth}\n{report}"
        );
    }
}

// ---------------------------------------------------------------- Dahl

const DA_K: f64 = 4.0 * PI * PI;
const DA_C: f64 = 0.2;
const DA_FC: f64 = 0.5;
const DA_XC: f64 = 0.01;

fn dahl_records(force_scale: f64) -> Vec<Record> {
    let element = SimDahl {
        f_c: DA_FC,
        x_c: DA_XC,
    };
    let wn = (DA_K / MASS).sqrt();
    let mut records = Vec::new();
    for ratio in [0.7, 1.4] {
        let omega = ratio * wn;
        let k_dyn = (DA_K - MASS * omega * omega).abs();
        for x in [0.005, 0.01, 0.02, 0.05, 0.1] {
            let drive = Drive {
                stiffness: DA_K,
                viscous: DA_C,
                force: k_dyn * x,
                omega,
            };
            records.push(record(&element, drive, 80, 10, force_scale));
        }
    }
    records
}

fn dahl_parametric() -> ParametricModel {
    ParametricModel::new(
        vec![NonlinearParameter::new("x_c", 0.02, 0.001, 0.1)],
        |eta| {
            Ok(DampingModel::new().with(viscous()).with(Term::history(
                Dahl::new(eta[0], 1.0)?,
                ground(),
                Coefficients::Shared("f_c".into()),
            )))
        },
    )
    .unwrap()
}

/// F_c and x_c within 5 %, and the invariant: the force × 3 gives F_c and c × 3 and
/// the same x_c.
#[test]
fn dahl_coefficient_and_shape_and_force_scaling() {
    let varpro = VarProSettings {
        profile: false,
        ..VarProSettings::default()
    };
    let base =
        identify_varpro(&dahl_parametric(), &dahl_records(1.0), &settings(), &varpro).unwrap();
    assert!(base.is_estimate(), "{base}");
    let found = [
        ("c", base.coefficient("c").unwrap(), DA_C),
        ("f_c", base.coefficient("f_c").unwrap(), DA_FC),
        ("x_c", base.parameter("x_c").unwrap(), DA_XC),
    ];
    for (name, value, truth) in found {
        assert!(
            relative(value, truth) < 0.05,
            "{name} = {value}, truth {truth}\n{base}"
        );
    }
    let scaled =
        identify_varpro(&dahl_parametric(), &dahl_records(3.0), &settings(), &varpro).unwrap();
    for name in ["c", "f_c"] {
        let (a, b) = (
            base.coefficient(name).unwrap(),
            scaled.coefficient(name).unwrap(),
        );
        assert!(relative(b, 3.0 * a) < 1e-6, "{name}: {b} vs 3 × {a}");
    }
    let (a, b) = (
        base.parameter("x_c").unwrap(),
        scaled.parameter("x_c").unwrap(),
    );
    assert!(relative(b, a) < 1e-6, "x_c: {b} vs {a}");
}

/// Force × 3 on the Bouc–Wen records with the shape known: α and c × 3 exactly (the
/// regressor is the same, b × 3).
#[test]
fn bouc_wen_force_scaling_scales_the_linear_coefficients() {
    let model = bouc_wen_model(BW_BETA, BW_GAMMA, BW_N).unwrap();
    let base = identify(
        &ParametricRegressor::linear(&model, bouc_wen_clean()),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    let scaled = identify(
        &ParametricRegressor::linear(&model, &bouc_wen_records(3.0)),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    for name in ["c", "alpha"] {
        let (a, b) = (
            base.coefficient(name).unwrap(),
            scaled.coefficient(name).unwrap(),
        );
        assert!(relative(b, 3.0 * a) < 1e-9, "{name}: {b} vs 3 × {a}");
    }
}

/// README.md's table of forces with memory has one row per built-in history kind, with
/// its parameters in order.
#[test]
fn readme_lists_every_history_kind() {
    let readme = std::fs::read_to_string("README.md").unwrap();
    for kind in dampid::terms::history::KINDS {
        let row = readme
            .lines()
            .find(|l| l.starts_with(&format!("| `{}` |", kind.name)))
            .unwrap_or_else(|| panic!("no README row for {}", kind.name));
        for (parameter, _) in kind.parameters {
            assert!(row.contains(&format!("`{parameter}`")), "{row}");
        }
    }
}

/// A model file's `kind = "bouc_wen"` term: the fixed shape parameters and the default
/// n build the element, an estimated one becomes a variable-projection parameter named
/// `<coefficient>.<parameter>`, and the model at its initial value identifies the SDOF
/// records as the program-built model does.
#[test]
fn model_file_bouc_wen_term_builds_the_same_model() {
    let text = format!(
        "dofs = 1\n\n[[terms]]\nkind = \"viscous\"\ncoefficient = \"c\"\nmatrix = \"identity\"\n\n[[terms]]\nkind = \"bouc_wen\"\nelements = [[1, 0]]\ncoefficient = \"alpha\"\nparameters = {{ beta = {{ estimate = true, initial = {BW_BETA}, lower = 5, upper = 200 }}, gamma = {BW_GAMMA}, n = {BW_N} }}\n\n[data]\nrecords = []\n"
    );
    let job = dampid::model_file::parse(
        &text,
        "bw.toml",
        std::path::Path::new("."),
        Default::default(),
    )
    .unwrap();
    let parametric = &job.law;
    let names: Vec<&str> = parametric
        .parameters()
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(names, ["alpha.beta"]);
    let from_file = identify(
        &ParametricRegressor::linear(&job.model, bouc_wen_clean()),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    let built = identify(
        &ParametricRegressor::linear(
            &bouc_wen_model(BW_BETA, BW_GAMMA, BW_N).unwrap(),
            bouc_wen_clean(),
        ),
        &settings(),
        &silent,
    )
    .unwrap()
    .report;
    for name in ["c", "alpha"] {
        assert_eq!(
            from_file.coefficient(name),
            built.coefficient(name),
            "{name}"
        );
    }
}

/// The shipped model file `models/iwan_joint.toml` (records simulated by
/// models/data/iwan_joint/generate.py, an integrator independent of this file's and of
/// dampid's, truth as in [`iwan_clean`]): its job estimates φ_max, χ, β with c and K_T,
/// every one within 1 % (found within 0.26 %).
#[test]
fn the_iwan_model_file_identifies_its_joint() {
    let job = dampid::model_file::load(
        std::path::Path::new("models/iwan_joint.toml"),
        Default::default(),
    )
    .unwrap();
    let parametric = &job.law;
    let varpro = VarProSettings {
        profile: false,
        ..VarProSettings::default()
    };
    let report = identify_varpro(parametric, &job.records, &job.settings, &varpro).unwrap();
    assert!(report.is_estimate(), "{report}");
    let found = [
        ("c", report.coefficient("c").unwrap(), IW_C),
        ("K_T", report.coefficient("k_t").unwrap(), IW_KT),
        (
            "phi_max",
            report.parameter("k_t.phi_max").unwrap(),
            IW_PHI_MAX,
        ),
        ("chi", report.parameter("k_t.chi").unwrap(), IW_CHI),
        ("beta", report.parameter("k_t.beta").unwrap(), IW_BETA),
    ];
    for (name, value, truth) in found {
        assert!(
            relative(value, truth) < 0.01,
            "{name} = {value}, truth {truth}\n{report}"
        );
    }
}
