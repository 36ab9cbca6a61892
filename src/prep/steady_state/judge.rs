//! One window judged: which periods are compared, the mismatch of the projected end
//! states, its noise, and the verdict in numbers and in words (formulas in the module
//! doc of [`crate::prep::steady_state`]).

use faer::Mat;

use crate::error::{Error, Result};
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::Window;
use crate::record::{LoadDistribution, Record, col};

use super::few;
use super::projection::{StateProjection, snap};
use super::{
    ComparedPeriods, Decisive, MIN_NEIGHBOUR, MIN_SAMPLES_PER_PERIOD, NON_HARMONIC_MARGIN,
    SteadyStateSettings, StoredEnergy, WindowCheck,
};

/// A compared span: (origin in samples, periods k', what it is).
pub(super) type Span = (f64, usize, ComparedPeriods);

/// Which periods to compare for `window` of `record`: each (origin in samples,
/// periods k', what it is), or why none can be.
pub(super) fn compared_spans(
    record: &Record,
    window: &Window,
) -> std::result::Result<Vec<Span>, String> {
    let length = record.period() / record.step();
    if length < MIN_SAMPLES_PER_PERIOD {
        return Err(format!(
            "cannot be judged: a period of {length:.2} samples is too short for a harmonic projection"
        ));
    }
    let start = window.start as f64;
    if window.cycles >= 2 {
        return Ok(vec![(
            start,
            window.cycles,
            ComparedPeriods::FirstAndLastPeriod,
        )]);
    }
    let mut spans = Vec::new();
    // The next period may be cut short by the record's end (the paper's 200 samples
    // hold 1.97 periods of 101.7): at least MIN_NEIGHBOUR of it.
    if snap(start + (1.0 + MIN_NEIGHBOUR) * length).ceil() <= record.samples() as f64 {
        spans.push((start, 2, ComparedPeriods::NextPeriod));
    }
    if snap(start - length) >= 0.0 {
        spans.push((start - length, 2, ComparedPeriods::PreviousPeriod));
    }
    if spans.is_empty() {
        return Err("cannot be judged from one period: the record holds no other whole period to compare with".into());
    }
    Ok(spans)
}

/// A window that cannot be judged: accepted, with the reason.
fn unjudged(mut check: WindowCheck, reason: String) -> WindowCheck {
    check.compared = ComparedPeriods::NotJudged;
    check.reason = reason;
    check
}

/// The check of `window` of `record`, from its compared spans ([`compared_spans`]) and
/// their projections (`projections[i]` that of `spans[i]`, projected once per record
/// and span however many windows compare it).
pub(super) fn check_window(
    record: &Record,
    window: &Window,
    quadrature: Quadrature,
    energy: Option<&StoredEnergy>,
    settings: &SteadyStateSettings,
    spans: &std::result::Result<Vec<Span>, String>,
    projections: &[&Result<StateProjection>],
) -> Result<WindowCheck> {
    let h = record.step();
    let input_work = input_work(record, window, quadrature)?;
    let check = WindowCheck {
        record: record.label().to_string(),
        record_index: window.record,
        window: window.index,
        start_time: record.start_time() + window.start as f64 * h,
        compared: ComparedPeriods::NotJudged,
        harmonics: Vec::new(),
        displacement_mismatch: 0.0,
        velocity_mismatch: 0.0,
        non_harmonic: 0.0,
        input_work,
        energy_change: None,
        energy_mismatch: None,
        decisive: None,
        steady: true,
        reason: String::new(),
    };
    let spans = match spans {
        Ok(spans) => spans,
        Err(reason) => return Ok(unjudged(check, reason.clone())),
    };
    // A period is steady when it matches one of its neighbours: the better comparison
    // decides.
    let mut best: Option<WindowCheck> = None;
    for (&(origin, periods, compared), projection) in spans.iter().zip(projections) {
        let projection = match projection {
            Ok(p) => p,
            Err(e @ Error::InvalidParameter { .. }) => {
                return Ok(unjudged(check, format!("cannot be judged: {e}")));
            }
            Err(e) => return Err(e.clone()),
        };
        let judged = judge(
            check.clone(),
            projection,
            origin,
            periods,
            window.cycles,
            compared,
            energy,
            settings,
        );
        if best
            .as_ref()
            .is_none_or(|b| excess(&judged, settings) < excess(b, settings))
        {
            best = Some(judged);
        }
    }
    // cannot fail: compared_spans returns Err rather than an empty list, and every span
    // sets `best` or returns.
    Ok(best.expect("at least one span"))
}

