//! Equivalent viscous damping ratio and loss factor versus amplitude, for a one-DOF
//! (one-mode) stepped-sine identification.
//!
//! With the identified coefficients θ and the columns g(X) of the model at amplitude X
//! and the natural frequency ω_n (dissipated energy per cycle per unit coefficient,
//! [`crate::regressor::stepped_sine::columns_of`]), the energy dissipated per cycle is
//! E_d(X) = g(X)ᵀθ. A viscous damper c_eq dissipating the same energy has
//! π c_eq ω_n X² = E_d, so with modal mass m and stiffness k = m ω_n²
//!
//! ```text
//!   ζ_eq(X) = c_eq / (2 m ω_n) = E_d(X) / (2π k X²),      η(X) = E_d(X) / (π k X²) = 2 ζ_eq(X),
//! ```
//!
//! the loss factor being E_d over 2π times the peak stored energy ½kX². Both are linear
//! in θ; when law parameters η were estimated with θ (variable projection), g depends on
//! them too, and to first order about (θ̂, η̂)
//!
//! ```text
//!   δE_d = g(X; η̂)ᵀ δθ + θ̂ᵀ ∂g/∂η(X; η̂) δη = uᵀ (δθ, δη),
//!   u = [g(X; η̂),  (∂g/∂η_j)ᵀ θ̂ for each law parameter j,  0 for the other unknowns],
//!   Var E_d(X) = uᵀ Σ u,
//! ```
//!
//! with Σ the covariance of the report ([`crate::report::FitReport::covariance`]: the
//! joint covariance of (θ, η), σ²(JᵀJ)⁻¹, when parameters were estimated, else the
//! coefficients' own; the modal mass is taken as exact). ∂g/∂η_j by central differences
//! of the columns at η̂ ± h e_j, h = 10⁻⁵ of the parameter's bound interval (one-sided at
//! a bound), as the joint Jacobian is differenced. Unknowns that change the table but
//! not the law (a table's residual receptances, which correct the measured response)
//! do not enter g: their entries of u are 0, though their covariance with θ still
//! reaches E_d through g(X; η̂)ᵀδθ. Intervals are ± 1.96 standard deviations.
//!
//! **Modal mass and stiffness.** From `[system]` (1 × 1 mass and stiffness), or
//! estimated from the frequency response of the lowest level (the sweep with the
//! smallest median amplitude, the most nearly linear): with Z = X e^{−iφ} the response
//! per unit force of a one-DOF oscillator satisfies Re(a/Z) = k − m ω², fitted by
//! least squares over that sweep's points (viscous or hysteretic damping only changes
//! the imaginary part).

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::analysis::measured_levels::{LevelDamping, crossings};
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::harmonic::residual::correct;
use crate::prep::harmonic::sweeps::SweptTable;
use crate::prep::harmonic::{SteppedSinePoint, SteppedSineTable};
use crate::regressor::stepped_sine::columns_of;
use crate::regressor::{NonlinearParameter, ParametricRegressor, SteppedSineSource};

/// Amplitudes the curves are evaluated at.
const GRID: usize = 12;

/// Where the modal mass and stiffness came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "source")]
pub enum ModalSource {
    /// The model file's `[system]`.
    System,
    /// Re(a/Z) = k − mω² over the lowest sweep.
    LowestLevelFrf {
        /// The sweep's name.
        sweep: String,
        /// Its points.
        points: usize,
        /// Whether the points were the response less the estimated residual
        /// receptance.
        #[serde(default)]
        less_residual: bool,
    },
}

/// Modal mass and stiffness of the one mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Modal {
    /// m.
    pub mass: f64,
    /// k.
    pub stiffness: f64,
    /// ω_n = √(k/m).
    pub natural_frequency: f64,
    /// Where they came from.
    pub source: ModalSource,
}

