//! The `dampid` command line: parse the arguments (args.rs), run the command through
//! the library, print what it returns. The library composes every report; this file
//! only draws progress bars, writes the HTML page where asked, and maps errors and
//! untrusted results to exit codes 2 and 1. Ctrl-C sets `dampid::cancel`: the running
//! work stops at its next step, nothing is written, and the exit code is 130 (128 +
//! SIGINT, as a shell reports a process stopped by Ctrl-C).

mod args;

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::Parser;
use dampid::analysis::bootstrap::{BootstrapSettings, bootstrap_groups, bootstrap_with_progress};
use dampid::io::output::Overwrite;
use dampid::io::pod_files::{Columns, PodTables, pod_of_files};
use dampid::model_file::{CheckReport, Job, load_with_progress};
use dampid::prep::pod::{PodBasis, PodSettings, Retain};
use dampid::prep::steady_state::SteadyStateReport;
use dampid::reference::FourMassSummary;
use dampid::regressor::Regressor;
use dampid::report::count;
use dampid::report::html::HtmlReport;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;

use args::{Cli, Command, ReferenceSystem};

/// The allocator: returns freed buffers to the system (see Cargo.toml), so that peak
/// memory follows the data, not the allocator's arenas.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// What a command prints, and whether its numbers can be trusted.
struct Outcome {
    text: String,
    trusted: bool,
}

fn main() -> ExitCode {
    // faer's default parallelism splits each product and decomposition over all of rayon's
    // threads, and how it splits changes the rounding. dampid's own parallelism (windows,
    // kernel passes, bootstrap replicates, design candidates) collects in index order, so
    // with faer sequential every result is bitwise the same at any RAYON_NUM_THREADS
    // (tests/threads.rs).
    faer::set_global_parallelism(faer::Par::Seq);
    // Without a handler Ctrl-C would kill the process mid-step; with it the library
    // returns Error::Cancelled at its next check and the temporary files are removed.
    // If the handler cannot be installed, Ctrl-C keeps its default (outputs are still
    // written through temporary files, so none is left partial).
    let _ = signal_hook::flag::register(signal_hook::consts::SIGINT, dampid::cancel::flag());
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
            let cancelled = e
                .chain()
                .filter_map(|cause| cause.downcast_ref::<dampid::Error>())
                .any(|cause| matches!(cause.innermost(), dampid::Error::Cancelled { .. }));
            ExitCode::from(if cancelled { 130 } else { 2 })
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<Outcome> {
    if let Some(bytes) = cli.max_memory {
        dampid::budget::set_max_memory(bytes);
    }
    if cli.no_time_limit {
        dampid::budget::set_time_limit(None);
    }
    match cli.command {
        Command::Init { files, out, force } => init(&files, &out, Overwrite::from_force(force)),
        Command::Identify {
            model,
            json,
            report,
            force,
            accept_transient,
            accept_negative_work,
            bootstrap,
            seed,
            strict,
        } => {
            NEGATIVE_WORK.store(accept_negative_work, std::sync::atomic::Ordering::Relaxed);
            let bootstrap = bootstrap.map(|replicates| BootstrapSettings {
                replicates,
                seed,
                ..Default::default()
            });
            let report =
                report.map(|folder| (folder.join("report.html"), Overwrite::from_force(force)));
            identify(&model, json, report, accept_transient, bootstrap, strict)
        }
        Command::Check {
            model,
            accept_transient,
            accept_negative_work,
            json,
        } => {
            NEGATIVE_WORK.store(accept_negative_work, std::sync::atomic::Ordering::Relaxed);
            check(&model, accept_transient, json)
        }
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
            laws,
            json,
        } => match (model_b, laws) {
            (Some(model_b), _) => compare(&model_a, &model_b, json),
            (None, Some(laws)) => rank_laws(&model_a, &laws, json),
            (None, None) => bail!("give a second model file or --laws"),
        },
        Command::Design { model, json } => design(&model, json),
        Command::Simulate { model, out, force } => {
            write_records(&model, &out, Overwrite::from_force(force))
        }
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

/// `progress(done, total)` drawn on `bar` (hidden when stderr is not a terminal).
fn on_bar(bar: &ProgressBar) -> impl Fn(u64, u64) + Sync + '_ {
    move |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    }
}