/// How far a judged window is beyond its thresholds (≤ 1: steady).
pub(super) fn excess(w: &WindowCheck, settings: &SteadyStateSettings) -> f64 {
    w.decisive
        .as_ref()
        .map_or(0.0, |c| c.mismatch / c.threshold)
        .max(w.non_harmonic / settings.max_state_mismatch)
}

/// The states x̂, v̂ of every channel of period `index` at the sample position `at`, and
/// the row b(t) they were evaluated with.
fn state(p: &StateProjection, index: usize, at: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let period = &p.periods[index];
    let row = p.row_at_sample(period.first, at);
    let dot = |c: &[f64]| few::dot(&row, c);
    let x = period.channels.displacements().map(dot).collect();
    let v = period.channels.velocities().map(dot).collect();
    (x, v, row)
}

/// One quantity of one channel compared: δ, its noise sd and the amplitude it is
/// relative to.
struct Component {
    quantity: &'static str,
    dof: usize,
    delta: f64,
    sd: f64,
    amplitude: f64,
}

/// Formats a noise-relative mismatch.
pub(super) fn sigmas_text(sigmas: f64) -> String {
    if sigmas.is_finite() && sigmas < 1e4 {
        format!("{sigmas:.1} σ of the noise")
    } else {
        "far beyond the noise (the records carry no measurable noise)".into()
    }
}

/// |a| / s, ∞ for s = 0 and a ≠ 0.
fn ratio(a: f64, s: f64) -> f64 {
    if a == 0.0 {
        0.0
    } else if s == 0.0 {
        f64::INFINITY
    } else {
        a.abs() / s
    }
}

