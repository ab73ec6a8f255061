//! The child process of an [`Exec`]: the command split like a shell would, the program checked
//! before any work, the run in its own process group under a timeout (killed when done, overdue
//! or stopped by Ctrl-C, always reaped) and the end of its stderr for messages.

use std::collections::BTreeSet;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rsts_harness::HarnessError;

use super::{Exec, MAX_TIMEOUT_SECONDS};
use crate::pipes::{Ended, Pipes};

/// Lines of a child's stderr shown in an error.
const STDERR_TAIL_LINES: usize = 15;

/// Process groups of the children now running (killed by [`kill_running`]).
static RUNNING: Mutex<BTreeSet<i32>> = Mutex::new(BTreeSet::new());
/// Set by [`kill_running`]: the children were stopped on purpose.
static STOPPED: AtomicBool = AtomicBool::new(false);

/// Kill every external integrator this process is running (for a Ctrl-C handler); their runs
/// end with an error saying they were stopped.
pub fn kill_running() {
    STOPPED.store(true, Ordering::SeqCst);
    if let Ok(set) = RUNNING.try_lock() {
        for &pgid in set.iter() {
            kill_group(pgid);
        }
    }
}

fn kill_group(pgid: i32) {
    // SAFETY: kill(2) with a negative pid signals a process group; no memory is involved.
    unsafe {
        libc::kill(-pgid, libc::SIGKILL);
    }
}

/// The one rule for a timeout: a finite number of seconds, > 0 and at most
/// [`MAX_TIMEOUT_SECONDS`] (about 31 years; a deadline that far ahead never overflows).
pub fn check_timeout(seconds: f64) -> Result<Duration, String> {
    if seconds.is_finite() && seconds > 0.0 && seconds <= MAX_TIMEOUT_SECONDS {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(format!(
            "must be a positive number of seconds, at most {MAX_TIMEOUT_SECONDS:e}; got {seconds}"
        ))
    }
}

