//! Columns that are round-off. Entry A_rk is the net work ∮ vᵀ f_k dt of term k over
//! window r. A term that does no net work over whole periods (a spring-like force in
//! phase with x, `expression = "x"`; a constant force, `expression = "1"`) gives a
//! column that is zero but for the rounding of its inputs, and column scaling then
//! blows that round-off up to a unit column the fit reads as information (k = 2.4·10⁵
//! ± 26 % "determined"). Each entry is compared with what rounding can produce: with
//! the gross work of the column in the window,
//!
//! ```text
//!   G_rk = ∮ |vᵀ f_k(x, v)| dt  ≈  (L h / n) Σ_j |v_jᵀ f_k(x_j, v_j)|,
//! ```
//!
//! on n = [`GROSS_SAMPLES`] samples j spread evenly over the window's L intervals
//! (measured velocities, else central differences of x), the entry counts as zero when
//!
//! ```text
//!   |A_rk| ≤ η · G_rk,   η = [`ROUND_OFF_SHARE`] = 10⁻⁴.
//! ```
//!
//! Why 10⁻⁴: the net work of a conservative force over a window is the change of its
//! potential between the window's ends, so its share of the gross work is the share by
//! which the window misses whole periods, as the inputs and the velocity estimate fix
//! them. A drive frequency written with six digits (`frequency = 0.765367`) is a
//! relative period error up to 6.5·10⁻⁷; f64 arithmetic adds N ε (2·10⁻¹⁰ for N = 10⁶
//! samples); spectral velocities over windows of a non-integer number of samples per
//! period leak. Spring and constant-force columns on the measured chain's records
//! (frequencies to six digits, samples to eleven) come out at 8·10⁻⁹ to 3·10⁻⁷ of
//! their gross work in the noise-robust pipeline and up to 1.5·10⁻⁵ with spectral
//! velocities. η leaves a factor 6 above the largest, while a dissipative term has
//! A_rk = G_rk (its power vᵀ f_k never changes sign): only a term dissipating less than
//! 10⁻⁴ of the work it exchanges, which no energy balance of such inputs can measure,
//! is set to zero. G_rk from n samples is an estimate within a few percent for the
//! smooth integrands of whole periods, ample for such a threshold. Not caught: a
//! conservative column whose window misses whole periods by more (a period detected
//! from noisy data, or given with three digits); its noise then shows in its standard
//! error.
//!
//! A column that is zero in every equation is reported
//! ([`crate::report::Warning::RoundOffColumn`]) and is not determined (a zero column
//! has a zero singular value). History and structural terms have no force at (x, v)
//! alone and are not tested.
//!

use faer::Mat;
use rayon::prelude::*;

use crate::model::DampingModel;
use crate::prep::window::Window;
use crate::record::{Record, col};
use crate::terms::{Coefficients, ElementTerm, OnElements, Term};

/// η: an entry whose net work is at most this share of its gross work is round-off of
/// its inputs (module doc).
pub const ROUND_OFF_SHARE: f64 = 1e-4;

/// Samples per window of the gross-work estimate.
pub const GROSS_SAMPLES: usize = 64;

