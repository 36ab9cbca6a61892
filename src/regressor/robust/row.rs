//! One equation of the noise-robust pipeline: the window projected on its kept
//! harmonics, every term's column on (x̂, v̂) less its expected noise contribution, the
//! input work, and the first-order sensitivities of all of them to the noise of each
//! channel (formulas in the module doc of [`crate::regressor::robust`]).
//!
//! A window that closes periodically ([`Window::closed`]) reads its L = kT/h samples:
//! weights w_i = h, the projection fitted over exactly those L samples, and in the
//! derivative-free form the last Stieltjes interval ends on the closing sample, r_L = r_0
//! (so ∂b/∂r_0 gathers the gradient of both ends: the closing sample is the first).

use crate::terms::OnElements;
use faer::Mat;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::fourier::RecordNoise;
use crate::prep::quadrature::Quadrature;
use crate::prep::window::Window;
use crate::record::{LoadDistribution, Record, Sensor};
use crate::regressor::derivative_free::{Path, stieltjes};
use crate::regressor::robust::WindowNoise;
use crate::regressor::robust::gradients::Gradients;
use crate::regressor::robust::projected::{ProjectedWindow, signed_ends};
use crate::regressor::robust::sensitivity::RowNoise;
use crate::regressor::robust::{quadratic, structural};
use crate::regressor::settings::WorkForm;
use crate::terms::{ElementTerm, MatrixTerm, Term};

/// A row of the noise-robust pipeline.
pub(super) struct RobustRow {
    pub(crate) columns: Vec<f64>,
    pub(crate) input: f64,
    pub(crate) noise: RowNoise,
    pub(crate) window: WindowNoise,
}

/// Σ over the path's intervals of a_j (row(t_{j+1}) − row(t_j)), the gradient in the
/// projection coefficients of Σ_j a_j Δx̂_j.
fn path_gradient(path: Path, projected: &ProjectedWindow, a: impl Fn(usize) -> f64) -> Vec<f64> {
    let p = projected.columns();
    let design = &projected.design;
    let mut u = vec![0.0; p];
    for j in 0..path.whole {
        let aj = a(j);
        if aj != 0.0 {
            for (k, uk) in u.iter_mut().enumerate() {
                *uk += aj * (design[(j + 1, k)] - design[(j, k)]);
            }
        }
    }
    if path.frac > 0.0 {
        let aj = a(path.whole);
        for (k, uk) in u.iter_mut().enumerate() {
            *uk += aj * (projected.end_row[k] - design[(path.whole, k)]);
        }
    }
    u
}

/// The generalized forces r_j = Σ_k D_jk s_k over samples `start..start + rows`, for
/// the loaded DOFs j only (those some channel acts on), in increasing DOF order: a
/// record of 100 DOFs driven at one is one column here, not 100 (the zeros were most
/// of the robust rows' allocation).
fn generalized_forces(record: &Record, start: usize, rows: usize) -> Vec<(usize, Vec<f64>)> {
    let forcing = record.forcing();
    let channels = forcing.signals.ncols();
    let loaded: Vec<usize> = match &forcing.distribution {
        LoadDistribution::Dofs(dofs) => {
            let mut dofs = dofs[..channels].to_vec();
            dofs.sort_unstable();
            dofs.dedup();
            dofs
        }
        LoadDistribution::Matrix(d) => (0..d.nrows())
            .filter(|&dof| (0..channels).any(|k| d[(dof, k)] != 0.0))
            .collect(),
    };
    let mut r: Vec<(usize, Vec<f64>)> = loaded.iter().map(|&dof| (dof, vec![0.0; rows])).collect();
    let slot = |dof: usize| loaded.binary_search(&dof).ok();
    for k in 0..channels {
        let s = &forcing.signals.col_as_slice(k)[start..start + rows];
        match &forcing.distribution {
            LoadDistribution::Dofs(dofs) => {
                if let Some(at) = slot(dofs[k]) {
                    for (t, s) in r[at].1.iter_mut().zip(s) {
                        *t += s;
                    }
                }
            }
            LoadDistribution::Matrix(d) => {
                for (dof, target) in r.iter_mut() {
                    let weight = d[(*dof, k)];
                    if weight != 0.0 {
                        for (t, s) in target.iter_mut().zip(s) {
                            *t += weight * s;
                        }
                    }
                }
            }
        }
    }
    r
}

