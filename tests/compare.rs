//! Nested-model comparison: AIC, BIC and the F-test on the change in residual, by hand
//! and on simulated data with and without Coulomb friction.

use dampid::analysis::compare::{CompareSettings, Verdict, Which, compare_regressors};
use dampid::prelude::*;
use dampid::simulate::{HarmonicForce, SimSettings, System, simulate};
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

mod support;
use support::cli::dampid_json;
use support::regressors::row_labels;

fn regressor(columns: &[(&str, &[f64])], b: &[f64]) -> Regressor {
    let m = b.len();
    let a = Mat::from_fn(m, columns.len(), |i, j| columns[j].1[i]);
    let names = columns.iter().map(|(n, _)| n.to_string()).collect();
    Regressor::from_parts(a, b.to_vec(), names, row_labels(m)).unwrap()
}

const X: [f64; 4] = [1.0, 1.0, 1.0, 1.0];
const Y: [f64; 4] = [1.0, -1.0, 1.0, -1.0];
const B: [f64; 4] = [1.0, 2.0, 3.0, 4.0];

/// b = (1, 2, 3, 4) on x = 1: mean 2.5, RSS_S = 1.5² + 0.5² + 0.5² + 1.5² = 5. Adding
/// y = (1, −1, 1, −1) (orthogonal to x, yᵀb = −2, ‖y‖² = 4) lowers it by 4/4: RSS_L = 4.
/// F = (1/1)/(4/2) = 0.5 with (1, 2) degrees of freedom; F(1, 2) is t₂², and
/// P(|t₂| > t) = 1 − t/√(t² + 2), so p = 1 − √0.5/√2.5 = 1 − √0.2.
/// AIC = 4 ln(RSS/4) + 2k: 4 ln 1.25 + 2 and 4; BIC = 4 ln(RSS/4) + k ln 4.
#[test]
fn f_test_aic_and_bic_by_hand() {
    let small = regressor(&[("x", &X)], &B);
    let large = regressor(&[("x", &X), ("y", &Y)], &B);
    let c = compare_regressors(
        ("small", &small),
        ("large", &large),
        &CompareSettings::default(),
    )
    .unwrap();
    assert_eq!(c.nested_in, Some(Which::First));
    assert!((c.first.residual_sum_of_squares - 5.0).abs() < 1e-12);
    assert!((c.second.residual_sum_of_squares - 4.0).abs() < 1e-12);
    let t = c.f_test.unwrap();
    assert_eq!((t.numerator_degrees, t.denominator_degrees), (1, 2));
    assert!((t.statistic - 0.5).abs() < 1e-12);
    assert!(
        (t.p_value - (1.0 - 0.2f64.sqrt())).abs() < 1e-12,
        "{}",
        t.p_value
    );
    assert!((c.first.aic - (4.0 * 1.25f64.ln() + 2.0)).abs() < 1e-12);
    assert!((c.second.aic - 4.0).abs() < 1e-12);
    assert!((c.first.bic - (4.0 * 1.25f64.ln() + 4f64.ln())).abs() < 1e-12);
    assert!((c.second.bic - 2.0 * 4f64.ln()).abs() < 1e-12);
    assert_eq!(c.verdict, Verdict::SmallerSuffices);
    assert_eq!((c.aic_prefers, c.bic_prefers), (Which::First, Which::First));
    assert!(c.text.starts_with("small suffices"), "{}", c.text);

    // The order of the arguments does not matter.
    let swapped = compare_regressors(
        ("large", &large),
        ("small", &small),
        &CompareSettings::default(),
    )
    .unwrap();
    assert_eq!(swapped.nested_in, Some(Which::Second));
    assert_eq!(swapped.verdict, Verdict::SmallerSuffices);
}