/// Sets to zero each entry of `matrix` (rows: `windows` of `records`, columns: `model`'s
/// coefficients) that is round-off of its inputs (module doc); returns the columns that
/// are zero in every row afterwards and were not before (their indices).
pub(crate) fn zero_round_off(
    model: &DampingModel,
    records: &[Record],
    windows: &[Window],
    matrix: &mut Mat<f64>,
) -> Vec<usize> {
    let p = matrix.ncols();
    let testable: Vec<bool> = model
        .term_columns()
        .flat_map(|(term, range)| {
            let ok = matches!(term, Term::Matrix(_) | Term::Elements(_));
            range.map(move |_| ok)
        })
        .collect();
    if testable.len() != p || !testable.iter().any(|t| *t) {
        return Vec::new();
    }
    let was_zero: Vec<bool> = (0..p)
        .map(|k| (0..matrix.nrows()).all(|r| matrix[(r, k)] == 0.0))
        .collect();
    // Each window's gross work on its own (bitwise the same on any thread), then the
    // entries in order.
    let gross: Vec<Option<Vec<f64>>> = windows
        .par_iter()
        .with_min_len(16)
        .map(|w| gross_of(model, &records[w.record], w, &testable))
        .collect();
    for (r, gross) in gross.iter().enumerate() {
        let Some(gross) = gross else {
            continue;
        };
        for (k, g) in gross.iter().enumerate() {
            if testable[k] && matrix[(r, k)].abs() <= ROUND_OFF_SHARE * g {
                matrix[(r, k)] = 0.0;
            }
        }
    }
    (0..p)
        .filter(|&k| !was_zero[k] && (0..matrix.nrows()).all(|r| matrix[(r, k)] == 0.0))
        .collect()
}

/// G_rk of every column of `model` over window `w` of `record` (module doc); `None`
/// for a window of fewer than two samples.
fn gross_of(
    model: &DampingModel,
    record: &Record,
    w: &Window,
    testable: &[bool],
) -> Option<Vec<f64>> {
    let h = record.step();
    let last = record.samples().checked_sub(1)?;
    let intervals = ((w.span / h).round() as usize).min(last.saturating_sub(w.start));
    if intervals == 0 {
        return None;
    }
    let n = GROSS_SAMPLES.min(intervals);
    let dofs = record.dofs();
    let x = record.displacements();
    let measured = record.velocities();
    let xs: Vec<&[f64]> = (0..dofs).map(|j| col(x, j)).collect();
    let vs: Option<Vec<&[f64]>> = measured.map(|v| (0..dofs).map(|j| col(v, j)).collect());
    let p = testable.len();
    let mut gross = vec![0.0; p];
    // Displacements are read only when a law uses them (a second read of each DOF's
    // samples) or the velocities are their differences; laws that do not use them are
    // given zeros, as the kernel gives them none.
    let read_x = vs.is_none()
        || model.terms().iter().any(|t| match t {
            Term::Elements(t) => t.law().uses_displacement(),
            Term::Matrix(_) | Term::History(_) | Term::Structural(_) => false,
        });
    // The n samples' displacements and velocities, read DOF by DOF (each DOF's samples
    // lie within one window of its column: a few dozen cache lines, where reading every
    // DOF at one sample, then at the next, is n × DOFs cache misses a column apart),
    // stored sample by sample for the terms below.
    let samples: Vec<(usize, usize, usize)> = (0..n)
        .map(|j| {
            let i = w.start + j * intervals / n;
            (i, i.saturating_sub(1), (i + 1).min(last))
        })
        .collect();
    let (mut x_at, mut v_at) = (vec![0.0; n * dofs], vec![0.0; n * dofs]);
    for d in 0..dofs {
        for (j, &(i, before, after)) in samples.iter().enumerate() {
            if read_x {
                x_at[j * dofs + d] = xs[d][i];
            }
            v_at[j * dofs + d] = match &vs {
                Some(vs) => vs[d][i],
                None => (xs[d][after] - xs[d][before]) / ((after - before) as f64 * h),
            };
        }
    }
    let mut force = vec![0.0; dofs];
    // The unit coefficients of one term (all zero between uses), allocated once per
    // window rather than per sample and term: on a small record these allocations were
    // about a third of this function's instructions.
    let widest = model
        .term_columns()
        .map(|(_, r)| r.len())
        .max()
        .unwrap_or(0);
    let mut units = vec![0.0; widest];
    // the terms and their column ranges, once per window rather than per sample
    let term_columns: Vec<(&Term, std::ops::Range<usize>)> = model.term_columns().collect();
    for j in 0..n {
        let (xi, vi) = (
            &x_at[j * dofs..(j + 1) * dofs],
            &v_at[j * dofs..(j + 1) * dofs],
        );
        for (term, range) in &term_columns {
            if let Term::Elements(t) = term
                && matches!(t.coefficients(), Coefficients::PerElement(_))
            {
                // One column per element: its power alone, without a force vector
                // over every DOF per column (which made this O(elements × DOFs)).
                for (e, k) in range.clone().enumerate() {
                    if testable[k] {
                        gross[k] += element_power(t, e, xi, vi).abs();
                    }
                }
                continue;
            }
            let unit = &mut units[..range.len()];
            for (local, k) in range.clone().enumerate() {
                if !testable[k] {
                    continue;
                }
                unit[local] = 1.0;
                force.iter_mut().for_each(|f| *f = 0.0);
                term.add_force(unit, xi, vi, &mut force);
                unit[local] = 0.0;
                let power: f64 = vi.iter().zip(&force).map(|(v, f)| v * f).sum();
                gross[k] += power.abs();
            }
        }
    }
    let scale = intervals as f64 * h / n as f64;
    gross.iter_mut().for_each(|g| *g *= scale);
    Some(gross)
}

