//! Where a benchmark ran: CPU model, SIMD path of the Taylor kernels, cores, OS and the rsts
//! version and commit (recorded at build time; "unknown" when built outside git), and the
//! library version each integrator from outside states. In every report with a timed figure
//! (`rsts bench`, `rsts compare`).

use rsts_dynamics::integrators::SimdPath;

use crate::integrator::Integrator;
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
    /// Git commit the build was made at (uncommitted changes are not marked).
    pub commit: String,
    /// The library version each integrator from outside stated (`"version"` in its answer);
    /// those that state none are not listed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub adapters: Vec<AdapterVersion>,
}

/// An integrator's self-reported library version.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdapterVersion {
    pub method: String,
    pub version: String,
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
            adapters: Vec::new(),
        }
    }

    /// Record the version `integrator` stated, if any (once per method and version).
    pub fn record(&mut self, integrator: &dyn Integrator) {
        if let Some(version) = integrator.version() {
            let entry = AdapterVersion {
                method: integrator.name(),
                version,
            };
            if !self.adapters.contains(&entry) {
                self.adapters.push(entry);
            }
        }
    }

    /// One line for a table header (and the adapters' versions).
    pub fn describe(&self) -> String {
        let mut line = format!(
            "rsts {} ({}) on {}, {} cores, SIMD {}, {}",
            self.rsts_version, self.commit, self.cpu, self.cores, self.simd, self.os
        );
        for a in &self.adapters {
            line.push_str(&format!("; {} {}", a.method, a.version));
        }
        line
    }
}