/// `--accept-negative-work` of `identify` or `check`, copied into the job's
/// `accept_negative_work` when it is loaded.
static NEGATIVE_WORK: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Loads a model file with a progress bar over simulating or reading its records.
fn load_job(path: &Path) -> anyhow::Result<Job> {
    let bar = progress_bar("records");
    let job = load_with_progress(path, &on_bar(&bar));
    bar.finish_and_clear();
    let mut job = job?;
    job.settings.fit.accept_negative_work |=
        NEGATIVE_WORK.load(std::sync::atomic::Ordering::Relaxed);
    Ok(job)
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
/// Estimated parameters, if any, stand at their initial values (`dampid check`).
fn build_regressor(job: &Job) -> anyhow::Result<Regressor> {
    let spinner = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    spinner.set_style(
        ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    spinner.set_message(format!(
        "building the regressor from {}",
        count(job.records.len(), "record")
    ));
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    let regressor = job.initial_regressor();
    spinner.finish_and_clear();
    Ok(regressor?)
}

fn identify(
    path: &Path,
    as_json: bool,
    html: Option<(PathBuf, Overwrite)>,
    accept_transient: bool,
    bootstrap: Option<BootstrapSettings>,
    strict: bool,
) -> anyhow::Result<Outcome> {
    // Refuse an existing report before any work, and again when it is renamed into place.
    if let Some((file, Overwrite::Refuse)) = &html {
        dampid::io::output::refuse_existing(file)?;
    }
    let (job, steady) = load_steady_job(path, accept_transient)?;
    job.settings.fit.validate()?;
    if let Some(mut fit) = job.identify_varpro().transpose()? {
        // Windows accepted although not in steady state are warnings of the linear fit
        // at η̂ too (and failures under --strict), as on the linear path.
        fit.report.fit = fit.report.fit.with_steady_state(steady.as_ref());
        let fit = match &bootstrap {
            Some(settings) if fit.report.is_estimate() => {
                let bar = progress_bar("bootstrap");
                let result = bootstrap_varpro(&job, &fit.report, settings, &on_bar(&bar));
                bar.finish_and_clear();
                dampid::model_file::VarProFit {
                    report: fit.report.with_bootstrap(result?),
                    ..fit
                }
            }
            Some(_) => {
                eprintln!(
                    "no bootstrap: the variable projection did not reach an estimate, so there is none to resample around"
                );
                fit
            }
            None => fit,
        };
        return identify_varpro(
            path,
            &job,
            &fit,
            steady.as_ref(),
            as_json,
            html,
            accept_transient,
            bootstrap.as_ref(),
            strict,
        );
    }
    let regressor = build_regressor(&job)?;
    let mut report = dampid::identify::identify_regressor(&regressor, &job.settings.fit)?
        .with_velocity_noise(dampid::analysis::velocity_noise::assess_or_none(
            &job.model,
            &job.records,
            &job.settings.regressor,
            &regressor,
        ))
        .with_steady_state(steady.as_ref());
    let flags = identify_flags(accept_transient, bootstrap.as_ref(), strict);
    if let Some(settings) = bootstrap {
        // Stepped-sine tables: errors are correlated within a sweep, so whole sweeps
        // are resampled.
        let bar = progress_bar("bootstrap");
        let intervals = match job.sweeps() {
            Some(sweeps) => bootstrap_groups(
                &regressor,
                &job.settings.fit,
                &settings,
                sweeps,
                &on_bar(&bar),
            ),
            None => {
                bootstrap_with_progress(&regressor, &job.settings.fit, &settings, &on_bar(&bar))
            }
        };
        bar.finish_and_clear();
        let intervals = intervals?;
        report = report.with_bootstrap(intervals);
    }
    let equivalent = job.equivalent_damping(&report);
    let mut out = String::new();
    if let Some((file, overwrite)) = html {
        let page = HtmlReport {
            title: &job.title,
            model: &job.model,
            records: &job.records,
            regressor: &regressor,
            report: &report,
            truth: job.truth.as_deref(),
            pod: job.pod.as_ref(),
            steady: steady.as_ref(),
            provenance: Some(&job.provenance(path, &flags)?),
            units: Some(&job.units),
        }
        .render_with(equivalent.as_ref().and_then(|e| e.as_ref().ok()))?;
        write_page(&file, overwrite, &page)?;
    }
    if as_json {
        let truth = truth_json(&job);
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
                "equivalent_damping": equivalent.as_ref().map(|e| match e {
                    Ok(e) => json!(e),
                    Err(e) => json!({ "error": e.to_string() }),
                }),
            }))?
        )?;
    } else {
        writeln!(out, "{}", job.title)?;
        writeln!(
            out,
            "{}, {}",
            count(job.records.len(), "record"),
            count(report.residuals.len(), "equation")
        )?;
        write!(out, "{}{report}", job.preamble(steady.as_ref()))?;
        if let Some(truth) = &job.truth {
            write!(out, "{}", report.against(truth))?;
        }
        match &equivalent {
            Some(Ok(e)) => write!(out, "{e}")?,
            Some(Err(e)) => writeln!(out, "equivalent damping not computed: {e}")?,
            None => {}
        }
    }
    let passes = passes_strict(strict, || report.strict_failures());
    Ok(Outcome {
        text: out,
        trusted: report.status.is_usable() && passes,
    })
}

