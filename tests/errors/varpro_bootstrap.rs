//! The bootstrap of variable projection (`varpro::bootstrap_varpro_regressor`): fewer
//! than two replicates, fewer than half of them kept, a table of a single sweep (whole
//! sweeps cannot be resampled from one), and a report that is not an estimate.

use dampid::analysis::bootstrap::BootstrapSettings;
use dampid::prelude::*;
use dampid::varpro::{VarProReport, VarProSettings, bootstrap_varpro_regressor};

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
    )
    .unwrap()
}

/// The fit of `job` (an estimate) and its bootstrap under `varpro` and `settings`.
fn boot(
    job: &dampid::model_file::Job,
    varpro: &VarProSettings,
    settings: &BootstrapSettings,
    report: Option<&VarProReport>,
) -> Result<dampid::varpro::VarProBootstrap> {
    let model = job.parametric_regressor().unwrap().unwrap();
    let fitted;
    let report = match report {
        Some(r) => r,
        None => {
            fitted = dampid::varpro::identify_varpro_regressor(
                &model,
                &job.settings,
                &job.varpro_settings(),
            )
            .unwrap();
            assert!(fitted.is_estimate(), "{fitted}");
            &fitted
        }
    };
    bootstrap_varpro_regressor(
        &model,
        job.sweeps(),
        &job.settings,
        varpro,
        report,
        settings,
        &dampid::progress::silent,
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
    let e = boot(
        &job("vb_one.csv", &[0.5, 1.0, 2.0]),
        &VarProSettings::default(),
        &replicates(1),
        None,
    )
    .unwrap_err();
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
    let limited = VarProSettings {
        max_iterations: 1,
        tolerance: 1e-16,
        ..job("vb_few.csv", &[0.5, 1.0, 2.0]).varpro_settings()
    };
    let e = boot(
        &job("vb_few.csv", &[0.5, 1.0, 2.0]),
        &limited,
        &replicates(8),
        None,
    )
    .unwrap_err();
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
        None,
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

/// A report whose outer loop did not converge has no estimate to resample around.
#[test]
fn a_report_that_is_not_an_estimate_is_refused() {
    let job = job("vb_not.csv", &[0.5, 1.0, 2.0]);
    let model = job.parametric_regressor().unwrap().unwrap();
    let limited = VarProSettings {
        max_iterations: 1,
        ..job.varpro_settings()
    };
    let report =
        dampid::varpro::identify_varpro_regressor(&model, &job.settings, &limited).unwrap();
    assert!(!report.is_estimate());
    let e = boot(
        &job,
        &VarProSettings::default(),
        &replicates(20),
        Some(&report),
    )
    .unwrap_err();
    assert!(
        matches!(&e, Error::InvalidChoice { reason, .. } if reason.contains("did not converge")),
        "{e}"
    );
}