/// vᵀ f of element `e` of `t` alone with coefficient 1 at the DOFs' displacements `x`
/// and velocities `v`: ω_e f(x_a − x_b, v_a − v_b) times v_a, less the same times v_b
/// (v_a ω_e f(x_a, v_a) to ground); bitwise what `add_force` with a unit coefficient
/// followed by Σ_j v_j f_j gives, since the other DOFs add zeros.
fn element_power(t: &ElementTerm, e: usize, x: &[f64], v: &[f64]) -> f64 {
    let element = &t.elements()[e];
    let weight = t.weights().map_or(1.0, |w| w[e]);
    match element.b {
        None => v[element.a] * (weight * t.law().force(x[element.a], v[element.a])),
        Some(b) => {
            let (a, xr, vr) = (element.a, x[element.a] - x[b], v[element.a] - v[b]);
            let f = weight * t.law().force(xr, vr);
            v[a] * f + v[b] * -f
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::terms::Element;
    use crate::terms::laws::{PowerLaw, Quadratic};

    /// An element's power alone is bitwise vᵀ f of the term's force with that element's
    /// coefficient 1 and the others 0 (the path every other term takes): dashpots in
    /// both orders of their DOFs and to ground, with weights, for two laws.
    #[test]
    fn element_power_is_the_unit_force_power() {
        let elements = vec![
            Element::to_ground(0),
            Element::between(0, 1),
            Element::between(2, 1),
            Element::between(3, 0),
            Element::to_ground(3),
        ];
        let power = PowerLaw::new(0.7).unwrap();
        let laws: [Arc<dyn crate::terms::Law>; 2] = [Arc::new(Quadratic), Arc::new(power)];
        for law in laws {
            for weights in [None, Some(vec![0.3, 1.7, 0.9, 2.1, 0.45])] {
                let mut t = ElementTerm::new(
                    law.clone(),
                    elements.clone(),
                    Coefficients::PerElement("c".into()),
                );
                if let Some(w) = &weights {
                    t = t.with_weights(w.clone());
                }
                for sample in 0..20 {
                    let s = sample as f64;
                    let x: Vec<f64> = (0..4).map(|d| (0.37 * s + d as f64).sin()).collect();
                    let v: Vec<f64> = (0..4).map(|d| (0.61 * s - d as f64).cos()).collect();
                    for e in 0..elements.len() {
                        let mut unit = vec![0.0; elements.len()];
                        unit[e] = 1.0;
                        let mut force = vec![0.0; 4];
                        t.add_force(&unit, &x, &v, &mut force);
                        let through_force: f64 = v.iter().zip(&force).map(|(v, f)| v * f).sum();
                        let alone = element_power(&t, e, &x, &v);
                        assert_eq!(
                            alone.abs().to_bits(),
                            through_force.abs().to_bits(),
                            "element {e}, sample {sample}: {alone} against {through_force}"
                        );
                    }
                }
            }
        }
    }
}
