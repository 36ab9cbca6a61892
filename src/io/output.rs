//! Output files that are either complete or absent, and never replace a user's file by
//! accident.
//!
//! Every file dampid writes goes through [`write_file`] (or a [`Staged`] set of files):
//!
//! 1. the content is written to a temporary file with a unique name (`.NAME.XXXXXX.tmp`)
//!    in the target's own folder, then flushed and synced to disk;
//! 2. the temporary file is renamed onto the target, which is atomic on one file
//!    system: a reader sees the old file or the new one, never a mix. A write that fails
//!    part way (a full disk, a cancelled run, an error in the content) removes the
//!    temporary file and leaves the target as it was;
//! 3. with [`Overwrite::Refuse`] an existing target (a file, a folder or a symbolic
//!    link) is an [`Error::OutputExists`], checked before any work and again at the
//!    rename (`renameat2(RENAME_NOREPLACE)` or `link` + `unlink`, through
//!    [`tempfile::NamedTempFile::persist_noclobber`]), so two runs racing for one name
//!    cannot both win. With [`Overwrite::Replace`] the rename replaces the directory
//!    entry: a symbolic link is replaced by the new file, never followed.
//!
//! Two runs writing into one folder each write their own temporary files; the renames
//! are the only commits, so rows of two runs can never interleave within a file.
//!
//! Permissions: a new file gets what a file created normally gets, `0o666` less the
//! umask (the temporary file is created with that mode, not tempfile's private `0o600`);
//! a file replaced under [`Overwrite::Replace`] keeps its mode.
//!
//! Stale temporary files: a run killed outright (`kill -9`, a power cut) cannot remove
//! its temporary files. Each temporary file is held under an exclusive advisory lock
//! (`flock`) for as long as its run lives, and the lock dies with the process, so the
//! first write into a folder ([`Staged::add`]) removes the files of dampid's naming,
//! `.NAME.XXXXXX.tmp`, that no live process locks and that were not modified within the
//! last [`STALE_AFTER`] (which covers the instant between a file's creation and its
//! lock); [`Staged::commit`] and [`write_file`] return what was removed, and the
//! command line says so.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use tempfile::NamedTempFile;

use crate::error::{Error, Result};

/// What to do when an output file already exists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overwrite {
    /// Stop with [`Error::OutputExists`] (the default everywhere).
    Refuse,
    /// Replace it (the command line's `--force`).
    Replace,
}

impl Overwrite {
    /// `Replace` when `force` is set.
    pub fn from_force(force: bool) -> Self {
        if force {
            Overwrite::Replace
        } else {
            Overwrite::Refuse
        }
    }
}

/// A temporary file of dampid's naming younger than this is never taken for stale.
pub const STALE_AFTER: Duration = Duration::from_secs(2);

/// Writes the file at `path` with `content`, atomically, under `overwrite`. Returns
/// the stale temporary files removed from its folder (module doc).
pub fn write_file(
    path: &Path,
    overwrite: Overwrite,
    content: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<Vec<PathBuf>> {
    let mut staged = Staged::new(overwrite);
    staged.add(path, content)?;
    Ok(staged.commit()?.stale)
}

/// What [`Staged::commit`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Committed {
    /// The targets written, in the order added.
    pub written: Vec<PathBuf>,
    /// Stale temporary files of earlier, killed runs removed from the targets' folders.
    pub stale: Vec<PathBuf>,
}

/// Files written to temporary names, renamed onto their targets together by
/// [`Staged::commit`]. Dropped without a commit, it removes every temporary file.
pub struct Staged {
    overwrite: Overwrite,
    files: Vec<(NamedTempFile, PathBuf)>,
    /// The folders already cleared of stale temporary files, and what was removed.
    cleared: Vec<PathBuf>,
    stale: Vec<PathBuf>,
}

impl Staged {
    /// An empty set of outputs.
    pub fn new(overwrite: Overwrite) -> Self {
        Staged {
            overwrite,
            files: Vec::new(),
            cleared: Vec::new(),
            stale: Vec::new(),
        }
    }

