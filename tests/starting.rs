//! What a newcomer meets after `dampid init`: `compare` with a terms-only second model,
//! `simulate` naming force columns by DOF and writing a ready `[data]` stub, `design`
//! printing its choice as TOML to paste, and `[simulation] noise`.

use std::path::{Path, PathBuf};

mod support;
use support::cli::{dampid_json, dampid_ok};

fn scratch(name: &str) -> PathBuf {
    let folder =
        std::env::temp_dir().join(format!("dampid-starting-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

/// A model B of `dofs` and `[[terms]]` alone gives the same comparison as the full
/// model file with the same terms (B contributes only its terms either way).
#[test]
fn compare_takes_a_terms_only_second_model() {
    let folder = scratch("compare");
    let terms_only = folder.join("viscous_only.toml");
    std::fs::write(
        &terms_only,
        "dofs = 3\n\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"chain\"\nper_element = \"dashpot\"\n",
    )
    .unwrap();
    let with_terms_only = dampid_json(&[
        "compare",
        "models/measured_chain.toml",
        terms_only.to_str().unwrap(),
        "--json",
    ]);
    let with_full_file = dampid_json(&[
        "compare",
        "models/measured_chain.toml",
        "models/measured_chain_no_friction.toml",
        "--json",
    ]);
    let numbers = |v: &serde_json::Value| {
        let mut v = v.clone();
        // The models are named by their files; everything else must agree.
        for side in ["first", "second"] {
            if let Some(m) = v.get_mut(side) {
                m["label"] = serde_json::Value::Null;
            }
        }
        v["text"] = serde_json::Value::Null;
        v
    };
    assert_eq!(numbers(&with_terms_only), numbers(&with_full_file));
    std::fs::remove_dir_all(&folder).ok();
}

/// `dampid simulate` names the force on DOF 4 `f4` and writes data.toml, whose
/// `[[data.records]]` read the run back: a model file of the generator's terms and
/// identification with the stub in place of `[simulation]` identifies the same
/// coefficients as the generator (the same records, read back from 11-digit CSV).
#[test]
fn simulate_names_forces_by_dof_and_writes_a_data_stub_that_reads_the_run_back() {
    let folder = scratch("stub");
    let run = folder.join("run");
    let printed = dampid_ok(&[
        "simulate",
        "models/four_mass.toml",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&printed.stdout).contains("data.toml"));
    let csv = std::fs::read_to_string(run.join("record_1.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert_eq!(header, "t,x1,x2,x3,x4,v1,v2,v3,v4,f4");
    let stub = std::fs::read_to_string(run.join("data.toml")).unwrap();
    assert_eq!(stub.matches("[[data.records]]").count(), 4);
    assert!(
        stub.contains("forces = [{ column = \"f4\", dof = 4 }]"),
        "{stub}"
    );

    let generator = std::fs::read_to_string("models/four_mass.toml").unwrap();
    let head = &generator[..generator.find("[simulation]").unwrap()];
    std::fs::write(run.join("model.toml"), format!("{head}\n{stub}")).unwrap();
    let from_files = dampid_json(&[
        "identify",
        run.join("model.toml").to_str().unwrap(),
        "--json",
    ]);
    let simulated = dampid_json(&["identify", "models/four_mass.toml", "--json"]);
    let values = |v: &serde_json::Value| -> Vec<f64> {
        v["report"]["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["value"].as_f64().unwrap())
            .collect()
    };
    for (a, b) in values(&from_files).iter().zip(values(&simulated)) {
        assert!(
            ((a - b) / b).abs() < 1e-6,
            "{a} from the files, {b} simulated"
        );
    }
    std::fs::remove_dir_all(&folder).ok();
}

/// The TOML `design` prints is the selected experiments of the model file, exactly:
/// parsed back, block k is candidate `selected()[k]` of `[[simulation.experiments]]`.
#[test]
fn design_prints_the_selected_experiments_as_toml() {
    let model = "models/per_dashpot.toml";
    let output = dampid_ok(&["design", model]);
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    let start = text
        .find("# The selected experiments")
        .unwrap_or_else(|| panic!("no TOML in\n{text}"));
    let pasted: toml::Value = toml::from_str(&text[start..]).unwrap();
    let blocks = pasted["simulation"]["experiments"].as_array().unwrap();

    let report = dampid_json(&["design", model, "--json"]);
    let selected: Vec<usize> = ["start", "chosen"]
        .iter()
        .flat_map(|k| report[*k].as_array().unwrap().clone())
        .map(|i| i.as_u64().unwrap() as usize)
        .collect();
    assert_eq!(blocks.len(), selected.len());
    let source: toml::Value = toml::from_str(&std::fs::read_to_string(model).unwrap()).unwrap();
    let candidates = source["simulation"]["experiments"].as_array().unwrap();
    for (block, k) in blocks.iter().zip(&selected) {
        let candidate = &candidates[*k];
        for key in ["force_dof", "amplitude", "frequency"] {
            assert_eq!(block[key], candidate[key], "{key} of candidate {}", k + 1);
        }
    }
}

/// `design --json` stands alone: beside the report it gives the selected experiments as
/// data (1-based candidate and DOF, as the model file writes them) and as the TOML to
/// paste, the same blocks the text output prints; each matches its candidate in the
/// model file.
#[test]
fn design_json_carries_the_selected_experiments() {
    let model = "models/per_dashpot.toml";
    let report = dampid_json(&["design", model, "--json"]);
    let selected: Vec<usize> = ["start", "chosen"]
        .iter()
        .flat_map(|k| report[*k].as_array().unwrap().clone())
        .map(|i| i.as_u64().unwrap() as usize)
        .collect();
    let experiments = report["selected_experiments"].as_array().unwrap();
    assert_eq!(experiments.len(), selected.len());
    assert!(!selected.is_empty());
    let source: toml::Value = toml::from_str(&std::fs::read_to_string(model).unwrap()).unwrap();
    let candidates = source["simulation"]["experiments"].as_array().unwrap();
    let toml_text = report["selected_experiments_toml"].as_str().unwrap();
    let pasted: toml::Value = toml::from_str(toml_text).unwrap();
    let blocks = pasted["simulation"]["experiments"].as_array().unwrap();
    assert_eq!(blocks.len(), selected.len());
    for ((e, block), k) in experiments.iter().zip(blocks).zip(&selected) {
        assert_eq!(e["candidate"].as_u64().unwrap() as usize, k + 1);
        let candidate = &candidates[*k];
        assert_eq!(
            e["force_dof"].as_i64(),
            candidate["force_dof"].as_integer(),
            "force_dof of candidate {}",
            k + 1
        );
        for key in ["amplitude", "frequency"] {
            assert_eq!(
                e[key].as_f64(),
                candidate[key].as_float(),
                "{key} of candidate {}",
                k + 1
            );
            assert_eq!(block[key], candidate[key], "{key} of candidate {}", k + 1);
        }
    }
    // The text output prints the same TOML.
    let text = String::from_utf8_lossy(&dampid_ok(&["design", model]).stdout).into_owned();
    assert!(text.contains(toml_text), "{text}");
}

/// The four-mass model file with `noise` and `noise_seed` in `[simulation]`.
fn four_mass_with(noise: &str) -> dampid::model_file::Job {
    let text = std::fs::read_to_string("models/four_mass.toml")
        .unwrap()
        .replace("[simulation]\n", &format!("[simulation]\n{noise}\n"));
    dampid::model_file::parse(
        &text,
        "four_mass.toml",
        Path::new("models"),
        Default::default(),
    )
    .unwrap()
}

/// `noise = ε` adds Gaussian noise of ε × each channel's RMS to every recorded
/// channel: the difference from the noise-free records has that standard deviation
/// (here 2%, estimated from 800 samples per record and kind to about ±3%), the same
/// seed gives the same records and another seed others.
#[test]
fn simulation_noise_is_gaussian_relative_to_each_channel_and_seeded() {
    let clean = four_mass_with("");
    let noisy = four_mass_with("noise = 0.02\nnoise_seed = 3");
    let again = four_mass_with("noise = 0.02\nnoise_seed = 3");
    let other = four_mass_with("noise = 0.02\nnoise_seed = 4");
    let columns = |m: faer::MatRef<'_, f64>| -> Vec<Vec<f64>> {
        (0..m.ncols())
            .map(|j| m.col(j).iter().copied().collect())
            .collect()
    };
    for (k, (c, n)) in clean
        .source_records
        .iter()
        .zip(noisy.source_records.iter())
        .enumerate()
    {
        let kinds = [
            (
                "displacements",
                columns(c.displacements()),
                columns(n.displacements()),
            ),
            (
                "velocities",
                columns(c.velocities().unwrap()),
                columns(n.velocities().unwrap()),
            ),
            (
                "forces",
                columns(c.forcing().signals.as_ref()),
                columns(n.forcing().signals.as_ref()),
            ),
        ];
        for (kind, clean_columns, noisy_columns) in kinds {
            // Each difference relative to its channel's RMS, pooled over the channels.
            let mut relative = Vec::new();
            for (cc, nc) in clean_columns.iter().zip(&noisy_columns) {
                let rms = (cc.iter().map(|x| x * x).sum::<f64>() / cc.len() as f64).sqrt();
                relative.extend(cc.iter().zip(nc).map(|(a, b)| (b - a) / rms));
            }
            let mean = relative.iter().sum::<f64>() / relative.len() as f64;
            let sd = (relative.iter().map(|r| (r - mean).powi(2)).sum::<f64>()
                / (relative.len() - 1) as f64)
                .sqrt();
            assert!(
                (sd / 0.02 - 1.0).abs() < 0.15,
                "record {k} {kind}: noise sd {sd} of the RMS, asked 0.02"
            );
            assert!(mean.abs() < 0.005, "record {k} {kind}: mean {mean}");
        }
        assert_eq!(
            n.displacements(),
            again.source_records[k].displacements(),
            "the same seed gives the same records"
        );
        assert_ne!(n.displacements(), other.source_records[k].displacements());
    }
}
