//! `[stepped_sine]`: a measured stepped-sine table read from a data file into a
//! [`SteppedSineSource`] (the points in their sweeps, the structural damping terms beside
//! the model's, the residual receptance unknowns), the equation source of the job.
//!
//! Each row is one point. A response column measured as velocity or acceleration is
//! mapped to displacement by its harmonic: v = V cos(ωt − φ_v) is the derivative of
//! X cos(ωt − φ_x) with X = V/ω and φ_x = φ_v + π/2; an acceleration A gives X = A/ω²
//! and φ_x = φ_a + π (lags, wrapped into (−π, π]). With `phase_convention = "lead"`
//! the column holds the phase of the response, φ = −(column). Noise columns, when
//! given, are mapped by the same factors (σ_X = σ_V/ω, σ_X = σ_A/ω²).
//!
//! Every bad cell is an [`Error::Data`] naming the file, the 1-based data row and the
//! column: a missing column, a non-positive frequency, force or amplitude, a phase
//! beyond ±2π after its gain (a phase in degrees needs `scale = 0.017453292519943295`),
//! a negative or non-finite standard deviation.
//!
//! `residual` makes each sweep's residual receptance of the out-of-band modes
//! ([`crate::prep::harmonic::residual`]) nonlinear unknowns estimated with the damping
//! by variable projection ([`crate::regressor::ParametricRegressor`]): r_k (and r_m) per
//! sweep, named `r_k (<sweep>)`, initial 0 (the middle of the bounds when they exclude
//! 0), bounds given once for every sweep or by default ±B_s (r_k) and ±B_s ω²_min,s
//! (r_m), B_s the sweep's smallest measured receptance X/a
//! ([`crate::prep::harmonic::residual::default_bounds`]).

use std::collections::HashMap;
use std::path::Path;

use super::context::Context;
use super::reduction::harmonic_settings;
use super::spec::{
    ColumnSpec, HarmonicApproximationSpec, PhaseConvention, Scale, SteppedSineSpec, StructuralSpec,
};
use crate::error::{Error, Result};
use crate::io::Table;
use crate::prep::fourier::wrap_phase;
use crate::prep::harmonic::residual::{self, ResidualKind};
use crate::prep::harmonic::sweeps::{PointNoise, SweptTable};
use crate::prep::harmonic::{SteppedSinePoint, SteppedSineTable};
use crate::regressor::stepped_sine::StructuralTerm;
use crate::regressor::{NonlinearParameter, SteppedSineSource};

/// A data error in `file`.
fn data_error(file: &str, row: usize, column: &str, message: impl Into<String>) -> Error {
    Error::Data {
        file: file.to_string(),
        row,
        column: column.to_string(),
        message: message.into(),
    }
}

/// The scale of `spec` as a number: given, or its named scalar in `named` (read from
/// the data file first, [`named_scales`]).
fn scale_of(spec: &ColumnSpec, named: &HashMap<String, f64>) -> f64 {
    match &spec.scale {
        None => 1.0,
        Some(Scale::Value(v)) => *v,
        // Every named scale was read before: NaN only if not, which `column` refuses.
        Some(Scale::Variable(name)) => named.get(name).copied().unwrap_or(f64::NAN),
    }
}

/// The named scales (`scale = "gtau"`) of `columns`: each a scalar variable of the data
/// file at `path`, read once.
fn named_scales(path: &Path, columns: &[&ColumnSpec]) -> Result<HashMap<String, f64>> {
    let mut named = HashMap::new();
    let mut file = None;
    for c in columns {
        if let Some(Scale::Variable(name)) = &c.scale
            && !named.contains_key(name)
        {
            let open = match file.take() {
                Some(open) => open,
                None => crate::io::data_file::DataFile::open(path)?,
            };
            let value = open.scalar(name);
            file = Some(open);
            named.insert(name.clone(), value?);
        }
    }
    Ok(named)
}

