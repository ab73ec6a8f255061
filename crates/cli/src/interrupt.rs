//! Ctrl-C, installed before anything else (so before any output file exists). SIGTERM and
//! SIGHUP (a `kill`, a closed terminal, a batch system's time limit) are handled the same way.
//!
//! A command that can stop early and still finish its outputs (`compare`: it stops after the
//! current piece and writes a complete file of what it did) calls [`stop_gracefully`]; its first
//! Ctrl-C only sets the flag it returns. Any other Ctrl-C — the first one for every
//! other command, the second one for those — removes the temporaries of the output files still
//! being written ([`rsts_io::close_temporaries`]: the targets keep what they had, and no new
//! temporary is made meanwhile by the working thread) and exits at once.
//!
//! The exit code follows the shell's convention, 128 + the signal: 130 for Ctrl-C (SIGINT), 143
//! for SIGTERM, 129 for SIGHUP ([`exit_code`]).
//!
//! A self-pipe: the signal handler only notes the signal and writes one byte to a pipe (both
//! async-signal-safe); a thread reading the pipe does the rest ([`on_stop`]), where locks and
//! file removal are allowed.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, LazyLock};

/// Exit code of a run stopped by Ctrl-C (128 + SIGINT).
const EXIT_INTERRUPTED: u8 = 130;

static GRACEFUL: AtomicBool = AtomicBool::new(false);
static REQUESTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
/// The last of SIGINT, SIGTERM, SIGHUP received (0: none yet).
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// The write end of the self-pipe (-1: not installed).
static PIPE: AtomicI32 = AtomicI32::new(-1);

/// The exit code of a run stopped by a signal: 128 + the signal received last (130 for Ctrl-C,
/// 143 for SIGTERM, 129 for SIGHUP).
pub fn exit_code() -> u8 {
    match SIGNAL.load(Ordering::SeqCst) {
        s @ 1..=127 => 128 + s as u8,
        _ => EXIT_INTERRUPTED,
    }
}

/// What a signal does, on the thread that reads the pipe.
fn on_stop() {
    // An external integrator's process (group) is killed at once either way.
    rsts_external::kill_running();
    if GRACEFUL.load(Ordering::SeqCst) && !REQUESTED.swap(true, Ordering::SeqCst) {
        return;
    }
    rsts_io::close_temporaries();
    std::process::exit(i32::from(exit_code()));
}

extern "C" fn on_signal(signal: libc::c_int) {
    // Async-signal-safe: an atomic store and write(2) of one byte (the pipe does not block).
    SIGNAL.store(signal, Ordering::SeqCst);
    let fd = PIPE.load(Ordering::SeqCst);
    if fd >= 0 {
        let byte = 1u8;
        // SAFETY: one byte from a live local to a descriptor this process owns.
        unsafe {
            libc::write(fd, (&byte as *const u8).cast(), 1);
        }
    }
}

/// Install the handler (once, first thing in `main`). If it cannot be installed, Ctrl-C keeps
/// its default action (the process dies and leaves hidden temporaries at worst, never a
/// damaged target).
pub fn install() {
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: pipe2(2) fills the two descriptors; fcntl(2) sets a flag on the write end.
    let (read, write) = unsafe {
        if libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) != 0 {
            return;
        }
        libc::fcntl(fds[1], libc::F_SETFL, libc::O_NONBLOCK);
        (fds[0], fds[1])
    };
    let watcher = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || loop {
            let mut byte = 0u8;
            // SAFETY: read(2) of one byte into a live local.
            let n = unsafe { libc::read(read, (&mut byte as *mut u8).cast(), 1) };
            if n == 1 {
                on_stop();
            } else if n == 0
                || std::io::Error::last_os_error().kind() != std::io::ErrorKind::Interrupted
            {
                return;
            }
        });
    if watcher.is_err() {
        return;
    }
    PIPE.store(write, Ordering::SeqCst);
    for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: sigaction(2) with a zeroed, then filled, structure; the handler is
        // async-signal-safe.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            libc::sigemptyset(&mut action.sa_mask);
            action.sa_flags = libc::SA_RESTART;
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

/// From now on the first Ctrl-C only asks the command to stop: the flag returned is set then.
pub fn stop_gracefully() -> Arc<AtomicBool> {
    GRACEFUL.store(true, Ordering::SeqCst);
    REQUESTED.clone()
}