impl Modal {
    /// Given m and k (both finite and positive).
    pub fn given(mass: f64, stiffness: f64) -> Result<Self> {
        for (name, v) in [("modal mass", mass), ("modal stiffness", stiffness)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(name, v, "must be finite and positive"));
            }
        }
        Ok(Modal {
            mass,
            stiffness,
            natural_frequency: (stiffness / mass).sqrt(),
            source: ModalSource::System,
        })
    }

    /// Estimated from the lowest sweep of a one-DOF table (module doc).
    pub fn from_lowest_level(swept: &SweptTable) -> Result<Self> {
        require_one_dof(swept)?;
        let points = swept.table.points();
        let median = |s: usize| {
            let mut x: Vec<f64> = swept
                .members(s)
                .iter()
                .map(|&i| points[i].amplitudes[0])
                .collect();
            x.sort_by(f64::total_cmp);
            x[x.len() / 2]
        };
        let lowest = (0..swept.sweep_names.len())
            .min_by(|&a, &b| median(a).total_cmp(&median(b)))
            .unwrap_or(0);
        let members = swept.members(lowest);
        // Normal equations of [1, −ω²] (k, m) = (a/X) cos φ, two unknowns.
        let (mut s11, mut s12, mut s22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &i in &members {
            let p = &points[i];
            let w2 = p.frequency * p.frequency;
            let y = p.force_amplitude / p.amplitudes[0] * p.phases[0].cos();
            s11 += 1.0;
            s12 -= w2;
            s22 += w2 * w2;
            r1 += y;
            r2 -= w2 * y;
        }
        let det = s11 * s22 - s12 * s12;
        let name = &swept.sweep_names[lowest];
        if det.is_nan() || det.abs() <= 1e-12 * s22 * s11 {
            return Err(Error::choice(
                "modal mass",
                format!("the frequency response of sweep '{name}'"),
                "its points do not span two frequencies; give the mass and stiffness in [system]",
            ));
        }
        let stiffness = (s22 * r1 - s12 * r2) / det;
        let mass = (s11 * r2 - s12 * r1) / det;
        if !(mass > 0.0 && stiffness > 0.0) {
            return Err(Error::choice(
                "modal mass",
                format!("m = {mass:e}, k = {stiffness:e} from sweep '{name}'"),
                "the lowest level's frequency response does not look like one mode; give the mass and stiffness in [system]",
            ));
        }
        Ok(Modal {
            mass,
            stiffness,
            natural_frequency: (stiffness / mass).sqrt(),
            source: ModalSource::LowestLevelFrf {
                sweep: name.clone(),
                points: members.len(),
                less_residual: false,
            },
        })
    }
}

fn require_one_dof(swept: &SweptTable) -> Result<()> {
    if swept.table.dofs() != 1 {
        return Err(Error::mismatch(
            "DOFs of a stepped-sine table for an equivalent damping ratio (one mode)",
            1,
            swept.table.dofs(),
        ));
    }
    Ok(())
}

/// ζ_eq and η at one amplitude.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EquivalentPoint {
    /// Response amplitude X.
    pub amplitude: f64,
    /// Dissipated energy per cycle E_d(X) at ω_n.
    pub dissipated_energy: f64,
    /// Each coefficient's share θ_k g_k(X) of it, in coefficient order.
    pub terms: Vec<f64>,
    /// ζ_eq(X).
    pub damping_ratio: f64,
    /// Its standard deviation (None without standard errors).
    pub damping_ratio_std: Option<f64>,
    /// η(X) = 2 ζ_eq(X).
    pub loss_factor: f64,
    /// Its standard deviation.
    pub loss_factor_std: Option<f64>,
}

/// Equivalent damping over the measured amplitude range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EquivalentDamping {
    /// The modal mass and stiffness used.
    pub modal: Modal,
    /// From the smallest to the largest measured amplitude, log-spaced.
    pub points: Vec<EquivalentPoint>,
    /// At each sweep's measured level (its resonance crossing): the fitted ζ_eq beside
    /// the table's own phase-slope estimate ([`crate::analysis::measured_levels`]).
    #[serde(default)]
    pub levels: Vec<LevelDamping>,
}

/// ζ_eq(X) and η(X) of a one-DOF stepped-sine `problem` at the estimate `values` (every
/// nonlinear parameter, in the problem's order; empty for a linear problem) with the
/// fitted `coefficients` (in column order) over the table's amplitude range, the modal
/// mass and stiffness from the table's `[system]` or its lowest level (module doc);
/// with `covariance` ((p + q) × (p + q) when parameters were estimated, else p × p),
/// intervals too. `None` when the problem is not a one-DOF table.
pub fn equivalent_damping(
    problem: &ParametricRegressor<'_>,
    values: &[f64],
    coefficients: &[f64],
    covariance: Option<&[Vec<f64>]>,
) -> Option<Result<EquivalentDamping>> {
    let table = problem.source().stepped_sine()?;
    if table.table.table.dofs() != 1 {
        return None;
    }
    Some((|| {
        let law = problem.law();
        let q_law = law.parameters().len();
        if values.len() < q_law {
            return Err(Error::mismatch(
                "estimated values vs the law's parameters",
                q_law,
                values.len(),
            ));
        }
        // The measured response less the residual receptance at the estimate.
        let corrected = corrected(table, &values[q_law..])?;
        let mut modal = match table.system {
            Some(system) => Modal::given(system.mass, system.stiffness),
            None => Modal::from_lowest_level(&corrected),
        }?;
        if let ModalSource::LowestLevelFrf { less_residual, .. } = &mut modal.source {
            *less_residual = values.len() > q_law;
        }
        of_table(
            &|eta| law.at(eta),
            &values[..q_law],
            law.parameters(),
            table,
            &corrected,
            coefficients,
            covariance,
            modal,
        )
    })())
}

