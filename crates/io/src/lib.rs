//! Output files written whole or not at all.
//!
//! Every file `rsts` writes goes through [`AtomicFile`] (or [`AtomicDir`] for a directory of
//! files): the bytes go to a temporary beside the target (same directory, so the final rename
//! stays on one file system) and [`AtomicFile::commit`] renames it into place. Until then the
//! target is untouched: a rejected, failed, interrupted or concurrent run leaves either the
//! previous file or a complete new one, never a partial one. Temporaries are removed when the
//! value is dropped uncommitted, and [`remove_temporaries`] removes those still open (call it from
//! a Ctrl-C handler before exiting).
//!
//! [`check_writable`] tells, before long work starts, whether a target can be written;
//! [`check_outputs`] that no output is an input; [`read_bounded`] reads an input whole only
//! within a stated bound ([`inputs`]).
//!
//! Atomic replace is for regular files only. A target that is a character device (`/dev/null`,
//! `/dev/stdout` on a terminal) or a FIFO is never renamed over: the bytes are staged in the
//! system's temporary directory and copied into it in place at the commit. Sockets and block
//! devices are refused.

use std::collections::BTreeSet;
use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;

pub mod inputs;
pub use inputs::{
    check_outputs, cut, human_bytes, open_bounded, read_bounded, read_stream_bounded,
    read_text_bounded, Bounded, Input, Output,
};
pub mod utc;

/// Temporaries currently open in this process (removed by [`remove_temporaries`]).
static OPEN: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());
static COUNTER: AtomicU64 = AtomicU64::new(0);
/// Set by [`close_temporaries`]: the process is exiting, no new temporary may be made.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Make the temporary `p` with `create` and register it, both while holding the set's lock, so
/// that a Ctrl-C handler running [`close_temporaries`] on another thread either sees it and
/// removes it, or comes first and the temporary is never made.
fn create_registered<T>(p: &Path, create: impl FnOnce() -> io::Result<T>) -> io::Result<T> {
    let mut set = OPEN.lock().unwrap_or_else(|e| e.into_inner());
    if CLOSED.load(Ordering::SeqCst) {
        // The Ctrl-C handler is exiting the process (exit code 130): wait for that instead of
        // failing with an error of our own and another exit code.
        drop(set);
        loop {
            std::thread::sleep(std::time::Duration::from_secs(3600));
        }
    }
    let made = create()?;
    set.insert(p.to_path_buf());
    Ok(made)
}

fn unregister(p: &Path) {
    if let Ok(mut set) = OPEN.lock() {
        set.remove(p);
    }
}

/// Remove every temporary file and directory this process still has open: the targets keep their
/// previous contents. Safe to call more than once; later temporaries are made as usual.
pub fn remove_temporaries() {
    remove_all();
}

/// [`remove_temporaries`] for a Ctrl-C handler that exits the process right after: from now on
/// no new temporary is made (another thread that tries waits for that exit), so none is left
/// behind by a thread that was creating one meanwhile.
pub fn close_temporaries() {
    CLOSED.store(true, Ordering::SeqCst);
    remove_all();
}

fn remove_all() {
    // Never block for long: a true signal handler must not wait for a lock the interrupted
    // thread may hold. The lock is only ever held for a set insertion or removal, so a few
    // tries over ~0.2 s get it unless that thread is itself stopped inside one.
    let mut paths: Option<Vec<PathBuf>> = None;
    for _ in 0..200 {
        match OPEN.try_lock() {
            Ok(mut set) => {
                paths = Some(std::mem::take(&mut *set).into_iter().collect());
                break;
            }
            Err(std::sync::TryLockError::Poisoned(p)) => {
                paths = Some(std::mem::take(&mut *p.into_inner()).into_iter().collect());
                break;
            }
            Err(std::sync::TryLockError::WouldBlock) => {
                std::thread::sleep(std::time::Duration::from_millis(1))
            }
        }
    }
    let Some(paths) = paths else { return };
    for p in paths {
        if p.is_dir() {
            let _ = fs::remove_dir_all(&p);
        } else {
            let _ = fs::remove_file(&p);
        }
    }
}