/// One shared coefficient is nested in one per element: its column is their sum.
/// x and y alone are not nested in each other.
#[test]
fn shared_coefficient_is_nested_in_per_element_ones() {
    let sum: Vec<f64> = X.iter().zip(&Y).map(|(x, y)| x + y).collect();
    let shared = regressor(&[("d", &sum)], &B);
    let per = regressor(&[("d[1]", &X), ("d[2]", &Y)], &B);
    let c = compare_regressors(
        ("shared", &shared),
        ("per element", &per),
        &CompareSettings::default(),
    )
    .unwrap();
    assert_eq!(c.nested_in, Some(Which::First));
    assert!(c.f_test.is_some());

    let x = regressor(&[("x", &X)], &B);
    let y = regressor(&[("y", &Y)], &B);
    let c = compare_regressors(("x", &x), ("y", &y), &CompareSettings::default()).unwrap();
    assert_eq!(c.verdict, Verdict::NotNested);
    assert!(c.f_test.is_none());
    assert!(c.text.contains("not nested"));
}

#[test]
fn regressors_of_different_equations_are_rejected() {
    let a = regressor(&[("x", &X)], &B);
    let b = regressor(&[("x", &X[..3])], &B[..3]);
    assert!(matches!(
        compare_regressors(("a", &a), ("b", &b), &CompareSettings::default()),
        Err(Error::DimensionMismatch {
            expected: 4,
            found: 3,
            ..
        })
    ));
    let c = regressor(&[("x", &X)], &[1.0, 2.0, 3.0, 5.0]);
    assert!(matches!(
        compare_regressors(("a", &a), ("c", &c), &CompareSettings::default()),
        Err(Error::InvalidParameter { .. })
    ));
}

fn chain2() -> Mat<f64> {
    Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 })
}

fn viscous() -> DampingModel {
    DampingModel::new().with(Term::stiffness_proportional("c", chain2()))
}

fn with_friction() -> DampingModel {
    viscous().with(Term::on_elements(
        Coulomb,
        vec![Element::to_ground(0)],
        Coefficients::Shared("friction".into()),
    ))
}

/// A 2-DOF chain with C = cK (c = 0.05) and, when `friction` > 0, Coulomb friction on
/// mass 1; driven on mass 1 at both resonances (ω = 1, √3) and amplitudes 0.5 and 1;
/// 1% white noise on every displacement channel (seeded).
fn noisy_records(friction: f64, seed: u64) -> Vec<Record> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut records = Vec::new();
    for omega in [1.0f64, 3f64.sqrt()] {
        for amplitude in [0.5, 1.0] {
            let system = System {
                mass: Mat::identity(2, 2),
                stiffness: chain2(),
                damping: with_friction(),
                damping_coefficients: vec![0.05, friction],
                conservative: Vec::new(),
                forcing: vec![HarmonicForce {
                    dof: 0,
                    amplitude,
                    frequency: omega,
                    phase: 0.0,
                }],
            };
            let period = 2.0 * std::f64::consts::PI / omega;
            let settings = SimSettings {
                step: 0.1,
                substeps: 4,
                transient_steps: 8000,
                recorded_steps: (8.0 * period / 0.1).ceil() as usize + 3,
            };
            let mut parts = simulate(&system, &settings, &dampid::progress::silent)
                .unwrap()
                .into_parts();
            let x = &mut parts.displacements;
            for j in 0..2 {
                let rms = (x.col(j).iter().map(|v| v * v).sum::<f64>() / x.nrows() as f64).sqrt();
                let noise = Normal::new(0.0, 0.01 * rms).unwrap();
                for i in 0..x.nrows() {
                    x[(i, j)] += noise.sample(&mut rng);
                }
            }
            parts.velocities = None;
            records.push(Record::new(parts).unwrap());
        }
    }
    records
}

fn regressor_settings() -> RegressorSettings {
    support::settings(
        WindowSpec::cycles(1),
        Quadrature::Trapezoid,
        VelocitySource::HarmonicProjection { harmonics: None },
    )
}

