//! Data whose magnitude double precision cannot carry through the energy balance.
//!
//! Every equation multiplies two signals and integrates over a window (b = ∫ fᵀv dt,
//! a viscous column ∫ vᵀv dt), and the noise model and the steady-state check form the
//! squares of signals and of their residuals. A signal of magnitude q therefore meets
//! the range of double precision, about 2^±1022 ≈ 10^±308, through q² long before q
//! itself does. The pipeline is scale-invariant while that holds: x and f × s leave
//! every viscous coefficient, standard error, χ² and verdict unchanged from s = 10⁻¹⁵⁰
//! to 10¹⁵⁰ (`tests/invariants.rs`). Beyond, products overflow to ∞ or sink into
//! subnormal numbers that keep a few bits: measured on `models/measured_chain.toml`
//! (x ≤ 3.5 and f ≤ 1 at s = 1), s = 10¹⁵³ gave every dashpot but one "0 at lower
//! bound" with no error, s = 10⁻¹⁶⁰ flipped a steady-state verdict, and s = 10⁻¹⁵² or
//! 10²⁰⁰ stopped on an infinite or NaN column that said nothing about units.
//!
//! Forces meet it only through the work, a product with the motion (the noise model
//! keeps standard deviations, formed as scaled norms): forces × 10^±250 on displacements
//! of order one change no reported figure but by the factor
//! (`tests/invariants.rs::extreme_force_scales_change_no_reported_figure`).
//! These bounds are measured, not derived: the margins above are a factor 10 to 100 from
//! the first failure seen; scaling the data on entry would lift them.
//!
//! So [`crate::regressor::Regressor::build`] and the steady-state check
//! ([`crate::prep::steady_state::check`]) refuse, before any product is formed, a record
//! whose largest displacement x̄, measured velocity v̄ or force f̄
//! ([`crate::record::Record::magnitudes`]) gives
//!
//! ```text
//!   x̄ or v̄ outside [2^−505, 2^505]  (≈ 9.5·10⁻¹⁵³ … 1.05·10¹⁵²),   or   x̄ f̄ outside [2^−1000, 2^1010],
//! ```
//!
//! so that the squares and the work stay within 2^±1010, a factor 2^12 (4096) inside
//! double precision for the sums and products that follow. The work's lower end is
//! higher because its noise, smaller by the signal-to-noise ratio, must stay a normal
//! number too: on the measured chain the noise-robust rows failed from a work of about
//! 10⁻³⁰³ (s = 3·10⁻¹⁵²) and held at 10⁻³⁰² (s = 10⁻¹⁵¹). The refusal is [`Error::DataScale`]
//! naming the record, the signal and its magnitude, and saying what to do: give the data
//! in other units (a channel's `scale` in a model file), which scales the coefficients
//! with them. A record without force (a free decay) or a signal that is zero everywhere
//! is not tested on that signal; a signal that never moves is
//! [`crate::regressor::dead_motion`]'s concern.

use crate::error::{Error, Result};
use crate::format::number;
use crate::record::Record;

/// log₂ of the largest magnitude of a record's motion, and half that of its work
/// (module doc).
pub const LARGEST_EXPONENT: i32 = 505;
/// log₂ of the smallest work x̄ f̄ (module doc).
pub const SMALLEST_WORK_EXPONENT: i32 = -1000;

/// [`Error::DataScale`] for the first record of `records` whose motion or work lies
/// outside what double precision carries (module doc).
pub fn require_representable(records: &[Record]) -> Result<()> {
    let motion = 2f64.powi(LARGEST_EXPONENT);
    let (smallest_work, largest_work) = (2f64.powi(SMALLEST_WORK_EXPONENT), motion * motion);
    let outside =
        |q: f64, (smallest, largest): (f64, f64)| q > largest || (q > 0.0 && q < smallest);
    // the power of ten that brings q to order one
    let factor = |q: f64| -(q.log10().round() as i32);
    for record in records {
        let m = record.magnitudes();
        let refuse = |signal: &str, magnitude: f64, reason: String, factor_exponent: i32| {
            Err(Error::DataScale {
                record: record.label().to_string(),
                signal: signal.to_string(),
                magnitude,
                reason,
                factor_exponent,
            })
        };
        let kinds = [
            ("displacement", Some(m.displacement)),
            ("velocity", m.velocity),
        ];
        for (signal, q) in kinds {
            let Some(q) = q.filter(|&q| outside(q, (1.0 / motion, motion))) else {
                continue;
            };
            let reason =
                "outside 2^±505 (about 1e±152), beyond which its square leaves double precision";
            return refuse(signal, q, reason.into(), factor(q));
        }
        let product = m.displacement * m.force;
        if outside(product, (smallest_work, largest_work)) {
            let reason = format!(
                "and with displacements up to {} the work x·f (up to {}) lies outside \
                 2^-1000 … 2^1010 (about 1e-301 … 1e304), beyond which it leaves double precision",
                number(m.displacement),
                number(product)
            );
            return refuse("force", m.force, reason, factor(product));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Forcing, RecordParts};
    use faer::Mat;

    fn record(x: f64, f: f64) -> Record {
        let n = 64;
        let wave = |a: f64| Mat::from_fn(n, 1, |i, _| a * (0.1 * i as f64).sin());
        Record::new(RecordParts {
            label: "r".into(),
            step: 0.1,
            start_time: 0.0,
            displacements: wave(x),
            velocities: None,
            forcing: Forcing::on_dofs(wave(f), vec![0]),
            period: 6.4,
        })
        .unwrap()
    }

    /// The band's ends: a magnitude just inside passes, just outside is refused and
    /// named, on either side; the force is tested through the work x·f, so forces far
    /// from order one pass on displacements that balance them; zero force is not tested.
    #[test]
    fn motion_and_work_within_their_bands() {
        // the amplitudes that put the sine's largest sample at 2^±505
        let peak = (0..64).fold(0.0, |m: f64, i| m.max((0.1 * i as f64).sin().abs()));
        let high = 2f64.powi(LARGEST_EXPONENT) / peak;
        let low = 2f64.powi(-LARGEST_EXPONENT) / peak;
        for (x, f) in [
            (high * 0.99, 1.0 / high),
            (
                low * 1.01,
                1.01 / low / low * 2f64.powi(SMALLEST_WORK_EXPONENT),
            ),
            (1.0, 1e250),
            (1.0, 1e-250),
            (1.0, 0.0),
            (low * 1.01, 0.99 * high * high * peak),
        ] {
            assert!(
                require_representable(&[record(x, f)]).is_ok(),
                "{x:e} {f:e}"
            );
        }
        for (x, f, signal) in [
            (high * 1.01, 1.0, "displacement"),
            (low * 0.99, 1.0, "displacement"),
            (1e-200, 1.0, "displacement"),
            (1.0, 1e306, "force"),
            (1.0, 1e-306, "force"),
            (1e150, 1e155, "force"),
            (1e-150, 1e-152, "force"),
        ] {
            match require_representable(&[record(x, f)]).unwrap_err() {
                Error::DataScale {
                    record,
                    signal: named,
                    ..
                } => assert_eq!(
                    (record.as_str(), named.as_str()),
                    ("r", signal),
                    "{x:e} {f:e}"
                ),
                other => panic!("{other}"),
            }
        }
    }
}
