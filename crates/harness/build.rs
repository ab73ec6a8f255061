//! Records the git commit the crate is built from (`RSTS_GIT_COMMIT`, "unknown" outside git):
//! the environment of a benchmark report names it.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

fn main() {
    println!("cargo:rerun-if-env-changed=RSTS_GIT_COMMIT");
    let commit = std::env::var("RSTS_GIT_COMMIT")
        .ok()
        .filter(|s| !s.is_empty())
        .or_else(|| {
            // Rebuild when HEAD moves (a worktree's HEAD and the branch it points to).
            if let Some(p) = git(&["rev-parse", "--git-path", "HEAD"]) {
                println!("cargo:rerun-if-changed={p}");
            }
            // The branch's ref file, or packed-refs when the ref is packed (a path that does not
            // exist would rerun this script on every build).
            if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
                for path in [r.as_str(), "packed-refs"] {
                    match git(&["rev-parse", "--git-path", path]) {
                        Some(p) if std::path::Path::new(&p).exists() => {
                            println!("cargo:rerun-if-changed={p}");
                            break;
                        }
                        _ => {}
                    }
                }
            }
            git(&["rev-parse", "--short=12", "HEAD"])
        })
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=RSTS_GIT_COMMIT={commit}");
}