/// The equation of window `w` of `record`, whose harmonics and noise are `noise`'s
/// (`prep/fourier/record_noise.rs`).
pub(super) fn robust_row(
    model: &DampingModel,
    record: &Record,
    w: &Window,
    quadrature: Quadrature,
    harmonics: Option<usize>,
    work_form: WorkForm,
    noise: &RecordNoise,
) -> Result<RobustRow> {
    let weights = w.weights(quadrature, record.step(), record.period())?;
    let count = weights.len();
    let path = Path::of_window(w, record.step());
    let rows = count.max(path.samples());
    let projected = ProjectedWindow::new(record, w.start, count, rows, w.span, harmonics, noise)?;
    let sigma = projected.noise_std.clone();
    let force_sigma = noise.force_std.clone();
    let forces = generalized_forces(record, w.start, rows);
    let derivative_free = work_form == WorkForm::DerivativeFree;
    let mut gradients = Gradients::new(projected.columns(), count);

    // Input work and its force-noise variance.
    let mut input = 0.0;
    // ∂b/∂r_{j,i}: per loaded DOF j (as in `forces`), per sample i
    let mut force_gradient: Vec<(usize, Vec<f64>)> = Vec::with_capacity(forces.len());
    for (j, r) in &forces {
        let (j, r) = (*j, r.as_slice());
        if r.iter().all(|v| *v == 0.0) {
            continue;
        }
        let x = projected.x(j);
        let v = projected.v(j);
        let mut g = vec![0.0; rows];
        if derivative_free {
            let x_end = projected.end_value(j);
            input += stieltjes(path, r, path.end(r), x, x_end);
            let mean = |i: usize| {
                if i < path.whole {
                    0.5 * (r[i] + r[i + 1])
                } else {
                    0.5 * (r[i] + path.end(r))
                }
            };
            let u = path_gradient(path, &projected, mean);
            gradients.add(j, 0, &u, 1.0);
            for i in 0..path.whole {
                let dx = 0.5 * (x[i + 1] - x[i]);
                g[i] += dx;
                g[i + 1] += dx;
            }
            if path.closed {
                // The end point is the window's first sample: r_E = r_0.
                let f = path.whole;
                let dx = 0.5 * (x_end - x[f]);
                g[f] += dx;
                g[0] += dx;
            } else if path.frac > 0.0 {
                let f = path.whole;
                let dx = 0.5 * (x_end - x[f]);
                g[f] += dx + dx * (1.0 - path.frac);
                g[f + 1] += dx * path.frac;
            }
        } else {
            let g_rows: Vec<f64> = (0..count).map(|i| weights[i] * r[i]).collect();
            input += g_rows.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
            gradients.add_on_derivative(j, 0, &g_rows, 1.0);
            for i in 0..count {
                g[i] = weights[i] * v[i];
            }
        }
        force_gradient.push((j, g));
    }
    let force_std = force_channel_std(record, &force_gradient, &force_sigma);

    // Columns.
    let mut columns = vec![0.0; model.coefficient_count()];
    for (term, range) in model.term_columns() {
        match term {
            Term::Matrix(t) => matrix_column(
                t,
                &projected,
                &weights,
                &sigma,
                range.start,
                &mut columns,
                &mut gradients,
            ),
            Term::Structural(t) => structural::add_columns(
                t,
                &projected,
                &weights,
                &sigma,
                range.start,
                &mut columns,
                &mut gradients,
            ),
            // refused before the robust rows are built (Regressor::build)
            Term::History(_) => {}
            Term::Elements(t) if quadratic::applies(t) => quadratic::add_columns(
                t,
                &projected,
                &weights,
                &sigma,
                range.start,
                &mut columns,
                &mut gradients,
            ),
            Term::Elements(t) => element_columns(
                t,
                &projected,
                &weights,
                w.span,
                &sigma,
                range.start,
                &mut columns,
                &mut gradients,
            ),
        }
    }
    if let Some((k, value)) = columns.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Error::NonFinite {
            what: format!("bias-corrected column '{}'", model.coefficient_names()[k]),
            row: w.index,
            column: k,
            value: *value,
        });
    }
    let channels = gradients.whiten(&projected, &sigma);
    Ok(RobustRow {
        columns,
        input,
        noise: RowNoise::new(&channels, force_std),
        window: WindowNoise {
            record: record.label().to_string(),
            window: w.index,
            harmonics: projected.kept.clone(),
            displacement_noise: sigma,
            sensors: if projected.sensors.iter().all(|s| *s == Sensor::Displacement) {
                Vec::new()
            } else {
                projected.sensors.clone()
            },
            force_noise: force_sigma,
        },
    })
}

