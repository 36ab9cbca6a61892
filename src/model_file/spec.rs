//! The TOML schema of a model file, as serde types. Unknown keys are rejected
//! (`deny_unknown_fields`); DOFs are numbered from 1 as engineers do, 0 meaning ground.
//! See `models/` and README.md for annotated examples.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use crate::analysis::design::Criterion;
use crate::fit::Relation;
use crate::prep::quadrature::Quadrature;

/// A whole model file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFileSpec {
    /// A title for reports.
    pub title: Option<String>,
    /// Number of DOFs (sensors) n.
    pub dofs: usize,
    /// Named matrices, n × n rows, for matrix terms and the simulation.
    #[serde(default)]
    pub matrices: BTreeMap<String, Spanned<Vec<Vec<f64>>>>,
    /// The damping model.
    pub terms: Vec<Spanned<TermSpec>>,
    /// How to identify.
    #[serde(default)]
    pub identification: IdentificationSpec,
    /// Generate the records by simulation.
    pub simulation: Option<Spanned<SimulationSpec>>,
    /// Read the records from files.
    pub data: Option<Spanned<DataSpec>>,
    /// Experiment design over the `[simulation]` experiments (`dampid design`).
    pub design: Option<Spanned<DesignSpec>>,
    /// Generate the records with the paper's string simulator (section 3.2.1).
    pub string_simulation: Option<Spanned<StringSimulationSpec>>,
    /// Mass and stiffness of measured data, for the steady-state energy check.
    pub system: Option<Spanned<SystemSpec>>,
    /// Reduce the records to their proper orthogonal modes before identifying.
    pub pod: Option<Spanned<PodSpec>>,
    /// Identify by the synchronous harmonic approximation (paper eq. 4).
    pub harmonic_approximation: Option<Spanned<HarmonicApproximationSpec>>,
    /// Identify from records that are not periodic, with stored energy and constant
    /// forces as extra unknowns (`dampid::regressor::nonperiodic`).
    pub non_periodic: Option<Spanned<NonPeriodicSpec>>,
    /// Read a measured stepped-sine table (`dampid::prep::harmonic::sweeps`) instead of
    /// records.
    pub stepped_sine: Option<Spanned<SteppedSineSpec>>,
    /// The units the numbers are in, for reports (`length = "m"`, `force = "N"`,
    /// `time = "s"`, `angle`, `mass`; [`crate::report::units`]).
    #[serde(default)]
    pub units: BTreeMap<String, Spanned<String>>,
}

/// `[stepped_sine]`: a measured stepped-sine table, one point per row: frequency, force
/// amplitude, and per DOF a response amplitude and phase. Every column may carry a gain
/// (value = `scale` × column + `offset`), e.g. `scale = 6.283185307179586` for a
/// frequency in Hz, `scale = 0.017453292519943295` for a phase in degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteppedSineSpec {
    /// The table file (CSV, NPY/NPZ, MAT), relative to the model file.
    pub file: String,
    /// Driving frequency ω (rad per unit time after the gain).
    pub frequency: ColumnSpec,
    /// Force amplitude a (the phase reference).
    pub force: ColumnSpec,
    /// The DOF the force acts on, 1-based (default 1).
    pub force_dof: Option<usize>,
    /// What the amplitude and phase columns measure: `"displacement"` (default),
    /// `"velocity"` or `"acceleration"`.
    #[serde(default)]
    pub response: crate::record::Sensor,
    /// Response amplitude per DOF (an entry without `dof` is the DOF of its position).
    pub amplitudes: Vec<Spanned<ColumnSpec>>,
    /// Response phase per DOF, in the order of `amplitudes`.
    pub phases: Vec<Spanned<ColumnSpec>>,
    /// `"lag"` (default): the response is X cos(ωt − φ); `"lead"`: X cos(ωt + φ), the
    /// phase of a frequency response function (−π/2 at resonance).
    #[serde(default)]
    pub phase_convention: PhaseConvention,
    /// A column whose distinct values group the points in sweeps (one force or
    /// response level each); without it all points are one sweep.
    pub sweep: Option<String>,
    /// σ of the force amplitude per point (a column, same gain as `force`) …
    pub force_std: Option<String>,
    /// … σ of each amplitude (columns, the gains of `amplitudes`) …
    pub amplitude_std: Option<Vec<String>>,
    /// … and σ of each phase (columns, the gains of `phases`); all three or none. Without
    /// them the noise is estimated from the scatter along each sweep.
    pub phase_std: Option<Vec<String>>,
    /// How the DOFs' common phase is read (as in `[harmonic_approximation]`).
    #[serde(default)]
    pub phase_reading: PhaseName,
    /// The DOF (1-based) whose lag is used with `phase_reading = "dof"`.
    pub phase_dof: Option<usize>,
    /// Structural damping terms: a loss factor on an element of given stiffness.
    #[serde(default)]
    pub structural: Vec<Spanned<StructuralSpec>>,
    /// The residual receptance of the out-of-band modes estimated per sweep with the
    /// damping: `"none"` (default), `"stiffness"` (r_k) or `"mass_and_stiffness"`
    /// (R = r_k − r_m/ω²); one-DOF tables with a `sweep` column.
    #[serde(default)]
    pub residual: crate::prep::harmonic::residual::ResidualKind,
    /// Bounds [lower, upper] of every sweep's r_k (default ± the sweep's smallest
    /// measured receptance X/a).
    pub residual_stiffness: Option<Spanned<[f64; 2]>>,
    /// Bounds [lower, upper] of every sweep's r_m (default ± that bound × the sweep's
    /// lowest ω²).
    pub residual_mass: Option<Spanned<[f64; 2]>>,
}