    /// Writes `content` to a temporary file beside `path` (refusing up front, under
    /// [`Overwrite::Refuse`], a `path` that exists).
    pub fn add(
        &mut self,
        path: &Path,
        content: impl FnOnce(&mut dyn Write) -> Result<()>,
    ) -> Result<()> {
        if self.overwrite == Overwrite::Refuse {
            refuse_existing(path)?;
        }
        if path.is_dir() && !path.is_symlink() {
            return Err(Error::OutputExists {
                path: path.display().to_string(),
                reason: "it is a folder".into(),
            });
        }
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let name = path
            .file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let failed = |e: &dyn std::fmt::Display| Error::Output {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        if !self.cleared.iter().any(|f| f == folder) {
            self.stale.extend(remove_stale_temporaries(folder)?);
            self.cleared.push(folder.to_path_buf());
        }
        let mut temporary =
            temporary_file(folder, &name, path, self.overwrite).map_err(|e| failed(&e))?;
        {
            let mut writer = BufWriter::new(temporary.as_file_mut());
            content(&mut writer)?;
            writer.flush().map_err(|e| failed(&e))?;
        }
        temporary.as_file().sync_all().map_err(|e| failed(&e))?;
        self.files.push((temporary, path.to_path_buf()));
        Ok(())
    }

    /// Renames every temporary file onto its target, in the order added; returns the
    /// targets. A cancellation requested before the first rename ([`crate::cancel`])
    /// stops the commit with [`Error::Cancelled`], and no target is written. Under [`Overwrite::Refuse`] the first target that appeared meanwhile
    /// stops the commit with [`Error::OutputExists`]; the files not yet renamed are
    /// removed.
    pub fn commit(self) -> Result<Committed> {
        // A run cancelled while its files were written commits none of them: dropping
        // the temporary files removes them.
        crate::cancel::check("writing the output files")?;
        let mut written = Vec::with_capacity(self.files.len());
        for (temporary, target) in self.files {
            let persisted = match self.overwrite {
                Overwrite::Refuse => temporary.persist_noclobber(&target),
                Overwrite::Replace => temporary.persist(&target),
            };
            persisted.map_err(|e| {
                if e.error.kind() == std::io::ErrorKind::AlreadyExists {
                    exists(&target)
                } else {
                    Error::Output {
                        path: target.display().to_string(),
                        message: e.error.to_string(),
                    }
                }
            })?;
            written.push(target);
        }
        Ok(Committed {
            written,
            stale: self.stale,
        })
    }
}

/// The temporary file for `name` in `folder`: created with mode `0o666` less the umask
/// (as a file created normally), or with the mode of the regular file it will replace
/// under [`Overwrite::Replace`]; locked for as long as it lives (module doc).
fn temporary_file(
    folder: &Path,
    name: &str,
    target: &Path,
    overwrite: Overwrite,
) -> std::io::Result<NamedTempFile> {
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let temporary = builder.tempfile_in(folder)?;
    temporary.as_file().lock()?;
    if overwrite == Overwrite::Replace
        && let Ok(existing) = std::fs::symlink_metadata(target)
        && existing.is_file()
    {
        temporary
            .as_file()
            .set_permissions(existing.permissions())?;
    }
    Ok(temporary)
}

/// Whether `name` is of dampid's temporary naming, `.NAME.XXXXXX.tmp` (tempfile's six
/// random alphanumeric characters).
fn is_temporary_name(name: &str) -> bool {
    let Some(inner) = name
        .strip_prefix('.')
        .and_then(|rest| rest.strip_suffix(".tmp"))
    else {
        return false;
    };
    match inner.rsplit_once('.') {
        Some((target, random)) => {
            !target.is_empty()
                && random.len() == 6
                && random.bytes().all(|b| b.is_ascii_alphanumeric())
        }
        None => false,
    }
}

/// Removes from `folder` the temporary files of dampid's naming that no live process
/// holds (their lock is free) and that were not modified within [`STALE_AFTER`]; returns
/// them. A file that cannot be inspected is left alone.
pub fn remove_stale_temporaries(folder: &Path) -> Result<Vec<PathBuf>> {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return Ok(Vec::new());
    };
    let now = SystemTime::now();
    let mut removed = Vec::new();
    for entry in entries.flatten() {
        if !is_temporary_name(&entry.file_name().to_string_lossy()) {
            continue;
        }
        let path = entry.path();
        let Ok(metadata) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        let recent = metadata
            .modified()
            .ok()
            .and_then(|m| now.duration_since(m).ok())
            .is_none_or(|age| age < STALE_AFTER);
        if !metadata.is_file() || recent {
            continue;
        }
        let Ok(file) = std::fs::File::open(&path) else {
            continue;
        };
        if file.try_lock().is_err() {
            continue; // a live run is writing it
        }
        std::fs::remove_file(&path).map_err(|e| Error::Output {
            path: path.display().to_string(),
            message: format!(
                "could not remove this stale temporary file of an interrupted run: {e}"
            ),
        })?;
        removed.push(path);
    }
    removed.sort();
    Ok(removed)
}

