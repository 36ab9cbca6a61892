//! The bootstrap of variable projection (`dampid::varpro::bootstrap`, which `identify`
//! runs with `--bootstrap`): fewer than two replicates, fewer than half of them kept, a
//! table of a single sweep (whole sweeps cannot be resampled from one), and a fit that
//! is not an estimate (no bootstrap, a warning).

use dampid::analysis::bootstrap::BootstrapSettings;
use dampid::prelude::*;
use dampid::report::Warning;
use dampid::varpro::VarProSettings;

use crate::table;

/// The residual-receptance job of the one-DOF oscillator table at force `levels`, six
/// points per sweep, 0.5 % noise.
fn job(name: &str, levels: &[f64]) -> dampid::model_file::Job {
    let columns = table::residual_columns_at(
        levels,
        6,
        table::R_K,
        0.0,
        1.0,
        Some((5, 0.005, 0.3f64.to_radians())),
    );
    let dir = std::env::temp_dir().join(format!("dampid_errors_vb_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    crate::support::write_scratch_csv(&file, &table::headers(), &columns);
    dampid::model_file::parse(
        &table::model_text(&file, "residual = \"stiffness\""),
        "m.toml",
        std::path::Path::new("."),
        Default::default(),
    )
    .unwrap()
}

/// The fit of `job` (an estimate), then the bootstrap stage around it under `varpro`
/// and `settings`.
fn boot(
    job: &dampid::model_file::Job,
    varpro: &VarProSettings,
    settings: &BootstrapSettings,
) -> Result<dampid::analysis::bootstrap::Bootstrap> {
    let problem = job.problem();
    let fitted = identify(&problem, &job.settings, &silent).unwrap().report;
    assert!(fitted.is_estimate(), "{fitted}");
    dampid::varpro::bootstrap(
        &problem,
        &job.settings.regressor,
        &job.settings.fit,
        varpro,
        &fitted.estimation.as_ref().unwrap().values(),
        settings,
        &silent,
    )
}

fn replicates(n: usize) -> BootstrapSettings {
    BootstrapSettings {
        replicates: n,
        ..BootstrapSettings::default()
    }
}

#[test]
fn one_replicate_is_refused() {
    let job = job("vb_one.csv", &[0.5, 1.0, 2.0]);
    let settings = IdentifySettings {
        bootstrap: Some(replicates(1)),
        ..job.settings.clone()
    };
    let e = identify(&job.problem(), &settings, &silent).unwrap_err();
    assert!(
        matches!(&e, Error::InvalidParameter { name, value, .. } if name == "replicates" && *value == 1.0),
        "{e}"
    );
}

/// An outer loop of one iteration that must lower the cost by less than 10⁻¹⁶ of
/// itself to stop converges in no replicate (each starts from the full data's
/// estimate, not the replicate's): fewer than half kept.
#[test]
fn too_few_kept_replicates_is_an_error() {
    let job = job("vb_few.csv", &[0.5, 1.0, 2.0]);
    let limited = VarProSettings {
        max_iterations: 1,
        tolerance: 1e-16,
        ..job.settings.estimation
    };
    let e = boot(&job, &limited, &replicates(8)).unwrap_err();
    match &e {
        Error::Numerical { stage, detail } => {
            assert!(stage.contains("variable projection"), "{e}");
            assert!(detail.contains("of 8 replicates kept"), "{e}");
            assert!(detail.contains("did not converge"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

/// One sweep cannot be resampled as a whole: a typed error, not an interval of zero
/// width (every replicate would be the data themselves).
#[test]
fn a_single_sweep_cannot_be_resampled() {
    let e = boot(
        &job("vb_single.csv", &[1.0]),
        &VarProSettings::default(),
        &replicates(20),
    )
    .unwrap_err();
    match &e {
        Error::InvalidChoice { given, reason, .. } => {
            assert_eq!(given, "1 group(s)");
            assert!(reason.contains("sweeps"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

/// A fit whose outer loop did not converge has no estimate to resample around: no
/// bootstrap, and a warning that says why.
#[test]
fn a_fit_that_is_not_an_estimate_is_not_bootstrapped() {
    let job = job("vb_not.csv", &[0.5, 1.0, 2.0]);
    let settings = IdentifySettings {
        estimation: VarProSettings {
            max_iterations: 1,
            ..job.settings.estimation
        },
        bootstrap: Some(replicates(20)),
        ..job.settings.clone()
    };
    let found = identify(&job.problem(), &settings, &silent).unwrap();
    assert!(!found.report.is_estimate());
    assert!(found.bootstrap.is_none() && found.report.bootstrap.is_none());
    assert!(
        found
            .report
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::NoBootstrap { reason } if reason.contains("did not reach an estimate"))),
        "{}",
        found.report
    );
}
