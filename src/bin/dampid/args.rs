//! The command-line arguments of `dampid` (clap), with the examples `--help` prints.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use dampid::prep::quadrature::Quadrature;

const EXAMPLES: &str = "Examples:
  dampid init                                    # model.toml: an annotated template that runs as is
  dampid init runs/*.csv --out mine.toml         # a model file for your files: columns, time, periods
  dampid identify models/four_mass.toml          # simulate the paper's chain and identify c, d
  dampid identify models/four_mass.toml --json   # the report as one JSON object
  dampid identify models/measured_chain.toml --report out/   # also out/report.html, with plots
  dampid identify models/measured_chain.toml --bootstrap 500   # with bootstrap intervals
  dampid identify models/measured_chain.toml --bootstrap 500 --seed 7   # another draw
  dampid check models/measured_chain.toml        # periods, steady state and conditioning, before any fit
  dampid check models/measured_chain.toml --json # the same as one JSON object
  dampid identify models/four_mass_pod.toml      # the same chain reduced to two POMs (paper 3.1)
  dampid identify models/string.toml             # the string with eight sensors (paper 3.2.1)
  dampid identify models/four_mass_harmonic.toml # the harmonic approximation (paper eq. 4)
  dampid identify models/drive_nonperiodic.toml  # non-periodic closed-loop motion; mass as a nuisance estimate
  dampid pod models/data/chain3/record_1.csv --prefix x   # energy table of the POMs of columns x1, x2, …
  dampid compare models/measured_chain.toml models/measured_chain_no_friction.toml   # is friction needed?
  dampid compare models/bolted_joint_stepped_sine.toml --laws linear,quadratic,linear+coulomb,linear+power:1.5   # rank candidate laws
  dampid backbones models/backbones_ringdown.toml models/backbones_stepped.toml --report out/   # ringdown vs stepped sine
  dampid design models/per_dashpot.toml          # choose experiments that separate the coefficients
  dampid simulate models/four_mass.toml --out runs/   # write the simulated records as CSV
  dampid reference four-mass                     # the paper's section 2.2, every case

Exit codes: 0 success; 1 a fit that did not converge, a missed reference target, or a
design that does not reach its target, and with `identify --strict` also a coefficient
that is not determined, a window accepted although not in steady state, a failed
model check (χ²), or an estimated law parameter on one of its bounds; 2 bad input (model file, data, settings), or a window that is not in
steady state (--accept-transient accepts it).

Progress bars are drawn on stderr only when it is a terminal. From CSV files to a report,
step by step: docs/walkthrough.md.";

/// Identify damping laws of vibrating structures by balancing energy over cycles.
#[derive(Parser)]
#[command(version, about, long_about = None, after_help = EXAMPLES)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
    /// Refuse inputs that would allocate more than this (bytes; k, M, G, T suffixes,
    /// decimal). Default: the memory the system reports available.
    #[arg(long, global = true, value_name = "BYTES", value_parser = parse_bytes)]
    pub(crate) max_memory: Option<u64>,
    /// Run simulations and bootstraps estimated to take longer than a day.
    #[arg(long, global = true)]
    pub(crate) no_time_limit: bool,
}

/// `4G`, `512M`, `1.5e9`: a byte count with an optional decimal suffix.
fn parse_bytes(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let (number, scale) = match trimmed.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let scale = match c.to_ascii_uppercase() {
                'K' => 1e3,
                'M' => 1e6,
                'G' => 1e9,
                'T' => 1e12,
                _ => return Err(format!("unknown unit '{c}': use k, M, G or T")),
            };
            (&trimmed[..i], scale)
        }
        _ => (trimmed, 1.0),
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("'{text}' is not a size (e.g. 4G, 512M)"))?;
    let bytes = value * scale;
    if !(bytes.is_finite() && bytes >= 1.0) {
        return Err(format!("'{text}' is not a positive size"));
    }
    Ok(bytes.min(u64::MAX as f64) as u64)
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Write a first, annotated model file: from data files (CSV, NPY, NPZ, MAT, UFF),
    /// with their columns, a guessed time column and the periods detected from the
    /// force; or, from no file, a template that simulates a 2-DOF chain and runs as is.
    Init {
        /// Data files, one record each (none: the runnable template).
        files: Vec<PathBuf>,
        /// The model file to write.
        #[arg(long, default_value = "model.toml")]
        out: PathBuf,
        /// Replace an existing model file (it is never replaced otherwise).
        #[arg(long)]
        force: bool,
    },
    /// Identify the coefficients of a model file's damping model from its records.
    Identify {
        /// The model file (TOML).
        model: PathBuf,
        /// Print the report as one JSON object.
        #[arg(long)]
        json: bool,
        /// Also write a self-contained HTML report with plots to DIR/report.html.
        #[arg(long, value_name = "DIR")]
        report: Option<PathBuf>,
        /// Replace an existing DIR/report.html (it is never replaced otherwise).
        #[arg(long, requires = "report")]
        force: bool,
        /// Identify from windows that are not in steady state (they are reported).
        #[arg(long)]
        accept_transient: bool,
        /// Fit even when the input work is negative beyond its noise (a sign, DOF or
        /// phase convention is then likely wrong); sets accept_negative_work.
        #[arg(long)]
        accept_negative_work: bool,
        /// Also give 95% percentile intervals from N bootstrap refits on windows
        /// resampled with replacement.
        #[arg(long, value_name = "N")]
        bootstrap: Option<usize>,
        /// The bootstrap's seed: the same seed gives the same intervals, at any number
        /// of threads.
        #[arg(long, value_name = "SEED", default_value_t = 0, requires = "bootstrap")]
        seed: u64,
        /// Exit with 1 (after printing the report) when a coefficient is not
        /// determined, a window was accepted although not in steady state, the
        /// model check (χ² of the weighted fit) fails, or an estimated law parameter
        /// sits on one of its bounds; without it these are warnings and the exit code
        /// is 0.
        #[arg(long)]
        strict: bool,
    },
    /// Validate a model file and its data: detected periods, how far each window is
    /// from steady state, and the regressor's conditioning, before any fit.
    Check {
        /// The model file (TOML).
        model: PathBuf,
        /// Do not fail on windows that are not in steady state.
        #[arg(long)]
        accept_transient: bool,
        /// Do not fail on input work that is negative beyond its noise; sets
        /// accept_negative_work.
        #[arg(long)]
        accept_negative_work: bool,
        /// Print the check as one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Proper orthogonal modes of record files (CSV, NPY, NPZ, MAT): energy table.
    Pod {
        /// The record files; one decomposition per file unless --shared.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Displacement columns, comma-separated (default: every column but t/time).
        #[arg(long, value_delimiter = ',', conflicts_with = "prefix")]
        columns: Option<Vec<String>>,
        /// Displacement columns: every column whose name starts with PREFIX.
        #[arg(long)]
        prefix: Option<String>,
        /// One basis for all files, from their stacked samples.
        #[arg(long)]
        shared: bool,
        /// Remove each column's mean first (the paper does not).
        #[arg(long)]
        remove_mean: bool,
        /// Modes counted as retained in the table: the fewest reaching this energy share.
        #[arg(long, default_value_t = 0.999)]
        energy: f64,
        /// Print the decompositions as one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Compare two damping models on MODEL_A's records: AIC, BIC and, when nested, an
    /// F-test on the change in residual. MODEL_B contributes only its terms.
    Compare {
        /// The first model file; its records and identification settings are used.
        model_a: PathBuf,
        /// The second model file: only its dofs, [matrices] and [[terms]] are read, so a
        /// file of terms only will do.
        #[arg(required_unless_present = "laws", conflicts_with = "laws")]
        model_b: Option<PathBuf>,
        /// Instead of a second model file: candidate laws fitted on the first file's data
        /// and ranked, separated by commas, laws of one candidate joined by `+`, a power
        /// law's exponent after `:`, or `:est` to estimate it in [0.1, 5] (e.g.
        /// `linear,coulomb,linear+coulomb,linear+power:1.5,linear+power:est`).
        #[arg(long, value_delimiter = ',', value_name = "LAWS")]
        laws: Option<Vec<String>>,
        /// Print the comparison as one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Put the backbones ζ(X), f(X) of one mode from ringdowns ([free_decay]) and
    /// one-mode stepped-sine tables side by side: each job identified with its own
    /// settings, each later job's fitted ζ against the first's at common amplitudes.
    Backbones {
        /// Two model files or more, each a free decay or a one-DOF stepped-sine table.
        #[arg(num_args = 2.., required = true)]
        models: Vec<PathBuf>,
        /// Print the comparison as one JSON object.
        #[arg(long)]
        json: bool,
        /// Also write an HTML page with the plots to DIR/backbones.html.
        #[arg(long, value_name = "DIR")]
        report: Option<PathBuf>,
        /// Replace an existing DIR/backbones.html (it is never replaced otherwise).
        #[arg(long, requires = "report")]
        force: bool,
    },
    /// Choose among a model file's [simulation] experiments a set that makes the
    /// coefficients identifiable (settings in [design]).
    Design {
        /// The model file (TOML) with a [simulation] section (the candidates).
        model: PathBuf,
        /// Print the design report as one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Simulate a model file's [simulation] section and write one CSV per record.
    Simulate {
        /// The model file (TOML) with a [simulation] section.
        model: PathBuf,
        /// Output folder (created if missing): record_1.csv …, data.toml (the records as
        /// a [data] section, force columns named by DOF: f4 acts on DOF 4) and manifest.json.
        #[arg(long)]
        out: PathBuf,
        /// Replace another run's files in the folder (refused otherwise); the extra
        /// record files its manifest.json lists are removed, no other file.
        #[arg(long)]
        force: bool,
    },
    /// Simulate and identify a reference system from the paper.
    Reference {
        /// Which reference system.
        system: ReferenceSystem,
        /// Print one JSON object {"cases": [{"case", "report"}]} instead of a table.
        #[arg(long)]
        json: bool,
        /// Quadrature rule for the window integrals (the paper's is rectangular).
        #[arg(long, value_enum, default_value_t = Rule::Rectangular)]
        quadrature: Rule,
    },
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ReferenceSystem {
    /// Four-mass chain, C = cK plus quadratic damping, with and without a cubic spring.
    FourMass,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Rule {
    Rectangular,
    Trapezoid,
    Spectral,
}

impl From<Rule> for Quadrature {
    fn from(rule: Rule) -> Self {
        match rule {
            Rule::Rectangular => Quadrature::Rectangular,
            Rule::Trapezoid => Quadrature::Trapezoid,
            Rule::Spectral => Quadrature::Spectral,
        }
    }
}