/// √(Σ_k σ_{f,k}² Σ_i (Σ_j D_jk ∂b/∂r_{j,i})²), over the DOFs j of `force_gradient`
/// (the others' gradient is zero): the standard deviation of the input work from the
/// force channels' noise, formed without squaring data-sized numbers
/// ([`super::sensitivity::norm`]).
fn force_channel_std(record: &Record, force_gradient: &[(usize, Vec<f64>)], sigma: &[f64]) -> f64 {
    let forcing = record.forcing();
    let mut terms = Vec::new();
    for (k, s) in sigma.iter().enumerate() {
        if *s == 0.0 {
            continue;
        }
        match &forcing.distribution {
            LoadDistribution::Dofs(dofs) => {
                if let Some((_, g)) = force_gradient.iter().find(|(j, _)| *j == dofs[k]) {
                    terms.extend(g.iter().map(|g| s * g));
                }
            }
            LoadDistribution::Matrix(d) => {
                let rows = force_gradient.first().map_or(0, |(_, g)| g.len());
                terms.extend((0..rows).map(|i| {
                    let g: f64 = force_gradient.iter().map(|(j, g)| d[(*j, k)] * g[i]).sum();
                    s * g
                }));
            }
        }
    }
    super::sensitivity::norm(&terms)
}

/// Whether some value of `g` is not zero (NaN counts as not zero), eight at a time: a
/// law whose force does not depend on x leaves its x-slopes all zero, and a scan that
/// stops at the first nonzero value cannot be vectorised.
fn any_nonzero(g: &[f64]) -> bool {
    let chunks = g.chunks_exact(8);
    let tail = chunks.remainder().iter().any(|g| *g != 0.0);
    tail || chunks
        .into_iter()
        .any(|c| c.iter().fold(false, |any, g| any | (*g != 0.0)))
}

/// A matrix term: Σ_i w_i v̂_iᵀ C₀ v̂_i − Σ_i w_i Var(v̂_i) Σ_j C₀,jj σ_j².
fn matrix_column(
    term: &MatrixTerm,
    projected: &ProjectedWindow,
    weights: &[f64],
    sigma: &[f64],
    column: usize,
    columns: &mut [f64],
    gradients: &mut Gradients,
) {
    let c0 = term.matrix();
    let n = c0.nrows();
    let count = weights.len();
    // (C₀ + C₀ᵀ) v̂_i, per sample, column-major (count × n)
    let mut cv = Mat::<f64>::zeros(count, n);
    let mut value = 0.0;
    for a in 0..n {
        for b in 0..n {
            let c = c0[(a, b)];
            if c == 0.0 {
                continue;
            }
            let (va, vb) = (projected.v(a), projected.v(b));
            for i in 0..count {
                value += weights[i] * c * va[i] * vb[i];
            }
            for i in 0..count {
                cv[(i, a)] += c * vb[i];
                cv[(i, b)] += c * va[i];
            }
        }
    }
    // Σ over sensor kinds of (Σ_i w_i Var v̂_i per unit variance) Σ_{j of that kind} C₀,jj σ_j²
    let mut bias = 0.0;
    let mut kinds = projected.sensors.clone();
    kinds.dedup();
    kinds.sort_unstable_by_key(|k| k.order());
    kinds.dedup();
    for kind in kinds {
        let of_kind: Vec<usize> = (0..n).filter(|&j| projected.sensors[j] == kind).collect();
        let diagonal_noise: f64 = of_kind
            .iter()
            .map(|&j| c0[(j, j)] * sigma[j] * sigma[j])
            .sum();
        let var_v = projected.var_v(of_kind[0]);
        bias += (0..count).map(|i| weights[i] * var_v[i]).sum::<f64>() * diagonal_noise;
    }
    columns[column] = value - bias;
    for j in 0..n {
        let g: Vec<f64> = (0..count).map(|i| weights[i] * cv[(i, j)]).collect();
        if g.iter().any(|g| *g != 0.0) {
            gradients.add_on_derivative(j, column + 1, &g, 1.0);
        }
    }
}