/// The points of `table` less their residual receptance at the unknowns `residual`
/// (the table as measured when it estimates none).
fn corrected(table: &SteppedSineSource, residual: &[f64]) -> Result<SweptTable> {
    let Some(r) = table.per_point(residual)? else {
        return Ok(table.table.clone());
    };
    let points = table
        .table
        .table
        .points()
        .iter()
        .zip(&r)
        .map(|(p, &r)| correct(p, r))
        .collect::<Result<Vec<_>>>()?;
    Ok(SweptTable {
        table: SteppedSineTable::new(points)?,
        ..table.table.clone()
    })
}

/// [`equivalent_damping`] of the model `law(η)` at the law parameters `eta` (bounds in
/// `specs`, for the difference step) on `table`, whose points less their residual are
/// `swept`.
#[allow(clippy::too_many_arguments)]
fn of_table(
    law: &(dyn Fn(&[f64]) -> Result<DampingModel> + Sync),
    eta: &[f64],
    specs: &[NonlinearParameter],
    table: &SteppedSineSource,
    swept: &SweptTable,
    coefficients: &[f64],
    covariance: Option<&[Vec<f64>]>,
    modal: Modal,
) -> Result<EquivalentDamping> {
    let (structural, approximation) = (&table.structural, &table.approximation);
    let p = coefficients.len();
    let q_law = eta.len();
    if let Some(c) = covariance
        && (c.len() < p + q_law || c.iter().any(|row| row.len() != c.len()))
    {
        return Err(Error::mismatch(
            "covariance rows vs coefficients and law parameters",
            p + q_law,
            c.len(),
        ));
    }
    // The grid over the measured amplitudes, then each sweep's crossing amplitude.
    let (mut grid, mut synthetic) = amplitude_grid(swept, &modal)?;
    let crossings = crossings(swept);
    grid.extend(crossings.iter().map(|c| c.amplitude));
    synthetic.extend(crossings.iter().map(|c| at_amplitude(c.amplitude, &modal)));
    let columns = columns_of(&law(eta)?, structural, approximation, &synthetic)?;
    if columns.first().is_some_and(|g| g.len() != p) {
        return Err(Error::mismatch(
            "columns of the model vs coefficients",
            p,
            columns[0].len(),
        ));
    }
    // (∂g/∂η_j)ᵀ θ̂ at each grid amplitude, per law parameter j.
    let mut sensitivities: Vec<Vec<f64>> = Vec::with_capacity(q_law);
    if covariance.is_some() {
        for (j, spec) in specs.iter().enumerate() {
            let h = 1e-5 * (spec.upper - spec.lower);
            let (lo, hi) = ((eta[j] - h).max(spec.lower), (eta[j] + h).min(spec.upper));
            let energies = |t: f64| -> Result<Vec<f64>> {
                let mut at = eta.to_vec();
                at[j] = t;
                let g = columns_of(&law(&at)?, structural, approximation, &synthetic)?;
                Ok(g.iter()
                    .map(|g| g.iter().zip(coefficients).map(|(g, t)| g * t).sum())
                    .collect())
            };
            let (e_lo, e_hi) = (energies(lo)?, energies(hi)?);
            sensitivities.push(
                e_lo.iter()
                    .zip(&e_hi)
                    .map(|(l, h)| (h - l) / (hi - lo))
                    .collect(),
            );
        }
    }
    let mut points = grid
        .iter()
        .zip(&columns)
        .enumerate()
        .map(|(i, (&x, g))| {
            let std = covariance.map(|c| {
                let mut u = vec![0.0; c.len()];
                u[..p].copy_from_slice(g);
                for (j, s) in sensitivities.iter().enumerate() {
                    u[p + j] = s[i];
                }
                quadratic_form(&u, c).max(0.0).sqrt()
            });
            point(x, g, coefficients, std, &modal)
        })
        .collect::<Vec<_>>();
    let levels = crossings
        .iter()
        .zip(points.split_off(GRID))
        .map(|(c, at)| LevelDamping {
            sweep: swept.sweep_names[c.sweep].clone(),
            frequency: c.frequency,
            amplitude: c.amplitude,
            fitted: at.damping_ratio,
            fitted_std: at.damping_ratio_std,
            measured: c.slope_damping,
            ratio: c.slope_damping.map(|m| at.damping_ratio / m),
        })
        .collect();
    Ok(EquivalentDamping {
        modal,
        points,
        levels,
    })
}