/// The directory a target lives in ("." for a bare file name).
fn parent_dir(target: &Path) -> PathBuf {
    match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A fresh temporary name beside `target`: `.NAME.tmp-PID-N`.
fn temporary_beside(target: &Path) -> io::Result<PathBuf> {
    let name = target.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is not a file name", target.display()),
        )
    })?;
    let mut tmp = OsString::from(".");
    tmp.push(name);
    tmp.push(format!(
        ".tmp-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    Ok(parent_dir(target).join(tmp))
}

/// A target that is written in place (following symlinks): a character device or a FIFO.
/// Sockets and block devices are refused; a regular file, a missing path or a directory is not
/// special (`Ok(false)`).
pub fn is_written_in_place(target: &Path) -> io::Result<bool> {
    use std::os::unix::fs::FileTypeExt;
    let Ok(meta) = fs::metadata(target) else {
        return Ok(false);
    };
    let kind = meta.file_type();
    let refused = if kind.is_socket() {
        "a socket"
    } else if kind.is_block_device() {
        "a block device"
    } else {
        return Ok(kind.is_char_device() || kind.is_fifo());
    };
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "{} is {refused}: rsts writes regular files, character devices (such as /dev/null) and FIFOs",
            target.display()
        ),
    ))
}

/// A character device or FIFO `target` can be opened for writing by this user (checked without
/// opening it: opening a FIFO would wait for a reader).
fn check_device_writable(target: &Path) -> io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(target.as_os_str().as_bytes())?;
    // SAFETY: `c` is a valid NUL-terminated path.
    if unsafe { libc::access(c.as_ptr(), libc::W_OK) } == 0 {
        Ok(())
    } else {
        Err(context(
            io::Error::last_os_error(),
            format!("cannot write {}", target.display()),
        ))
    }
}

/// The system's temporary directory, where the bytes for a `target` written in place are
/// staged, checked to be a directory (an error names TMPDIR, not the target, when it is not).
fn check_staging_dir(target: &Path) -> io::Result<()> {
    let dir = std::env::temp_dir();
    if dir.is_dir() {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::NotFound,
        format!(
            "cannot stage the bytes for {} in the temporary directory {} ({}): it is not a \
             directory; set TMPDIR to one",
            target.display(),
            dir.display(),
            match std::env::var_os("TMPDIR") {
                Some(_) => "TMPDIR",
                None => "the default; TMPDIR is unset",
            }
        ),
    ))
}

/// A fresh temporary name in the system's temporary directory for a target written in place.
fn temporary_elsewhere(target: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    std::env::temp_dir().join(format!(
        ".rsts-{name}.tmp-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ))
}

/// Prefix an I/O error with what was being done (the OS message, e.g. "No space left on device",
/// is kept).
fn context(e: io::Error, what: impl std::fmt::Display) -> io::Error {
    io::Error::new(e.kind(), format!("{what}: {e}"))
}

/// Check, before long work starts, that `target` can be written: it is not a directory, and a
/// file can be created in its directory — or, when that directory does not exist yet, in its
/// nearest existing ancestor, which must be a directory (the missing ones are created only when
/// the file is written). Nothing is left behind, not even a directory.
pub fn check_writable(target: &Path) -> io::Result<()> {
    if is_written_in_place(target)? {
        check_device_writable(target)?;
        return check_staging_dir(target);
    }
    if target.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is a directory", target.display()),
        ));
    }
    let dir = parent_dir(target);
    let mut existing = dir.as_path();
    while !existing.exists() {
        match existing.parent() {
            Some(p) if !p.as_os_str().is_empty() => existing = p,
            _ => {
                existing = Path::new(".");
                break;
            }
        }
    }
    if !existing.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::NotADirectory,
            format!(
                "cannot create {}: {} is not a directory",
                dir.display(),
                existing.display()
            ),
        ));
    }
    let probe = temporary_beside(&existing.join("probe"))?;
    let created = create_registered(&probe, || {
        File::options().write(true).create_new(true).open(&probe)
    })
    .map_err(|e| context(e, format!("cannot write in {}", existing.display())));
    if created.is_ok() {
        let _ = fs::remove_file(&probe);
    }
    unregister(&probe);
    created.map(drop)
}