/// The command line's own settings of `dampid identify`, for the provenance.
fn identify_flags(
    accept_transient: bool,
    bootstrap: Option<&BootstrapSettings>,
    strict: bool,
) -> Vec<(String, String)> {
    vec![
        (
            "command line".to_string(),
            std::env::args().collect::<Vec<_>>().join(" "),
        ),
        (
            "--accept-transient".to_string(),
            if accept_transient {
                "given (accept_transient = true whatever [identification] says)".to_string()
            } else {
                "not given".to_string()
            },
        ),
        (
            "--bootstrap".to_string(),
            bootstrap.map_or("not given".to_string(), |b| {
                format!(
                    "{} replicates, seed {}, {}% percentile intervals",
                    b.replicates,
                    b.seed,
                    100.0 * b.level
                )
            }),
        ),
        (
            "--strict".to_string(),
            if strict { "given" } else { "not given" }.to_string(),
        ),
    ]
}

/// With `--strict`, prints each of `failures` on stderr; true when there are none (or
/// without `--strict`).
fn passes_strict(strict: bool, failures: impl FnOnce() -> Vec<String>) -> bool {
    let failures = if strict { failures() } else { Vec::new() };
    for failure in &failures {
        eprintln!("strict: {failure}");
    }
    failures.is_empty()
}

/// `dampid identify` of a job with estimated nonlinear parameters (its variable-projection
/// `fit`): the report, the equivalent damping of a one-mode stepped-sine job at η̂, and
/// the HTML page where asked.
/// Percentile intervals of a variable-projection fit from refits on resampled data:
/// whole sweeps of a stepped-sine table, windows of records.
fn bootstrap_varpro(
    job: &Job,
    report: &dampid::varpro::VarProReport,
    settings: &BootstrapSettings,
    progress: dampid::progress::Progress<'_>,
) -> anyhow::Result<dampid::varpro::VarProBootstrap> {
    let varpro = job.varpro_settings();
    Ok(
        match (job.parametric_regressor().transpose()?, &job.parametric) {
            (Some(regressor), _) => dampid::varpro::bootstrap_varpro_regressor(
                &regressor,
                job.sweeps(),
                &job.settings,
                &varpro,
                report,
                settings,
                progress,
            )?,
            (None, Some(parametric)) => dampid::varpro::bootstrap_varpro(
                parametric,
                &job.records,
                &job.settings,
                &varpro,
                report,
                settings,
                progress,
            )?,
            (None, None) => {
                anyhow::bail!("nothing is estimated by variable projection in this job")
            }
        },
    )
}

#[allow(clippy::too_many_arguments)]
fn identify_varpro(
    path: &Path,
    job: &Job,
    fit: &dampid::model_file::VarProFit,
    steady: Option<&SteadyStateReport>,
    as_json: bool,
    html: Option<(PathBuf, Overwrite)>,
    accept_transient: bool,
    bootstrap: Option<&BootstrapSettings>,
    strict: bool,
) -> anyhow::Result<Outcome> {
    let report = &fit.report;
    // Not an estimate: no equivalent damping either (the text report's rule).
    let equivalent = job
        .equivalent_damping_varpro(&fit.model, report)
        .map(|e| match e {
            Ok(_) if !report.is_estimate() => Err("the fit is not an estimate".to_string()),
            e => e.map_err(|e| e.to_string()),
        });
    if let Some((file, overwrite)) = html {
        let flags = identify_flags(accept_transient, bootstrap, strict);
        let page = HtmlReport {
            title: &job.title,
            model: &fit.model,
            records: &job.records,
            regressor: &fit.regressor,
            report: &report.fit,
            truth: job.truth.as_deref(),
            pod: job.pod.as_ref(),
            steady,
            provenance: Some(&job.provenance(path, &flags)?),
            units: Some(&job.units),
        }
        .render_varpro(report, equivalent.as_ref().and_then(|e| e.as_ref().ok()))?;
        write_page(&file, overwrite, &page)?;
    }
    let mut out = String::new();
    if as_json {
        let truth = truth_json(job);
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&json!({
                "model": job.title,
                "varpro": report,
                "truth": truth,
                "steady_state": steady,
                "detected_periods": job.detected_periods,
                "equivalent_damping": equivalent.as_ref().map(|e| match e {
                    Ok(e) => json!(e),
                    Err(e) => json!({ "error": e }),
                }),
            }))?
        )?;
    } else {
        writeln!(out, "{}", job.title)?;
        write!(out, "{report}")?;
        match &equivalent {
            Some(Ok(e)) => write!(out, "{e}")?,
            Some(Err(e)) => writeln!(out, "equivalent damping not computed: {e}")?,
            None => {}
        }
    }
    let passes = passes_strict(strict, || report.strict_failures());
    Ok(Outcome {
        text: out,
        trusted: report.is_estimate() && passes,
    })
}