/// Which way a stepped-sine phase is counted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseConvention {
    /// x = X cos(ωt − φ): φ is the lag behind the force.
    #[default]
    Lag,
    /// x = X cos(ωt + φ): φ is the phase of the response (an FRF's phase).
    Lead,
}

/// `{ coefficient = "eta", stiffness = 2.0e5, element = [1, 0] }`: a loss factor η on
/// an element of stiffness k (DOFs 1-based, 0 = ground), dissipating π η k X² per cycle.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructuralSpec {
    /// The loss factor's name.
    pub coefficient: String,
    /// k.
    pub stiffness: f64,
    /// [a, b], 1-based, 0 = ground (default [1, 0]).
    pub element: Option<[usize; 2]>,
}

/// `[non_periodic]`: windows of a fixed length, and what stores energy.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonPeriodicSpec {
    /// Window length in time units.
    pub window: f64,
    /// `"each_dof"` (an unknown lumped mass per DOF, the default), `"none"`, or
    /// `{ known = <matrix> }`.
    #[serde(default)]
    pub mass: Option<StorageSpec>,
    /// `"none"` (the default), `"each_dof"`, `"chain"`, DOF pairs (an unknown spring
    /// per element), or `{ known = <matrix> }`.
    #[serde(default)]
    pub stiffness: Option<StorageSpec>,
    /// DOFs (1-based) with an unknown constant force, or `"each_dof"`.
    #[serde(default)]
    pub offsets: Option<OffsetsSpec>,
    /// Cut-off frequency f_c (cycles per time unit) of the zero-phase high-pass that
    /// treats the drift when velocity or acceleration columns are integrated
    /// (`dampid::prep::motion`); required with such columns, unused without.
    pub high_pass: Option<Spanned<f64>>,
}

/// A stored-energy term of `[non_periodic]`.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum StorageSpec {
    /// `"none"`, `"each_dof"`, `"chain"` or DOF pairs (1-based, 0 = ground).
    Elements(ElementsSpec),
    /// A known matrix.
    Known {
        /// The matrix (a name or rows).
        known: MatrixRef,
    },
}

/// The DOFs with a constant force.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum OffsetsSpec {
    /// `"each_dof"` or `"none"`.
    Named(String),
    /// DOFs, 1-based.
    Dofs(Vec<usize>),
}

/// `[system]`: what stores energy in measured data (never used by the fit).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SystemSpec {
    /// M.
    pub mass: MatrixRef,
    /// K.
    pub stiffness: MatrixRef,
    /// Grounded cubic springs k x³.
    #[serde(default)]
    pub cubic_springs: Vec<CubicSpec>,
}

