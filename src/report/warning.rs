//! Warnings: what the user must know before trusting the numbers, as data (serde,
//! tagged by `kind`) with a `Display` that says in words what happened and what to do.
//! [`crate::report::FitReport::new`] raises them from the fit's status, the rank and
//! condition number of the column-scaled regressor (κ > [`ILL_CONDITIONED`]), the χ²
//! check of the weighted fit (P < [`INADEQUATE_P_VALUE`]), redundancy, the
//! identifiability analysis, negative damping coefficients of an unconstrained fit,
//! and the noise bias of a differencing velocity estimator
//! ([`crate::report::FitReport::with_velocity_noise`]).

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::analysis::identifiability::list;
use crate::fit::{BoundSide, FitStatus};
use crate::report::count;

/// The free coefficients a [`Warning::BoundSetsCoefficients`] lists by name (the rest
/// are counted; all are in the JSON).
const MOVED_LISTED: usize = 4;

/// Condition number of the column-scaled regressor above which the report warns.
pub const ILL_CONDITIONED: f64 = 1e8;

/// Upper-tail probability of χ² below which the report warns that the residuals are
/// larger than the estimated noise explains, and shows standard errors scaled by
/// √(χ²/dof) ([`crate::analysis::diagnostics::REJECTION_P_VALUE`]).
pub const INADEQUATE_P_VALUE: f64 = crate::analysis::diagnostics::REJECTION_P_VALUE;

