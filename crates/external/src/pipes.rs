//! The three pipes of an external integrator, served from one thread by `poll(2)` until a
//! deadline: the request written to its stdin, its stdout read up to a cap, only the tail of its
//! stderr kept. Nothing here waits past the deadline, whatever process still holds a pipe (a
//! grandchild in a session of its own keeps it open after the child has gone).

use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsRawFd;
use std::process::{Child, ChildStderr, ChildStdin, ChildStdout, ExitStatus};
use std::time::{Duration, Instant};

/// Bytes of a child's stderr kept (its end; the message shows its last lines).
pub const STDERR_KEPT_BYTES: usize = 64 * 1024;
/// How long the pipes are still read after the child has exited (for an end of file that a
/// lingering grandchild may never give).
pub const AFTER_EXIT: Duration = Duration::from_millis(500);

/// How a conversation ended.
pub enum Ended {
    /// The child exited (its status), its pipes read to their end or for [`AFTER_EXIT`].
    Exited(ExitStatus),
    /// The deadline came first.
    Overdue,
    /// Its stdout passed the cap (the child is still running).
    TooLong,
}

/// The pipes of one child.
pub struct Pipes {
    stdin: Option<ChildStdin>,
    request: Vec<u8>,
    written: usize,
    stdout: Option<ChildStdout>,
    stderr: Option<ChildStderr>,
    /// Everything the child wrote on stdout (at most the cap plus one read).
    pub out: Vec<u8>,
    /// The end of what it wrote on stderr.
    pub err: Vec<u8>,
    max_out: usize,
}

fn nonblocking(fd: i32) {
    // SAFETY: fcntl on a pipe descriptor this process owns; no memory is involved.
    unsafe {
        let flags = libc::fcntl(fd, libc::F_GETFL);
        if flags >= 0 {
            libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK);
        }
    }
}

impl Pipes {
    /// Take the piped stdin, stdout and stderr of `child`; `request` is written to its stdin,
    /// at most `max_out` bytes are accepted from its stdout.
    pub fn new(child: &mut Child, request: &[u8], max_out: usize) -> Self {
        let stdin = child.stdin.take();
        let stdout = child.stdout.take();
        let stderr = child.stderr.take();
        for fd in [
            stdin.as_ref().map(|p| p.as_raw_fd()),
            stdout.as_ref().map(|p| p.as_raw_fd()),
            stderr.as_ref().map(|p| p.as_raw_fd()),
        ]
        .into_iter()
        .flatten()
        {
            nonblocking(fd);
        }
        Self {
            stdin,
            request: request.to_vec(),
            written: 0,
            stdout,
            stderr,
            out: Vec::new(),
            err: Vec::new(),
            max_out,
        }
    }

    /// Serve the pipes until the child has exited and its pipes are done (or [`AFTER_EXIT`] has
    /// passed since), until `deadline`, or until its stdout passes the cap.
    pub fn serve(&mut self, child: &mut Child, deadline: Instant) -> Ended {
        let mut status: Option<ExitStatus> = None;
        let mut until = deadline;
        loop {
            if status.is_none() {
                if let Ok(Some(s)) = child.try_wait() {
                    status = Some(s);
                    until = deadline.min(Instant::now() + AFTER_EXIT);
                    // It cannot read its request any more.
                    self.stdin = None;
                }
            }
            let open = self.stdout.is_some() || self.stderr.is_some();
            if let (Some(s), false) = (status, open) {
                return Ended::Exited(s);
            }
            let now = Instant::now();
            if now >= until {
                return status.map_or(Ended::Overdue, Ended::Exited);
            }
            self.poll_once((until - now).min(Duration::from_millis(20)));
            if self.out.len() > self.max_out {
                return Ended::TooLong;
            }
        }
    }

    /// One `poll(2)` of the open pipes (at most `wait`), then whatever I/O they are ready for.
    fn poll_once(&mut self, wait: Duration) {
        let mut fds: Vec<libc::pollfd> = Vec::with_capacity(3);
        let mut push = |fd: Option<i32>, events: libc::c_short| {
            if let Some(fd) = fd {
                fds.push(libc::pollfd {
                    fd,
                    events,
                    revents: 0,
                });
            }
        };
        push(self.stdin.as_ref().map(|p| p.as_raw_fd()), libc::POLLOUT);
        push(self.stdout.as_ref().map(|p| p.as_raw_fd()), libc::POLLIN);
        push(self.stderr.as_ref().map(|p| p.as_raw_fd()), libc::POLLIN);
        let ms = wait.as_millis().clamp(1, 1000) as libc::c_int;
        // SAFETY: `fds` is a valid array of `fds.len()` pollfd structures.
        let ready = unsafe { libc::poll(fds.as_mut_ptr(), fds.len() as libc::nfds_t, ms) };
        if ready <= 0 {
            return;
        }
        self.write_request();
        read_some(&mut self.stdout, &mut self.out, usize::MAX);
        read_some(&mut self.stderr, &mut self.err, STDERR_KEPT_BYTES);
    }

    /// Write what the pipe takes of the rest of the request; close stdin when all is written or
    /// the child closed its end (its answer and status tell what went wrong).
    fn write_request(&mut self) {
        let Some(pipe) = self.stdin.as_mut() else {
            return;
        };
        while self.written < self.request.len() {
            match pipe.write(&self.request[self.written..]) {
                Ok(0) => break,
                Ok(n) => self.written += n,
                Err(e) if e.kind() == ErrorKind::WouldBlock => return,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => break,
            }
        }
        self.stdin = None;
    }
}

/// Read what `pipe` has now into `buf` (keeping only its last `keep` bytes); close the pipe at
/// its end or on an error.
fn read_some<R: Read>(pipe: &mut Option<R>, buf: &mut Vec<u8>, keep: usize) {
    let Some(p) = pipe.as_mut() else {
        return;
    };
    let mut chunk = [0u8; 64 * 1024];
    let mut this_round = 0;
    loop {
        match p.read(&mut chunk) {
            Ok(0) => {
                *pipe = None;
                return;
            }
            Ok(n) => {
                buf.extend_from_slice(&chunk[..n]);
                if buf.len() > keep.saturating_mul(2) {
                    buf.drain(..buf.len() - keep);
                }
                // Enough for this round: the caller checks the cap between rounds.
                this_round += n;
                if this_round >= 1 << 20 {
                    return;
                }
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => return,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => {
                *pipe = None;
                return;
            }
        }
    }
}