/// `[pod]`: project every record on its leading proper orthogonal modes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PodSpec {
    /// Retain this many modes …
    pub modes: Option<usize>,
    /// … or the fewest whose cumulative energy share reaches this (default 0.999).
    pub energy: Option<f64>,
    /// One basis per record (default, the paper's) or one shared by all.
    #[serde(default)]
    pub basis: crate::prep::pod::PodBasis,
    /// Remove the column means before the decomposition (the paper does not).
    #[serde(default)]
    pub remove_mean: bool,
}

/// Phase readings of the harmonic approximation.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseName {
    /// Arithmetic mean lag (the paper's reading).
    #[default]
    ArithmeticMean,
    /// Circular mean lag.
    CircularMean,
    /// Amplitude-weighted circular mean lag.
    AmplitudeWeightedMean,
    /// The lag of one DOF (`dof`).
    Dof,
    /// Every DOF its own lag (not synchronous).
    PerDof,
}

/// `[harmonic_approximation]`: fundamentals per window (`[identification]` windows),
/// synchronous motion, eq. 4.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicApproximationSpec {
    /// How the DOFs' common phase is read.
    #[serde(default)]
    pub phase: PhaseName,
    /// The DOF (1-based) whose lag is used with `phase = "dof"`.
    pub dof: Option<usize>,
    /// Samples per synthesized period (default 512).
    pub samples_per_period: Option<usize>,
}

/// `[string_simulation]`: a uniform string on its linear modes, sensed at equally spaced
/// points, driven by a point load at each amplitude (`dampid::reference::string`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StringSimulationSpec {
    /// Tension T (default 1).
    #[serde(default = "unit")]
    pub tension: f64,
    /// Mass per unit length ρ (default 1).
    #[serde(default = "unit")]
    pub density: f64,
    /// Length L (default 1).
    #[serde(default = "unit")]
    pub length: f64,
    /// Load position L_a (a sensor position).
    pub force_position: f64,
    /// Driving frequency ω.
    pub frequency: f64,
    /// Load amplitudes a, one record each.
    pub amplitudes: Vec<f64>,
    /// Linear modes simulated.
    pub modes: usize,
    /// Points of the rectangular rule for the simulated damping integral.
    pub damping_points: usize,
    /// True coefficients by model name.
    pub coefficients: BTreeMap<String, f64>,
    /// The model coefficient that is the string's linear damping c ż.
    pub linear: String,
    /// The model coefficient that is the string's quadratic damping d ż|ż|.
    pub quadratic: String,
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step.
    #[serde(default = "one")]
    pub substeps: usize,
    /// Dropped steps.
    pub transient_steps: usize,
    /// Recorded steps.
    pub recorded_steps: usize,
}

fn unit() -> f64 {
    1.0
}

/// A matrix: a name from `[matrices]`, a built-in (`identity`, `chain`), or inline rows.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum MatrixRef {
    /// `"identity"`, `"chain"` (tridiag(−1, 2, −1), fixed at both ends) or a name.
    Name(String),
    /// Inline rows.
    Rows(Vec<Vec<f64>>),
}

/// One damping term.
#[derive(Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TermSpec {
    /// C = θ C₀ with a given C₀.
    Viscous {
        /// Coefficient name.
        coefficient: String,
        /// C₀.
        matrix: MatrixRef,
    },
    /// C = θ K.
    StiffnessProportional {
        /// Coefficient name.
        coefficient: String,
        /// K.
        matrix: MatrixRef,
    },
    /// C = θ M.
    MassProportional {
        /// Coefficient name.
        coefficient: String,
        /// M.
        matrix: MatrixRef,
    },
    /// A law on elements.
    Law {
        /// A name from the law registry (`dampid::terms::laws::Registry`): built in,
        /// `linear`, `quadratic`, `coulomb`, `power` or `expression`.
        law: String,
        /// The law's numeric parameters by name, `parameters = { exponent = 1.5 }`, each
        /// a number or estimated, `{ estimate = true, initial = …, lower = …, upper = … }`.
        #[serde(default)]
        parameters: BTreeMap<String, ParameterSpec>,
        /// `exponent = p`, shorthand for `parameters = { exponent = p }` (a power law's).
        exponent: Option<ParameterSpec>,
        /// f(x, v) of a law that takes an expression.
        expression: Option<String>,
        /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
        elements: ElementsSpec,
        /// One shared coefficient with this name …
        coefficient: Option<String>,
        /// … or one per element, named `prefix[label]`.
        per_element: Option<String>,
        /// Element weights (sensor spacing or area).
        weights: Option<Vec<f64>>,
    },
    /// A Bouc–Wen element on elements (`dampid::terms::history`).
    BoucWen(HistorySpec),
    /// A Dahl element on elements.
    Dahl(HistorySpec),
    /// A four-parameter Iwan joint on elements.
    Iwan(HistorySpec),
    /// Structural damping: a loss factor on elements of given stiffness
    /// (`dampid::terms::structural`), periodic windows only.
    Structural(StructuralTermSpec),
}

