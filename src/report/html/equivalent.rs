//! The equivalent damping of a one-mode stepped-sine table
//! ([`crate::analysis::equivalent`]), on every page that has it, linear fits and fits
//! with estimated parameters alike:
//!
//! - **energy per cycle** against amplitude (log-log): each point's measured input work
//!   E_p = π a X sin φ (the regressor's right-hand side) at its amplitude X_p, coloured
//!   by sweep, and the fitted law's E_d(X) at ω_n, in all and per term;
//! - **ζ_eq(X)** on a log amplitude axis: the fitted ζ_eq(X) = E_d(X)/(2π k X²) with its
//!   ±1.96σ band, and each point's own ζ_p = E_p/(2π k X_p²) for the points within
//!   [`NEAR_RESONANCE`] of ω_n, coloured by sweep. The equivalence holds near resonance
//!   only: a viscous law dissipates E_p = π c ω_p X_p², so ζ_p = ζ ω_p/ω_n;
//! - the table of ζ_eq and the loss factor η = 2ζ_eq with their intervals (± 1.96
//!   standard deviations; with estimated parameters from the joint covariance).
//!
//! X_p is the amplitude of the point's force DOF, less the estimated residual
//! receptance r a of its sweep when the fit estimated one
//! ([`crate::prep::harmonic::residual::correct`]); k and ω_n are the modal stiffness and
//! natural frequency the equivalent damping used.

use std::f64::consts::PI;
use std::fmt::Write as _;

use super::plots::{self, Curve, ZetaCurve};
use super::{HtmlReport, escape};
use crate::analysis::equivalent::EquivalentDamping;
use crate::error::Result;
use crate::prep::harmonic::residual;

/// The measured ζ_p are shown for points with |ω_p/ω_n − 1| at most this.
pub(crate) const NEAR_RESONANCE: f64 = 0.02;

/// One table point as the plots read it.
#[derive(Debug, Clone, Copy)]
struct Measured {
    /// Amplitude X_p of the force DOF (less the residual receptance's response).
    amplitude: f64,
    /// Input work per cycle E_p = π a X sin φ.
    energy: f64,
    /// Frequency ω_p.
    frequency: f64,
}