/// [`check_writable`] for a directory of outputs (`dir` itself may exist; files go inside it).
pub fn check_writable_dir(dir: &Path) -> io::Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} exists and is not a directory", dir.display()),
        ));
    }
    check_writable(&dir.join("probe"))
}

/// A file that appears at its path only when [`commit`](Self::commit)ted (a character device
/// or FIFO receives all the bytes only then, in place).
#[derive(Debug)]
pub struct AtomicFile {
    target: PathBuf,
    tmp: PathBuf,
    file: Option<BufWriter<File>>,
    in_place: bool,
}

impl AtomicFile {
    /// Start writing `target` (its directory is created when missing). The target is not touched.
    pub fn create(target: impl AsRef<Path>) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        let in_place = is_written_in_place(&target)?;
        if target.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} is a directory", target.display()),
            ));
        }
        let tmp = if in_place {
            check_device_writable(&target)?;
            check_staging_dir(&target)?;
            temporary_elsewhere(&target)
        } else {
            let dir = parent_dir(&target);
            fs::create_dir_all(&dir)
                .map_err(|e| context(e, format!("cannot create {}", dir.display())))?;
            temporary_beside(&target)?
        };
        let file = create_registered(&tmp, || {
            OpenOptions::new()
                .read(true)
                .write(true)
                .create_new(true)
                .open(&tmp)
        })
        .map_err(|e| {
            if in_place {
                context(
                    e,
                    format!(
                        "cannot stage the bytes for {} in {} (TMPDIR)",
                        target.display(),
                        parent_dir(&tmp).display()
                    ),
                )
            } else {
                context(e, format!("cannot create {}", target.display()))
            }
        })?;
        Ok(Self {
            target,
            tmp,
            file: Some(BufWriter::new(file)),
            in_place,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.target
    }

    fn inner(&mut self) -> io::Result<&mut BufWriter<File>> {
        self.file
            .as_mut()
            .ok_or_else(|| io::Error::other("the file was already committed"))
    }

    /// Flush, sync and rename into place. On error the temporary is removed and the target keeps
    /// what it had.
    pub fn commit(mut self) -> io::Result<()> {
        let target = self.target.clone();
        let mut w = self.file.take().expect("an uncommitted file has a writer");
        let result = (|| {
            w.flush()?;
            let f = w.into_inner().map_err(|e| e.into_error())?;
            if self.in_place {
                return copy_in_place(f, &target);
            }
            f.sync_all()?;
            drop(f);
            fs::rename(&self.tmp, &target)?;
            // Best effort: make the rename itself durable.
            if let Ok(d) = File::open(parent_dir(&target)) {
                let _ = d.sync_all();
            }
            Ok(())
        })();
        match result {
            Ok(()) => {
                if self.in_place {
                    let _ = fs::remove_file(&self.tmp);
                }
                unregister(&self.tmp);
                Ok(())
            }
            Err(e) => {
                let _ = fs::remove_file(&self.tmp);
                unregister(&self.tmp);
                Err(context(e, format!("writing {}", target.display())))
            }
        }
    }
}

/// Copy the staged bytes of `staged` into the device or FIFO `target`, opened for writing
/// without creating or truncating anything (a full device fails here: "No space left on
/// device").
fn copy_in_place(mut staged: File, target: &Path) -> io::Result<()> {
    staged.seek(SeekFrom::Start(0))?;
    let mut out = OpenOptions::new().write(true).open(target)?;
    io::copy(&mut staged, &mut out)?;
    out.flush()
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.inner()?.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner()?.flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.inner()?.seek(pos)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = fs::remove_file(&self.tmp);
            unregister(&self.tmp);
        }
    }
}

