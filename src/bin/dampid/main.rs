//! The `dampid` command line: parse the arguments (args.rs), run the command through
//! the library's command layer ([`dampid::command`]), print what it returns. The library
//! composes every outcome (text, JSON, HTML page, exit status); this file writes the
//! HTML page where asked and maps errors to exit code 2 (progress.rs draws the bars).
//! Ctrl-C sets `dampid::cancel`: the running work stops at its next step, nothing is
//! written, and the exit code is 130 (128 + SIGINT, as a shell reports a process
//! stopped by Ctrl-C).

mod args;
mod progress;

use std::io::Write as _;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::Parser;
use dampid::analysis::bootstrap::BootstrapSettings;
use dampid::command::identify::{Identified, IdentifyOptions};
use dampid::command::{self, Outcome};
use dampid::io::output::Overwrite;
use dampid::io::pod_files::Columns;
use dampid::prep::pod::{PodBasis, PodSettings, Retain};

use args::{Cli, Command, ReferenceSystem};
use progress::{load, on_bar, progress_bar};

/// The allocator: returns freed buffers to the system (see Cargo.toml), so that peak
/// memory follows the data, not the allocator's arenas.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
        Ok(status) => ExitCode::from(status),
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

fn run(cli: Cli) -> anyhow::Result<u8> {
    if let Some(bytes) = cli.max_memory {
        dampid::budget::set_max_memory(bytes);
    }
    if cli.no_time_limit {
        dampid::budget::set_time_limit(None);
    }
    match cli.command {
        Command::Init { files, out, force } => print(
            &command::init::run(&files, &out, Overwrite::from_force(force))?,
            false,
            false,
        ),
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
            let page = report.map(|folder| folder.join("report.html"));
            let overwrite = Overwrite::from_force(force);
            // Refuse an existing report before any work, and again when it is renamed.
            if let (Some(file), Overwrite::Refuse) = (&page, overwrite) {
                dampid::io::output::refuse_existing(file)?;
            }
            let job = load(&model)?;
            let options = IdentifyOptions {
                accept_transient,
                accept_negative_work,
                bootstrap: bootstrap.map(|replicates| BootstrapSettings {
                    replicates,
                    seed,
                    ..Default::default()
                }),
                strict,
                command_line: std::env::args().collect::<Vec<_>>().join(" "),
            };
            let bar = progress_bar("bootstrap");
            let found = command::identify::run(&job, &options, &on_bar(&bar));
            bar.finish_and_clear();
            let found = found.map_err(|e| transient_hint(e, &model))?;
            let outcome = Identified {
                job: &job,
                options: &options,
                identification: &found,
            };
            if let Some(file) = page {
                write_page(&file, overwrite, &outcome.html(&model)?)?;
            }
            print(&outcome, json, strict)
        }
        Command::Check {
            model,
            accept_transient,
            accept_negative_work,
            json,
        } => {
            let job = load(&model)?;
            let options = command::check::CheckOptions {
                accept_transient,
                accept_negative_work,
            };
            let report =
                command::check::run(&job, options).context("the regressor cannot be fitted")?;
            print(&report, json, false)
        }
        Command::Pod {
            files,
            columns,
            prefix,
            shared,
            remove_mean,
            energy,
            json,
        } => {
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
            print(&command::pod::run(&files, &choice, &settings)?, json, false)
        }
        Command::Compare {
            model_a,
            model_b,
            laws,
            json,
        } => {
            let first = model_a.display().to_string();
            match (model_b, laws) {
                (Some(model_b), _) => {
                    let job = load(&model_a)?;
                    // Only model B's terms are used: its records are not simulated or read.
                    let (_, other) = dampid::model_file::load_parametric_model(&model_b)?;
                    let second = model_b.display().to_string();
                    print(
                        &command::compare::models(&job, &first, &other, &second)?,
                        json,
                        false,
                    )
                }
                (None, Some(laws)) => {
                    let job = load(&model_a)?;
                    print(&command::compare::laws(&job, &first, &laws)?, json, false)
                }
                (None, None) => bail!("give a second model file or --laws"),
            }
        }
        Command::Backbones {
            models,
            json,
            report,
            force,
        } => {
            let page = report.map(|folder| folder.join("backbones.html"));
            let overwrite = Overwrite::from_force(force);
            if let (Some(file), Overwrite::Refuse) = (&page, overwrite) {
                dampid::io::output::refuse_existing(file)?;
            }
            let jobs = models
                .iter()
                .map(|m| Ok((m.display().to_string(), load(m)?)))
                .collect::<anyhow::Result<Vec<_>>>()?;
            let bar = progress_bar("jobs");
            let compared = command::backbones::run(&jobs, &on_bar(&bar));
            bar.finish_and_clear();
            let compared = compared?;
            if let Some(file) = page {
                write_page(&file, overwrite, &compared.html()?)?;
            }
            print(&compared, json, false)
        }
        Command::Design { model, json } => {
            let job = load(&model)?;
            let bar = progress_bar("design");
            let designed = command::design::run(&job, &model.display().to_string(), &on_bar(&bar));
            bar.finish_and_clear();
            print(&designed?, json, false)
        }
        Command::Simulate { model, out, force } => {
            let job = load(&model)?;
            let source = model.display().to_string();
            let written =
                command::simulate::run(&job, &source, &out, Overwrite::from_force(force))?;
            print(&written, false, false)
        }
        Command::Reference {
            system: ReferenceSystem::FourMass,
            json,
            quadrature,
        } => {
            let reference =
                command::reference::four_mass(quadrature.into()).context("four-mass reference")?;
            print(&reference, json, false)
        }
    }
}

/// Prints `outcome` (JSON or text) on stdout, its notices, `--strict` failures and
/// refusal on stderr, and returns its exit status.
fn print(outcome: &impl Outcome, json: bool, strict: bool) -> anyhow::Result<u8> {
    let text = if json {
        command::json(outcome)?
    } else {
        outcome.to_string()
    };
    // A closed pipe (`dampid … | head`) is not an error of ours.
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
    for notice in outcome.notices() {
        eprintln!("{notice}");
    }
    let (status, failures) = command::exit_status(outcome, strict);
    for failure in &failures {
        eprintln!("strict: {failure}");
    }
    if let Some(refusal) = outcome.refused() {
        eprintln!("error: {refusal}");
    }
    Ok(status)
}

/// A steady-state refusal with what accepts it on the command line.
fn transient_hint(e: dampid::Error, model: &Path) -> anyhow::Error {
    if e.kind() == "not_steady" {
        anyhow::Error::new(e).context(format!("{}: {}", model.display(), command::TRANSIENT_HINT))
    } else {
        e.into()
    }
}

/// Writes the HTML `page` to `file` (its folder created) and says so on stderr (stdout
/// stays pure JSON with --json).
fn write_page(file: &Path, overwrite: Overwrite, page: &str) -> anyhow::Result<()> {
    if let Some(folder) = file.parent() {
        std::fs::create_dir_all(folder)
            .with_context(|| format!("creating {}", folder.display()))?;
    }
    let stale = dampid::io::output::write_file(file, overwrite, |sink| {
        sink.write_all(page.as_bytes())
            .map_err(|e| dampid::Error::Output {
                path: file.display().to_string(),
                message: e.to_string(),
            })
    })?;
    for stale in stale {
        eprintln!("{}", dampid::command::stale_notice(&stale));
    }
    eprintln!("wrote {}", file.display());
    Ok(())
}
