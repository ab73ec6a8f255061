//! Ctrl-C, installed before anything else (so before any output file exists). SIGTERM and
//! SIGHUP (a `kill`, a closed terminal, a batch system's time limit) are handled the same way:
//! ctrlc's `termination` feature routes all three to the one handler.
//!
//! A command that can stop early and still finish its outputs (`compare`: it stops after the
//! current piece and writes a complete file of what it did) calls [`stop_gracefully`]; its first
//! Ctrl-C only sets the flag it returns. Any other Ctrl-C — the first one for every
//! other command, the second one for those — removes the temporaries of the output files still
//! being written ([`rsts_io::close_temporaries`]: the targets keep what they had, and no new
//! temporary is made meanwhile by the working thread) and exits
//! with code 130 at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, LazyLock};

/// Exit code of a run stopped by Ctrl-C (128 + SIGINT).
pub const EXIT_INTERRUPTED: u8 = 130;

static GRACEFUL: AtomicBool = AtomicBool::new(false);
static REQUESTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));

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
        std::process::exit(i32::from(EXIT_INTERRUPTED));
    });
}

/// From now on the first Ctrl-C only asks the command to stop: the flag returned is set then.
pub fn stop_gracefully() -> Arc<AtomicBool> {
    GRACEFUL.store(true, Ordering::SeqCst);
    REQUESTED.clone()
}
