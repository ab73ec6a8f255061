//! The double-double state at an f64 time compiled twice and chosen at run time: once with the
//! FMA instructions (`#[target_feature(enable = "fma")]`), once for any x86-64 (what the build
//! targets). The generic evaluation (phase, sn cn, the radicals, ω α β and every double-double
//! operation) is `#[inline(always)]`, so all of it is instantiated inside each entry point and
//! every `f64::mul_add` of the error-free products becomes one instruction on the FMA path
//! (on the portable path, a call of the library's `fma`). Both round once per `mul_add`, so
//! both paths give the same bits (tested).

use rsts_dynamics::scalar::DoubleDouble;

use super::ExplicitMotion;
use crate::formulas::{BodyState, ExplicitState};

/// A build of the double-double state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DdPath {
    /// Compiled with FMA (x86-64 CPUs from 2013 on).
    Fma,
    /// For any CPU the build targets.
    Portable,
}

impl DdPath {
    /// Can this CPU run the path?
    pub fn available(self) -> bool {
        match self {
            DdPath::Portable => true,
            #[cfg(target_arch = "x86_64")]
            DdPath::Fma => std::arch::is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            DdPath::Fma => false,
        }
    }

    /// The fastest path of this CPU.
    #[inline]
    pub fn detect() -> Self {
        if DdPath::Fma.available() {
            DdPath::Fma
        } else {
            DdPath::Portable
        }
    }
}

impl ExplicitMotion<DoubleDouble> {
    /// ω, α, β at the f64 time `t` on the fastest path of this CPU.
    #[inline]
    pub fn body_at_f64(&self, t: f64) -> BodyState<DoubleDouble> {
        self.on_path(DdPath::detect(), t, body_fma, body_portable)
    }

    /// The whole state at the f64 time `t` on the fastest path of this CPU.
    #[inline]
    pub fn at_f64(&self, t: f64) -> ExplicitState<DoubleDouble> {
        self.on_path(DdPath::detect(), t, state_fma, state_portable)
    }

    /// [`Self::body_at_f64`] on a given path; `None` when this CPU lacks it.
    pub fn body_at_f64_on(&self, path: DdPath, t: f64) -> Option<BodyState<DoubleDouble>> {
        path.available()
            .then(|| self.on_path(path, t, body_fma, body_portable))
    }

    /// `fma` or `portable` of the motion at `t` by `path`, which this CPU must have.
    #[inline(always)]
    fn on_path<R>(
        &self,
        path: DdPath,
        t: f64,
        #[allow(unused_variables)] fma: unsafe fn(&Self, f64) -> R,
        portable: fn(&Self, f64) -> R,
    ) -> R {
        match path {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the callers pass DdPath::Fma only when the CPU has FMA (detected).
            DdPath::Fma => unsafe { fma(self, t) },
            _ => portable(self, t),
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn body_fma(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    m.body_at(&DoubleDouble::from_f64_exact(t))
}

fn body_portable(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    m.body_at(&DoubleDouble::from_f64_exact(t))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn state_fma(m: &ExplicitMotion<DoubleDouble>, t: f64) -> ExplicitState<DoubleDouble> {
    m.at(&DoubleDouble::from_f64_exact(t))
}

fn state_portable(m: &ExplicitMotion<DoubleDouble>, t: f64) -> ExplicitState<DoubleDouble> {
    m.at(&DoubleDouble::from_f64_exact(t))
}
