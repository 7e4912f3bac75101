//! Records the git commit gridplan is built from, for `gridplan --version`: the short hash
//! of `git rev-parse HEAD` (uncommitted changes are not marked), or `unknown` outside a
//! git checkout or without git. Never fails the build.

use std::path::Path;
use std::process::Command;

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let output = Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(args)
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    Some(String::from_utf8_lossy(&output.stdout).trim().to_string())
}

fn main() {
    let manifest_dir: std::path::PathBuf =
        std::env::var_os("CARGO_MANIFEST_DIR").map_or_else(|| ".".into(), Into::into);
    let dir = manifest_dir.as_path();
    let commit = git(dir, &["rev-parse", "--short=12", "HEAD"]).filter(|c| !c.is_empty());
    let version = commit.unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=GRIDPLAN_GIT_COMMIT={version}");
    // Rebuild when HEAD moves: the worktree's HEAD and the branch it names.
    if let Some(head) = git(dir, &["rev-parse", "--git-path", "HEAD"]) {
        println!("cargo:rerun-if-changed={}", dir.join(head).display());
    }
    if let Some(branch) = git(dir, &["symbolic-ref", "-q", "HEAD"]) {
        if let Some(path) = git(dir, &["rev-parse", "--git-path", &branch]) {
            println!("cargo:rerun-if-changed={}", dir.join(path).display());
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
