//! ζ at the measured levels of a one-mode stepped-sine table: where each sweep's phase
//! lag φ(ω) of the displacement crosses π/2 (resonance, the −π/2 of a phase lead), the
//! sweep's amplitude X_c there and the table's own damping estimate from the phase slope,
//! to set beside the fitted law's ζ_eq(X_c).
//!
//! For one mode with viscous damping, ω cot φ = (ω_n² − ω²)/(2ζω_n) is linear in ω²,
//! and ω X/(a sin φ) = 1/c is constant (a the force amplitude), so from the two points
//! that bracket the crossing, by linear interpolation in ω²,
//!
//! ```text
//!   ω_c² where ω cot φ = 0,   ζ_slope = −1 / (2 ω_c · d(ω cot φ)/d(ω²)),
//!   X_c = a_c · [ω X/(a sin φ)]_c / ω_c        (sin φ = 1 at the crossing),
//! ```
//!
//! exact for viscous damping however far apart the two points are. This is the
//! phase-slope estimate labs read off a sweep (at φ = π/2, dφ/dω = 1/(ζ ω_n)), in a
//! form that secants of φ and X, off by tens of percent when the points are a half-power
//! bandwidth apart, do not spoil. For amplitude-dependent damping it is the damping at
//! the crossing's amplitude (exactly so for a response-controlled sweep, which holds X;
//! a force-controlled sweep's X, and so ζ, varies between the two points). A sweep whose
//! phase does not cross π/2 gives none. The points are the response less the estimated
//! residual receptance when one was estimated
//! ([`crate::prep::harmonic::residual::correct`]).

use serde::{Deserialize, Serialize};

use crate::prep::harmonic::SteppedSinePoint;
use crate::prep::harmonic::sweeps::SweptTable;

/// Where one sweep's phase lag crosses π/2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Crossing {
    /// The sweep.
    pub sweep: usize,
    /// ω_c.
    pub frequency: f64,
    /// X_c.
    pub amplitude: f64,
    /// −1 / (2 ω_c d(ω cot φ)/d(ω²)), when the slope is negative.
    pub slope_damping: Option<f64>,
}

/// ζ at one sweep's measured level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelDamping {
    /// The sweep's name.
    pub sweep: String,
    /// ω_c, where the phase lag crosses π/2 (rad per unit time).
    pub frequency: f64,
    /// The amplitude X_c there.
    pub amplitude: f64,
    /// The fitted ζ_eq(X_c).
    pub fitted: f64,
    /// Its standard deviation (None without standard errors).
    pub fitted_std: Option<f64>,
    /// The table's own estimate from the phase slope, −1/(2ω_c d(ω cot φ)/d(ω²))
    /// (None when the slope at the crossing is not negative).
    pub measured: Option<f64>,
    /// fitted / measured.
    pub ratio: Option<f64>,
}

/// The crossing of π/2 by each sweep of the one-DOF `swept` (sweeps without one are
/// left out), in sweep order.
pub(crate) fn crossings(swept: &SweptTable) -> Vec<Crossing> {
    let points = swept.table.points();
    (0..swept.sweep_names.len())
        .filter_map(|s| {
            let mut members = swept.members(s);
            members.sort_by(|&a, &b| points[a].frequency.total_cmp(&points[b].frequency));
            members.windows(2).find_map(|pair| {
                let (a, b) = (&points[pair[0]], &points[pair[1]]);
                let (pa, pb) = (a.phases[0], b.phases[0]);
                let lags = pa.sin() > 0.0 && pb.sin() > 0.0;
                let (ua, ub) = (a.frequency.powi(2), b.frequency.powi(2));
                let (ya, yb) = (a.frequency / pa.tan(), b.frequency / pb.tan());
                let crosses = lags && ya >= 0.0 && yb <= 0.0 && ya != yb;
                (crosses && ub > ua).then(|| {
                    let t = ya / (ya - yb);
                    let lerp = |u: f64, v: f64| u + t * (v - u);
                    let frequency = lerp(ua, ub).sqrt();
                    let slope = (yb - ya) / (ub - ua);
                    // ω X/(a sin φ) = 1/c_eq, and sin φ = 1 at the crossing.
                    let inverse_c = |p: &SteppedSinePoint, phase: f64| {
                        p.frequency * p.amplitudes[0] / (p.force_amplitude * phase.sin())
                    };
                    Crossing {
                        sweep: s,
                        frequency,
                        amplitude: lerp(a.force_amplitude, b.force_amplitude)
                            * lerp(inverse_c(a, pa), inverse_c(b, pb))
                            / frequency,
                        slope_damping: (slope < 0.0).then(|| -1.0 / (2.0 * frequency * slope)),
                    }
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::harmonic::SteppedSineTable;
    use crate::prep::harmonic::sweeps::PointNoise;

    /// A viscous oscillator (m = 1, ω_n = 10, ζ = 0.02) swept at unit force: the phase
    /// slope at the crossing gives ζ, ω_n and X_c back to round-off from points spaced 2ζ apart (a
    /// half-power bandwidth, the crossing midway between two); X_c = 1/(2ζ k), the resonant
    /// amplitude.
    #[test]
    fn phase_slope_of_a_viscous_oscillator() {
        let (wn, zeta) = (10.0f64, 0.02);
        let k = wn * wn;
        let points: Vec<SteppedSinePoint> = (0..41)
            .map(|i| {
                let w = wn * (0.61 + 0.04 * i as f64);
                let (re, im) = (k - w * w, 2.0 * zeta * wn * w);
                SteppedSinePoint {
                    label: format!("p{i}"),
                    frequency: w,
                    force_dof: 0,
                    force_amplitude: 1.0,
                    amplitudes: vec![1.0 / re.hypot(im)],
                    phases: vec![im.atan2(re)],
                }
            })
            .collect();
        let noise = PointNoise {
            force: 0.0,
            amplitudes: vec![0.0],
            phases: vec![0.0],
        };
        let swept = SweptTable::with_noise(
            SteppedSineTable::new(points).unwrap(),
            vec![0; 41],
            vec!["one".into()],
            vec![noise; 41],
        )
        .unwrap();
        let found = crossings(&swept);
        assert_eq!(found.len(), 1);
        let c = found[0];
        assert!((c.frequency - wn).abs() < 1e-12 * wn, "{c:?}");
        assert!(
            (c.slope_damping.unwrap() - zeta).abs() < 1e-12 * zeta,
            "{c:?}"
        );
        let resonant = 1.0 / (2.0 * zeta * k);
        assert!((c.amplitude - resonant).abs() < 1e-12 * resonant, "{c:?}");
    }
}