#[allow(clippy::too_many_arguments)]
fn judge(
    mut check: WindowCheck,
    p: &StateProjection,
    origin: f64,
    periods: usize,
    cycles: usize,
    compared: ComparedPeriods,
    energy: Option<&StoredEnergy>,
    settings: &SteadyStateSettings,
) -> WindowCheck {
    let z = settings.noise_sigmas;
    let length = 2.0 * std::f64::consts::PI / (p.omega * p.step);
    // the start of the first period and the end of the last, scaled to the window
    let scale = cycles as f64 / (periods - 1) as f64;
    let (x_a, v_a, row_a) = state(p, 0, origin);
    let (x_b, v_b, row_b) = state(p, 1, origin + periods as f64 * length);
    let (amp_x, amp_v) = p.amplitudes();
    let zero = vec![0.0; row_a.len()];
    let excess = |delta: f64, sd: f64, amplitude: f64| {
        ratio(delta, (settings.max_state_mismatch * amplitude).max(z * sd))
    };
    // one pass over the channels: the largest relative mismatch of each quantity, and
    // the component of the largest excess over its threshold (the last of equals, in
    // the order displacement then velocity of DOF 1, 2, …)
    let (mut displacement_mismatch, mut velocity_mismatch) = (0.0f64, 0.0f64);
    let mut worst: Option<(Component, f64)> = None;
    // bᵀ U b of each end, once per unit covariance U (shared by a sensor kind's channels)
    let mut unit: Option<(&Mat<f64>, &Mat<f64>, [f64; 4])> = None;
    let (ends_a, ends_b) = (&p.periods[0].channels, &p.periods[1].channels);
    let worse = |e: f64, worst: &Option<(Component, f64)>| {
        worst
            .as_ref()
            .is_none_or(|(_, w)| e.total_cmp(w) != std::cmp::Ordering::Less)
    };
    let units = ends_a
        .unit_covariances()
        .iter()
        .zip(ends_b.unit_covariances());
    let noises = ends_a
        .noise_variances()
        .iter()
        .zip(ends_b.noise_variances());
    let ends = x_a.iter().zip(&x_b).zip(v_a.iter().zip(&v_b));
    for (j, ((units, noises), ((x_a, x_b), (v_a, v_b)))) in units.zip(noises).zip(ends).enumerate()
    {
        let (unit_a, unit_b): (&Mat<f64>, &Mat<f64>) = (units.0, units.1);
        let u = match unit {
            Some((ua, ub, u)) if std::ptr::eq(ua, unit_a) && std::ptr::eq(ub, unit_b) => u,
            _ => {
                let (a, b) = (ends_a.channel(j), ends_b.channel(j));
                let u = [
                    a.unit_variance(&row_a, &zero),
                    b.unit_variance(&row_b, &zero),
                    a.unit_variance(&zero, &row_a),
                    b.unit_variance(&zero, &row_b),
                ];
                unit = Some((unit_a, unit_b, u));
                u
            }
        };
        // σ̂_j² times each unit variance, at least 0 (`ChannelProjection::scaled`)
        let (noise_a, noise_b) = (*noises.0, *noises.1);
        let scaled = |noise: f64, unit: f64| (noise * unit).max(0.0);
        let sd_x = scale * (scaled(noise_a, u[0]) + scaled(noise_b, u[1])).sqrt();
        let sd_v = scale * (scaled(noise_a, u[2]) + scaled(noise_b, u[3])).sqrt();
        let (delta_x, delta_v) = (scale * (x_b - x_a), scale * (v_b - v_a));
        displacement_mismatch = displacement_mismatch.max(ratio(delta_x, amp_x));
        velocity_mismatch = velocity_mismatch.max(ratio(delta_v, amp_v));
        for (quantity, delta, sd, amplitude) in [
            ("displacement", delta_x, sd_x, amp_x),
            ("velocity", delta_v, sd_v, amp_v),
        ] {
            let e = excess(delta, sd, amplitude);
            if worse(e, &worst) {
                let component = Component {
                    quantity,
                    dof: j,
                    delta,
                    sd,
                    amplitude,
                };
                worst = Some((component, e));
            }
        }
    }
    check.displacement_mismatch = displacement_mismatch;
    check.velocity_mismatch = velocity_mismatch;
    check.compared = compared;
    check.harmonics = p.orders.clone();
    // Non-harmonic content: significant and above the state tolerance.
    let significant = 1.0 + z * (2.0 / p.residual_dof as f64).sqrt() + NON_HARMONIC_MARGIN;
    let (mut worst_non_harmonic, mut non_harmonic_dof) = (0.0f64, 0);
    for (j, (r, ratio_j)) in p.non_harmonic.iter().zip(&p.residual_ratio).enumerate() {
        let share = ratio(*r, amp_x);
        if *ratio_j > significant && share > worst_non_harmonic {
            (worst_non_harmonic, non_harmonic_dof) = (share, j);
        }
    }
    check.non_harmonic = worst_non_harmonic;

    let decisive = if let Some(e) = energy {
        let change = scale * (e.energy(&x_b, &v_b) - e.energy(&x_a, &v_a));
        let (gx_a, gv_a) = e.gradient(&x_a, &v_a);
        let (gx_b, gv_b) = e.gradient(&x_b, &v_b);
        let times = |g: &[f64], s: f64| g.iter().map(|a| a * s).collect::<Vec<f64>>();
        let variance: f64 = (0..x_a.len())
            .map(|j| {
                let (a, b) = (
                    p.periods[0].channels.channel(j),
                    p.periods[1].channels.channel(j),
                );
                a.variance(&times(&row_a, gx_a[j]), &times(&row_a, gv_a[j]))
                    + b.variance(&times(&row_b, gx_b[j]), &times(&row_b, gv_b[j]))
            })
            .sum();
        let sd = scale * variance.sqrt();
        let work = check.input_work.abs();
        let mismatch = ratio(change, work);
        check.energy_change = Some(change);
        check.energy_mismatch = Some(mismatch);
        let sd_relative = if work == 0.0 {
            f64::INFINITY
        } else {
            sd / work
        };
        Decisive {
            measure: "stored-energy mismatch |ΔE|/|W|".into(),
            mismatch,
            threshold: settings.max_energy_mismatch.max(z * sd_relative),
            sigmas: ratio(change, sd),
            what: "the stored energy at the end".into(),
            tolerance: settings.max_energy_mismatch,
            of: "of the input work",
        }
    } else {
        // cannot fail: two components per DOF, and Record::new refuses a record
        // without DOFs.
        let (worst, _) = worst.expect("at least one DOF");
        let Component {
            quantity,
            dof,
            delta,
            sd,
            amplitude,
        } = worst;
        Decisive {
            measure: format!("state mismatch ({quantity} of DOF {})", dof + 1),
            mismatch: ratio(delta, amplitude),
            threshold: settings.max_state_mismatch.max(ratio(z * sd, amplitude)),
            sigmas: ratio(delta, sd),
            what: format!("the {quantity} of DOF {} at the end", dof + 1),
            tolerance: settings.max_state_mismatch,
            of: "of its amplitude",
        }
    };
    let state_steady = decisive.mismatch <= decisive.threshold;
    let harmonic_steady = worst_non_harmonic <= settings.max_state_mismatch;
    check.steady = state_steady && harmonic_steady;
    let against = match compared {
        ComparedPeriods::FirstAndLastPeriod => "the start (first and last period projected)",
        ComparedPeriods::NextPeriod => "the start (this period and the next projected)",
        ComparedPeriods::PreviousPeriod => "the start (this period and the previous projected)",
        ComparedPeriods::NotJudged => "the start",
    };
    check.reason = if !state_steady {
        format!(
            "not steady: {} differs from {against} by {:.3}% {}, {} (limit {}% or {z} σ): skip more of the transient",
            decisive.what,
            100.0 * decisive.mismatch,
            decisive.of,
            sigmas_text(decisive.sigmas),
            100.0 * decisive.tolerance,
        )
    } else if !harmonic_steady {
        format!(
            "not steady: the displacement of DOF {} holds {:.2}% of the amplitude at frequencies that are not harmonics of the drive, {:.1} times the noise power (limit {}%): a transient, a drift or another excitation",
            non_harmonic_dof + 1,
            100.0 * worst_non_harmonic,
            p.residual_ratio[non_harmonic_dof],
            100.0 * settings.max_state_mismatch,
        )
    } else {
        format!(
            "steady: {} matches {against} within {:.3}% {}, {}",
            decisive.what,
            100.0 * decisive.mismatch,
            decisive.of,
            sigmas_text(decisive.sigmas),
        )
    };
    check.decisive = Some(decisive);
    check
}

