//! A simulation run written to a folder: `record_1.csv` … `record_K.csv` (the layout of
//! [`crate::io::records`]), `data.toml`, the records as a ready `[[data.records]]`
//! section for a model file ([`DATA_STUB`]), and `manifest.json`, which lists this run's
//! records:
//!
//! ```json
//! { "dampid": "0.1.0", "source": "models/four_mass.toml",
//!   "records": [ { "file": "record_1.csv", "label": "…", "period": 0.628 } ] }
//! ```
//!
//! A folder that already holds record files or a manifest (of another run, or of an
//! earlier dampid that wrote no manifest) is refused under [`Overwrite::Refuse`], so a
//! model file listing `record_*.csv` never mixes two runs. Under
//! [`Overwrite::Replace`] the new files replace the old ones of the same names, and of
//! the earlier run's other record files only those its `manifest.json` lists are
//! removed: a record file no manifest lists (a measured data set, a file of another
//! program) is never deleted, and a manifest entry that is not a plain `record_K.csv`
//! name in this folder is ignored. Every file is staged and renamed into place
//! ([`crate::io::output::Staged`]), the manifest last: a run that fails part way leaves
//! the folder as it was. Stale temporary files of a killed earlier run are removed
//! first ([`crate::io::output::remove_stale_temporaries`]) and reported.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::io::output::{Overwrite, Staged};
use crate::io::{csv, records};
use crate::record::Record;

/// The manifest's file name.
pub const MANIFEST: &str = "manifest.json";
/// The `[data]` stub's file name: every record with its time, displacement and force
/// columns (each force's DOF) and its period, paths relative to the folder.
pub const DATA_STUB: &str = "data.toml";

/// What a run wrote and removed.
#[derive(Debug, Clone, PartialEq)]
pub struct RunFiles {
    /// The record files, the `[data]` stub, then the manifest.
    pub written: Vec<PathBuf>,
    /// An earlier run's record files, listed by its manifest, that this run does not
    /// replace (only under [`Overwrite::Replace`]).
    pub removed: Vec<PathBuf>,
    /// Stale temporary files of an interrupted earlier run, removed from the folder.
    pub stale: Vec<PathBuf>,
}

#[derive(Serialize)]
struct Manifest<'a> {
    dampid: &'static str,
    source: &'a str,
    records: Vec<Entry<'a>>,
}

#[derive(Serialize)]
struct Entry<'a> {
    file: String,
    label: &'a str,
    period: f64,
}

/// The file name of record `k` (1-based).
pub fn record_file(k: usize) -> String {
    format!("record_{k}.csv")
}

/// Writes `records` into `folder` (created if missing) with a manifest naming
/// `source` (the model file), under `overwrite`.
pub fn write_run(
    folder: &Path,
    records: &[Record],
    source: &str,
    overwrite: Overwrite,
) -> Result<RunFiles> {
    let failed = |e: &dyn std::fmt::Display| Error::Output {
        path: folder.display().to_string(),
        message: e.to_string(),
    };
    crate::cancel::check("writing the run")?;
    std::fs::create_dir_all(folder).map_err(|e| failed(&e))?;
    let earlier = earlier_run(folder).map_err(|e| failed(&e))?;
    if overwrite == Overwrite::Refuse
        && let Some(first) = earlier.first()
    {
        let names: Vec<String> = earlier
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        return Err(Error::OutputExists {
            path: first.display().to_string(),
            reason: format!(
                "the folder holds another run's files ({}); pass --force to replace that run, or write to an empty folder",
                names.join(", ")
            ),
        });
    }
    let mut staged = Staged::new(overwrite);
    let mut entries = Vec::with_capacity(records.len());
    for (k, record) in records.iter().enumerate() {
        let name = record_file(k + 1);
        let (headers, columns) = records::record_columns(record);
        staged.add(&folder.join(&name), |sink| {
            csv::write_to(sink, &headers, &columns).map_err(|e| Error::Output {
                path: folder.join(&name).display().to_string(),
                message: e.to_string(),
            })
        })?;
        entries.push(Entry {
            file: name,
            label: record.label(),
            period: record.period(),
        });
    }
    let stub_path = folder.join(DATA_STUB);
    let stub = data_stub(records, source);
    staged.add(&stub_path, |sink| {
        sink.write_all(stub.as_bytes()).map_err(|e| Error::Output {
            path: stub_path.display().to_string(),
            message: e.to_string(),
        })
    })?;
    let manifest = Manifest {
        dampid: env!("CARGO_PKG_VERSION"),
        source,
        records: entries,
    };
    let manifest_path = folder.join(MANIFEST);
    staged.add(&manifest_path, |sink| {
        serde_json::to_writer_pretty(&mut *sink, &manifest)
            .and_then(|()| sink.write_all(b"\n").map_err(serde_json::Error::io))
            .map_err(|e| Error::Output {
                path: manifest_path.display().to_string(),
                message: e.to_string(),
            })
    })?;
    let listed = listed_records(folder);
    let committed = staged.commit()?;
    let written = committed.written;
    let mut removed = Vec::new();
    for stale in listed.into_iter().filter(|p| !written.contains(p)) {
        std::fs::remove_file(&stale).map_err(|e| Error::Output {
            path: stale.display().to_string(),
            message: format!("could not remove the earlier run's file: {e}"),
        })?;
        removed.push(stale);
    }
    Ok(RunFiles {
        written,
        removed,
        stale: committed.stale,
    })
}