/// The column `spec` of `table`, with its gain, or a data error naming it.
fn column(table: &Table, spec: &ColumnSpec, named: &HashMap<String, f64>) -> Result<Vec<f64>> {
    let scale = scale_of(spec, named);
    let offset = spec.offset.unwrap_or(0.0);
    if !(scale.is_finite() && scale != 0.0 && offset.is_finite()) {
        return Err(Error::invalid(
            &format!("gain of column '{}'", spec.column),
            if scale.is_finite() { offset } else { scale },
            "scale must be finite and not zero, offset finite (value = scale × column + offset)",
        ));
    }
    raw(table, &spec.column).map(|v| v.iter().map(|c| scale * c + offset).collect())
}

/// The column `name` of `table` as stored.
fn raw(table: &Table, name: &str) -> Result<Vec<f64>> {
    match table.headers.iter().position(|h| h == name) {
        Some(k) => Ok(table.columns[k].clone()),
        None => Err(data_error(
            &table.file,
            0,
            name,
            format!("no column '{name}' (columns: {})", table.headers.join(", ")),
        )),
    }
}

/// The columns `names` (and the sweep column) of the MAT file at `path`. A name the file
/// lacks is a data error listing its columns and, when struct arrays hold fields of that
/// name, how to read them as sweeps (`sweeps = "<path>"`).
fn mat_columns(path: &Path, names: &[&str], sweep: Option<&str>) -> Result<Table> {
    let data = crate::io::data_file::DataFile::open(path)?;
    let mut wanted = names.to_vec();
    wanted.extend(sweep);
    match data.table(&wanted) {
        Err(Error::UnknownName { name, known, .. }) => {
            let suffix = format!(".{name}");
            let arrays: Vec<String> = data
                .contents()
                .unwrap_or_default()
                .iter()
                .filter_map(|e| e.path.strip_suffix(&suffix))
                .map(|element| match element.strip_suffix(')') {
                    Some(indexed) => indexed
                        .rsplit_once('(')
                        .map_or(element, |(array, _)| array)
                        .to_string(),
                    None => element.to_string(),
                })
                .fold(Vec::new(), |mut list, a| {
                    if !list.contains(&a) {
                        list.push(a);
                    }
                    list
                });
            let hint = if arrays.is_empty() {
                String::new()
            } else {
                format!(
                    "; the file's structs {} hold '{name}' fields: read each element as a sweep with `sweeps = {:?}` (docs/stepped_sine.md)",
                    arrays.join(", "),
                    arrays
                )
            };
            Err(data_error(
                &path.display().to_string(),
                0,
                &name,
                format!("no column '{name}' (columns: {known}){hint}"),
            ))
        }
        other => other,
    }
}

