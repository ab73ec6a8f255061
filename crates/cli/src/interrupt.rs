//! Ctrl-C, installed before anything else (so before any output file exists). SIGTERM and
//! SIGHUP (a `kill`, a closed terminal, a batch system's time limit) are handled the same way:
//! ctrlc's `termination` feature routes all three to the one handler.
//!
//! A command that can stop early and still finish its outputs (`compare`: it stops after the
//! current piece and writes a complete file of what it did) calls [`stop_gracefully`]; its first
//! Ctrl-C only sets the flag it returns. Any other Ctrl-C — the first one for every
//! other command, the second one for those — removes the temporaries of the output files still
//! being written ([`rsts_io::close_temporaries`]: the targets keep what they had, and no new
//! temporary is made meanwhile by the working thread) and exits at once.
//!
//! The exit code follows the shell's convention, 128 + the signal: 130 for Ctrl-C (SIGINT), 143
//! for SIGTERM, 129 for SIGHUP ([`exit_code`]). ctrlc does not say which signal came, so a small
//! handler in front of ctrlc's records it ([`record_signals`]).

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, LazyLock};

/// Exit code of a run stopped by Ctrl-C (128 + SIGINT).
const EXIT_INTERRUPTED: u8 = 130;

static GRACEFUL: AtomicBool = AtomicBool::new(false);
static REQUESTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
/// The last of SIGINT, SIGTERM, SIGHUP received (0: none yet).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// The exit code of a run stopped by a signal: 128 + the signal received last (130 for Ctrl-C,
/// 143 for SIGTERM, 129 for SIGHUP).
pub fn exit_code() -> u8 {
    match SIGNAL.load(Ordering::SeqCst) {
        s @ 1..=127 => 128 + s as u8,
        _ => EXIT_INTERRUPTED,
    }
}

/// Install the handler (once, first thing in `main`).
pub fn install() {
    // If the handler cannot be installed, Ctrl-C keeps its default action (the process dies and
    // leaves hidden temporaries at worst, never a damaged target).
    let _ = ctrlc::set_handler(|| {
        // An external integrator's process (group) is killed at once either way.
        rsts_external::kill_running();
        if GRACEFUL.load(Ordering::SeqCst) && !REQUESTED.swap(true, Ordering::SeqCst) {
            return;
        }
        rsts_io::close_temporaries();
        std::process::exit(i32::from(exit_code()));
    });
    record_signals();
}

/// ctrlc's own handler of SIGINT, SIGTERM and SIGHUP (one function for the three), called by
/// [`on_signal`] after it has noted the signal.
#[cfg(unix)]
static CHAINED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

#[cfg(unix)]
extern "C" fn on_signal(signal: libc::c_int) {
    // Async-signal-safe: an atomic store, then ctrlc's handler (it writes to a pipe).
    SIGNAL.store(signal, Ordering::SeqCst);
    let chained = CHAINED.load(Ordering::SeqCst);
    if chained != 0 {
        // SAFETY: `chained` is the plain handler ctrlc installed with sigaction (no SA_SIGINFO).
        let handler: extern "C" fn(libc::c_int) = unsafe { std::mem::transmute(chained) };
        handler(signal);
    }
}

/// Puts [`on_signal`] in front of each signal whose handler ctrlc installed (a signal left at
/// its default or ignored is left so).
#[cfg(unix)]
fn record_signals() {
    for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: sigaction(2) with zeroed, then filled, structures; the old action is read
        // first and replaced only when it is a plain handler (ctrlc's).
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction == libc::SIG_DFL
                || old.sa_sigaction == libc::SIG_IGN
                || old.sa_flags & libc::SA_SIGINFO != 0
            {
                continue;
            }
            CHAINED.store(old.sa_sigaction, Ordering::SeqCst);
            let mut new = old;
            new.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            libc::sigaction(signal, &new, std::ptr::null_mut());
        }
    }
}

#[cfg(not(unix))]
fn record_signals() {}

/// From now on the first Ctrl-C only asks the command to stop: the flag returned is set then.
pub fn stop_gracefully() -> Arc<AtomicBool> {
    GRACEFUL.store(true, Ordering::SeqCst);
    REQUESTED.clone()
}
