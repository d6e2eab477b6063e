//! Sets `TOUCH_ARM_COMMIT`: the git commit the crate is built from, as the
//! firmware's boot line prints it (`info touch-arm <version> commit <c> reset
//! <cause>`): `git rev-parse --short=12 HEAD`, with `-dirty` when a tracked
//! file differs from it, or `unknown` without git or a repository (a crate
//! tarball, or a copy inside another repository).
//!
//! Cargo reruns this when HEAD moves (the HEAD file, the branch's ref and
//! packed-refs, wherever `git rev-parse` says they are: in a worktree `.git`
//! is a file), when the index changes (`git add`, a commit) and when a file of
//! this crate changes, so `-dirty` follows edits too.

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    Some(String::from_utf8(out.stdout).ok()?.trim().to_string())
}

fn main() {
    for p in ["build.rs", "Cargo.toml", "src", "examples", "memory.x"] {
        println!("cargo:rerun-if-changed={p}");
    }
    // Only this repository's commit: a tarball unpacked inside another
    // repository is `unknown` too.
    let manifest = std::env::var("CARGO_MANIFEST_DIR").ok().and_then(|d| PathBuf::from(d).canonicalize().ok());
    let top = git(&["rev-parse", "--show-toplevel"]).and_then(|d| PathBuf::from(d).canonicalize().ok());
    let ours = manifest.is_some() && manifest == top;
    let commit = match git(&["rev-parse", "--short=12", "HEAD"]).filter(|_| ours) {
        Some(c) if !c.is_empty() => {
            let dir = git(&["rev-parse", "--git-dir"]).map(PathBuf::from);
            let common = git(&["rev-parse", "--git-common-dir"]).map(PathBuf::from);
            if let Some(dir) = &dir {
                println!("cargo:rerun-if-changed={}", dir.join("HEAD").display());
                println!("cargo:rerun-if-changed={}", dir.join("index").display());
            }
            if let (Some(common), Some(head_ref)) = (&common, git(&["symbolic-ref", "-q", "HEAD"])) {
                println!("cargo:rerun-if-changed={}", common.join(&head_ref).display());
                println!("cargo:rerun-if-changed={}", common.join("packed-refs").display());
            }
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{c}-dirty")
            } else {
                c
            }
        }
        _ => "unknown".to_string(),
    };
    println!("cargo:rustc-env=TOUCH_ARM_COMMIT={commit}");
}
