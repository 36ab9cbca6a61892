//! Bad input gets a typed error that names the offending field and value: never a
//! panic, never a silently wrong number.
//!
//! Every variant of [`dampid::Error`] is produced here through the public API
//! (`variants::every_variant_is_reachable`, checked against `dampid::error::KINDS`,
//! which the crate keeps complete with an exhaustive match). DOFs are numbered from 1
//! in every message, as in model files. Fixtures (`fixtures.rs`) are small hand-built records of
//! harmonic motion whose forces balance linear damping c = 0.3, and a 2-DOF chain to
//! simulate; every test changes exactly one thing.
//!
//! | variant | raised by | tests |
//! |---|---|---|
//! | `NonFinite` | `Record::new`; model matrices and element weights; regressor columns and `Regressor::from_parts`; `simulate` (mass matrix) | record, model, regressor, simulate, regressions |
//! | `DimensionMismatch` | `Record::new`; matrix terms and element weights; `Regressor::from_parts`; `simulate` (matrices, coefficients) | record, model, regressor, simulate, regressions, stepped_sine (`analysis::equivalent`) |
//! | `InvalidParameter` | `Record::new` (step, period, start time); window settings and spectral velocities; elements and power laws; constraint values and fit settings; `simulate` (settings, forces, coefficients); estimated law parameters' bounds and initial values, variable-projection settings | record, prep, model, fit, simulate, regressions, model_file, varpro |
//! | `InvalidChoice` | a setting that is a choice and does not fit: a spectral rule or velocity on non-periodic windows, noise correction without harmonic projection, propagated weights without a noise model, a bootstrap of whole sweeps from a single sweep or of a variable-projection report that is not an estimate, an expression for a law that takes none, one key or another (`time`/`step`, `coefficient`/`per_element`), element `[0, 0]`, a history term in non-periodic spans, the noise-robust rows or the simulator, a structural term in non-periodic spans or the simulator | variants, model_file (tests/), noise (tests/), nonperiodic (tests/), registry (tests/), history, structural, varpro_bootstrap |
//! | `Missing` | a law parameter the law needs; an estimated parameter's `initial`, `lower` or `upper`; a `[simulation]` coefficient; `dof` for `phase = "dof"` | model_file, variants, registry (tests/) |
//! | `RecordTooShort` | `Record::new` (under three samples); windows that do not fit a record | record, prep, regressions |
//! | `TooFewEquations` | the fit: fewer rows than free coefficients | fit |
//! | `DofOutOfRange` | `Record::new` (force channels); model elements; `simulate` (springs, forces, elements) | record, model, simulate |
//! | `Empty` | `Record::new` (no DOFs); an empty model or term; no records; `simulate` (no forcing, no DOFs) | record, model, regressor, simulate |
//! | `MotionSensors` | a model file's `[[data.records]]` with a DOF that has no motion column or two kinds (displacement, velocity, acceleration) | variants, record |
//! | `DuplicateCoefficient` | model validation | model |
//! | `UnknownCoefficient` | constraints naming a coefficient the model lacks | fit |
//! | `InfeasibleBounds` | bounds and fixed values that admit no value | fit, regressions |
//! | `MissingVelocities` | measured velocities on a record without them | prep |
//! | `Numerical` | `simulate` (singular mass, divergence, NaN forces); a bootstrap keeping fewer than half its replicates | simulate, regressions, varpro_bootstrap |
//! | `Expression` | `Expression::parse` (the model-file law) | model_file |
//! | `ModelFile` | `model_file::parse`, at the line of the block concerned, keeping the typed `cause` | model_file, regressions |
//! | `UnknownName` | `Table::column` | data_files |
//! | `Data` | `io::csv::parse`, `io::read_mat`, `io::npy::read_npy` (a header claiming more data than the file holds), `io::uff::parse` (tests/uff.rs), `io::read_table` of a damaged `.npz` (tests/formats.rs); MAT struct sweeps, named scales and struct files with nothing to read (mat_structs); damaged, plain-HDF5 and self-referring MAT v7.3 files (mat73); a time column that does not increase (`Table::uniform_step`) | data_files |
//! | `TimeJitter` | `Table::uniform_step`: time steps departing from their mean by more than `io::table::MAX_TIME_JITTER` | variants, data_files |
//! | `NoPeriod` | `prep::period::detect_period` | prep |
//! | `NotSteady` | `prep::steady_state` (`enforce`) | prep |
//! | `NoInputWork` | `Regressor::build` (`regressor::input_work`): a record whose force channels read zero or are absent, a window whose net work is nothing beside its gross work | variants, regressor, degenerate (tests/), nonperiodic (tests/), cli (tests/) |
//! | `NoInformation` | `identify_regressor` and `RegressorCheck::new` (`analysis::identifiability::require_information`): every column of the regressor zero | variants, regressor, degenerate (tests/), cli (tests/) |
//! | `InfeasibleConstraints` | the constrained fit: linear constraints that no coefficients meet (clarabel's infeasibility certificate) | variants, constraints (tests/) |
//! | `TooLarge` | `budget::require` before allocations sized by input (simulated records, named `dofs` × `dofs` matrices, bootstrap replicates), `budget::Stopwatch`/`require_time` for work estimated past the time limit (simulation, bootstrap) | variants, simulate, cli (tests/) |
//! | `OutputExists` | `io::output` (every file dampid writes): the target exists and `Overwrite::Refuse` | variants, data_files, outputs (tests/), `io::output` unit tests |
//! | `Output` | `io::output`: the temporary file cannot be created, written or renamed | variants, data_files |
//! | `NegativeInputWork` | `identify_regressor` and `RegressorCheck::new` (`regressor::passive`): input work negative beyond its noise in a record or sweep, or overall | variants, physics, physics (tests/) |
//! | `DeadMotionSensor` | `Regressor::build` (`regressor::dead_motion`): a motion channel that never moves while others do | variants, physics, physics (tests/) |
//! | `DataScale` | `Regressor::build` and `steady_state::check` (`prep::data_scale`): a record's largest displacement, velocity or force outside 2^±505 | variants, physics, invariants (tests/) |
//! | `Incomparable` | `analysis::backbones::compare` (length or time units that differ), `command::backbones::job_backbone` (a job without one mode's backbone) | variants, backbones |

mod backbones;
mod data_files;
mod fit;
mod fixtures;
mod free_decay;
mod history;
mod limits;
mod mat73;
mod mat_structs;
#[path = "../support/mat_writer.rs"]
mod mat_writer;
mod messages;
mod model;
mod model_file;
#[path = "../support/npy.rs"]
mod npy_file;
mod physics;
mod prep;
mod record;
mod regressions;
mod regressor;
mod simulate;
mod stepped_sine;
mod structural;
#[path = "../support/mod.rs"]
mod support;
#[path = "../support/stepped_sine_table.rs"]
mod table;
mod variants;
mod varpro;
mod varpro_bootstrap;
