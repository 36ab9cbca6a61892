//! The periodic orbit of a history element driven by one period of its displacement.
//!
//! The path is x_0 … x_{L−1}, the samples of one window of whole periods, read
//! cyclically: after x_{L−1} it returns to x_0 (x_L = x_0 when the window holds kT/h
//! samples exactly; otherwise the closing step is the small jump x_{L−1} → x_0). One
//! pass is the state carried once around the path, z ↦ P(z). The state is on its
//! periodic orbit when one more pass leaves it unchanged,
//!
//! ```text
//!   ‖P(z) − z‖_∞ ≤ TOLERANCE · scale,
//! ```
//!
//! scale = [`super::Hysteresis::state_scale`] of the half range of x (a displacement
//! for Bouc–Wen and Iwan, 1 for Dahl). The force s_i = S(z_i, x_i) is read on that last
//! pass. Start: the virgin state at x_0. A one-variable state (Bouc–Wen, Dahl) solves
//! P(z) = z by the secant method on g(z) = P(z) − z, a step that does not shrink |g|
//! undone for the plain pass z ← P(z) from the better point (P is
//! monotone and contracts on these elements, but slowly at small amplitude, where the
//! plain iteration can need thousands of passes); the Iwan joint's sliders repeat
//! exactly after the pass that has visited the path's extremes, so plain passes end
//! in two. No orbit after [`MAX_PASSES`] passes (or a term's own cap,
//! `HistoryTerm::with_max_passes`) is [`NoOrbit`], which the regressor
//! reports as an error naming the record and window.

use super::Hysteresis;

/// Relative tolerance of the repeat check.
pub const TOLERANCE: f64 = 1e-10;

/// Passes through the window at most.
pub const MAX_PASSES: usize = 200;

/// The state did not repeat.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoOrbit {
    /// Passes made.
    pub passes: usize,
    /// ‖P(z) − z‖_∞ on the last pass.
    pub change: f64,
    /// The tolerance it had to meet.
    pub tolerance: f64,
}

/// One pass from `state` (updated in place to P(state)); the force at each sample in `force`.
fn pass(element: &dyn Hysteresis, path: &[f64], state: &mut [f64], force: &mut [f64]) {
    let next = path.iter().skip(1).chain(path.first());
    for ((out, &x), &next) in force.iter_mut().zip(path).zip(next) {
        *out = element.force(state, x);
        element.step(state, x, next);
    }
}

fn change(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The force per unit coefficient s_i on the periodic orbit of `element` driven by the
/// cyclic `path` (at least one sample), in at most [`MAX_PASSES`] passes.
pub fn periodic_force(element: &dyn Hysteresis, path: &[f64]) -> Result<Vec<f64>, NoOrbit> {
    periodic_force_within(element, path, MAX_PASSES)
}

/// [`periodic_force`] in at most `max_passes` passes.
pub fn periodic_force_within(
    element: &dyn Hysteresis,
    path: &[f64],
    max_passes: usize,
) -> Result<Vec<f64>, NoOrbit> {
    let (lo, hi) = path
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    let tolerance = TOLERANCE * element.state_scale(0.5 * (hi - lo));
    let mut force = vec![0.0; path.len()];
    let mut state = vec![0.0; element.state_len()];
    element.start(path[0], &mut state);
    let scalar = state.len() == 1;
    // (z, g(z)) of the previous pass, for the secant step.
    let mut previous: Option<(f64, f64)> = None;
    let mut last_change = f64::INFINITY;
    for passes in 1..=max_passes {
        let start = state.clone();
        pass(element, path, &mut state, &mut force);
        last_change = change(&start, &state);
        if last_change <= tolerance || !last_change.is_finite() {
            if last_change.is_finite() {
                return Ok(force);
            }
            return Err(NoOrbit {
                passes,
                change: last_change,
                tolerance,
            });
        }
        if scalar {
            let (z, g) = (start[0], state[0] - start[0]);
            match previous {
                // the last secant step made |g| worse: back to the better point's
                // plain pass, P(z0) = z0 + g0
                Some((z0, g0)) if g.abs() >= g0.abs() => state[0] = z0 + g0,
                Some((z0, g0)) => {
                    let secant = z - g * (z - z0) / (g - g0);
                    if g != g0 && secant.is_finite() {
                        state[0] = secant;
                    }
                    previous = Some((z, g));
                }
                None => previous = Some((z, g)),
            }
        }
    }
    Err(NoOrbit {
        passes: max_passes,
        change: last_change,
        tolerance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::history::{BoucWen, Dahl, Iwan};

    fn sine(samples: usize, amplitude: f64, offset: f64) -> Vec<f64> {
        (0..samples)
            .map(|i| {
                offset + amplitude * (2.0 * std::f64::consts::PI * i as f64 / samples as f64).sin()
            })
            .collect()
    }

    /// On the orbit one more pass changes nothing, whatever the start: two paths that
    /// differ by a rotation (a window starting elsewhere in the period) give rotated
    /// forces.
    #[test]
    fn the_orbit_does_not_depend_on_where_the_window_starts() {
        let elements: Vec<Box<dyn Hysteresis>> = vec![
            Box::new(BoucWen::new(40.0, 10.0, 1.5).unwrap()),
            Box::new(Dahl::new(0.05, 1.0).unwrap()),
            Box::new(Iwan::new(0.1, -0.4, 0.5).unwrap()),
        ];
        for element in &elements {
            let path = sine(400, 0.08, 0.01);
            let mut rotated = path[100..].to_vec();
            rotated.extend_from_slice(&path[..100]);
            let a = periodic_force(element.as_ref(), &path).unwrap();
            let b = periodic_force(element.as_ref(), &rotated).unwrap();
            // Iwan's stuck sliders keep the offset of their start: compare the loop's
            // shape, s minus its mean.
            let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
            let (ma, mb) = (mean(&a), mean(&b));
            for (i, &ai) in a.iter().enumerate() {
                let j = (i + 400 - 100) % 400;
                assert!(
                    ((ai - ma) - (b[j] - mb)).abs() < 1e-7,
                    "{}: sample {i}: {} vs {}",
                    element.name(),
                    ai,
                    b[j]
                );
            }
        }
    }

    /// A slowly contracting Bouc–Wen element (small amplitude, n = 2) still reaches its
    /// orbit within the cap, by the secant step.
    #[test]
    fn slow_contraction_converges() {
        let element = BoucWen::new(5.0, 1.0, 2.0).unwrap();
        let result = periodic_force(&element, &sine(200, 0.01, 0.0));
        assert!(result.is_ok(), "{:?}", result.err());
    }
}
