//! The vector instructions of the Taylor kernels, chosen **at run time**: AVX-512 (one 8-lane
//! register), AVX2 with FMA (two 4-lane registers) or portable code (no target feature: what
//! the build targets). The build has no target-cpu flag, so the binary runs anywhere; each path
//! is compiled into a function with `#[target_feature]` and picked with
//! `is_x86_feature_detected!` ([`SimdPath::detect`]). `RSTS_SIMD=avx512|avx2|portable`
//! forces a path ([`SimdPath::from_env`]).
//!
//! A path is a type implementing [`Isa`]: 8-lane vectors of f64 and the few operations the
//! kernels use. The kernels are written once, generic over it, with `#[inline(always)]`, and
//! are instantiated inside each path's `#[target_feature]` entry point, so every operation
//! (and every `f64::mul_add` of the scalar code) compiles to that path's instructions; the
//! portable path never calls `fma` (it has no FMA unit to rely on: error-free products use
//! Dekker's splitting).

use std::fmt;
use std::str::FromStr;

use crate::error::DynamicsError;

use super::layout::{PermSpec, LANES};

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
pub(crate) mod portable;

/// Environment variable that forces a path.
pub const SIMD_ENV: &str = "RSTS_SIMD";

/// A row of 8 lanes, aligned for one AVX-512 load.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Row8(pub [f64; LANES]);

/// The code path of the Taylor kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimdPath {
    /// AVX-512F: one 8-lane register per row.
    Avx512,
    /// AVX2 and FMA: two 4-lane registers per row.
    Avx2,
    /// No target feature (SSE2 on x86-64); products made exact by Dekker's splitting.
    Portable,
}

impl SimdPath {
    pub const ALL: [SimdPath; 3] = [SimdPath::Avx512, SimdPath::Avx2, SimdPath::Portable];

    pub fn as_str(&self) -> &'static str {
        match self {
            SimdPath::Avx512 => "avx512",
            SimdPath::Avx2 => "avx2",
            SimdPath::Portable => "portable",
        }
    }

    /// Can this CPU run the path?
    pub fn available(&self) -> bool {
        match self {
            SimdPath::Portable => true,
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx2")
                    && is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The fastest path this CPU has.
    pub fn detect() -> SimdPath {
        Self::ALL
            .into_iter()
            .find(|p| p.available())
            .unwrap_or(SimdPath::Portable)
    }

    /// The path to run: the one named by `RSTS_SIMD` if set (an error if it is unknown or this
    /// CPU lacks it), else [`SimdPath::detect`].
    pub fn from_env() -> Result<SimdPath, DynamicsError> {
        Self::resolve(std::env::var(SIMD_ENV).ok().as_deref())
    }

    /// [`SimdPath::from_env`] for a given value of the variable (`None`: unset; an empty value
    /// counts as unset).
    pub fn resolve(value: Option<&str>) -> Result<SimdPath, DynamicsError> {
        match value.map(str::trim) {
            None | Some("") => Ok(Self::detect()),
            Some(v) => {
                let path: SimdPath = v.parse()?;
                if path.available() {
                    Ok(path)
                } else {
                    Err(DynamicsError::Settings(format!(
                        "{SIMD_ENV}={v}: this CPU cannot run the {v} path (available: {})",
                        Self::ALL
                            .iter()
                            .filter(|p| p.available())
                            .map(|p| p.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )))
                }
            }
        }
    }
}

impl fmt::Display for SimdPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for SimdPath {
    type Err = DynamicsError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|p| p.as_str() == s.to_ascii_lowercase())
            .ok_or_else(|| {
                DynamicsError::Settings(format!(
                    "{SIMD_ENV}={s}: unknown path (known: avx512, avx2, portable)"
                ))
            })
    }
}

/// The operations of one code path on 8-lane vectors of f64 (and the scalar error-free
/// product). All are `unsafe`: they may only run on a CPU that has the path's features,
/// inside that path's `#[target_feature]` entry point.
pub(crate) trait Isa: Copy + 'static {
    /// 8 lanes of f64.
    type V: Copy;
    /// A lane permutation prepared for [`Isa::permute`].
    type P: Copy;

    unsafe fn zero() -> Self::V;
    unsafe fn splat(x: f64) -> Self::V;
    unsafe fn load(r: &Row8) -> Self::V;
    unsafe fn store(v: Self::V, r: &mut Row8);
    unsafe fn add(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn sub(a: Self::V, b: Self::V) -> Self::V;
    unsafe fn mul(a: Self::V, b: Self::V) -> Self::V;
    /// a·b + c, fused where the path has FMA (one rounding), else two roundings.
    unsafe fn mul_add(a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// (p, e) with p = fl(a·b), p + e = a·b exactly.
    unsafe fn two_prod(a: Self::V, b: Self::V) -> (Self::V, Self::V);
    unsafe fn prepare(spec: &PermSpec) -> Self::P;
    /// The lanes of `spec` gathered from a row in lane form: Q lanes `q` (positions 0..8) and
    /// N values `n` (positions 8..12, in lanes 0..4 of `n`); zero where `spec` has `None`.
    unsafe fn permute(q: Self::V, n: Self::V, p: &Self::P) -> Self::V;
    /// max over the lanes of |v|.
    unsafe fn max_abs(v: Self::V) -> f64;
    /// Scalar (p, e): p = fl(a·b), p + e = a·b exactly.
    unsafe fn two_prod_f64(a: f64, b: f64) -> (f64, f64);
    /// Scalar a·b + c (fused where the path has FMA).
    unsafe fn mul_add_f64(a: f64, b: f64, c: f64) -> f64;
}
