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

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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

/// Writes the file at `path` with `content`, atomically, under `overwrite`.
pub fn write_file(
    path: &Path,
    overwrite: Overwrite,
    content: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    let mut staged = Staged::new(overwrite);
    staged.add(path, content)?;
    staged.commit()?;
    Ok(())
}

/// Files written to temporary names, renamed onto their targets together by
/// [`Staged::commit`]. Dropped without a commit, it removes every temporary file.
pub struct Staged {
    overwrite: Overwrite,
    files: Vec<(NamedTempFile, PathBuf)>,
}

impl Staged {
    /// An empty set of outputs.
    pub fn new(overwrite: Overwrite) -> Self {
        Staged {
            overwrite,
            files: Vec::new(),
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
        let mut temporary = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(folder)
            .map_err(|e| failed(&e))?;
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
    pub fn commit(self) -> Result<Vec<PathBuf>> {
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
        Ok(written)
    }
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