/// Simulated without friction, the Coulomb term is not needed; simulated with friction
/// 0.02 (a few percent of the dissipation), it is, and BIC agrees with the F-test.
/// (Seeds 1–5 gave the same verdicts: p from 0.08 to 0.99 without friction, about 1e-23
/// with it.)
#[test]
fn coulomb_term_is_needed_only_when_the_data_have_friction() {
    for (friction, needed) in [(0.0, false), (0.02, true)] {
        let records = noisy_records(friction, 17);
        let c = compare(
            ("viscous", &viscous()),
            ("viscous + Coulomb", &with_friction()),
            &records,
            &regressor_settings(),
            &CompareSettings::default(),
        )
        .unwrap();
        eprintln!("friction {friction}: {}", c.text);
        assert_eq!(c.nested_in, Some(Which::First), "{c}");
        let expected = if needed {
            Verdict::LargerNeeded
        } else {
            Verdict::SmallerSuffices
        };
        assert_eq!(c.verdict, expected, "friction {friction}: {c}");
        let preferred = if needed { Which::Second } else { Which::First };
        assert_eq!(c.bic_prefers, preferred, "{c}");
        if needed {
            assert!(c.text.contains("extra terms (friction)"), "{}", c.text);
        }
    }
}

/// `dampid compare` on the bundled measured data, whose generator has friction 0.05.
#[test]
fn compare_command_says_friction_is_needed() {
    let json = dampid_json(&[
        "compare",
        "models/measured_chain_no_friction.toml",
        "models/measured_chain.toml",
        "--json",
    ]);
    assert_eq!(json["verdict"], "larger_needed");
    assert_eq!(json["nested_in"], "first");
    assert_eq!(json["second"]["coefficients"][4], "friction");
}

/// A regressor without equations or without coefficients is a typed error.
#[test]
fn empty_regressors_are_typed_errors() {
    let no_rows =
        Regressor::from_parts(Mat::zeros(0, 1), Vec::new(), vec!["x".into()], Vec::new()).unwrap();
    assert!(matches!(
        compare_regressors(
            ("a", &no_rows),
            ("b", &no_rows),
            &CompareSettings::default()
        ),
        Err(Error::TooFewEquations { equations: 0, .. })
    ));
    let labels = row_labels(4);
    let no_columns =
        Regressor::from_parts(Mat::zeros(4, 0), B.to_vec(), Vec::new(), labels).unwrap();
    let x = regressor(&[("x", &X)], &B);
    assert!(matches!(
        compare_regressors(("a", &no_columns), ("b", &x), &CompareSettings::default()),
        Err(Error::Empty { .. })
    ));
}

/// A model that wins the F-test only through a negative Coulomb coefficient is flagged.
/// Columns c = (1, 2, 3, 4) and friction = (1, 1, 1, 1); b = c − 0.5 friction plus
/// (0, 0.01, −0.01, 0): least squares with both gives friction ≈ −0.5 and a tiny
/// residual, c alone cannot follow the offset, so the larger model is "needed"; the
/// conclusion says its preference rests on negative damping and that c alone is physical.
#[test]
fn negative_coulomb_winning_is_flagged() {
    let c = [1.0, 2.0, 3.0, 4.0];
    let b = [0.5, 1.51, 2.49, 3.5];
    let with = regressor(&[("c", &c), ("friction", &X)], &b);
    let without = regressor(&[("c", &c)], &b);
    let comparison = compare_regressors(
        ("with_friction", &with),
        ("viscous", &without),
        &CompareSettings::default(),
    )
    .unwrap();
    assert_eq!(comparison.verdict, Verdict::LargerNeeded);
    assert!(comparison.first.values[1] < -0.4);
    let text = &comparison.text;
    assert!(
        text.contains("caution: with_friction is preferred with negative damping (friction = -"),
        "{text}"
    );
    assert!(text.contains("while viscous is physical"), "{text}");
    // Physical coefficients: no caution.
    let b = [1.5, 2.51, 3.49, 4.5];
    let with = regressor(&[("c", &c), ("friction", &X)], &b);
    let without = regressor(&[("c", &c)], &b);
    let comparison = compare_regressors(
        ("with_friction", &with),
        ("viscous", &without),
        &CompareSettings::default(),
    )
    .unwrap();
    assert!(!comparison.text.contains("caution"), "{}", comparison.text);
}

