//! Where a benchmark ran: CPU model, SIMD path of the Taylor kernels, cores, OS and the rsts
//! version and commit (recorded at build time; "unknown" when built outside git).

use rsts_dynamics::integrators::SimdPath;
use serde::{Deserialize, Serialize};

/// The environment of a report (`environment` in `rsts bench --format json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Environment {
    /// CPU model name (/proc/cpuinfo; "unknown" elsewhere).
    pub cpu: String,
    /// SIMD path the f64 and double-double Taylor kernels take (`RSTS_SIMD` or detected).
    pub simd: String,
    /// Logical cores available to this process.
    pub cores: usize,
    pub os: String,
    pub rsts_version: String,
    /// Git commit of the build (`-dirty` with uncommitted changes).
    pub commit: String,
}

impl Environment {
    /// The environment of this process.
    pub fn detect() -> Self {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split_once(':'))
                    .map(|(_, v)| v.trim().to_string())
            })
            .unwrap_or_else(|| "unknown".to_string());
        Self {
            cpu,
            simd: SimdPath::from_env()
                .map(|p| p.as_str().to_string())
                .unwrap_or_else(|e| format!("unavailable ({e})")),
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
            rsts_version: env!("CARGO_PKG_VERSION").to_string(),
            commit: env!("RSTS_GIT_COMMIT").to_string(),
        }
    }

    /// One line for a table header.
    pub fn describe(&self) -> String {
        format!(
            "rsts {} ({}) on {}, {} cores, SIMD {}, {}",
            self.rsts_version, self.commit, self.cpu, self.cores, self.simd, self.os
        )
    }
}