/// Writes the HTML `page` to `file` (its folder created) and says so on stderr (stdout
/// stays pure JSON with --json).
fn write_page(file: &Path, overwrite: Overwrite, page: &str) -> anyhow::Result<()> {
    if let Some(folder) = file.parent() {
        std::fs::create_dir_all(folder)
            .with_context(|| format!("creating {}", folder.display()))?;
    }
    dampid::io::output::write_file(file, overwrite, |sink| {
        sink.write_all(page.as_bytes())
            .map_err(|e| dampid::Error::Output {
                path: file.display().to_string(),
                message: e.to_string(),
            })
    })?;
    eprintln!("wrote {}", file.display());
    Ok(())
}

fn init(files: &[PathBuf], out: &Path, overwrite: Overwrite) -> anyhow::Result<Outcome> {
    use dampid::model_file::init::{InitRecord, init as annotated, path_in_model};
    // Refuse an existing model file before reading any data, and again at the rename.
    if overwrite == Overwrite::Refuse {
        dampid::io::output::refuse_existing(out)?;
    }
    let records = files
        .iter()
        .map(|file| {
            let table = dampid::io::read_table(file)?;
            Ok(InitRecord::guess(&path_in_model(file, out), &table))
        })
        .collect::<dampid::Result<Vec<_>>>()?;
    let model = annotated(records);
    dampid::io::output::write_file(out, overwrite, |sink| {
        sink.write_all(model.text.as_bytes())
            .map_err(|e| dampid::Error::Output {
                path: out.display().to_string(),
                message: e.to_string(),
            })
    })?;
    Ok(Outcome {
        text: format!("wrote {}: {model}next: dampid check {0}\n", out.display()),
        trusted: true,
    })
}