/// Structural damping on elements: `kind = "structural"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructuralTermSpec {
    /// Each element's stiffness k: one number for every element or a list, one per
    /// element.
    pub stiffness: StiffnessSpec,
    /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
    pub elements: ElementsSpec,
    /// One shared loss factor with this name …
    pub coefficient: Option<String>,
    /// … or one per element, named `prefix[label]`.
    pub per_element: Option<String>,
}

/// The stiffness of structural damping's elements.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum StiffnessSpec {
    /// The same stiffness for every element.
    Each(f64),
    /// One per element, in element order.
    PerElement(Vec<f64>),
}

/// A force with memory on elements: `kind = "bouc_wen"`, `"dahl"` or `"iwan"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistorySpec {
    /// The kind's shape parameters by name (`beta`, `gamma`, `n`; `x_c`, `exponent`;
    /// `phi_max`, `chi`, `beta`), each a number or `{ estimate = true, initial, lower,
    /// upper }`.
    #[serde(default)]
    pub parameters: BTreeMap<String, ParameterSpec>,
    /// `"each_dof"`, `"chain"` or a list of [a, b] DOF pairs (1-based, 0 = ground).
    pub elements: ElementsSpec,
    /// One shared coefficient with this name …
    pub coefficient: Option<String>,
    /// … or one per element, named `prefix[label]`.
    pub per_element: Option<String>,
}

/// A law parameter: a number, or estimated with the coefficients (variable projection,
/// `dampid::varpro`).
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum ParameterSpec {
    /// A fixed value.
    Value(f64),
    /// `{ estimate = true, initial = 1.5, lower = 0.5, upper = 4.0 }`.
    Estimated(EstimatedSpec),
}

/// An estimated law parameter; `initial`, `lower` and `upper` are all required (checked
/// when the term is built, so the error carries the term's line).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatedSpec {
    /// Must be true (a fixed parameter is written as a number).
    pub estimate: bool,
    /// Initial value, within the bounds.
    pub initial: Option<f64>,
    /// Lower bound.
    pub lower: Option<f64>,
    /// Upper bound.
    pub upper: Option<f64>,
}

/// Where a law acts.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum ElementsSpec {
    /// `"each_dof"` or `"chain"`.
    Named(String),
    /// DOF pairs, 1-based, 0 = ground.
    Pairs(Vec<[usize; 2]>),
}

/// Velocity source names.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocityName {
    /// Measured (or simulated) velocities.
    Measured,
    /// Central differences of the displacements.
    CentralDifference,
    /// Fourier series in harmonics of the drive (`harmonics` sets K).
    Spectral,
    /// Projection of whole periods on the harmonics above the noise floor (`harmonics`
    /// sets 1..K instead); with `noise = "auto"` the noise-robust pipeline.
    #[default]
    HarmonicProjection,
}

/// Bounds on one coefficient.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundSpec {
    /// Lower bound.
    pub lower: Option<f64>,
    /// Upper bound.
    pub upper: Option<f64>,
}

