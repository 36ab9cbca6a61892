//! Records the git commit dampid is built from, for the HTML report's provenance
//! (`DAMPID_GIT_COMMIT`: the full hash, or "unknown" outside a git checkout or without
//! git). Never fails the build.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!text.is_empty()).then_some(text)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let commit = git(&["rev-parse", "HEAD"]);
    // Rebuild when HEAD moves: HEAD itself (a branch switch) and the branch's ref (a
    // commit); only paths that exist, since a missing one would rerun every build.
    if commit.is_some() {
        let mut watched = vec!["HEAD".to_string()];
        if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watched.push(branch);
        }
        for name in watched {
            if let Some(path) = git(&["rev-parse", "--git-path", &name])
                && std::path::Path::new(&path).exists()
            {
                println!("cargo:rerun-if-changed={path}");
            }
        }
    }
    println!(
        "cargo:rustc-env=DAMPID_GIT_COMMIT={}",
        commit.unwrap_or_else(|| "unknown".into())
    );
}