/// A law on elements: per element Σ_i w_i [p(x̂, v̂) − E(noise contribution)] on
/// relative motion, or for Coulomb the exact total variation of the relative x̂.
#[allow(clippy::too_many_arguments)]
fn element_columns(
    term: &ElementTerm,
    projected: &ProjectedWindow,
    weights: &[f64],
    span: f64,
    sigma: &[f64],
    first: usize,
    columns: &mut [f64],
    gradients: &mut Gradients,
) {
    let law = term.law();
    let count = weights.len();
    let rows = projected.rows();
    // relative motion of two-ended elements (a grounded one reads its DOF's columns)
    let mut x_rel = vec![0.0; rows];
    let mut v_rel = vec![0.0; rows];
    // per-sample noise variances and weighted slopes, one set of buffers per term
    let (mut var_x, mut var_v) = (vec![0.0; count], vec![0.0; count]);
    let (mut g_x, mut g_v) = (vec![0.0; count], vec![0.0; count]);
    for (e, element) in term.elements().iter().enumerate() {
        let weight = term.weights().map_or(1.0, |w| w[e]);
        let column = first + term.coefficients().column_of(e);
        let (xa, va) = (projected.x(element.a), projected.v(element.a));
        let mut variance = sigma[element.a].powi(2);
        // the second end's noise, when its sensor differs (its own Var per unit variance)
        let mut other: Option<(f64, usize)> = None;
        let (xr, vr): (&[f64], &[f64]) = match element.b {
            None => (xa, va),
            Some(b) => {
                let (xb, vb) = (projected.x(b), projected.v(b));
                for i in 0..rows {
                    x_rel[i] = xa[i] - xb[i];
                    v_rel[i] = va[i] - vb[i];
                }
                if projected.sensors[b] == projected.sensors[element.a] {
                    variance += sigma[b].powi(2);
                } else {
                    other = Some((sigma[b].powi(2), b));
                }
                (&x_rel, &v_rel)
            }
        };
        if law.is_total_variation() {
            // ∫ |v̂| dt exactly: the total variation of the projected displacement
            let ends = signed_ends(element);
            let (tv, u) = projected.total_variation(&projected.combination(&ends), vr, span);
            columns[column] += weight * tv;
            gradients.add(element.a, column + 1, &u, weight);
            if let Some(b) = element.b {
                gradients.add(b, column + 1, &u, -weight);
            }
        } else {
            let (unit_x, unit_v) = (projected.var_x(element.a), projected.var_v(element.a));
            // per sample σ² Var-per-unit of each end (one loop per form, no branch inside)
            let (unit_x, unit_v) = (&unit_x[..count], &unit_v[..count]);
            for ((vx, vv), (ux, uv)) in var_x
                .iter_mut()
                .zip(var_v.iter_mut())
                .zip(unit_x.iter().zip(unit_v))
            {
                *vx = variance * ux;
                *vv = variance * uv;
            }
            if let Some((s2, b)) = other {
                let (ox, ov) = (&projected.var_x(b)[..count], &projected.var_v(b)[..count]);
                for ((vx, vv), (ox, ov)) in var_x
                    .iter_mut()
                    .zip(var_v.iter_mut())
                    .zip(ox.iter().zip(ov))
                {
                    *vx += s2 * ox;
                    *vv += s2 * ov;
                }
            }
            let value = law.robust_sums(
                &xr[..count],
                &vr[..count],
                &var_x,
                &var_v,
                weights,
                &mut g_x,
                &mut g_v,
            );
            columns[column] += weight * value;
            let moves_x = any_nonzero(&g_x);
            for (channel, sign) in signed_ends(element) {
                gradients.add_on_derivative(channel, column + 1, &g_v, sign * weight);
                if moves_x {
                    gradients.add_on_design(channel, column + 1, &g_x, sign * weight);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::prep::motion::{Integration, SensorParts, record_from_sensors};
    use crate::record::Forcing;
    use crate::terms::laws::Linear;
    use crate::terms::{Coefficients, Element};

    /// Viscous columns as quadratic forms in the coefficients (`quadratic.rs`) are the
    /// sample path's sums to round-off: the columns less their noise bias, and every
    /// whitened gradient. Two periods and the closing sample of 64 samples each, with
    /// noise, mixed sensors (a velocity sensor between two displacement ones, so that an
    /// element's ends have different unit variances), weighted elements to ground and
    /// between DOFs, and two elements sharing one coefficient.
    #[test]
    fn quadratic_columns_are_the_sample_sums() {
        let (n, periods, period) = (64, 2, 0.8);
        let step = period / n as f64;
        let rows = periods * n + 1;
        let omega = 2.0 * std::f64::consts::PI / period;
        let mut state = 12345u64;
        let mut noise = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2e-3
        };
        let mut motion = Mat::<f64>::zeros(rows, 3);
        for i in 0..rows {
            let t = i as f64 * step;
            for j in 0..3 {
                let phase = 0.7 * j as f64;
                let x = (omega * t + phase).cos() + 0.2 * (3.0 * omega * t - phase).sin();
                let v = -omega * (omega * t + phase).sin()
                    + 0.6 * omega * (3.0 * omega * t - phase).cos();
                motion[(i, j)] = if j == 1 { v } else { x } + noise();
            }
        }
        let force = Mat::from_fn(rows, 1, |i, _| (omega * i as f64 * step).sin());
        let record = record_from_sensors(SensorParts {
            label: "test".into(),
            step,
            start_time: 0.0,
            motion,
            sensors: vec![Sensor::Displacement, Sensor::Velocity, Sensor::Displacement],
            forcing: Forcing::on_dofs(force, vec![0]),
            period,
            integration: Integration::WholePeriods,
        })
        .expect("a valid record");
        let noise = RecordNoise::of(&record).expect("the record's noise");
        let span = periods as f64 * period;
        let projected = ProjectedWindow::new(&record, 0, rows, rows, span, None, &noise)
            .expect("a projected window");
        let weights: Vec<f64> = (0..rows)
            .map(|i| {
                if i == 0 || i == rows - 1 {
                    step / 2.0
                } else {
                    step
                }
            })
            .collect();
        let sigma = projected.noise_std.clone();
        assert!(sigma.iter().all(|s| *s > 0.0), "noise estimated: {sigma:?}");
        let elements = vec![
            Element::to_ground(0),
            Element::between(0, 1),
            Element::between(1, 2),
            Element::between(2, 0),
        ];
        let terms = [
            ElementTerm::new(
                Arc::new(Linear),
                elements.clone(),
                Coefficients::PerElement("c".into()),
            )
            .with_weights(vec![0.5, 1.5, 2.0, 0.25]),
            ElementTerm::new(Arc::new(Linear), elements, Coefficients::Shared("c".into())),
        ];
        for term in &terms {
            assert!(quadratic::applies(term));
            let width = term.coefficients().count(term.elements().len());
            let mut results = Vec::new();
            for by_coefficients in [false, true] {
                let mut columns = vec![0.0; width];
                let mut gradients = Gradients::new(projected.columns(), rows);
                if by_coefficients {
                    quadratic::add_columns(
                        term,
                        &projected,
                        &weights,
                        &sigma,
                        0,
                        &mut columns,
                        &mut gradients,
                    );
                } else {
                    element_columns(
                        term,
                        &projected,
                        &weights,
                        periods as f64 * period,
                        &sigma,
                        0,
                        &mut columns,
                        &mut gradients,
                    );
                }
                results.push((columns, gradients.whiten(&projected, &sigma)));
            }
            let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-12 * scale;
            let (samples, quadratic) = (&results[0], &results[1]);
            let scale = samples.0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in samples.0.iter().zip(&quadratic.0) {
                assert!(close(*a, *b, scale), "column {a} against {b}");
            }
            assert_eq!(samples.1.len(), quadratic.1.len());
            for (a, b) in samples.1.iter().zip(&quadratic.1) {
                assert_eq!(a.channel, b.channel);
                assert_eq!(a.columns.len(), b.columns.len());
                for ((ka, za), (kb, zb)) in a.columns.iter().zip(&b.columns) {
                    assert_eq!(ka, kb);
                    let scale = za.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for (x, y) in za.iter().zip(zb) {
                        assert!(
                            close(*x, *y, scale),
                            "channel {} column {ka}: {x} against {y}",
                            a.channel
                        );
                    }
                }
            }
        }
    }

    /// `any_nonzero` is `iter().any(|g| *g != 0.0)` at every length and position: −0 is
    /// zero, NaN and subnormals are not.
    #[test]
    fn any_nonzero_is_the_scalar_scan() {
        for n in 0..40 {
            let zeros = vec![0.0; n];
            assert!(!any_nonzero(&zeros));
            for at in 0..n {
                for value in [-0.0, f64::NAN, 5e-324, -1.0, f64::INFINITY] {
                    let mut g = zeros.clone();
                    g[at] = value;
                    assert_eq!(
                        any_nonzero(&g),
                        g.iter().any(|g| *g != 0.0),
                        "{n} {at} {value}"
                    );
                }
            }
        }
    }
}
