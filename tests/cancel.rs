//! Cancellation and progress of long work (`dampid::cancel`, `dampid::progress`): a
//! simulation, the records of a model file, the regressor, the bootstrap and the design
//! each stop with `Error::Cancelled` at a check between steps, and after `cancel::clear`
//! the same work gives the same bits as a run never cancelled (a cancelled run leaves
//! no state behind). Progress counts reach the total once each, in order of finishing.
//! Output files of a run cancelled before their commit are never written.
//!
//! The cancellation flag is process-wide, so everything runs in one test, one step
//! after another (this file is its own test binary).

use std::path::Path;
use std::sync::Mutex;

use dampid::analysis::bootstrap::{BootstrapSettings, bootstrap};
use dampid::analysis::design::select;
use dampid::io::output::{Overwrite, Staged};
use dampid::io::run::write_run;
use dampid::model_file::load;
use dampid::reference::{four_mass_model, four_mass_system};
use dampid::simulate::{SimSettings, simulate};

fn cancelled<T: std::fmt::Debug>(result: dampid::Result<T>, what: &str) {
    let e = result.unwrap_err();
    assert_eq!(e.innermost().kind(), "cancelled", "{e}");
    assert!(e.to_string().contains(what), "'{what}' not in {e}");
    dampid::cancel::clear();
}

/// Every `progress(done, total)` call, in order.
#[derive(Default)]
struct Calls(Mutex<Vec<(u64, u64)>>);

impl Calls {
    fn record(&self) -> impl Fn(u64, u64) + Sync + '_ {
        |done, total| self.0.lock().unwrap().push((done, total))
    }

    /// `done` took every value 1..=total once (in any order: from worker threads).
    fn assert_complete(&self) {
        let calls = self.0.lock().unwrap();
        let total = calls.last().unwrap().1;
        assert!(calls.iter().all(|c| c.1 == total));
        let mut done: Vec<u64> = calls.iter().map(|c| c.0).collect();
        done.sort_unstable();
        done.dedup();
        assert_eq!(done, (1..=total).collect::<Vec<_>>());
    }
}

#[test]
fn long_work_stops_at_a_check_and_leaves_no_state() {
    dampid::cancel::clear();

    // Simulation: stopped after 3 checks (192 steps), then run in full.
    let job = load(Path::new("models/four_mass.toml"), Default::default()).unwrap();
    let system = four_mass_system(0.25, false);
    let settings = SimSettings::default();
    let before = simulate(&system, &settings, &dampid::progress::silent).unwrap();
    dampid::cancel::request_after(3);
    cancelled(
        simulate(&system, &settings, &dampid::progress::silent),
        "the simulation",
    );
    let after = simulate(&system, &settings, &dampid::progress::silent).unwrap();
    assert_eq!(before.displacements(), after.displacements());

    // The records of a model file (simulated there).
    dampid::cancel::request_after(5);
    cancelled(
        load(Path::new("models/four_mass.toml"), Default::default()),
        "simulation",
    );

    // The regressor, before its first window.
    let regressor = job.initial_regressor().unwrap();
    dampid::cancel::request();
    cancelled(job.initial_regressor(), "building the regressor");
    assert_eq!(
        job.initial_regressor().unwrap().matrix(),
        regressor.matrix()
    );

    // The bootstrap: progress reaches every count once; cancelled after 5 replicates;
    // the rerun gives the same intervals.
    let boot = BootstrapSettings {
        replicates: 200,
        ..Default::default()
    };
    let calls = Calls::default();
    let first = bootstrap(&regressor, &job.settings.fit, &boot, None, &calls.record()).unwrap();
    calls.assert_complete();
    assert_eq!(calls.0.lock().unwrap().last().unwrap().1, 200);
    dampid::cancel::request_after(5);
    cancelled(
        bootstrap(
            &regressor,
            &job.settings.fit,
            &boot,
            None,
            &dampid::progress::silent,
        ),
        "the bootstrap",
    );
    let again = bootstrap(
        &regressor,
        &job.settings.fit,
        &boot,
        None,
        &dampid::progress::silent,
    )
    .unwrap();
    assert_eq!(first.coefficients, again.coefficients);

    // The design: 4 candidates, 2 picks = 4 blocks + 4 + 3 evaluations.
    let design = dampid::analysis::design::DesignSettings {
        picks: 2,
        ..Default::default()
    };
    let model = four_mass_model();
    let calls = Calls::default();
    let chosen = select(
        &model,
        &job.records,
        &job.settings.regressor,
        &design,
        &calls.record(),
    )
    .unwrap();
    assert_eq!(job.records.len(), 4);
    let last = *calls.0.lock().unwrap().last().unwrap();
    assert_eq!(last, (11, 11));
    dampid::cancel::request_after(6);
    cancelled(
        select(
            &model,
            &job.records,
            &job.settings.regressor,
            &design,
            &dampid::progress::silent,
        ),
        "the design",
    );
    let again = select(
        &model,
        &job.records,
        &job.settings.regressor,
        &design,
        &dampid::progress::silent,
    )
    .unwrap();
    assert_eq!(chosen.chosen, again.chosen);

    // Output files: a cancellation requested after the content is staged (the last
    // moment before the renames) commits nothing; the folder holds no file, not even a
    // temporary one. The same run after `clear` writes every file.
    let folder = std::env::temp_dir().join(format!("dampid-cancel-out-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    std::fs::create_dir_all(&folder).unwrap();
    let mut staged = Staged::new(Overwrite::Refuse);
    for name in ["a.csv", "b.csv"] {
        staged
            .add(&folder.join(name), |sink| {
                sink.write_all(b"t,x\n0,1\n")
                    .map_err(|e| dampid::Error::Output {
                        path: name.into(),
                        message: e.to_string(),
                    })
            })
            .unwrap();
    }
    dampid::cancel::request();
    cancelled(staged.commit(), "writing the output files");
    assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0);
    // A whole simulation run (records, [data] stub, manifest): cancelled, nothing.
    dampid::cancel::request();
    let run = folder.join("run");
    cancelled(
        write_run(
            &run,
            &job.source_records,
            "four_mass.toml",
            Overwrite::Refuse,
        ),
        "writing the run",
    );
    assert!(!run.exists());
    let written = write_run(
        &run,
        &job.source_records,
        "four_mass.toml",
        Overwrite::Refuse,
    )
    .unwrap()
    .written;
    assert_eq!(written.len(), job.source_records.len() + 2);
    std::fs::remove_dir_all(&folder).ok();
}