/// Whether `name` is a record file's name, `record_K.csv`.
fn is_record_name(name: &str) -> bool {
    name.strip_prefix("record_")
        .and_then(|rest| rest.strip_suffix(".csv"))
        .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
}

/// The record files the folder's `manifest.json` lists that are regular files in it
/// (plain `record_K.csv` names only); none when there is no readable manifest.
fn listed_records(folder: &Path) -> Vec<PathBuf> {
    let path = folder.join(MANIFEST);
    // Not a FIFO (which would block) nor a file larger than the memory budget.
    if !matches!(super::regular_file(&path, "manifest", ""), Ok(Ok(_))) {
        return Vec::new();
    }
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Vec::new();
    };
    let Ok(manifest) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    let mut listed: Vec<PathBuf> = manifest["records"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|entry| entry["file"].as_str())
        .filter(|name| is_record_name(name))
        .map(|name| folder.join(name))
        .filter(|path| std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file()))
        .collect();
    listed.sort();
    listed.dedup();
    listed
}

/// The `[[data.records]]` entries that read `records` back from this folder.
fn data_stub(records: &[Record], source: &str) -> String {
    // A JSON string is a TOML basic string (the same escapes, UTF-8 as is).
    let quote = |s: &str| serde_json::Value::from(s).to_string();
    let list = |names: Vec<String>| {
        let quoted: Vec<String> = names.iter().map(|n| quote(n)).collect();
        format!("[{}]", quoted.join(", "))
    };
    let mut text = format!(
        "# The records of this run (dampid simulate {}) as a [data] section: paste it into a\n\
         # model file in this folder, or put this folder's path, relative to the model file,\n\
         # before each file name. The model file's [simulation] section then goes.\n",
        source.replace('\n', " ")
    );
    for (k, record) in records.iter().enumerate() {
        let n = record.dofs();
        let named = |prefix: &str| (1..=n).map(|j| format!("{prefix}{j}")).collect::<Vec<_>>();
        text.push_str(&format!(
            "\n[[data.records]]\nfile = {}\nlabel = {}\ntime = \"t\"\ndisplacements = {}\n",
            quote(&record_file(k + 1)),
            quote(record.label()),
            list(named("x"))
        ));
        if record.velocities().is_some() {
            text.push_str(&format!(
                "# velocities = {}   # the simulated velocities, read with velocity = \"measured\"\n",
                list(named("v"))
            ));
        }
        let columns = records::force_columns(record);
        if columns.iter().any(|(_, dof)| dof.is_none()) {
            text.push_str(
                "# these channels share a DOF or a load distribution: set each one's dof\n",
            );
        }
        let forces: Vec<String> = columns
            .into_iter()
            .map(|(column, dof)| {
                format!(
                    "{{ column = {}, dof = {} }}",
                    quote(&column),
                    dof.unwrap_or(1)
                )
            })
            .collect();
        text.push_str(&format!(
            "forces = [{}]\nperiod = {}\n",
            forces.join(", "),
            record.period()
        ));
    }
    text
}

/// The record files and manifest already in `folder`, sorted by record number.
fn earlier_run(folder: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut found: Vec<(usize, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(folder)? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let number = name
            .strip_prefix("record_")
            .and_then(|rest| rest.strip_suffix(".csv"))
            .and_then(|k| k.parse::<usize>().ok());
        match number {
            Some(k) => found.push((k, entry.path())),
            None if name == DATA_STUB => found.push((usize::MAX - 1, entry.path())),
            None if name == MANIFEST => found.push((usize::MAX, entry.path())),
            None => {}
        }
    }
    found.sort();
    Ok(found.into_iter().map(|(_, p)| p).collect())
}
