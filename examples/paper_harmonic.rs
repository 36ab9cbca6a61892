//! Paper section 2.2, eq. 4 (Feeny 2009): the harmonic approximation on the four-mass
//! chain. The chain (C = cK, quadratic damping d ẋ|ẋ| on every mass, c = 0.15,
//! d = 0.10, a cos 0.618t on mass 4, a ∈ {0.25, 0.5, 0.75, 1}) is simulated with the
//! paper's settings (RK4, h = 0.1, 1000 transient steps, 200 recorded steps). Each
//! record gives one stepped-sine point: the least-squares fundamental (amplitude X_i,
//! lag φ_i behind the force) of every mass over the first whole period of the recorded
//! steady state. The synchronous motion x_i = X_i cos(ωt − φ̄), φ̄ the arithmetic mean of
//! the lags, is integrated by the ordinary regressor, which gives eq. 4,
//! 2πωc A_c + (8/3)ω² d A_d = π a X_4 sin φ̄, one equation per amplitude, solved by
//! least squares. The same is done again from the amplitude/phase table alone, written
//! to CSV and read back. Targets: the paper's c_h = 0.1341, d_h = 0.1216 within 2%.
//!
//! The paper leaves open which window and which mean; the other readings are printed
//! below the targets (they are not targets). Measured: the circular and
//! amplitude-weighted means agree with the arithmetic mean to 0.02% in c_h; the last
//! whole period of the record, or a transient eight times longer, moves c_h by at most
//! 0.15% (so the remaining 1.6% against the paper's c_h is not the transient); the lag
//! of the driven mass alone misses the paper by 12–14%, and that of mass 1 by 3–4%;
//! keeping every mass's own lag (no synchronicity) lands within 0.4% of the truth, as
//! the paper's diagnosis ("the main source of error is in the synchronicity
//! assumption") predicts. Peak amplitudes instead of fundamentals (tried outside this
//! example) move c_h away from the paper's, to +2.1%.
//!
//!   cargo run --release --example paper_harmonic                 # table
//!   cargo run --release --example paper_harmonic -- --json       # {"cases": [...]}
//!   cargo run --release --example paper_harmonic -- --table T.csv  # where the CSV goes
//!
//! Exits with status 1 when a target is missed.

use std::path::{Path, PathBuf};

use dampid::prelude::*;
use dampid::prep::harmonic::{HarmonicApproximation, PhaseReading, SteppedSineTable};
use dampid::reference::{FOUR_MASS_C, FOUR_MASS_D, four_mass_model, four_mass_records_with};
use dampid::simulate::SimSettings;
use serde_json::json;

/// The paper's harmonic-approximation estimates (section 2.2).
const PAPER: (f64, f64) = (0.1341, 0.1216);
/// Largest acceptable relative error against the paper's values.
const TOLERANCE: f64 = 0.02;

struct Case {
    name: String,
    /// Compared against the paper (a target) or shown for information.
    target: bool,
    report: FitReport,
}

impl Case {
    fn estimates(&self) -> (f64, f64) {
        (
            self.report.coefficient("c").unwrap_or(f64::NAN),
            self.report.coefficient("d").unwrap_or(f64::NAN),
        )
    }
    fn errors(&self) -> (f64, f64) {
        let (c, d) = self.estimates();
        ((c - PAPER.0).abs() / PAPER.0, (d - PAPER.1).abs() / PAPER.1)
    }
    fn truth_errors(&self) -> (f64, f64) {
        let (c, d) = self.estimates();
        (
            (c - FOUR_MASS_C).abs() / FOUR_MASS_C,
            (d - FOUR_MASS_D).abs() / FOUR_MASS_D,
        )
    }
    fn passes(&self) -> bool {
        let (ec, ed) = self.errors();
        ec <= TOLERANCE && ed <= TOLERANCE
    }
}

/// Records of 200 steady-state steps after `transient_steps` (the paper: 1000).
fn simulated(transient_steps: usize) -> Result<Vec<Record>> {
    let settings = SimSettings {
        transient_steps,
        ..SimSettings::default()
    };
    four_mass_records_with(false, &settings)
}

