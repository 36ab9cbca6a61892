//! Stepped-sine rows in closed form (`terms/harmonic_work.rs`, used by
//! `regressor/stepped_sine.rs` when every term has one) against the synthesized
//! period's quadrature of the same laws written as expressions, which keep the
//! synthesis: the closed form is the exact single-harmonic integral, so the two differ
//! by the 512-sample quadrature's error alone (exact for viscous terms; N^{−(q+1)} for a
//! power |v|^q, measured in the unit tests of `terms/harmonic_work.rs`), on a two-DOF
//! table with a dashpot between the DOFs, for the synchronous and the per-DOF phase
//! readings.

use dampid::model::DampingModel;
use dampid::prep::harmonic::{HarmonicApproximation, PhaseReading, SteppedSinePoint};
use dampid::regressor::stepped_sine::columns_of;
use dampid::terms::laws::{Coulomb, Expression, Linear, PowerLaw, Quadratic};
use dampid::terms::{Coefficients, Element, Law, Term};

fn points() -> Vec<SteppedSinePoint> {
    (0..7)
        .map(|i| {
            let t = i as f64;
            SteppedSinePoint {
                label: format!("p{i}"),
                frequency: 30.0 + 2.5 * t,
                force_dof: 0,
                force_amplitude: 1.0 + 0.3 * t,
                amplitudes: vec![1e-3 * (1.0 + 0.2 * t), 0.4e-3 * (1.0 + 0.1 * t)],
                phases: vec![0.3 + 0.35 * t, 0.9 + 0.2 * t],
            }
        })
        .collect()
}

/// The four laws on ground and between the DOFs, one coefficient per element.
fn model(laws: [std::sync::Arc<dyn Law>; 4]) -> DampingModel {
    let elements = vec![Element::to_ground(0), Element::between(0, 1)];
    laws.into_iter()
        .zip(["c", "q", "f", "d"])
        .fold(DampingModel::new(), |m, (law, name)| {
            m.with(Term::Elements(dampid::terms::ElementTerm::new(
                law,
                elements.clone(),
                Coefficients::PerElement(name.into()),
            )))
        })
}

#[test]
fn closed_form_rows_are_the_limit_of_the_synthesized_ones() {
    use std::sync::Arc;
    let closed = model([
        Arc::new(Linear),
        Arc::new(Quadratic),
        Arc::new(Coulomb),
        Arc::new(PowerLaw::new(1.5).unwrap()),
    ]);
    let expression = |text: &str| -> Arc<dyn Law> { Arc::new(Expression::parse(text).unwrap()) };
    let synthesized = model([
        expression("v"),
        expression("v*abs(v)"),
        expression("sign(v)"),
        expression("sign(v)*abs(v)^1.5"),
    ]);
    // Columns: c[1] c[1-2] q[1] q[1-2] f[1] f[1-2] d[1] d[1-2]; worst relative
    // differences allowed (module doc).
    let tolerance = [1e-12, 1e-12, 5e-10, 5e-10, 2e-5, 2e-5, 4e-9, 4e-9];
    for phase in [PhaseReading::ArithmeticMean, PhaseReading::PerDof] {
        let approximation = HarmonicApproximation {
            phase,
            ..HarmonicApproximation::default()
        };
        let a = columns_of(&closed, &[], &approximation, &points()).unwrap();
        let b = columns_of(&synthesized, &[], &approximation, &points()).unwrap();
        let mut worst = [0.0f64; 8];
        for (ra, rb) in a.iter().zip(&b) {
            for (k, (x, y)) in ra.iter().zip(rb).enumerate() {
                assert!(*x > 0.0, "{phase:?}: column {k} {x}");
                worst[k] = worst[k].max((x - y).abs() / x);
            }
        }
        for (k, (w, t)) in worst.iter().zip(tolerance).enumerate() {
            assert!(*w < t, "{phase:?}: column {k}: {w}");
        }
        // The Coulomb columns' quadrature error is real and of the expected size:
        // the comparison is not between two copies of the same computation.
        assert!(worst[4] > 1e-8, "{phase:?}: {}", worst[4]);
    }
}
