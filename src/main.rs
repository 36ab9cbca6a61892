//! The `dampid` command line.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::{Parser, Subcommand, ValueEnum};
use dampid::io::pod_files::{Columns, PodTables, pod_of_files};
use dampid::model_file::{Job, load_with_progress};
use dampid::prep::pod::{PodBasis, PodSettings, Retain};
use dampid::prep::quadrature::Quadrature;
use dampid::prep::steady_state::SteadyStateReport;
use dampid::reference::FourMassSummary;
use dampid::regressor::Regressor;
use dampid::report::FitReport;
use dampid::report::html::HtmlReport;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;

const EXAMPLES: &str = "Examples:
  dampid identify models/four_mass.toml          # simulate the paper's chain and identify c, d
  dampid identify models/four_mass.toml --json   # the report as one JSON object
  dampid identify models/measured_chain.toml --report out/   # also out/report.html, with plots
  dampid identify models/measured_chain.toml --bootstrap 500   # with bootstrap intervals
  dampid check models/measured_chain.toml        # periods, steady state and conditioning, before any fit
  dampid identify models/four_mass_pod.toml      # the same chain reduced to two POMs (paper 3.1)
  dampid identify models/string.toml             # the string with eight sensors (paper 3.2.1)
  dampid identify models/four_mass_harmonic.toml # the harmonic approximation (paper eq. 4)
  dampid identify models/drive_nonperiodic.toml  # non-periodic closed-loop motion; mass as a nuisance estimate
  dampid pod models/data/chain3/record_1.csv --prefix x   # energy table of the POMs of columns x1, x2, …
  dampid compare models/measured_chain.toml models/measured_chain_no_friction.toml   # is friction needed?
  dampid design models/per_dashpot.toml          # choose experiments that separate the coefficients
  dampid simulate models/four_mass.toml --out runs/   # write the simulated records as CSV
  dampid reference four-mass                     # the paper's section 2.2, every case

Exit codes: 0 success; 1 a fit that did not converge, a missed reference target, or a
design that does not reach its target; 2 bad input (model file, data, settings), or a
window that is not in steady state (--accept-transient accepts it).

Progress bars are drawn on stderr only when it is a terminal. From CSV files to a report,
step by step: docs/walkthrough.md.";