/// Check, before any work, that `program` can be started: a path names an executable file, a
/// bare name one found on the `PATH` (a run would otherwise fail only when its turn comes, after
/// the rest of a benchmark or suite).
pub fn check_program(program: &str) -> Result<(), String> {
    let executable = |p: &std::path::Path| {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    };
    if program.contains('/') {
        let p = std::path::Path::new(program);
        if !p.exists() {
            return Err(format!("cannot start `{program}`: no such file"));
        }
        if !executable(p) {
            return Err(format!(
                "cannot start `{program}`: not an executable file (chmod +x, or name its interpreter first: python3 {program})"
            ));
        }
        return Ok(());
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    if std::env::split_paths(&path).any(|d| executable(&d.join(program))) {
        Ok(())
    } else {
        Err(format!(
            "cannot start `{program}`: no such program on the PATH"
        ))
    }
}

/// The files an external command names: its words that are existing files (the program, a
/// script given to an interpreter). They are inputs of the run: no output may replace them
/// ([`rsts_io::check_outputs`]). A command that cannot be split names none.
pub fn command_files(command: &str) -> Vec<std::path::PathBuf> {
    split_command(command)
        .unwrap_or_default()
        .into_iter()
        .map(std::path::PathBuf::from)
        .filter(|p| p.is_file())
        .collect()
}

/// Split a command line like a POSIX shell would (quotes, backslashes), without running a shell.
pub fn split_command(command: &str) -> Result<Vec<String>, String> {
    let argv = shlex::split(command).ok_or_else(|| {
        format!("cannot split `{command}`: unbalanced quotes or a trailing backslash")
    })?;
    if argv.is_empty() {
        return Err("the command is empty".into());
    }
    Ok(argv)
}

impl Exec {
    /// Run the child on `request`: its stdout (at most `max_answer` bytes, else an error), the
    /// end of its stderr and its wall time.
    pub fn run_raw(
        &self,
        request: &[u8],
        max_answer: usize,
    ) -> Result<(Vec<u8>, Vec<u8>, f64), HarnessError> {
        let mut cmd = Command::new(&self.argv[0]);
        cmd.args(&self.argv[1..])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        #[cfg(unix)]
        std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
        let started = Instant::now();
        let mut child = cmd.spawn().map_err(|e| {
            HarnessError::Integrator(format!(
                "external integrator `{}`: cannot start `{}`: {e}",
                self.command_line(),
                self.argv[0]
            ))
        })?;
        let pgid = child.id() as i32;
        if let Ok(mut set) = RUNNING.lock() {
            set.insert(pgid);
        }
        let result = self.talk(&mut child, request, started, max_answer);
        // Whatever happened: no process of the group left behind, the child reaped.
        kill_group(pgid);
        let _ = child.wait();
        if let Ok(mut set) = RUNNING.lock() {
            set.remove(&pgid);
        }
        result
    }

    fn talk(
        &self,
        child: &mut Child,
        request: &[u8],
        started: Instant,
        max_answer: usize,
    ) -> Result<(Vec<u8>, Vec<u8>, f64), HarnessError> {
        // One thread serves the three pipes until the deadline, whatever still holds them.
        let mut pipes = Pipes::new(child, request, max_answer);
        let ended = pipes.serve(child, started + self.timeout);
        let wall = started.elapsed().as_secs_f64();
        kill_group(child.id() as i32);
        let _ = child.wait();
        let (stdout, stderr) = (
            std::mem::take(&mut pipes.out),
            std::mem::take(&mut pipes.err),
        );
        match ended {
            Ended::Overdue => Err(self.fail(
                format_args!(
                    "no answer within {} s (the timeout, --exec-timeout); the process was killed",
                    self.timeout.as_secs_f64()
                ),
                &stderr,
            )),
            Ended::TooLong => Err(self.fail(
                format_args!(
                    "its answer passed {max_answer} bytes, the most an answer to this request may take \
                     (samples x digits, see docs/output.md); the process was killed"
                ),
                &stderr,
            )),
            Ended::Exited(_) if STOPPED.load(Ordering::SeqCst) => {
                Err(self.fail("stopped (Ctrl-C)", &stderr))
            }
            Ended::Exited(s) if !s.success() => Err(self.fail(describe_status(s), &stderr)),
            Ended::Exited(_) => Ok((stdout, stderr, wall)),
        }
    }
}

fn describe_status(s: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = s.signal() {
            return format!("killed by signal {sig}");
        }
    }
    match s.code() {
        Some(c) => format!("exited with status {c}"),
        None => "exited abnormally".into(),
    }
}

/// The last lines of a child's stderr, indented; "(its stderr is empty)" when there is none.
pub fn stderr_tail(stderr: &[u8]) -> String {
    let text = String::from_utf8_lossy(stderr);
    let lines: Vec<&str> = text.trim_end().lines().collect();
    if lines.is_empty() {
        return " (its stderr is empty)".into();
    }
    let from = lines.len().saturating_sub(STDERR_TAIL_LINES);
    let shown: Vec<String> = lines[from..]
        .iter()
        .map(|l| {
            let l: String = l.chars().take(300).collect();
            format!("  | {l}")
        })
        .collect();
    format!(
        "; {} of its stderr:\n{}",
        if from > 0 { "the end" } else { "all" },
        shown.join("\n")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_are_split_like_a_shell_would() {
        assert_eq!(
            split_command(r#"python3 "my adapter.py" --m 'a b' x\ y"#).unwrap(),
            vec!["python3", "my adapter.py", "--m", "a b", "x y"]
        );
        assert!(split_command("").is_err());
        assert!(split_command("   ").is_err());
        assert!(split_command("python3 'open")
            .unwrap_err()
            .contains("unbalanced"));
    }

    #[test]
    fn the_stderr_tail_keeps_the_last_lines() {
        let text: String = (0..40).map(|k| format!("line {k}\n")).collect();
        let tail = stderr_tail(text.as_bytes());
        assert!(
            tail.contains("line 39") && !tail.contains("line 24\n"),
            "{tail}"
        );
        assert!(tail.starts_with("; the end of its stderr"));
        assert_eq!(stderr_tail(b""), " (its stderr is empty)");
    }
}
