//! How a message should tell the user to run rsts again: `rsts` only when that name on the PATH
//! is this binary; `scripts/run.sh` when this binary is the build of a checkout (the way README's
//! Quick start runs it); else the binary's own path.

use std::path::{Path, PathBuf};

/// The command that runs this rsts from the current directory, e.g. `scripts/run.sh`.
pub fn invocation() -> String {
    let Some(exe) = std::env::current_exe().ok().map(canonical) else {
        return "rsts".into();
    };
    if let Some(paths) = std::env::var_os("PATH") {
        if std::env::split_paths(&paths).any(|dir| canonical(dir.join("rsts")) == exe) {
            return "rsts".into();
        }
    }
    // <checkout>/target/<profile>/rsts
    if let Some(checkout) = exe.ancestors().nth(3) {
        let script = checkout.join("scripts").join("run.sh");
        if script.is_file() {
            let here = std::env::current_dir().ok().map(canonical);
            return match here {
                Some(d) if d == checkout => "scripts/run.sh".into(),
                _ => script.display().to_string(),
            };
        }
    }
    exe.display().to_string()
}

fn canonical(p: impl AsRef<Path>) -> PathBuf {
    let p = p.as_ref();
    p.canonicalize().unwrap_or_else(|_| p.to_path_buf())
}
