#![allow(dead_code)]

use std::path::PathBuf;

use rsts_mcap::demo::{self, Precession};
use rsts_mcap::{Sample, TrajectoryLog};

pub const EPS: f64 = 1e-3;
pub const T_END: f64 = 10.0;

/// A unique temporary path for this test.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rsts-mcap-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The samples of the demo motion.
pub fn samples(n: usize) -> Vec<Sample> {
    (0..n)
        .map(|i| demo::sample(&Precession::EXAMPLE, EPS, T_END, i, n))
        .collect()
}

/// Writes a complete log of `n` samples and returns its path and samples.
pub fn write_log(name: &str, n: usize) -> (PathBuf, Vec<Sample>) {
    let path = tmp(name);
    let samples = samples(n);
    let mut log =
        TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, T_END, n)).unwrap();
    for s in &samples {
        log.log_sample(s).unwrap();
    }
    log.finish().unwrap();
    (path, samples)
}