fn check(path: &Path, accept_transient: bool, as_json: bool) -> anyhow::Result<Outcome> {
    let mut job = load_job(path)?;
    job.steady_state.accept_transient |= accept_transient;
    let steady = job.steady_state()?;
    if let Some(Err(e)) = steady.as_ref().map(|s| s.enforce()) {
        // The table says which windows and by how much; print it with the error.
        if let Some(steady) = &steady {
            eprint!("{}{steady}", job.periods());
        }
        return Err(anyhow::Error::new(e).context(format!(
            "{}: set accept_transient = true in [identification] or pass --accept-transient to use these windows anyway",
            path.display()
        )));
    }
    job.settings.fit.validate()?;
    let regressor = build_regressor(&job)?;
    let report =
        CheckReport::new(&job, steady, &regressor).context("the regressor cannot be fitted")?;
    let text = if as_json {
        format!("{}\n", serde_json::to_string_pretty(&report)?)
    } else {
        report.to_string()
    };
    Ok(Outcome {
        text,
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
    // Only model B's terms are used: its records, if it has any, are not simulated or read.
    let (other, other_law) = dampid::model_file::load_parametric_model(second)?;
    // Both models on the first file's records, windows and mode (in the non-periodic
    // mode both regressors carry the same nuisance columns); estimated parameters (and
    // the first file's residual receptances) at their least-squares values.
    let a = job.compared(
        &first.display().to_string(),
        &job.model,
        job.parametric.as_ref(),
    )?;
    let b = job.compared(&second.display().to_string(), &other, other_law.as_ref())?;
    let comparison = dampid::analysis::compare::compare_candidates(
        a.candidate(),
        b.candidate(),
        &dampid::analysis::compare::CompareSettings {
            rank_tolerance: job.settings.fit.rank_tolerance,
            ..Default::default()
        },
    )?;
    on_records_of(&comparison, first, as_json)
}

/// A comparison's output: JSON, or its text under the name of the model file whose
/// records and settings it used.
fn on_records_of(
    result: &(impl serde::Serialize + std::fmt::Display),
    source: &Path,
    as_json: bool,
) -> anyhow::Result<Outcome> {
    let text = if as_json {
        format!("{}\n", serde_json::to_string_pretty(result)?)
    } else {
        format!(
            "records and identification settings of {}\n{result}",
            source.display()
        )
    };
    Ok(Outcome {
        text,
        trusted: true,
    })
}

/// Candidate laws fitted on the data of one model file and ranked.
fn rank_laws(path: &Path, laws: &[String], as_json: bool) -> anyhow::Result<Outcome> {
    let job = load_job(path)?;
    let dofs = job.records.first().map_or(1, |r| r.dofs());
    let registry = dampid::terms::laws::Registry::builtin();
    let regressors = laws
        .iter()
        .map(|spec| {
            let (model, law) = dampid::model_file::candidate(spec, dofs, &registry)
                .with_context(|| format!("candidate '{spec}'"))?;
            // Its estimated exponents and the table's residual receptances (if the job
            // estimates them) at their least-squares values.
            job.compared(spec, &model, law.as_ref())
                .with_context(|| format!("candidate '{spec}'"))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let candidates: Vec<_> = regressors.iter().map(|c| c.candidate()).collect();
    let ranking = dampid::analysis::compare::rank_candidates(
        &candidates,
        &dampid::analysis::compare::CompareSettings {
            rank_tolerance: job.settings.fit.rank_tolerance,
            ..Default::default()
        },
    )?;
    on_records_of(&ranking, path, as_json)
}

fn design(path: &Path, as_json: bool) -> anyhow::Result<Outcome> {
    let job = load_job(path)?;
    if job.truth.is_none() {
        bail!(
            "{} has no [simulation] section: its experiments are the candidates a design chooses from",
            path.display()
        );
    }
    let settings = job.design.clone().unwrap_or_default();
    let bar = progress_bar("design");
    let report = dampid::analysis::design::select_with_progress(
        &job.model,
        &job.records,
        &job.settings.regressor,
        &settings,
        &on_bar(&bar),
    );
    bar.finish_and_clear();
    let report = report?;
    let text = if as_json {
        // The report, with the selected experiments as data and as the TOML to paste:
        // the JSON stands alone.
        let mut json = serde_json::to_value(&report)?;
        if let Some(object) = json.as_object_mut() {
            object.insert(
                "selected_experiments".into(),
                serde_json::to_value(dampid::model_file::selected_experiments(
                    &report,
                    &job.experiments,
                ))?,
            );
            object.insert(
                "selected_experiments_toml".into(),
                json!(dampid::model_file::selected_experiments_toml(
                    &report,
                    &job.experiments
                )),
            );
        }
        format!("{}\n", serde_json::to_string_pretty(&json)?)
    } else {
        format!(
            "{}: the [simulation] coefficients are the nominal damping\n{report}\n{}",
            job.title,
            dampid::model_file::selected_experiments_toml(&report, &job.experiments)
        )
    };
    Ok(Outcome {
        text,
        trusted: report.succeeded(),
    })
}

fn write_records(path: &Path, folder: &Path, overwrite: Overwrite) -> anyhow::Result<Outcome> {
    let job = load_job(path)?;
    if job.truth.is_none() {
        bail!(
            "{} has no [simulation] section: nothing to simulate",
            path.display()
        );
    }
    // Ctrl-C after the last simulation step: still nothing written.
    dampid::cancel::check("simulate --out")?;
    let source = path.display().to_string();
    let run = dampid::io::run::write_run(folder, &job.source_records, &source, overwrite)?;
    let mut out = String::new();
    for (file, record) in run.written.iter().zip(job.source_records.iter()) {
        writeln!(
            out,
            "{} ({}, period {:.6})",
            file.display(),
            record.label(),
            record.period()
        )?;
    }
    if let [.., stub, manifest] = run.written.as_slice() {
        writeln!(
            out,
            "{} (the records as a [data] section for a model file)",
            stub.display()
        )?;
        writeln!(out, "{} (this run's records)", manifest.display())?;
    }
    for stale in &run.removed {
        eprintln!("removed {} (an earlier run's record)", stale.display());
    }
    Ok(Outcome {
        text: out,
        trusted: true,
    })
}

/// The simulation's true coefficients as a JSON object (`None` for measured data).
fn truth_json(job: &Job) -> Option<serde_json::Map<String, serde_json::Value>> {
    job.truth.as_ref().map(|t| {
        t.iter()
            .map(|(n, v)| (n.clone(), json!(v)))
            .collect::<serde_json::Map<_, _>>()
    })
}