impl Context<'_> {
    /// Reads `[stepped_sine]` for a model of `n` DOFs.
    pub(super) fn stepped_sine(
        &self,
        spec: &SteppedSineSpec,
        n: usize,
        base: &Path,
    ) -> Result<SteppedSineSource> {
        let path = base.join(&spec.file);
        // A CSV sweep column may hold text (`FC1`, `RC3`); other formats hold numbers.
        let csv = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("csv") || e.eq_ignore_ascii_case("txt"));
        let mat = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("mat"));
        // The columns the table's keys name, each once.
        let mut names: Vec<&str> = vec![&spec.frequency.column, &spec.force.column];
        names.extend(spec.amplitudes.iter().map(|a| a.get_ref().column.as_str()));
        names.extend(spec.phases.iter().map(|p| p.get_ref().column.as_str()));
        names.extend(spec.force_std.as_deref());
        names.extend(spec.amplitude_std.iter().flatten().map(String::as_str));
        names.extend(spec.phase_std.iter().flatten().map(String::as_str));
        let mut unique: Vec<&str> = Vec::new();
        for name in names {
            if !unique.contains(&name) {
                unique.push(name);
            }
        }
        let (table, labels) = match (&spec.sweep, &spec.sweeps) {
            (Some(_), Some(sweeps)) => {
                return Err(self.typed_error_at(
                    sweeps,
                    Error::choice(
                        "stepped_sine.sweeps",
                        "both `sweep` and `sweeps`",
                        "give `sweep` (a column whose values group the points) or `sweeps` (the struct arrays of a MAT file whose elements are the sweeps), not both",
                    ),
                ));
            }
            (None, Some(sweeps)) => {
                if !mat {
                    return Err(self.typed_error_at(
                        sweeps,
                        Error::choice(
                            "stepped_sine.sweeps",
                            format!("{:?} on {}", sweeps.get_ref().list(), spec.file),
                            "`sweeps` names struct arrays of a .mat file; in other files a column groups the points: `sweep = \"<column>\"`",
                        ),
                    ));
                }
                let (table, labels) =
                    crate::io::mat::sweep_table(&path, &sweeps.get_ref().list(), &unique)?;
                (table, Some(labels))
            }
            (Some(name), None) if csv => {
                let (table, mut labels) = crate::io::csv::read_with_labels(&path, &[name])?;
                (table, labels.pop())
            }
            // A MAT file: only the variables named (it may hold others of other lengths).
            (sweep, None) if mat => (mat_columns(&path, &unique, sweep.as_deref())?, None),
            _ => (crate::io::read_table(&path)?, None),
        };
        // The sweep grouping: a column, or the struct-array elements of `sweeps`.
        let sweep_key: Option<&str> = match (&spec.sweep, &spec.sweeps) {
            (Some(name), _) => Some(name),
            (None, Some(_)) => Some("sweeps"),
            (None, None) => None,
        };
        let mut scaled: Vec<&ColumnSpec> = vec![&spec.frequency, &spec.force];
        scaled.extend(spec.amplitudes.iter().map(toml::Spanned::get_ref));
        scaled.extend(spec.phases.iter().map(toml::Spanned::get_ref));
        let named = named_scales(&path, &scaled)?;
        let file = table.file.clone();
        if spec.amplitudes.len() != n || spec.phases.len() != n {
            return Err(Error::mismatch(
                "amplitude and phase columns of [stepped_sine] vs dofs",
                n,
                if spec.amplitudes.len() != n {
                    spec.amplitudes.len()
                } else {
                    spec.phases.len()
                },
            ));
        }
        let force_dof = spec.force_dof.unwrap_or(1);
        if force_dof == 0 || force_dof > n {
            return Err(Error::DofOutOfRange {
                what: "stepped_sine.force_dof".into(),
                dof: force_dof,
                dofs: n,
            });
        }
        // Each DOF's amplitude and phase column, in DOF order.
        let mut by_dof: Vec<Option<(&ColumnSpec, &ColumnSpec, usize)>> = vec![None; n];
        for (k, (a, p)) in spec.amplitudes.iter().zip(&spec.phases).enumerate() {
            let dof = a.get_ref().dof.unwrap_or(k + 1);
            if dof == 0 || dof > n {
                return Err(self.typed_error_at(
                    a,
                    Error::DofOutOfRange {
                        what: format!("amplitude column '{}'", a.get_ref().column),
                        dof,
                        dofs: n,
                    },
                ));
            }
            if by_dof[dof - 1].is_some() {
                return Err(self.error_at(a, format!("DOF {dof} has two amplitude columns")));
            }
            by_dof[dof - 1] = Some((a.get_ref(), p.get_ref(), k));
        }
        let by_dof: Vec<(&ColumnSpec, &ColumnSpec, usize)> = by_dof
            .into_iter()
            // cannot fail: n column pairs, each on a distinct DOF in 1..=n (checked above),
            // fill all n slots
            .map(|c| c.expect("n entries for n DOFs, each DOF once"))
            .collect();
        let omega = column(&table, &spec.frequency, &named)?;
        let force = column(&table, &spec.force, &named)?;
        let amplitudes = by_dof
            .iter()
            .map(|(a, _, _)| column(&table, a, &named))
            .collect::<Result<Vec<_>>>()?;
        let phases = by_dof
            .iter()
            .map(|(_, p, _)| column(&table, p, &named))
            .collect::<Result<Vec<_>>>()?;
        let rows = table.rows();
        let order = spec.response.order() as i32;
        for r in 0..rows {
            let line = r + 1;
            let positive = |value: f64, name: &str, what: &str| -> Result<()> {
                if value.is_finite() && value > 0.0 {
                    Ok(())
                } else {
                    Err(data_error(
                        &file,
                        line,
                        name,
                        format!("{what} {value} must be finite and positive"),
                    ))
                }
            };
            positive(omega[r], &spec.frequency.column, "frequency")?;
            positive(force[r], &spec.force.column, "force amplitude")?;
            for (j, (a, p, _)) in by_dof.iter().enumerate() {
                positive(
                    amplitudes[j][r],
                    &a.column,
                    &format!("amplitude of DOF {}", j + 1),
                )?;
                let phi = phases[j][r];
                if !(phi.is_finite() && phi.abs() <= 2.0 * std::f64::consts::PI) {
                    return Err(data_error(
                        &file,
                        line,
                        &p.column,
                        format!(
                            "phase of DOF {} is {phi} rad after its gain, out of range [-2π, 2π] (a phase in degrees needs scale = 0.017453292519943295)",
                            j + 1
                        ),
                    ));
                }
            }
        }
        // Sweeps: distinct values of the sweep column in order of first appearance.
        let (sweeps, sweep_names) = match sweep_key {
            None => (vec![0; rows], vec!["all points".to_string()]),
            Some(name) => {
                // Numbers name a sweep "level = 2"; text names it as written.
                let numbers = match &labels {
                    None => Some(raw(&table, name)?),
                    Some(text) => text.iter().map(|t| t.parse::<f64>().ok()).collect(),
                };
                let keys: Vec<String> = match (&numbers, labels) {
                    (Some(values), _) => {
                        if let Some(r) = values.iter().position(|v| !v.is_finite()) {
                            return Err(data_error(&file, r + 1, name, "not a finite number"));
                        }
                        values.iter().map(|v| format!("{name} = {v}")).collect()
                    }
                    (None, Some(text)) => text,
                    (None, None) => Vec::new(),
                };
                if let Some(r) = keys.iter().position(String::is_empty) {
                    return Err(data_error(&file, r + 1, name, "an empty sweep label"));
                }
                let mut names: Vec<String> = Vec::new();
                let mut sweeps = Vec::with_capacity(rows);
                for key in keys {
                    let s = match names.iter().position(|n| *n == key) {
                        Some(s) => s,
                        None => {
                            names.push(key);
                            names.len() - 1
                        }
                    };
                    sweeps.push(s);
                }
                (sweeps, names)
            }
        };
        // Response → displacement: X = R/ω^order, lag + order·π/2.
        let lag = |phi: f64| match spec.phase_convention {
            PhaseConvention::Lag => phi,
            PhaseConvention::Lead => -phi,
        };
        let points: Vec<SteppedSinePoint> = (0..rows)
            .map(|r| {
                let w = omega[r];
                SteppedSinePoint {
                    label: format!("row {}", r + 1),
                    frequency: w,
                    force_dof: force_dof - 1,
                    force_amplitude: force[r],
                    amplitudes: (0..n).map(|j| amplitudes[j][r] / w.powi(order)).collect(),
                    phases: (0..n)
                        .map(|j| {
                            wrap_phase(
                                lag(phases[j][r]) + order as f64 * std::f64::consts::FRAC_PI_2,
                            )
                        })
                        .collect(),
                }
            })
            .collect();
        // The rows `keep` selects (all without it), before any noise is estimated.
        let (points, sweeps, sweep_names, kept) = match &spec.keep {
            None => (points, sweeps, sweep_names, (0..rows).collect::<Vec<_>>()),
            Some(keep) => {
                let kept = self.at(keep, |k| {
                    super::keep::kept(k, &points, &sweeps, &sweep_names)
                })?;
                let (sweeps, names) = super::keep::sweeps_of(&sweeps, &sweep_names, &kept);
                (super::keep::at(&points, &kept), sweeps, names, kept)
            }
        };
        let table_points = SteppedSineTable::new(points)?;
        let given = [
            spec.force_std.is_some(),
            spec.amplitude_std.is_some(),
            spec.phase_std.is_some(),
        ];
        let swept = if given.iter().all(|g| *g) {
            let std_column = |name: &str, gain: f64| -> Result<Vec<f64>> {
                let values = raw(&table, name)?;
                for (r, v) in values.iter().enumerate() {
                    if !(v.is_finite() && *v >= 0.0) {
                        return Err(data_error(
                            &file,
                            r + 1,
                            name,
                            format!("standard deviation {v} must be finite and nonnegative"),
                        ));
                    }
                }
                Ok(values.iter().map(|v| v * gain.abs()).collect())
            };
            let amplitude_std = spec.amplitude_std.as_deref().unwrap_or_default();
            let phase_std = spec.phase_std.as_deref().unwrap_or_default();
            if amplitude_std.len() != n || phase_std.len() != n {
                return Err(Error::mismatch(
                    "amplitude_std and phase_std columns vs dofs",
                    n,
                    amplitude_std.len().min(phase_std.len()),
                ));
            }
            let sf = std_column(
                spec.force_std.as_deref().unwrap_or_default(),
                scale_of(&spec.force, &named),
            )?;
            let mut sa = Vec::new();
            let mut sp = Vec::new();
            for (a, p, k) in &by_dof {
                sa.push(std_column(&amplitude_std[*k], scale_of(a, &named))?);
                sp.push(std_column(&phase_std[*k], scale_of(p, &named))?);
            }
            let noise = kept
                .iter()
                .map(|&r| PointNoise {
                    force: sf[r],
                    amplitudes: (0..n).map(|j| sa[j][r] / omega[r].powi(order)).collect(),
                    phases: (0..n).map(|j| sp[j][r]).collect(),
                })
                .collect();
            SweptTable::with_noise(table_points, sweeps, sweep_names, noise)?
        } else if given.iter().any(|g| *g) {
            return Err(Error::choice(
                "stepped_sine noise columns",
                "some of force_std, amplitude_std, phase_std",
                "give all three (the noise of every point) or none (estimated from the scatter along each sweep)",
            ));
        } else {
            SweptTable::from_scatter(table_points, sweeps, sweep_names)?
        };
        let approximation = harmonic_settings(
            &HarmonicApproximationSpec {
                phase: spec.phase_reading,
                dof: spec.phase_dof,
                samples_per_period: None,
            },
            n,
        )?;
        let structural = spec
            .structural
            .iter()
            .map(|s| self.at(s, |s| structural_term(s, n)))
            .collect::<Result<Vec<_>>>()?;
        let (residual, residual_parameters) = self.residual(spec, n, &swept)?;
        Ok(SteppedSineSource {
            table: swept,
            structural,
            approximation,
            residual,
            residual_parameters,
            file: Some(file),
            system: None,
        })
    }

    /// The residual unknowns of `spec` on `swept` (module doc): their kind and the
    /// unknowns with their bounds.
    fn residual(
        &self,
        spec: &SteppedSineSpec,
        n: usize,
        swept: &SweptTable,
    ) -> Result<(ResidualKind, Vec<NonlinearParameter>)> {
        let kind = spec.residual;
        let given = |bounds: &Option<toml::Spanned<[f64; 2]>>, key: &str| -> Result<()> {
            match bounds {
                Some(b) => Err(self.typed_error_at(
                    b,
                    Error::choice(
                        &format!("stepped_sine.{key}"),
                        format!("{:?}", b.get_ref()),
                        &format!("bounds of an unknown that residual = \"{kind}\" does not estimate (set residual = \"{}\")", if key == "residual_mass" { "mass_and_stiffness" } else { "stiffness" }),
                    ),
                )),
                None => Ok(()),
            }
        };
        match kind {
            ResidualKind::None => {
                given(&spec.residual_stiffness, "residual_stiffness")?;
                given(&spec.residual_mass, "residual_mass")?;
                return Ok((ResidualKind::None, Vec::new()));
            }
            ResidualKind::Stiffness => given(&spec.residual_mass, "residual_mass")?,
            ResidualKind::MassAndStiffness => {}
        }
        if n != 1 {
            return Err(Error::choice(
                "stepped_sine.residual",
                format!("\"{kind}\" on a table of {n} DOFs"),
                "the residual receptance is estimated for one-DOF tables (a driving-point measurement of one mode) only: a table of several DOFs needs a residual per response point and a cross term per pair, which dampid does not estimate",
            ));
        }
        let Some(sweep) = spec
            .sweep
            .as_deref()
            .or(spec.sweeps.as_ref().map(|_| "sweeps"))
        else {
            return Err(Error::choice(
                "stepped_sine.residual",
                format!("\"{kind}\" without a sweep column"),
                "the residual is estimated per sweep: give `sweep = \"<column>\"` (one sweep per level)",
            ));
        };
        if kind == ResidualKind::MassAndStiffness {
            // r_k and r_m/ω² are told apart only by ω: a sweep at one frequency cannot.
            for (s, name) in swept.sweep_names.iter().enumerate() {
                let mut frequencies = swept
                    .table
                    .points()
                    .iter()
                    .zip(&swept.sweeps)
                    .filter(|(_, q)| **q == s)
                    .map(|(p, _)| p.frequency);
                let first = frequencies.next().unwrap_or(f64::NAN);
                if frequencies.all(|w| w == first) {
                    return Err(Error::choice(
                        "stepped_sine.residual",
                        format!(
                            "\"mass_and_stiffness\" with sweep '{name}' (column '{sweep}') at one frequency"
                        ),
                        "r_k and r_m/ω² are told apart only by the frequency: every sweep needs two frequencies at least (or residual = \"stiffness\")",
                    ));
                }
            }
        }
        let defaults = residual::default_bounds(swept);
        let parameter = |name: String,
                         given: &Option<toml::Spanned<[f64; 2]>>,
                         default: f64|
         -> Result<NonlinearParameter> {
            let [lower, upper] = given.as_ref().map_or([-default, default], |b| *b.get_ref());
            let initial = if lower <= 0.0 && 0.0 <= upper {
                0.0
            } else {
                0.5 * (lower + upper)
            };
            let p = NonlinearParameter::new(name, initial, lower, upper).as_nuisance();
            match given {
                Some(b) => self.at(b, |_| p.validate())?,
                None => p.validate()?,
            }
            Ok(p)
        };
        let mut parameters = Vec::new();
        for (s, name) in swept.sweep_names.iter().enumerate() {
            let (bk, bm) = defaults[s];
            parameters.push(parameter(
                format!("r_k ({name})"),
                &spec.residual_stiffness,
                bk,
            )?);
            if kind == ResidualKind::MassAndStiffness {
                parameters.push(parameter(format!("r_m ({name})"), &spec.residual_mass, bm)?);
            }
        }
        Ok((kind, parameters))
    }
}

/// A structural damping term from its spec (DOFs 1-based, 0 = ground).
fn structural_term(spec: &StructuralSpec, n: usize) -> Result<StructuralTerm> {
    let [a, b] = spec.element.unwrap_or([1, 0]);
    let dof = |d: usize| -> Result<Option<usize>> {
        if d > n {
            return Err(Error::DofOutOfRange {
                what: format!("structural damping '{}'", spec.coefficient),
                dof: d,
                dofs: n,
            });
        }
        Ok(d.checked_sub(1))
    };
    let term = StructuralTerm {
        coefficient: spec.coefficient.clone(),
        stiffness: spec.stiffness,
        from: dof(a)?,
        to: dof(b)?,
    };
    term.validate(n)?;
    Ok(term)
}