/// Leave-one-out cross-validation by hand: b = (1, 2, 3, 4) on x = 1 has residuals
/// (−1.5, −0.5, 0.5, 1.5) and leverages h_ii = 1/4, so PRESS = Σ (e_i/(3/4))² =
/// 5 · 16/9 = 80/9 (refitting without b_1 gives mean 3, error 2 = 1.5/(3/4): the
/// formula is the exact refit). Adding a column that fits b exactly makes every
/// residual zero: PRESS 0 unless a leverage is 1.
#[test]
fn leave_one_out_cross_validation_by_hand() {
    let small = regressor(&[("x", &X)], &B);
    let large = regressor(&[("x", &X), ("b", &B)], &B);
    let c = compare_regressors(
        ("small", &small),
        ("large", &large),
        &CompareSettings::default(),
    )
    .unwrap();
    let press = c.first.cross_validation.unwrap();
    assert!((press - 80.0 / 9.0).abs() < 1e-12, "{press}");
    assert!(c.second.cross_validation.unwrap() < 1e-20);
    assert_eq!(c.cross_validation_prefers, Some(Which::Second));
    assert!(
        c.text
            .contains("leave-one-out cross-validation prefers large"),
        "{}",
        c.text
    );
}

/// `--laws` ranking: three candidates on the same b. With b = c − 0.5·friction plus a
/// little noise, viscous + friction ranks first by AIC with a negative friction, so the
/// ranking names the best physical candidate (viscous alone, ahead of friction alone).
#[test]
fn ranking_flags_a_negative_winner_and_names_the_best_physical_one() {
    use dampid::analysis::compare::rank;
    let c = [1.0, 2.0, 3.0, 4.0, 5.0];
    let one = [1.0; 5];
    let b = [0.5, 1.51, 2.49, 3.5, 4.51];
    let both = regressor(&[("c", &c), ("friction", &one)], &b);
    let viscous = regressor(&[("c", &c)], &b);
    let friction = regressor(&[("friction", &one)], &b);
    let ranking = rank(
        &[
            ("friction", &friction),
            ("viscous", &viscous),
            ("linear+coulomb", &both),
        ],
        &CompareSettings::default(),
    )
    .unwrap();
    let order: Vec<&str> = ranking
        .models
        .iter()
        .map(|m| m.fit.label.as_str())
        .collect();
    assert_eq!(order, ["linear+coulomb", "viscous", "friction"]);
    assert_eq!(ranking.models[0].negative.len(), 1);
    assert_eq!(ranking.best_physical.as_deref(), Some("viscous"));
    assert!(
        ranking
            .text
            .contains("the best physical candidate is viscous"),
        "{}",
        ranking.text
    );
    let table = ranking.to_string();
    assert!(table.contains("(negative)"), "{table}");
    // Different input work: not the same data.
    let other = regressor(&[("c", &c)], &[1.0, 2.0, 3.0, 4.0, 5.0]);
    assert!(
        rank(
            &[("a", &viscous), ("b", &other)],
            &CompareSettings::default()
        )
        .is_err()
    );
}