/// W = Σ_i w_i v_iᵀ r_i with trapezoid weights over [t₀, t₀ + kT]; the window's own
/// weights when the record ends before the trapezoid's last sample, or the window
/// closes periodically. Velocities measured, else central differences (wrapped in a
/// window that closes periodically), of the loaded DOFs only when the load is on DOFs.
fn input_work(record: &Record, window: &Window, rule: Quadrature) -> Result<f64> {
    let (h, period) = (record.step(), record.period());
    let available = record.samples() - window.start;
    let trapezoid = Quadrature::Trapezoid.weights(window.span, h, period)?;
    let weights = if trapezoid.len() <= available && !window.closed {
        trapezoid
    } else {
        window.weights(rule, h, period)?
    };
    let count = weights.len().min(available);
    let source = if record.velocities().is_some() {
        VelocitySource::Measured
    } else {
        VelocitySource::CentralDifference
    };
    let forcing = record.forcing();
    let signals = &forcing.signals;
    let mut work = 0.0;
    match &forcing.distribution {
        LoadDistribution::Dofs(dofs) => {
            // the velocities of the loaded DOFs only (each channel's column in `v`)
            let mut loaded = dofs.clone();
            loaded.sort_unstable();
            loaded.dedup();
            let v = source.velocities_of_dofs(record, window, count, &loaded)?;
            let at: Vec<usize> = dofs
                .iter()
                .map(|dof| loaded.partition_point(|d| d < dof))
                .collect();
            // each force channel's samples over the window and its DOF's velocities
            let pairs: Vec<(&[f64], &[f64])> = at
                .iter()
                .enumerate()
                .map(|(c, &q)| {
                    let force = &col(signals.as_ref(), c)[window.start..window.start + count];
                    (force, &col(v.as_ref(), q)[..count])
                })
                .collect();
            for (k, w) in weights.iter().enumerate().take(count) {
                let power: f64 = pairs.iter().map(|(f, v)| f[k] * v[k]).sum();
                work += w * power;
            }
        }
        LoadDistribution::Matrix(d) => {
            let velocities = source.velocities_of(record, window, count)?;
            let v = velocities.as_ref();
            for (k, w) in weights.iter().enumerate().take(count) {
                let i = window.start + k;
                let power: f64 = (0..d.ncols())
                    .map(|c| {
                        let load: f64 = (0..d.nrows()).map(|j| d[(j, c)] * v[(k, j)]).sum();
                        signals[(i, c)] * load
                    })
                    .sum();
                work += w * power;
            }
        }
    }
    Ok(work)
}