/// Identify damping laws of vibrating structures by balancing energy over cycles.
#[derive(Parser)]
#[command(version, about, long_about = None, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
        /// Identify from windows that are not in steady state (they are reported).
        #[arg(long)]
        accept_transient: bool,
        /// Also give 95% percentile intervals from N bootstrap refits on windows
        /// resampled with replacement (seed 0).
        #[arg(long, value_name = "N")]
        bootstrap: Option<usize>,
    },
    /// Validate a model file and its data: detected periods, how far each window is
    /// from steady state, and the regressor's conditioning, before any fit.
    Check {
        /// The model file (TOML).
        model: PathBuf,
        /// Do not fail on windows that are not in steady state.
        #[arg(long)]
        accept_transient: bool,
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
        /// The second model file (its damping terms).
        model_b: PathBuf,
        /// Print the comparison as one JSON object.
        #[arg(long)]
        json: bool,
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
        /// Output folder (created if missing).
        #[arg(long)]
        out: PathBuf,
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
enum ReferenceSystem {
    /// Four-mass chain, C = cK plus quadratic damping, with and without a cubic spring.
    FourMass,
}

#[derive(Clone, Copy, ValueEnum)]
enum Rule {
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

/// What a command prints, and whether its numbers can be trusted.
struct Outcome {
    text: String,
    trusted: bool,
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(outcome) => {
            // A closed pipe (`dampid … | head`) is not an error of ours.
            let _ = std::io::stdout().lock().write_all(outcome.text.as_bytes());
            if outcome.trusted {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            }
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<Outcome> {
    match cli.command {
        Command::Identify {
            model,
            json,
            report,
            accept_transient,
            bootstrap,
        } => identify(&model, json, report.as_deref(), accept_transient, bootstrap),
        Command::Check {
            model,
            accept_transient,
        } => check(&model, accept_transient),
        Command::Pod {
            files,
            columns,
            prefix,
            shared,
            remove_mean,
            energy,
            json,
        } => pod(&files, columns, prefix, shared, remove_mean, energy, json),
        Command::Compare {
            model_a,
            model_b,
            json,
        } => compare(&model_a, &model_b, json),
        Command::Design { model, json } => design(&model, json),
        Command::Simulate { model, out } => write_records(&model, &out),
        Command::Reference {
            system: ReferenceSystem::FourMass,
            json,
            quadrature,
        } => {
            let summary = FourMassSummary::run(quadrature.into()).context("four-mass reference")?;
            let text = if json {
                format!("{}\n", serde_json::to_string_pretty(&summary.to_json())?)
            } else {
                summary.to_string()
            };
            Ok(Outcome {
                text,
                trusted: summary.all_pass(),
            })
        }
    }
}

/// A progress bar on stderr, hidden when stderr is not a terminal.
fn progress_bar(message: &'static str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template("{msg:>10} [{bar:40}] {percent:>3}% ({eta} left)")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    bar.set_style(style);
    bar.set_message(message);
    bar
}

/// Loads a model file with a progress bar over simulating or reading its records.
fn load_job(path: &Path) -> anyhow::Result<Job> {
    let bar = progress_bar("records");
    let job = load_with_progress(path, &|done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish_and_clear();
    Ok(job?)
}

/// Loads a model file and enforces steady state on its windows (unless accepted; the
/// non-periodic mode has no steady state to check).
fn load_steady_job(
    path: &Path,
    accept_transient: bool,
) -> anyhow::Result<(Job, Option<SteadyStateReport>)> {
    let mut job = load_job(path)?;
    job.steady_state.accept_transient |= accept_transient;
    let steady = job.steady_state()?;
    steady.as_ref().map_or(Ok(()), |s| s.enforce()).with_context(|| {
        format!(
            "{}: set accept_transient = true in [identification] or pass --accept-transient to use these windows anyway",
            path.display()
        )
    })?;
    Ok((job, steady))
}

/// The regressor with a spinner while it is built: it is built in one call (its rows
/// in parallel, and a noise model across them), so there is no per-record count to show.
fn build_regressor(job: &Job) -> anyhow::Result<Regressor> {
    let spinner = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    spinner.set_style(
        ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    spinner.set_message(format!(
        "building the regressor from {} records",
        job.records.len()
    ));
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    let regressor = job.regressor();
    spinner.finish_and_clear();
    Ok(regressor?)
}

fn identify(
    path: &Path,
    as_json: bool,
    html: Option<&Path>,
    accept_transient: bool,
    bootstrap: Option<usize>,
) -> anyhow::Result<Outcome> {
    let (job, steady) = load_steady_job(path, accept_transient)?;
    job.settings.fit.validate()?;
    let regressor = build_regressor(&job)?;
    let mut report = dampid::identify::identify_regressor(&regressor, &job.settings.fit)?;
    if let Some(replicates) = bootstrap {
        let settings = dampid::analysis::bootstrap::BootstrapSettings {
            replicates,
            ..Default::default()
        };
        let intervals =
            dampid::analysis::bootstrap::bootstrap(&regressor, &job.settings.fit, &settings)?;
        report = report.with_bootstrap(intervals);
    }
    let mut out = String::new();
    if let Some(folder) = html {
        let page = HtmlReport {
            title: &job.title,
            model: &job.model,
            records: &job.records,
            regressor: &regressor,
            report: &report,
            truth: job.truth.as_deref(),
            pod: job.pod.as_ref(),
        }
        .render()?;
        std::fs::create_dir_all(folder)
            .with_context(|| format!("creating {}", folder.display()))?;
        let file = folder.join("report.html");
        std::fs::write(&file, page).with_context(|| format!("writing {}", file.display()))?;
        // Keep stdout pure JSON with --json: say where the report went on stderr.
        eprintln!("wrote {}", file.display());
    }
    if as_json {
        let truth = job.truth.as_ref().map(|t| {
            t.iter()
                .map(|(n, v)| (n.clone(), json!(v)))
                .collect::<serde_json::Map<_, _>>()
        });
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&json!({
                "model": job.title,
                "report": report,
                "truth": truth,
                "steady_state": steady,
                "detected_periods": job.detected_periods,
                "pod": job.pod.as_ref().map(|r| r.reports()),
            }))?
        )?;
    } else {
        writeln!(out, "{}", job.title)?;
        writeln!(
            out,
            "{} records, {} equations",
            job.records.len(),
            report.residuals.len()
        )?;
        write_preamble(&mut out, &job, steady.as_ref())?;
        write!(out, "{report}")?;
        if let Some(truth) = &job.truth {
            write_truth(&mut out, &report, truth)?;
        }
    }
    Ok(Outcome {
        text: out,
        trusted: report.status.is_usable(),
    })
}

fn write_truth(out: &mut String, report: &FitReport, truth: &[(String, f64)]) -> std::fmt::Result {
    writeln!(out, "against the simulation's true coefficients:")?;
    for (name, value) in truth {
        if let Some(estimate) = report.coefficient(name) {
            let error = if *value != 0.0 {
                format!("{:+.3}%", 100.0 * (estimate - value) / value.abs())
            } else {
                format!("{:+.3e}", estimate - value)
            };
            writeln!(
                out,
                "  {name:<18} true {value:<12} estimate {estimate:<14.6e} error {error}"
            )?;
        }
    }
    Ok(())
}

/// What identify prints before the fit: detected periods, windows accepted although
/// not steady, the POD reduction and the harmonic approximation, when there are any.
fn write_preamble(
    out: &mut String,
    job: &Job,
    steady: Option<&SteadyStateReport>,
) -> std::fmt::Result {
    write_periods(out, job)?;
    if let Some(spans) = job.settings.regressor.windows.spans() {
        writeln!(
            out,
            "non-periodic energy balance: windows of {} time units, stored energy and constant forces as unknowns",
            spans.length
        )?;
    }
    let rejected: Vec<_> = steady.iter().flat_map(|s| s.rejected()).collect();
    if !rejected.is_empty() {
        writeln!(
            out,
            "warning: {} window(s) not in steady state, accepted (dampid check shows them)",
            rejected.len()
        )?;
    }
    if let Some(reduction) = &job.pod {
        let reports = reduction.reports();
        let retained = reports.iter().map(|r| r.retained).max().unwrap_or(0);
        writeln!(
            out,
            "POD: {} basis(es), {} mode(s) retained; energy share of the retained modes:",
            reports.len(),
            retained
        )?;
        for (k, r) in reports.iter().enumerate() {
            let label = match reduction.bases.len() {
                1 if job.source_records.len() > 1 => "all records (stacked)".to_string(),
                _ => job.source_records[k].label().to_string(),
            };
            let shares: Vec<String> = r
                .modes
                .iter()
                .map(|m| format!("{:.4}", 100.0 * m.energy_share))
                .collect();
            writeln!(
                out,
                "  {label:<32} retained {:.4}%, every mode [{}] %",
                100.0 * r.retained_share,
                shares.join(", ")
            )?;
        }
    }
    if let Some(table) = &job.harmonic {
        writeln!(
            out,
            "harmonic approximation (eq. 4): {} stepped-sine points, synchronous motion synthesized",
            table.points().len()
        )?;
    }
    Ok(())
}

fn write_periods(out: &mut String, job: &Job) -> std::fmt::Result {
    for (record, detected) in job.source_records.iter().zip(&job.detected_periods) {
        if let Some(p) = detected {
            writeln!(
                out,
                "period detected from the force of '{}': T = {:.9} (ω = {:.9}), {:.1} cycles, the fundamental explains {:.3}% of the force",
                record.label(),
                p.period,
                p.frequency,
                p.cycles,
                100.0 * p.explained
            )?;
        }
    }
    Ok(())
}

fn check(path: &Path, accept_transient: bool) -> anyhow::Result<Outcome> {
    let mut job = load_job(path)?;
    job.steady_state.accept_transient |= accept_transient;
    let steady = job.steady_state()?;
    let mut head = String::new();
    write_periods(&mut head, &job)?;
    match &steady {
        Some(steady) => write!(head, "{steady}")?,
        None => writeln!(
            head,
            "non-periodic mode: windows of {} time units, no steady state needed",
            job.settings
                .regressor
                .windows
                .spans()
                .map_or(0.0, |s| s.length)
        )?,
    }
    if let Some(Err(e)) = steady.as_ref().map(|s| s.enforce()) {
        // The table says which windows and by how much; print it with the error.
        eprint!("{head}");
        return Err(anyhow::Error::new(e).context(format!(
            "{}: set accept_transient = true in [identification] or pass --accept-transient to use these windows anyway",
            path.display()
        )));
    }
    job.settings.fit.validate()?;
    let regressor = build_regressor(&job)?;
    let fit = dampid::fit::least_squares(&regressor, job.settings.fit.rank_tolerance)
        .context("the regressor cannot be fitted")?;
    let diagnostics =
        dampid::analysis::diagnostics::diagnose(&regressor, &fit, job.settings.fit.rank_tolerance);
    let mut out = String::new();
    writeln!(out, "{}: model and data are valid", job.title)?;
    out.push_str(&head);
    writeln!(
        out,
        "{} records, {} equations, {} coefficients: {}",
        job.records.len(),
        regressor.equations(),
        regressor.columns().len(),
        regressor.columns().join(", ")
    )?;
    let sv: Vec<String> = diagnostics
        .singular_values
        .iter()
        .map(|s| format!("{s:.3e}"))
        .collect();
    writeln!(
        out,
        "singular values of the column-scaled regressor: [{}]",
        sv.join(", ")
    )?;
    writeln!(
        out,
        "numerical rank: {} of {}",
        diagnostics.rank,
        regressor.columns().len()
    )?;
    if diagnostics.condition_number.is_finite() {
        writeln!(
            out,
            "condition number: {:.3e}",
            diagnostics.condition_number
        )?;
    } else {
        writeln!(
            out,
            "condition number: infinite: these data cannot separate the coefficients"
        )?;
    }
    write!(out, "{}", diagnostics.identifiability)?;
    if let Some(c) = diagnostics
        .correlation
        .as_ref()
        .filter(|c| c.names.len() > 1)
    {
        write!(out, "{c}")?;
    }
    Ok(Outcome {
        text: out,
        trusted: true,
    })
}

fn pod(
    files: &[PathBuf],
    columns: Option<Vec<String>>,
    prefix: Option<String>,
    shared: bool,
    remove_mean: bool,
    energy: f64,
    as_json: bool,
) -> anyhow::Result<Outcome> {
    let choice = match (columns, prefix) {
        (Some(names), _) => Columns::Named(names),
        (None, Some(prefix)) => Columns::Prefix(prefix),
        (None, None) => Columns::AllButTime,
    };
    let settings = PodSettings {
        remove_mean,
        retain: Retain::Energy(energy),
        basis: if shared {
            PodBasis::Shared
        } else {
            PodBasis::PerRecord
        },
    };
    let pods = pod_of_files(files, &choice, &settings)?;
    let text = if as_json {
        format!(
            "{}\n",
            serde_json::to_string_pretty(&json!({ "decompositions": pods }))?
        )
    } else {
        PodTables(&pods).to_string()
    };
    Ok(Outcome {
        text,
        trusted: true,
    })
}

fn compare(first: &Path, second: &Path, as_json: bool) -> anyhow::Result<Outcome> {
    let job = load_job(first)?;
    let other = load_job(second)?;
    // Both models on the first file's records, windows and mode (in the non-periodic
    // mode both regressors carry the same nuisance columns).
    let comparison = dampid::analysis::compare::compare_regressors(
        (&first.display().to_string(), &job.regressor()?),
        (
            &second.display().to_string(),
            &job.regressor_of(&other.model)?,
        ),
        &dampid::analysis::compare::CompareSettings {
            rank_tolerance: job.settings.fit.rank_tolerance,
            ..Default::default()
        },
    )?;
    let text = if as_json {
        format!("{}\n", serde_json::to_string_pretty(&comparison)?)
    } else {
        format!(
            "records and identification settings of {}\n{comparison}",
            first.display()
        )
    };
    Ok(Outcome {
        text,
        trusted: true,
    })
}

fn design(path: &Path, as_json: bool) -> anyhow::Result<Outcome> {
    let job = load_job(path)?;
    if job.truth.is_none() {
        bail!(
            "{} has no [simulation] section: its experiments are the candidates a design chooses from",
            path.display()
        );
    }
    if job.settings.regressor.windows.spans().is_some() {
        bail!(
            "{}: design works on periodic windows; it does not support [non_periodic] yet",
            path.display()
        );
    }
    let settings = job.design.clone().unwrap_or_default();
    let report = dampid::analysis::design::select(
        &job.model,
        &job.records,
        &job.settings.regressor,
        &settings,
    )?;
    let text = if as_json {
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        format!(
            "{}: the [simulation] coefficients are the nominal damping\n{report}",
            job.title
        )
    };
    Ok(Outcome {
        text,
        trusted: report.succeeded(),
    })
}

fn write_records(path: &Path, folder: &Path) -> anyhow::Result<Outcome> {
    let job = load_job(path)?;
    if job.truth.is_none() {
        bail!(
            "{} has no [simulation] section: nothing to simulate",
            path.display()
        );
    }
    std::fs::create_dir_all(folder).with_context(|| format!("creating {}", folder.display()))?;
    let mut out = String::new();
    for (k, record) in job.source_records.iter().enumerate() {
        let file = folder.join(format!("record_{}.csv", k + 1));
        dampid::io::records::write_record(&file, record)?;
        writeln!(
            out,
            "{} ({}, period {:.6})",
            file.display(),
            record.label(),
            record.period()
        )?;
    }
    Ok(Outcome {
        text: out,
        trusted: true,
    })
}