/// A model with an estimated exponent is compared at its least-squares exponent, which
/// counts in k: on the four-mass chain simulated with d|v|^1.7 sign v (noise-free), the
/// estimated exponent comes back within 1 %, and the same model with the exponent fixed
/// at that value has the same RSS and k one less, so its AIC is lower by exactly 2 and
/// its BIC by ln m.
#[test]
fn estimated_exponent_counts_in_k_and_sits_at_its_least_squares_value() {
    let job = dampid::model_file::load(
        std::path::Path::new("models/four_mass_power.toml"),
        Default::default(),
    )
    .unwrap();
    let law = &job.law;
    assert!(!law.is_fixed(), "an estimated exponent");
    let estimated = job.compared("estimated", law).unwrap();
    let (name, exponent) = &estimated.estimated[0];
    assert_eq!(name, "d.exponent");
    assert!((exponent - 1.7).abs() < 0.017, "exponent {exponent}");
    let fixed_model = law.at(&[*exponent]).unwrap();
    let fixed = job
        .compared(
            "fixed",
            &dampid::regressor::ParametricModel::fixed(fixed_model),
        )
        .unwrap();
    assert!(fixed.estimated.is_empty());
    let c = dampid::analysis::compare::compare_candidates(
        estimated.candidate(),
        fixed.candidate(),
        &CompareSettings::default(),
    )
    .unwrap();
    assert_eq!(c.first.parameters, c.second.parameters + 1);
    let rss = c.first.residual_sum_of_squares;
    assert!((c.second.residual_sum_of_squares - rss).abs() <= 1e-9 * rss);
    let m = c.equations as f64;
    assert!((c.first.aic - c.second.aic - 2.0).abs() < 1e-6);
    assert!((c.first.bic - c.second.bic - m.ln()).abs() < 1e-6);
    assert!(
        c.text
            .contains("k counts the estimated parameters of estimated")
    );
}

/// `--laws` with `power:est`: the candidates with an estimated exponent are fitted at
/// their least-squares exponent, and on the chain simulated with stiffness-proportional
/// damping plus d|v|^1.7 the one with a linear term ranks first, its exponent within 2 %
/// (the linear term stands in for the stiffness-proportional one); a fixed quadratic
/// law ranks last. An exponent that is neither a number nor `est` is a typed error.
#[test]
fn laws_with_estimated_exponents_are_ranked() {
    let json = dampid_json(&[
        "compare",
        "models/four_mass_power.toml",
        "--laws",
        "quadratic,power:est,linear+power:est",
        "--json",
    ]);
    let models = json["models"].as_array().unwrap();
    assert_eq!(models[0]["fit"]["label"], "linear+power:est");
    assert_eq!(models[2]["fit"]["label"], "quadratic");
    let estimated = &models[0]["fit"]["estimated"][0];
    assert_eq!(estimated[0], "power.exponent");
    let p = estimated[1].as_f64().unwrap();
    assert!((p - 1.7).abs() < 0.034, "exponent {p}");
    assert_eq!(models[0]["fit"]["parameters"], 3);
    let registry = dampid::terms::laws::Registry::builtin();
    let err = dampid::model_file::candidate("power:often", 1, &registry).unwrap_err();
    assert!(err.to_string().contains("law:est"), "{err}");
}

/// A stepped-sine table whose residual receptances are estimated: every candidate of
/// `--laws` is fitted with its own residuals (nuisance parameters, counted in k), and
/// the shipped table, generated with c v + d |v|^1.5 sign v, ranks linear+power:1.5
/// first, ahead of the same law with its exponent estimated (one more parameter, the
/// same residual within the noise).
#[test]
fn table_residuals_are_estimated_per_candidate() {
    let json = dampid_json(&[
        "compare",
        "models/bolted_joint_stepped_sine_residual.toml",
        "--laws",
        "linear,linear+power:1.5,linear+power:est",
        "--json",
    ]);
    let models = json["models"].as_array().unwrap();
    assert_eq!(models[0]["fit"]["label"], "linear+power:1.5");
    assert_eq!(models[0]["fit"]["nuisance"].as_array().unwrap().len(), 7);
    assert_eq!(models[0]["fit"]["parameters"], 9);
    assert_eq!(models[2]["fit"]["label"], "linear");
}