fn run(table_path: &Path) -> Result<Vec<Case>> {
    let model = four_mass_model();
    let fit = FitSettings::default();
    let records = simulated(SimSettings::default().transient_steps)?;
    let first_period = WindowSpec::cycles(1).first(1);
    let table = SteppedSineTable::from_records(&records, &first_period)?;
    table.save_csv(table_path, dampid::io::output::Overwrite::Replace)?;
    let read_back = SteppedSineTable::load_csv(table_path)?;
    let paper_reading = HarmonicApproximation::default();
    let mut cases = vec![
        Case {
            name: "eq. 4 from the time series (first whole period, arithmetic mean lag)".into(),
            target: true,
            report: identify(
                &ParametricRegressor::linear(&model, &paper_reading.records(&table)?),
                &IdentifySettings::harmonic_approximation(fit.clone()),
                &silent,
            )?
            .report,
        },
        Case {
            name: "eq. 4 from the amplitude/phase table (CSV written and read back)".into(),
            target: true,
            report: identify(
                &ParametricRegressor::linear(&model, &paper_reading.records(&read_back)?),
                &IdentifySettings::harmonic_approximation(fit.clone()),
                &silent,
            )?
            .report,
        },
    ];
    let with = |phase| HarmonicApproximation {
        phase,
        ..HarmonicApproximation::default()
    };
    for (name, phase) in [
        ("reading: circular mean lag", PhaseReading::CircularMean),
        (
            "reading: amplitude-weighted mean lag",
            PhaseReading::AmplitudeWeightedMean,
        ),
        ("reading: lag of the driven mass 4", PhaseReading::Dof(3)),
        ("reading: lag of mass 1", PhaseReading::Dof(0)),
        (
            "reading: every mass its own lag (not synchronous)",
            PhaseReading::PerDof,
        ),
    ] {
        cases.push(Case {
            name: name.into(),
            target: false,
            report: identify(
                &ParametricRegressor::linear(&model, &with(phase).records(&table)?),
                &IdentifySettings::harmonic_approximation(fit.clone()),
                &silent,
            )?
            .report,
        });
    }
    // The last whole period of the 200 recorded steps (101.7 samples per period).
    let last_period = WindowSpec {
        skip: 98,
        ..first_period
    };
    let late = SteppedSineTable::from_records(&records, &last_period)?;
    cases.push(Case {
        name: "reading: last whole period of the record, arithmetic mean lag".into(),
        target: false,
        report: identify(
            &ParametricRegressor::linear(&model, &paper_reading.records(&late)?),
            &IdentifySettings::harmonic_approximation(fit.clone()),
            &silent,
        )?
        .report,
    });
    // The transient fully gone: the reading's own answer, free of the paper's transient.
    let steady = SteppedSineTable::from_records(&simulated(8000)?, &first_period)?;
    cases.push(Case {
        name: "reading: 8000 transient steps instead of 1000, arithmetic mean lag".into(),
        target: false,
        report: identify(
            &ParametricRegressor::linear(&model, &paper_reading.records(&steady)?),
            &IdentifySettings::harmonic_approximation(fit.clone()),
            &silent,
        )?
        .report,
    });
    Ok(cases)
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let json_output = args.iter().any(|a| a == "--json");
    let table_path = args
        .iter()
        .position(|a| a == "--table")
        .and_then(|k| args.get(k + 1))
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("dampid_four_mass_stepped_sine.csv"));
    let cases = run(&table_path)?;
    if json_output {
        let list: Vec<_> = cases
            .iter()
            .map(|case| json!({"case": case.name, "report": case.report}))
            .collect();
        println!("{}", json!({ "cases": list }));
    } else {
        println!(
            "Four-mass chain, harmonic approximation (Feeny 2009, eq. 4): true c = {FOUR_MASS_C}, d = {FOUR_MASS_D}"
        );
        println!(
            "Reading kept: least-squares fundamentals over the first whole period of the 200 recorded steps,"
        );
        println!(
            "synchronous motion with the arithmetic mean lag (on the branch centred at the circular mean)."
        );
        println!("Amplitude/phase table: {}", table_path.display());
        println!(
            "{:<68} {:>8} {:>8} {:>8} {:>8} {:>7} {:>7} {:>9} {:>9}",
            "case",
            "paper c",
            "paper d",
            "ours c",
            "ours d",
            "err c",
            "err d",
            "truth: c",
            "truth: d"
        );
        for case in &cases {
            let (c, d) = case.estimates();
            let (ec, ed) = case.errors();
            let (tc, td) = case.truth_errors();
            let verdict = match (case.target, case.passes()) {
                (true, true) => "ok",
                (true, false) => "MISS",
                (false, _) => "(not a target)",
            };
            println!(
                "{:<68} {:>8.4} {:>8.4} {:>8.4} {:>8.4} {:>6.2}% {:>6.2}% {:>8.2}% {:>8.2}% {verdict}",
                case.name,
                PAPER.0,
                PAPER.1,
                c,
                d,
                100.0 * ec,
                100.0 * ed,
                100.0 * tc,
                100.0 * td
            );
        }
        println!(
            "targets: c_h and d_h within {:.0}% of the paper (err c, err d); truth: error against c = {FOUR_MASS_C}, d = {FOUR_MASS_D}",
            100.0 * TOLERANCE
        );
    }
    if cases.iter().any(|case| case.target && !case.passes()) {
        eprintln!("a target was missed");
        std::process::exit(1);
    }
    Ok(())
}