/// [`Error::OutputExists`] when something (even a dangling symbolic link) is at `path`.
pub fn refuse_existing(path: &Path) -> Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(_) => Err(exists(path)),
        Err(_) => Ok(()),
    }
}

fn exists(path: &Path) -> Error {
    let what = if path.is_symlink() {
        "it exists (a symbolic link)"
    } else {
        "it exists"
    };
    Error::OutputExists {
        path: path.display().to_string(),
        reason: format!("{what}; dampid does not replace files unless told to (--force)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("dampid-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn bytes(content: &'static [u8]) -> impl FnOnce(&mut dyn Write) -> Result<()> {
        move |w| {
            w.write_all(content).map_err(|e| Error::Output {
                path: "test".into(),
                message: e.to_string(),
            })
        }
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_refuses_and_replaces() {
        let dir = folder("replace");
        let file = dir.join("a.txt");
        write_file(&file, Overwrite::Refuse, bytes(b"one")).unwrap();
        let again = write_file(&file, Overwrite::Refuse, bytes(b"two"));
        assert_eq!(again.unwrap_err().kind(), "output_exists");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "one");
        write_file(&file, Overwrite::Replace, bytes(b"two")).unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "two");
        assert_eq!(entries(&dir), ["a.txt"]);
    }

    /// Content that fails part way leaves neither the target nor a temporary file.
    #[test]
    fn a_failed_write_leaves_nothing() {
        let dir = folder("failed");
        let file = dir.join("b.csv");
        let result = write_file(&file, Overwrite::Refuse, |w| {
            w.write_all(b"t,x\n0,1\n").unwrap();
            Err(Error::invalid("rows", 2.0, "cut short"))
        });
        assert!(result.is_err());
        assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
    }

    /// dampid's temporary naming, `.NAME.XXXXXX.tmp`, and nothing else.
    #[test]
    fn temporary_names() {
        for name in [
            ".record_1.csv.aB3dE9.tmp",
            ".report.html.000000.tmp",
            ".a.b.c.Zz9Zz9.tmp",
        ] {
            assert!(is_temporary_name(name), "{name}");
        }
        for name in [
            "record_1.csv.aB3dE9.tmp",
            ".record_1.csv.aB3dE.tmp",
            ".record_1.csv.aB3dE9.tmpx",
            "..aB3dE9.tmp",
            ".aB3dE9.tmp",
            ".notes.tmp",
            ".x.aB-dE9.tmp",
        ] {
            assert!(!is_temporary_name(name), "{name}");
        }
    }

    /// A symbolic link is refused, and with Replace it is replaced, not followed.
    #[cfg(unix)]
    #[test]
    fn symbolic_links_are_not_followed() {
        let dir = folder("link");
        let outside = dir.join("outside.txt");
        std::fs::write(&outside, "keep").unwrap();
        let link = dir.join("report.html");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let refused = write_file(&link, Overwrite::Refuse, bytes(b"new"));
        assert!(refused.unwrap_err().to_string().contains("symbolic link"));
        write_file(&link, Overwrite::Replace, bytes(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep");
        assert!(!link.is_symlink());
        assert_eq!(std::fs::read_to_string(&link).unwrap(), "new");
    }

    /// A staged set dropped before its commit removes its temporary files; a target
    /// that appears between staging and commit stops the commit.
    #[test]
    fn staged_sets_commit_together_or_not_at_all() {
        let dir = folder("staged");
        let mut staged = Staged::new(Overwrite::Refuse);
        staged.add(&dir.join("x.csv"), bytes(b"1")).unwrap();
        drop(staged);
        assert!(entries(&dir).is_empty());

        let mut staged = Staged::new(Overwrite::Refuse);
        staged.add(&dir.join("y.csv"), bytes(b"1")).unwrap();
        std::fs::write(dir.join("y.csv"), "another run").unwrap();
        assert_eq!(staged.commit().unwrap_err().kind(), "output_exists");
        assert_eq!(
            std::fs::read_to_string(dir.join("y.csv")).unwrap(),
            "another run"
        );
        assert_eq!(entries(&dir), ["y.csv"]);
    }
}