/// Write `bytes` to `target` whole or not at all.
pub fn write_atomic(target: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(target)?;
    f.write_all(bytes)?;
    f.commit()
}

/// A directory of output files (a report) that appears at its path only when committed; an
/// existing directory at that path is replaced only then.
#[derive(Debug)]
pub struct AtomicDir {
    target: PathBuf,
    tmp: PathBuf,
    committed: bool,
}

impl AtomicDir {
    /// Start building `target` in a temporary directory beside it.
    pub fn create(target: impl AsRef<Path>) -> io::Result<Self> {
        let target = target.as_ref().to_path_buf();
        if target.exists() && !target.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} exists and is not a directory", target.display()),
            ));
        }
        let dir = parent_dir(&target);
        fs::create_dir_all(&dir)
            .map_err(|e| context(e, format!("cannot create {}", dir.display())))?;
        let tmp = temporary_beside(&target)?;
        create_registered(&tmp, || fs::create_dir(&tmp))
            .map_err(|e| context(e, format!("cannot create {}", target.display())))?;
        Ok(Self {
            target,
            tmp,
            committed: false,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Where the files go until the commit (write them there, e.g. with [`write_atomic`] or
    /// plain `fs::write`: the whole directory is what is atomic).
    pub fn staging(&self) -> &Path {
        &self.tmp
    }

    /// Move the finished directory into place. An existing directory at the target is swapped
    /// out in one step where the OS can (Linux `renameat2(RENAME_EXCHANGE)`), else moved aside
    /// first; then removed.
    pub fn commit(mut self) -> io::Result<()> {
        let result = replace_dir(&self.tmp, &self.target);
        if result.is_err() {
            let _ = fs::remove_dir_all(&self.tmp);
        }
        unregister(&self.tmp);
        self.committed = true;
        result.map_err(|e| context(e, format!("writing {}", self.target.display())))
    }
}

impl Drop for AtomicDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.tmp);
            unregister(&self.tmp);
        }
    }
}

fn replace_dir(new: &Path, target: &Path) -> io::Result<()> {
    if !target.exists() {
        return fs::rename(new, target);
    }
    #[cfg(target_os = "linux")]
    {
        use std::ffi::CString;
        use std::os::unix::ffi::OsStrExt;
        let a = CString::new(new.as_os_str().as_bytes())?;
        let b = CString::new(target.as_os_str().as_bytes())?;
        // SAFETY: both are valid NUL-terminated paths; AT_FDCWD resolves them relative to the cwd.
        let rc = unsafe {
            libc::renameat2(
                libc::AT_FDCWD,
                a.as_ptr(),
                libc::AT_FDCWD,
                b.as_ptr(),
                libc::RENAME_EXCHANGE,
            )
        };
        if rc == 0 {
            // `new` now holds the old directory.
            let _ = fs::remove_dir_all(new);
            return Ok(());
        }
    }
    let aside = temporary_beside(target)?;
    fs::rename(target, &aside)?;
    if let Err(e) = fs::rename(new, target) {
        let _ = fs::rename(&aside, target);
        return Err(e);
    }
    let _ = fs::remove_dir_all(&aside);
    Ok(())
}

/// An error with all its causes, `outer: inner: os error` (keeps the underlying OS error, e.g.
/// "No space left on device", that many wrappers' own messages leave out). A cause whose text is
/// already part of the previous one is not repeated.
pub fn error_text(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let t = c.to_string();
        if !text.contains(&t) {
            text.push_str(": ");
            text.push_str(&t);
        }
        cause = c.source();
    }
    text
}

