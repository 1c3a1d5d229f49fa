//! Records the git commit towride is built from (`TOWRIDE_GIT_COMMIT`), so that every
//! run can say what produced it: "+modified" when the sources differ from it, "unknown"
//! outside a git checkout.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

fn main() {
    let mut commit = git(&["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // A build from changed sources is not that commit: say so, or a run's provenance lies.
    let changed = Command::new("git")
        .args([
            "diff",
            "--quiet",
            "HEAD",
            "--",
            "src",
            "crates",
            "Cargo.toml",
            "Cargo.lock",
        ])
        .status()
        .is_ok_and(|s| s.code() == Some(1));
    if changed {
        commit.push_str("+modified");
    }
    println!("cargo:rustc-env=TOWRIDE_GIT_COMMIT={commit}");
    // Build again when HEAD moves (HEAD itself, the branch it names, packed refs) and when
    // the sources change (the "+modified" mark).
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=crates");
    let mut watch = vec!["HEAD".to_string(), "packed-refs".to_string()];
    if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
        watch.push(r);
    }
    for w in watch {
        if let Some(p) = git(&["rev-parse", "--git-path", &w]) {
            if std::path::Path::new(&p).exists() {
                println!("cargo:rerun-if-changed={p}");
            }
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