/// `[identification]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentificationSpec {
    /// Quadrature rule.
    pub quadrature: Quadrature,
    /// Velocity source (default: harmonic projection; central difference for
    /// `[non_periodic]`).
    pub velocity: Option<VelocityName>,
    /// K for spectral or harmonic-projection velocities.
    pub harmonics: Option<usize>,
    /// Noise correction: `"auto"` (with harmonic projection), `"ignore"`, `"correct"`.
    pub noise: crate::regressor::NoiseTreatment,
    /// Equation weights: `"auto"`, `"ordinary"`, `"propagated"`.
    pub weighting: crate::fit::Weighting,
    /// Input and Coulomb work: `"velocity"` or `"derivative_free"`.
    pub work_form: crate::regressor::WorkForm,
    /// Whole periods per window.
    pub cycles: usize,
    /// Windows per record (absent: as many as fit).
    pub windows: Option<usize>,
    /// Samples to skip at the start of each record.
    pub skip: usize,
    /// All coefficients ≥ 0.
    pub nonnegative: bool,
    /// Per-coefficient bounds.
    pub bounds: BTreeMap<String, BoundSpec>,
    /// Per-coefficient fixed values.
    pub fixed: BTreeMap<String, f64>,
    /// Linear relations between coefficients.
    pub constraints: Vec<LinearConstraintSpec>,
    /// Largest stored-energy mismatch |ΔE|/|W| of a steady window (M and K known).
    pub max_energy_mismatch: f64,
    /// Largest state mismatch of a steady window (M and K unknown).
    pub max_state_mismatch: f64,
    /// Identify from windows that are not steady (they are reported, not rejected).
    pub accept_transient: bool,
    /// Fit rows whose input work is negative beyond its noise
    /// ([`crate::regressor::passive`]).
    pub accept_negative_work: bool,
}

/// `{ terms = { "dashpot[0-1]" = 1, "dashpot[4-5]" = -1 }, relation = "=", value = 0 }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearConstraintSpec {
    /// Coefficient name → multiplier.
    pub terms: BTreeMap<String, f64>,
    /// `"="`, `"<="` or `">="`.
    pub relation: Relation,
    /// Right-hand side (default 0).
    #[serde(default)]
    pub value: f64,
}

/// `[design]`: how `dampid design` chooses among the `[simulation]` experiments.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignSpec {
    /// `"d_optimal"` (default) or `"condition"`.
    #[serde(default)]
    pub criterion: Criterion,
    /// Most experiments to add (default 3).
    pub picks: Option<usize>,
    /// Experiments always included, 1-based in the order of `[[simulation.experiments]]`.
    #[serde(default)]
    pub start: Vec<usize>,
    /// Stop once the column-scaled condition number falls below this.
    pub target_condition: Option<f64>,
}

impl Default for IdentificationSpec {
    fn default() -> Self {
        IdentificationSpec {
            quadrature: Quadrature::default(),
            velocity: None,
            harmonics: None,
            noise: crate::regressor::NoiseTreatment::default(),
            weighting: crate::fit::Weighting::default(),
            work_form: crate::regressor::WorkForm::default(),
            cycles: 1,
            windows: None,
            skip: 0,
            nonnegative: false,
            bounds: BTreeMap::new(),
            fixed: BTreeMap::new(),
            constraints: Vec::new(),
            max_energy_mismatch: crate::prep::steady_state::DEFAULT_MAX_ENERGY_MISMATCH,
            max_state_mismatch: crate::prep::steady_state::DEFAULT_MAX_STATE_MISMATCH,
            accept_transient: false,
            accept_negative_work: false,
        }
    }
}

/// `[simulation]`: M x'' + Q_d + K x + cubic springs = harmonic forces.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// M.
    pub mass: MatrixRef,
    /// K.
    pub stiffness: MatrixRef,
    /// True damping coefficients, by name (every coefficient of the model).
    pub coefficients: BTreeMap<String, f64>,
    /// True values of estimated law parameters, by their reported name
    /// (`"d.exponent" = 1.7`); one not given is simulated at its initial value.
    #[serde(default)]
    pub parameters: BTreeMap<String, f64>,
    /// Grounded cubic springs k x³.
    #[serde(default)]
    pub cubic_springs: Vec<CubicSpec>,
    /// Recording step h.
    pub step: f64,
    /// RK4 steps per recorded step.
    #[serde(default = "one")]
    pub substeps: usize,
    /// Dropped steps.
    pub transient_steps: usize,
    /// Recorded steps.
    pub recorded_steps: usize,
    /// One simulated record per experiment.
    pub experiments: Vec<Spanned<ExperimentSpec>>,
    /// Gaussian noise added to every recorded channel (displacements, velocities,
    /// forces), its standard deviation this fraction of the channel's RMS (default: none).
    pub noise: Option<f64>,
    /// Seed of the noise (default 0): the same seed gives the same records.
    #[serde(default)]
    pub noise_seed: u64,
}