/// The [`GRID`] amplitudes, log-spaced from the smallest to the largest measured one
/// of the one-DOF `swept`, and a synthetic point at each (unit force at ω_n, phase
/// lag π/2), whose columns are g(X).
fn amplitude_grid(swept: &SweptTable, modal: &Modal) -> Result<(Vec<f64>, Vec<SteppedSinePoint>)> {
    require_one_dof(swept)?;
    let points = swept.table.points();
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
        (lo.min(p.amplitudes[0]), hi.max(p.amplitudes[0]))
    });
    let grid: Vec<f64> = (0..GRID)
        .map(|i| lo * (hi / lo).powf(i as f64 / (GRID - 1) as f64))
        .collect();
    let synthetic = grid.iter().map(|&x| at_amplitude(x, modal)).collect();
    Ok((grid, synthetic))
}

/// A synthetic point at amplitude `x` (unit force at ω_n, phase lag π/2), whose columns
/// are g(X).
fn at_amplitude(x: f64, modal: &Modal) -> SteppedSinePoint {
    SteppedSinePoint {
        label: format!("X = {x:e}"),
        frequency: modal.natural_frequency,
        force_dof: 0,
        force_amplitude: 1.0,
        amplitudes: vec![x],
        phases: vec![std::f64::consts::FRAC_PI_2],
    }
}

/// uᵀ C u.
fn quadratic_form(u: &[f64], c: &[Vec<f64>]) -> f64 {
    let mut v = 0.0;
    for (i, ui) in u.iter().enumerate() {
        for (j, uj) in u.iter().enumerate() {
            v += ui * c[i][j] * uj;
        }
    }
    v
}

/// The point at amplitude `x` with columns `g`, coefficients `theta` and the standard
/// deviation `std` of E_d(X).
fn point(x: f64, g: &[f64], theta: &[f64], std: Option<f64>, modal: &Modal) -> EquivalentPoint {
    let energy: f64 = g.iter().zip(theta).map(|(g, t)| g * t).sum();
    let factor = 2.0 * std::f64::consts::PI * modal.stiffness * x * x;
    EquivalentPoint {
        amplitude: x,
        dissipated_energy: energy,
        terms: g.iter().zip(theta).map(|(g, t)| g * t).collect(),
        damping_ratio: energy / factor,
        damping_ratio_std: std.map(|s| s / factor),
        loss_factor: 2.0 * energy / factor,
        loss_factor_std: std.map(|s| 2.0 * s / factor),
    }
}

impl fmt::Display for ModalSource {
    /// Where the modal mass and stiffness came from, as the report says it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModalSource::System => write!(f, "from [system]"),
            ModalSource::LowestLevelFrf {
                sweep,
                points,
                less_residual,
            } => write!(
                f,
                "estimated from the frequency response of the lowest level ({sweep}, {points} points{})",
                if *less_residual {
                    ", less the estimated residual receptance"
                } else {
                    ""
                }
            ),
        }
    }
}

impl fmt::Display for EquivalentDamping {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = &self.modal;
        let source = m.source.to_string();
        writeln!(
            f,
            "equivalent damping at ω_n = {:.6e} (modal mass {:.6e}, stiffness {:.6e}, {source}):",
            m.natural_frequency, m.mass, m.stiffness
        )?;
        writeln!(
            f,
            "  {:>12}  {:>12}  {:>26}  {:>26}",
            "amplitude", "E_d/cycle", "ζ_eq (95%)", "η (95%)"
        )?;
        for p in &self.points {
            let band = |v: f64, s: Option<f64>| match s {
                Some(s) => format!("{v:.4e} ± {:.2e}", 1.96 * s),
                None => format!("{v:.4e}"),
            };
            writeln!(
                f,
                "  {:>12.4e}  {:>12.4e}  {:>26}  {:>26}",
                p.amplitude,
                p.dissipated_energy,
                band(p.damping_ratio, p.damping_ratio_std),
                band(p.loss_factor, p.loss_factor_std)
            )?;
        }
        if !self.levels.is_empty() {
            writeln!(
                f,
                "at the measured levels (where each sweep's phase lag crosses π/2; measured: the phase slope at the crossing):"
            )?;
            writeln!(
                f,
                "  {:<24} {:>12} {:>12}  {:>26}  {:>12} {:>8}",
                "sweep", "f_c (Hz)", "X_c", "ζ_eq fitted (95%)", "ζ measured", "ratio"
            )?;
            for l in &self.levels {
                let fitted = match l.fitted_std {
                    Some(s) => format!("{:.4e} ± {:.2e}", l.fitted, 1.96 * s),
                    None => format!("{:.4e}", l.fitted),
                };
                writeln!(
                    f,
                    "  {:<24} {:>12.6e} {:>12.4e}  {fitted:>26}  {:>12} {:>8}",
                    l.sweep,
                    l.frequency / (2.0 * std::f64::consts::PI),
                    l.amplitude,
                    l.measured.map_or("-".into(), |m| format!("{m:.4e}")),
                    l.ratio.map_or("-".into(), |r| format!("{r:.4}")),
                )?;
            }
        }
        Ok(())
    }
}