/// Something the user must know before trusting the numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Warning {
    /// The solver did not reach a solution: the coefficients are not estimates.
    NotConverged {
        /// The solver's status.
        status: FitStatus,
    },
    /// The regressor is rank deficient: the data cannot separate the coefficients.
    RankDeficient {
        /// Numerical rank.
        rank: usize,
        /// Number of coefficients.
        coefficients: usize,
    },
    /// The column-scaled regressor is badly conditioned.
    IllConditioned {
        /// Its condition number.
        condition_number: f64,
    },
    /// As many equations as free coefficients: no redundancy, no uncertainty estimate.
    NoRedundancy {
        /// Equations.
        equations: usize,
    },
    /// Experiments whose equations alone determine a combination of the coefficients
    /// ([`crate::analysis::replicates::unchecked`]): the fit reproduces them whatever
    /// they hold, so a record with wrong units, a wrong sign or a force on the wrong DOF
    /// cannot be detected, and the χ² check and the standard errors see only the scatter
    /// between windows of one record. Every experiment, when there are no more
    /// experiments than free coefficients and parameters.
    NoRecordRedundancy {
        /// Experiments: records of replicate windows, stepped-sine points, spans.
        experiments: usize,
        /// Free coefficients plus estimated nonlinear parameters.
        parameters: usize,
        /// The experiments nothing checks (all of them when `experiments ≤ parameters`).
        unchecked: Vec<String>,
    },
    /// A coefficient held at its bound that the data cannot tell from values well inside
    /// it ([`crate::analysis::bound_set`]): free coefficients correlated with it move by
    /// more than [`crate::analysis::bound_set::MOVES`] of their standard errors over the
    /// values the data allow, so their values and intervals hold only if the bound is
    /// exact.
    BoundSetsCoefficients {
        /// The coefficient at its bound.
        coefficient: String,
        /// Which bound.
        side: BoundSide,
        /// The bound's value.
        bound: f64,
        /// Its estimate when it is left free (the other active coefficients held).
        free_estimate: f64,
        /// That estimate's standard error.
        free_std_error: f64,
        /// The far end of the values the data allow on the feasible side (95 %); `null`
        /// when the data exclude that side: the bound holds the coefficient where the
        /// data do not put it, and the others compensate.
        allowed: Option<f64>,
        /// (name, how far it moves over the allowed values, that in its standard errors).
        moved: Vec<(String, f64, f64)>,
    },
    /// The weighted residuals are larger than the propagated noise explains.
    ModelInadequate {
        /// χ².
        chi_square: f64,
        /// Its degrees of freedom.
        degrees_of_freedom: usize,
        /// Its upper-tail probability.
        p_value: f64,
    },
    /// An unweighted fit whose records' mean residuals differ far more than their
    /// windows scatter ([`crate::analysis::lack_of_fit`]): the model misses a mechanism
    /// or records are not what their files say; the standard errors are then taken from
    /// the records' means.
    LackOfFit {
        /// √SS_lof / ‖b‖: the share of the input work the records' means leave unexplained.
        relative_misfit: f64,
        /// κ · √SS_lof / ‖b‖: how far the misfit can move the (column-scaled)
        /// coefficients relative to their size.
        coefficient_bound: f64,
        /// F of the test (`null`: infinite, every record's windows agree exactly).
        f_statistic: Option<f64>,
        /// Its degrees of freedom: experiments − free parameters, and Σ (windows − 1).
        degrees_of_freedom: (usize, usize),
        /// Its upper-tail probability.
        p_value: f64,
        /// The factor on the residual-variance standard errors.
        scale: f64,
        /// The experiments with the largest shares of the misfit, with those shares.
        records: Vec<(String, f64)>,
    },
    /// The velocity estimator's noise is a material share of the damping columns
    /// ([`crate::analysis::velocity_noise`]): the coefficients are biased low.
    VelocityNoiseBias {
        /// The estimator used (model-file name).
        estimator: String,
        /// Its velocity noise relative to the fundamental's, σ_v/(ωσ).
        gain: f64,
        /// The largest displacement noise σ estimated.
        displacement_noise: f64,
        /// The column with the largest noise share.
        worst: String,
        /// Its share Σ B / Σ |A|.
        share: f64,
        /// Each coefficient's least-squares estimate with the bias removed.
        shifts: Vec<(String, f64)>,
        /// The estimator to use instead (model-file name).
        recommended: String,
    },
    /// Some directions of the column-scaled regressor are practically null (below the
    /// level the equation noise can resolve): these coefficients are not separated.
    Unidentifiable {
        /// The coefficients that appear in a near-null direction.
        coefficients: Vec<String>,
        /// Each near-null direction in words.
        trade_offs: Vec<String>,
        /// The combinations that are determined (when any).
        determined: Vec<String>,
        /// The fit was constrained: the constraints, not the data, place the solution
        /// along the near-null directions.
        constrained: bool,
        /// The lack-of-fit test rejected the fit ([`Warning::LackOfFit`]): the records'
        /// disagreement is part of the noise level that makes these directions null, so
        /// the model or the records need correcting before new experiments help.
        #[serde(default)]
        misfit: bool,
    },
    /// An unconstrained fit gave damping coefficients below zero: a damper that feeds
    /// energy in, which no passive joint does.
    NegativeDamping {
        /// Each negative coefficient, its value and its standard error (when known).
        coefficients: Vec<(String, f64, Option<f64>)>,
    },
    /// Windows that are not in steady state were accepted (`accept_transient`): their
    /// energy balance misses the change of stored energy.
    TransientAccepted {
        /// How many windows.
        windows: usize,
        /// The records they belong to.
        records: Vec<String>,
    },
    /// The fit explains nothing: its relative residual is at least
    /// [`crate::report::explains::NOTHING_EXPLAINED`], or every coefficient sits on a
    /// bound ([`crate::report::explains`]).
    FitExplainsNothing {
        /// ‖b − Aθ‖ / ‖b‖.
        relative_residual: f64,
        /// The coefficients, when every one sits on a bound (empty otherwise).
        at_bounds: Vec<String>,
    },
    /// One record disagrees with the others: without it the rest fit far better and the
    /// estimates move ([`crate::report::outliers`]).
    InconsistentRecord {
        /// The record's label.
        record: String,
        /// The others' weighted squared residual at the fit without the record, over
        /// the whole fit's.
        remaining_misfit: f64,
        /// The record's RMS (weighted) residual at the fit of the others, over their
        /// residual standard deviation (`None` when the others fit exactly).
        deleted_residual: Option<f64>,
        /// Its F test's upper-tail probability (`None` without degrees of freedom).
        p_value: Option<f64>,
        /// Each coefficient: its value without the record and the shift θ − θ₋ᵣ in
        /// standard errors of the fit without it (when known).
        shifts: Vec<(String, f64, Option<f64>)>,
        /// The coefficients that are not determined with the record.
        undetermined: Vec<String>,
    },
    /// Columns that are round-off of their inputs in every equation
    /// ([`crate::regressor::round_off`]): the terms do no net work over whole periods.
    RoundOffColumn {
        /// The coefficients.
        coefficients: Vec<String>,
    },
    /// One record holds most of the residual ([`crate::report::records`]).
    RecordDominates {
        /// The record's label.
        record: String,
        /// Its share of the squared residual.
        residual_share: f64,
        /// Its share of the equations.
        equation_share: f64,
        /// Its standardised residual.
        standardised_residual: Option<f64>,
    },
    /// A bootstrap was asked for but not run.
    NoBootstrap {
        /// Why.
        reason: String,
    },
}