impl HtmlReport<'_> {
    /// The energy per cycle, ζ_eq(X) and the equivalent-damping table, or why the
    /// equivalent damping was not computed; nothing for other problems.
    pub(super) fn equivalent_section(&self) -> Result<String> {
        let equivalent = match self.equivalent {
            None => return Ok(String::new()),
            Some(Err(reason)) => {
                return Ok(format!(
                    "\n<h2>Equivalent damping</h2>\n<p>Not computed: {}.</p>\n",
                    escape(reason)
                ));
            }
            Some(Ok(e)) => e,
        };
        let measured = self.measured_points();
        let mut out = self.energy_section(equivalent, &measured)?;
        out.push_str(&self.damping_ratio_section(equivalent, &measured)?);
        out.push_str(&self.equivalent_table(equivalent));
        Ok(out)
    }

    /// Each equation's table point (module doc), in row order (`None` where it cannot
    /// be read: the rows are not a table's, or a residual correction failed).
    fn measured_points(&self) -> Vec<Option<Measured>> {
        let rhs = self.regressor.rhs();
        let Some(table) = self.source.stepped_sine() else {
            return vec![None; rhs.len()];
        };
        let points = table.table.table.points();
        if points.len() != rhs.len() {
            return vec![None; rhs.len()];
        }
        // The estimated residual receptances are the last unknowns of the estimation.
        let residuals = match &self.report.estimation {
            Some(e) if !table.residual_parameters.is_empty() => {
                let values = e.values();
                let start = values.len().saturating_sub(table.residual_parameters.len());
                residual::per_point(table.residual, &values[start..], &table.table).ok()
            }
            _ => None,
        };
        points
            .iter()
            .zip(rhs)
            .enumerate()
            .map(|(i, (p, &energy))| {
                let r = residuals.as_ref().and_then(|r| r.get(i)).copied();
                let point = match r {
                    Some(r) => residual::correct(p, r).ok()?,
                    None => p.clone(),
                };
                Some(Measured {
                    amplitude: *point.amplitudes.get(point.force_dof)?,
                    energy,
                    frequency: p.frequency,
                })
            })
            .collect()
    }

    /// A note on the amplitudes when residual receptances were removed.
    fn corrected_note(&self) -> &'static str {
        let corrected = self.report.estimation.is_some()
            && self
                .source
                .stepped_sine()
                .is_some_and(|t| !t.residual_parameters.is_empty());
        if corrected {
            " Amplitudes less the estimated residual receptance's response r a."
        } else {
            ""
        }
    }

    /// Energy per cycle against amplitude, log-log.
    fn energy_section(
        &self,
        equivalent: &EquivalentDamping,
        measured: &[Option<Measured>],
    ) -> Result<String> {
        let mut curves = vec![Curve {
            name: "fitted law at ω_n".into(),
            points: equivalent
                .points
                .iter()
                .map(|p| (p.amplitude, p.dissipated_energy))
                .collect(),
            band: None,
            measured: None,
        }];
        for (k, c) in self.report.coefficients.iter().enumerate() {
            curves.push(Curve {
                name: format!("{} term", c.name),
                points: equivalent
                    .points
                    .iter()
                    .filter_map(|p| p.terms.get(k).map(|e| (p.amplitude, *e)))
                    .collect(),
                band: None,
                measured: None,
            });
        }
        // Room for the curves and the markers' note.
        let room = plots::MOST_ENTRIES.saturating_sub(curves.len() + 1);
        let groups = self.by_group(room, |i| {
            let m = measured.get(i).copied().flatten()?;
            Some((m.amplitude, m.energy))
        });
        Ok(format!(
            "\n<h2>Dissipated energy per cycle</h2>\n<p>Measured input work π a X sin φ of each point against its amplitude, coloured by sweep, and the fitted laws evaluated at ω_n = {:.4e} over the measured amplitude range only (log-log).{}</p>\n{}\n",
            equivalent.modal.natural_frequency,
            self.corrected_note(),
            plots::energy_per_cycle(&groups, &curves)?
        ))
    }

    /// ζ_eq(X) with its band and the measured ζ_p near resonance.
    fn damping_ratio_section(
        &self,
        equivalent: &EquivalentDamping,
        measured: &[Option<Measured>],
    ) -> Result<String> {
        let m = &equivalent.modal;
        let (k, omega_n) = (m.stiffness, m.natural_frequency);
        let near = |p: &Measured| (p.frequency / omega_n - 1.0).abs() <= NEAR_RESONANCE;
        // Room for the curve, its band, the markers' note and the measured levels.
        let room = plots::MOST_ENTRIES - 3 - usize::from(!equivalent.levels.is_empty());
        let groups = self.by_group(room, |i| {
            let p = measured.get(i).copied().flatten().filter(near)?;
            let zeta = p.energy / (2.0 * PI * k * p.amplitude * p.amplitude);
            zeta.is_finite().then_some((p.amplitude, zeta))
        });
        let shown: usize = groups.iter().map(|g| g.points.len()).sum();
        let curve = ZetaCurve {
            name: "fitted ζ_eq(X) at ω_n".into(),
            points: equivalent
                .points
                .iter()
                .map(|p| (p.amplitude, p.damping_ratio, p.damping_ratio_std))
                .collect(),
        };
        let levels: Vec<(f64, f64)> = equivalent
            .levels
            .iter()
            .filter_map(|l| Some((l.amplitude, l.measured?)))
            .collect();
        let percent = 100.0 * NEAR_RESONANCE;
        let note = format!(
            "markers: each point's ζ_p = E_p/(2π k X_p²) within {percent}% of ω_n, by sweep:"
        );
        let which = if shown == 0 {
            format!("No point lies within {percent}% of ω_n, so no point's own ζ_p is shown.")
        } else {
            format!(
                "The markers are each point's own ζ_p = E_p/(2π k X_p²) from its input work E_p = π a X sin φ, for the {shown} of {} points within {percent}% of ω_n (|ω_p/ω_n − 1| ≤ {NEAR_RESONANCE}), coloured by sweep: the equivalence holds near resonance only (a viscous damper dissipates π c ω_p X², so its ζ_p is ζ ω_p/ω_n).",
                measured.iter().flatten().count()
            )
        };
        let squares = if levels.is_empty() {
            ""
        } else {
            " The open squares are the table's own ζ at each sweep's measured level: the phase slope where the sweep's phase lag crosses π/2, at the amplitude there (the table below the plot sets them beside the fitted law)."
        };
        Ok(format!(
            "\n<h2>Equivalent damping</h2>\n<p>The fitted law's equivalent viscous damping ratio ζ_eq(X) = E_d(X)/(2π k X²) at ω_n = {omega_n:.4e} with modal stiffness k = {k:.4e}, with its ±1.96σ band (log amplitude axis). {which}{squares}{}</p>\n{}\n{}",
            self.corrected_note(),
            plots::damping_ratio(&curve, &groups, &note, &levels)?,
            levels_table(equivalent)
        ))
    }

    /// The equivalent damping table, ± 1.96 standard deviations.
    fn equivalent_table(&self, equivalent: &EquivalentDamping) -> String {
        let m = &equivalent.modal;
        let source = escape(&m.source.to_string());
        let intervals = if self.report.estimation.is_some() {
            "Intervals ± 1.96 standard deviations from the joint covariance of the coefficients and the estimated nonlinear parameters (the law parameters through the change of the law, every unknown through its correlation with the coefficients)."
        } else {
            "Intervals ± 1.96 standard deviations from the covariance of the coefficients (the modal mass taken as exact)."
        };
        let mut out = format!(
            "<p>Equivalent viscous damping ratio ζ_eq = E_d/(2πkX²) and loss factor η = 2ζ_eq at ω_n = {:.4e}, modal mass {:.4e}, stiffness {:.4e} ({source}). {intervals}</p>\n<table><tr><th>amplitude</th><th>E_d per cycle</th><th>ζ_eq</th><th>ζ_eq interval</th><th>η</th><th>η interval</th></tr>\n",
            m.natural_frequency, m.mass, m.stiffness
        );
        for p in &equivalent.points {
            let band = |v: f64, s: Option<f64>| {
                s.map_or("–".to_string(), |s| {
                    format!("[{:.4e}, {:.4e}]", v - 1.96 * s, v + 1.96 * s)
                })
            };
            let _ = writeln!(
                out,
                "<tr><td>{:.4e}</td><td>{:.4e}</td><td>{:.4e}</td><td>{}</td><td>{:.4e}</td><td>{}</td></tr>",
                p.amplitude,
                p.dissipated_energy,
                p.damping_ratio,
                band(p.damping_ratio, p.damping_ratio_std),
                p.loss_factor,
                band(p.loss_factor, p.loss_factor_std)
            );
        }
        out.push_str("</table>\n");
        out
    }
}