fn one() -> usize {
    1
}

/// A grounded cubic spring.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CubicSpec {
    /// DOF, 1-based.
    pub dof: usize,
    /// k in k x³.
    pub coefficient: f64,
}

/// One simulated experiment: a cos(ωt + φ) on one DOF.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    /// DOF, 1-based.
    pub force_dof: usize,
    /// a.
    pub amplitude: f64,
    /// ω (rad per unit time).
    pub frequency: f64,
    /// φ (rad).
    #[serde(default)]
    pub phase: f64,
}

/// `[data]`: measured records.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DataSpec {
    /// One entry per record file.
    pub records: Vec<Spanned<RecordSpec>>,
}

/// One measured record in a data file with a header row.
///
/// Motion: per DOF exactly one of a displacement, velocity or acceleration column
/// (`displacements`, `velocities`, `accelerations`; an entry without `dof` is the DOF of
/// its position in the list). Displacements *and* velocities for every DOF keep their
/// older meaning: measured velocities beside the displacements (`velocity = "measured"`).
/// Every column may carry a gain: physical value = `scale` × column + `offset`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordSpec {
    /// Path, relative to the model file.
    pub file: String,
    /// A label (default: the file name).
    pub label: Option<String>,
    /// The time column (uniform step required) …
    pub time: Option<String>,
    /// … or the step h.
    pub step: Option<f64>,
    /// Time = `time_scale` × the time column (default 1), e.g. 1e-3 for milliseconds.
    pub time_scale: Option<Spanned<f64>>,
    /// Displacement columns.
    #[serde(default)]
    pub displacements: Vec<Spanned<ColumnSpec>>,
    /// Velocity columns (velocity sensors, or measured velocities beside displacements
    /// of every DOF).
    #[serde(default)]
    pub velocities: Vec<Spanned<ColumnSpec>>,
    /// Acceleration columns.
    #[serde(default)]
    pub accelerations: Vec<Spanned<ColumnSpec>>,
    /// Force columns and the DOF each acts on.
    pub forces: Vec<Spanned<ForceColumn>>,
    /// Driving period T …
    pub period: Option<f64>,
    /// … or driving frequency ω (rad per unit time); with neither, the period is
    /// detected from the force columns (`dampid::prep::period`).
    pub frequency: Option<f64>,
    /// DOFs (from 1) held still in this experiment: their motion columns may read a
    /// constant ([`crate::regressor::dead_motion`]).
    #[serde(default)]
    pub fixed_dofs: Option<Spanned<Vec<usize>>>,
}

/// A motion column: its name (`"x1"`), or `{ column = "qm", dof = 2, scale = 1e-3,
/// offset = 0.0 }` (all but `column` optional).
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSpec {
    /// Column name.
    pub column: String,
    /// DOF, 1-based (default: the entry's position in its list).
    pub dof: Option<usize>,
    /// Gain: physical value = scale × column + offset (default 1).
    pub scale: Option<f64>,
    /// Offset in physical units (default 0).
    pub offset: Option<f64>,
}

/// The table form of [`ColumnSpec`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ColumnTable {
    column: String,
    dof: Option<usize>,
    scale: Option<f64>,
    offset: Option<f64>,
}

impl<'de> Deserialize<'de> for ColumnSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = ColumnSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a column name or a table { column, dof, scale, offset }")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<ColumnSpec, E> {
                Ok(ColumnSpec {
                    column: name.to_string(),
                    dof: None,
                    scale: None,
                    offset: None,
                })
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<ColumnSpec, A::Error> {
                let t =
                    ColumnTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(ColumnSpec {
                    column: t.column,
                    dof: t.dof,
                    scale: t.scale,
                    offset: t.offset,
                })
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// A force column, the DOF (1-based) it acts on, and its gain.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceColumn {
    /// Column name.
    pub column: String,
    /// DOF, 1-based.
    pub dof: usize,
    /// Gain: force = scale × column + offset (default 1), e.g. 35.15 N/V.
    pub scale: Option<f64>,
    /// Offset in force units (default 0).
    pub offset: Option<f64>,
}