/// `'a', 'b' and 'c'`; after 6 names, `and N more`.
fn quoted(names: &[String]) -> String {
    const SHOWN: usize = 6;
    let mut quoted: Vec<String> = names.iter().take(SHOWN).map(|n| format!("'{n}'")).collect();
    if names.len() > SHOWN {
        quoted.push(format!("{} more", names.len() - SHOWN));
    }
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => quoted.join(""),
    }
}

impl Warning {
    /// Whether `identify --strict` fails on this warning: a coefficient not determined,
    /// a window accepted as transient, or the model check (χ²) failing.
    pub fn fails_strict(&self) -> bool {
        matches!(
            self,
            Warning::Unidentifiable { .. }
                | Warning::RankDeficient { .. }
                | Warning::TransientAccepted { .. }
                | Warning::ModelInadequate { .. }
                | Warning::LackOfFit { .. }
                | Warning::FitExplainsNothing { .. }
                | Warning::InconsistentRecord { .. }
                | Warning::RoundOffColumn { .. }
        )
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::NotConverged { status } => write!(
                f,
                "the solver ended with status {status:?}: these numbers are not a solution"
            ),
            Warning::RankDeficient { rank, coefficients } => write!(
                f,
                "the regressor has rank {rank} for {coefficients} coefficients: these data cannot separate the coefficients, and the values shown are a minimum-norm least-squares solution, not estimates; add experiments at other frequencies, amplitudes or forcing points"
            ),
            Warning::IllConditioned { condition_number } => write!(
                f,
                "the column-scaled regressor has condition number {condition_number:.3e}: some combination of coefficients is barely determined by these data"
            ),
            Warning::ModelInadequate {
                chi_square,
                degrees_of_freedom,
                p_value,
            } => write!(
                f,
                "the weighted residual sum of squares is {chi_square:.3e} for {degrees_of_freedom} degrees of freedom (P = {p_value:.1e}): the residuals are larger than the estimated sensor noise explains, so the model may miss a mechanism, the records may not be in steady state, the noise is not white, or (on clean simulated data) the residual is discretisation error; the plug-in standard errors would be too small, so the standard errors and intervals shown are scaled by √(χ²/dof) = {:.3}",
                (chi_square / *degrees_of_freedom as f64).sqrt()
            ),
            Warning::LackOfFit {
                relative_misfit,
                coefficient_bound,
                f_statistic,
                degrees_of_freedom,
                p_value,
                scale,
                records,
            } => {
                let shares: Vec<String> = records
                    .iter()
                    .map(|(name, share)| format!("'{name}' ({:.0} %)", 100.0 * share))
                    .collect();
                write!(
                    f,
                    "lack of fit: the records' mean residuals differ far more than the windows of each record scatter (F = {} for {} and {} degrees of freedom, P = {p_value:.1e}); they leave {:.3} % of the input work unexplained, which can move the coefficients by up to {:.2} % of their size, most of it in {}. The model may miss a mechanism, or some records are not what their files say (velocities given as displacements, a force on another DOF, in other units or with the wrong sign, a sensor's polarity): check those records; the standard errors shown come from the records' means (× {scale:.3})",
                    f_statistic.map_or("∞".to_string(), |v| format!("{v:.3e}")),
                    degrees_of_freedom.0,
                    degrees_of_freedom.1,
                    100.0 * relative_misfit,
                    100.0 * coefficient_bound,
                    shares.join(", ")
                )
            }
            Warning::VelocityNoiseBias {
                estimator,
                gain,
                displacement_noise,
                worst,
                share,
                shifts,
                recommended,
            } => {
                let corrected: Vec<String> = shifts
                    .iter()
                    .map(|(name, value)| format!("{name} = {value:.4e}"))
                    .collect();
                write!(
                    f,
                    "the {} velocities amplify the displacement noise (σ up to {displacement_noise:.2e}) {gain:.1} times relative to the fundamental, and their noise makes up {:.1}% of the {worst} column (the damping columns are biased upwards by Var v, so the coefficients come out low or negative); with the bias removed least squares gives {}; use velocity = \"{recommended}\" with noise = \"auto\" (the default noise-robust pipeline), which corrects for it, before adding experiments",
                    estimator.replace('_', " "),
                    100.0 * share,
                    corrected.join(", ")
                )
            }
            Warning::NegativeDamping { coefficients } => {
                let items: Vec<String> = coefficients
                    .iter()
                    .map(|(name, value, se)| match se {
                        Some(se) if *se > 0.0 => {
                            format!(
                                "{name} = {value:.4e} ({:.1} standard errors below zero)",
                                -value / se
                            )
                        }
                        _ => format!("{name} = {value:.4e}"),
                    })
                    .collect();
                write!(
                    f,
                    "the unconstrained fit gives negative damping: {}; a negative coefficient feeds energy in, so the law may be the wrong one or it compensates another term; refit with nonnegative = true in [identification] and compare the two (`dampid compare`)",
                    items.join(", ")
                )
            }
            Warning::NoRedundancy { equations } => write!(
                f,
                "{} for as many free coefficients: the fit is exact by construction and gives no uncertainty; add windows or records",
                count(*equations, "equation")
            ),
            Warning::NoRecordRedundancy {
                experiments,
                parameters,
                ..
            } if experiments <= parameters => write!(
                f,
                "{} for {parameters} free coefficients and parameters: the windows of a record repeat one experiment, so the fit reproduces every record whatever it holds; a record with the wrong units, a wrong sign or a force on the wrong DOF would go unnoticed, and the χ² check and the standard errors only measure the scatter between windows of one record; add records (other frequencies, amplitudes or forcing points) until there are more records than free coefficients and parameters",
                count(*experiments, "independent experiment"),
            ),
            Warning::NoRecordRedundancy {
                experiments,
                unchecked,
                ..
            } => {
                let (which, verb, them) = if unchecked.len() == 1 {
                    ("one", "determines", "it")
                } else {
                    ("each one", "determine", "them")
                };
                write!(
                    f,
                    "{}, {which} of the {experiments} independent experiments, alone {verb} a combination of the coefficients (leverage ≥ {}): the fit reproduces {them} whatever {} hold, so wrong units, a wrong sign or a force on the wrong DOF there would go unnoticed, and the χ² check does not test {them}; repeat {them} (the same frequency and forcing point, another amplitude) or add records at other frequencies or forcing points",
                    quoted(unchecked),
                    crate::analysis::replicates::UNCHECKED_LEVERAGE,
                    if unchecked.len() == 1 {
                        "it may"
                    } else {
                        "they"
                    }
                )
            }
            Warning::BoundSetsCoefficients {
                coefficient,
                side,
                bound,
                free_estimate,
                free_std_error,
                allowed,
                moved,
            } => {
                let (side, extent) = match side {
                    BoundSide::Upper => ("upper", "down to"),
                    _ => ("lower", "up to"),
                };
                let bound_value = *bound;
                // "c moves by …, d by …" (or "moves c by …, d by …" with `first` = "").
                let listed = |first: &str| -> String {
                    moved
                        .iter()
                        .take(MOVED_LISTED)
                        .enumerate()
                        .map(|(k, (name, shift, sigmas))| {
                            let verb = if k == 0 { first } else { "" };
                            format!("{name}{verb} by {shift:.3e} ({sigmas:.0} standard errors)")
                        })
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                let more = match moved.len().saturating_sub(MOVED_LISTED) {
                    0 => String::new(),
                    n => format!(" and {n} more coefficients"),
                };
                let bound = crate::format::number(*bound);
                let Some(allowed) = allowed else {
                    let beyond = (free_estimate - bound_value).abs() / free_std_error;
                    return write!(
                        f,
                        "{coefficient} sits at its {side} bound {bound}, but left free it is {free_estimate:.3e} ± {free_std_error:.2e}, {beyond:.1} standard errors beyond it: the data contradict the bound, and holding {coefficient} there moves {}{more}; these values are not estimates of the model: check the signs, DOFs, units and sensor kinds of the records, the noise of measured velocities (it biases the damping columns upwards; the default noise-robust pipeline corrects it), and whether the model misses a mechanism",
                        listed("")
                    );
                };
                write!(
                    f,
                    "{coefficient} sits at its {side} bound {bound}, but the data allow it {extent} {allowed:.3e} (left free it is {free_estimate:.3e} ± {free_std_error:.2e}); over that range {}{more}: their values and standard errors hold only if {coefficient} is exactly {bound}; if it is, fix it there or remove its term; if not, these data cannot separate {coefficient} from them: add experiments that do (`dampid design`)",
                    listed(" moves")
                )
            }
            Warning::Unidentifiable {
                coefficients,
                trade_offs,
                determined,
                constrained,
                misfit,
            } => {
                let remedy = if *misfit {
                    "the records disagree beyond the scatter of their windows (lack of fit): correct the model (a missing mechanism) or the records (units, signs, DOFs, sensor kinds) first, then add experiments if needed (`dampid design`)"
                } else {
                    "add experiments at other frequencies, amplitudes or forcing points (`dampid design`)"
                };
                let names: Vec<&str> = coefficients.iter().map(String::as_str).collect();
                if names.len() > crate::analysis::digest::FULL_LISTING {
                    // Hundreds of names and directions: counts, the lists are in the
                    // identifiability diagnostics.
                    write!(
                        f,
                        "these data cannot separate {} coefficients (by term: {}) along {} direction(s), and determine only {} combination(s) (listed with the identifiability diagnostics)",
                        names.len(),
                        crate::analysis::digest::by_term_text(names.iter().copied()),
                        trade_offs.len(),
                        determined.len()
                    )?;
                    if *constrained {
                        write!(
                            f,
                            "; the constraints, not the data, decide where the solution lies along these directions"
                        )?;
                    }
                    return write!(f, "; their values are not estimates; {remedy}");
                }
                write!(
                    f,
                    "these data cannot separate {}: {}",
                    list(&names),
                    trade_offs.join("; ")
                )?;
                match determined.len() {
                    0 => {}
                    1 | 2 => {
                        let combos: Vec<&str> = determined.iter().map(String::as_str).collect();
                        let verb = if determined.len() == 1 { "is" } else { "are" };
                        write!(f, "; only {} {verb} determined", list(&combos))?;
                    }
                    k => write!(
                        f,
                        "; only {k} combinations of the coefficients are determined (listed with the identifiability diagnostics)"
                    )?,
                }
                if *constrained {
                    write!(
                        f,
                        "; the constraints, not the data, decide where the solution lies along these directions"
                    )?;
                }
                write!(
                    f,
                    "; the values shown for {} are not estimates; {remedy}",
                    list(&names)
                )
            }
            Warning::TransientAccepted { windows, records } => {
                let names: Vec<&str> = records.iter().map(String::as_str).collect();
                write!(
                    f,
                    "{windows} window(s) not in steady state, accepted (dampid check shows them), in {}: over them the stored energy does not return to its start, so the estimates carry a bias the standard errors do not include; skip the transient (`skip` in [identification]) or record longer",
                    list(&names)
                )
            }
            Warning::FitExplainsNothing {
                relative_residual,
                at_bounds,
            } => {
                let names: Vec<&str> = at_bounds.iter().map(String::as_str).collect();
                if names.is_empty() {
                    write!(
                        f,
                        "the fit explains nothing: relative residual {relative_residual:.3} ≥ {}",
                        super::explains::NOTHING_EXPLAINED
                    )?;
                } else {
                    write!(
                        f,
                        "every coefficient sits on a bound ({}): the constraints, not the data, set the values (relative residual {relative_residual:.3})",
                        list(&names)
                    )?;
                }
                write!(
                    f,
                    "; the damping model does not account for the input work, so these are not estimates: check the signs, DOFs and units of the force and motion columns (over whole periods the input work is what the damping dissipates), the sensor kinds, and whether the model has the mechanism"
                )
            }
            Warning::InconsistentRecord {
                record,
                remaining_misfit,
                deleted_residual,
                p_value,
                shifts,
                undetermined,
            } => {
                write!(
                    f,
                    "record '{record}' disagrees with the others: without it their squared residual falls to {remaining_misfit:.2e} of the whole fit's"
                )?;
                match (deleted_residual, p_value) {
                    (Some(z), Some(p)) => write!(
                        f,
                        ", and its equations stand {z:.1} residual standard deviations off the fit of the others (P = {p:.1e})"
                    )?,
                    _ => write!(f, ", which then fit exactly")?,
                }
                let moved: Vec<String> = shifts
                    .iter()
                    .map(|(name, value, shift)| match shift {
                        Some(z) => format!("{name} = {value:.4e} ({z:+.1} se)"),
                        None => format!("{name} = {value:.4e}"),
                    })
                    .collect();
                if !moved.is_empty() {
                    write!(f, ", and without it {}", moved.join(", "))?;
                }
                if !undetermined.is_empty() {
                    let names: Vec<&str> = undetermined.iter().map(String::as_str).collect();
                    write!(
                        f,
                        "; with it the fit cannot separate {}: this record, not the design of the experiments, is the problem",
                        list(&names)
                    )?;
                }
                write!(
                    f,
                    "; check its units (`scale`), its force's DOF and sign, and whether its motion columns are displacements, velocities or accelerations as declared; identify without it to compare"
                )
            }
            Warning::RoundOffColumn { coefficients } => {
                let names: Vec<&str> = coefficients.iter().map(String::as_str).collect();
                write!(
                    f,
                    "the column of {} is round-off of its inputs in every equation: the term does no net work over whole periods of these records (a spring-like force in phase with x, a constant force, or an element that does not move), so an energy balance cannot estimate it and its column counts as zero; remove the term, or give records where it dissipates",
                    list(&names)
                )
            }
            Warning::RecordDominates {
                record,
                residual_share,
                equation_share,
                standardised_residual,
            } => {
                let z = standardised_residual
                    .map(|z| format!(", standardised residual {z:.2}"))
                    .unwrap_or_default();
                write!(
                    f,
                    "record '{record}' holds {:.1}% of the squared residual from {:.1}% of the equations{z}: check its force columns' DOF and sign, its period, whether it is in steady state, and whether the model misses a mechanism this record excites; identify without it to compare",
                    100.0 * residual_share,
                    100.0 * equation_share
                )
            }
            Warning::NoBootstrap { reason } => write!(f, "no bootstrap: {reason}"),
        }
    }
}