/// Tests that cannot run here (an optional tool such as node, scipy or heyoka is missing) call
/// this instead of passing silently: it prints `SKIPPED: TEST: REASON` on stderr and appends the
/// same line to the file named by `RSTS_SKIP_LOG` (set by `scripts/test.sh`, which counts the
/// skipped tests in its summary line).
pub fn report_skip(test: &str, reason: &str) {
    let line = format!("SKIPPED: {test}: {reason}");
    eprintln!("{line}");
    if let Some(path) = std::env::var_os("RSTS_SKIP_LOG") {
        if let Ok(mut f) = OpenOptions::new().create(true).append(true).open(path) {
            let _ = writeln!(f, "{line}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `remove_temporaries` empties the process-wide set: tests that hold temporaries take this
    /// lock so that one test's clean-up does not remove another's open file.
    static SERIAL: Mutex<()> = Mutex::new(());

    fn serial() -> std::sync::MutexGuard<'static, ()> {
        SERIAL.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("rsts-io-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn uncommitted_file_leaves_the_old_one_and_no_temporary() {
        let _serial = serial();
        let d = scratch("drop");
        let p = d.join("keep.txt");
        fs::write(&p, "old").unwrap();
        {
            let mut f = AtomicFile::create(&p).unwrap();
            f.write_all(b"new, half").unwrap();
            assert_eq!(
                fs::read_to_string(&p).unwrap(),
                "old",
                "target touched early"
            );
        }
        assert_eq!(fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(entries(&d), vec!["keep.txt"]);
    }

    #[test]
    fn commit_replaces_whole() {
        let _serial = serial();
        let d = scratch("commit");
        let p = d.join("sub/out.bin");
        fs::create_dir_all(p.parent().unwrap()).unwrap();
        fs::write(&p, "old").unwrap();
        let mut f = AtomicFile::create(&p).unwrap();
        f.write_all(b"complete").unwrap();
        f.commit().unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "complete");
        assert_eq!(entries(p.parent().unwrap()), vec!["out.bin"]);
    }

    #[test]
    fn remove_temporaries_cleans_open_files() {
        let _serial = serial();
        let d = scratch("signal");
        let p = d.join("x.mcap");
        let mut f = AtomicFile::create(&p).unwrap();
        f.write_all(b"partial").unwrap();
        f.flush().unwrap();
        assert_eq!(entries(&d).len(), 1);
        remove_temporaries();
        assert!(entries(&d).is_empty(), "{:?}", entries(&d));
        drop(f); // removing again is harmless
        assert!(!p.exists());
    }

    #[test]
    fn directory_target_and_unwritable_places_are_refused() {
        let _serial = serial();
        let d = scratch("refuse");
        assert!(AtomicFile::create(&d).is_err());
        assert!(check_writable(&d).is_err());
        assert!(check_writable(Path::new("/proc/rsts-io-test/x")).is_err());
        let file = d.join("file");
        fs::write(&file, "x").unwrap();
        assert!(check_writable(&file.join("below/x.json")).is_err());
        assert!(check_writable_dir(&file).is_err());
        check_writable(&d.join("new/deeper/file.json")).unwrap();
        check_writable_dir(&d.join("new/report")).unwrap();
        assert_eq!(entries(&d), vec!["file"], "nothing is created");
    }

    #[test]
    fn atomic_dir_swaps_whole_directories() {
        let _serial = serial();
        let d = scratch("dir");
        let target = d.join("report");
        fs::create_dir_all(&target).unwrap();
        fs::write(target.join("old.json"), "1").unwrap();
        {
            let a = AtomicDir::create(&target).unwrap();
            fs::write(a.staging().join("new.json"), "2").unwrap();
            // dropped: the old report stays
        }
        assert_eq!(entries(&target), vec!["old.json"]);
        assert_eq!(entries(&d), vec!["report"]);
        let a = AtomicDir::create(&target).unwrap();
        fs::write(a.staging().join("new.json"), "2").unwrap();
        a.commit().unwrap();
        assert_eq!(entries(&target), vec!["new.json"]);
        assert_eq!(entries(&d), vec!["report"]);
    }
}
