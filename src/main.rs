//! The `dampid` command line.

use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand, ValueEnum};
use dampid::quadrature::Quadrature;
use dampid::reference::FourMassSummary;

/// Identify damping laws of vibrating structures by balancing energy over cycles.
#[derive(Parser)]
#[command(version, about, long_about = None, after_help = "Examples:\n  dampid reference four-mass            # the paper's section 2.2, as a table\n  dampid reference four-mass --json     # the same, one JSON object\n  dampid reference four-mass --quadrature trapezoid")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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

/// Exit codes: 0 all targets met, 1 a target missed, 2 an error.
fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<bool> {
    match cli.command {
        Command::Reference {
            system: ReferenceSystem::FourMass,
            json,
            quadrature,
        } => {
            let summary = FourMassSummary::run(quadrature.into()).context("four-mass reference")?;
            if json {
                println!("{}", serde_json::to_string_pretty(&summary.to_json())?);
            } else {
                print!("{summary}");
            }
            Ok(summary.all_pass())
        }
    }
}