/// ζ at each sweep's measured level: the fitted ζ_eq(X_c) with its interval beside the
/// phase-slope estimate ([`crate::analysis::measured_levels`]); nothing without levels.
fn levels_table(equivalent: &EquivalentDamping) -> String {
    if equivalent.levels.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "<p>ζ at the measured levels: where each sweep's phase lag crosses π/2, its frequency f_c and amplitude X_c, the fitted law's ζ_eq(X_c) (± 1.96σ) and the sweep's own ζ from its phase slope there, −1/(2ω_c d(ω cot φ)/d(ω²)), exact for viscous damping.</p>\n<table><tr><th>sweep</th><th>f_c (Hz)</th><th>X_c</th><th>ζ_eq fitted</th><th>ζ measured</th><th>fitted / measured</th></tr>\n",
    );
    for l in &equivalent.levels {
        let fitted = match l.fitted_std {
            Some(s) => format!("{:.4e} ± {:.2e}", l.fitted, 1.96 * s),
            None => format!("{:.4e}", l.fitted),
        };
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{:.6e}</td><td>{:.4e}</td><td>{fitted}</td><td>{}</td><td>{}</td></tr>",
            escape(&l.sweep),
            l.frequency / (2.0 * PI),
            l.amplitude,
            l.measured.map_or("–".into(), |m| format!("{m:.4e}")),
            l.ratio.map_or("–".into(), |r| format!("{r:.4}")),
        );
    }
    out.push_str("</table>\n");
    out
}
