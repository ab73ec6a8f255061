//! Inputs: read whole only within a stated bound, and never the place an output goes.
//!
//! [`read_bounded`] reads a file (or a device, a FIFO, `/dev/stdin`) whole only when it holds at
//! most a stated number of bytes: a regular file's size is checked before anything is read, any
//! other input stops one byte past the bound (a zero-filled device or an endless FIFO ends there
//! instead of growing memory until it runs out).
//!
//! [`check_outputs`] refuses, before any work, an output that is one of the inputs (the same
//! file by device and inode: the same path, a hard link, a symbolic link to it), an output
//! directory that holds an input (it is replaced whole), and two outputs that are one file: a
//! run would otherwise replace what it reads.

use std::fs;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// Characters of a value shown in a message ([`cut`]).
pub const SHOWN_CHARS: usize = 40;

/// A value as shown in a message: at most [`SHOWN_CHARS`] characters, then `… (N characters)`
/// (a 50 MB field or a 200 kB line is not repeated whole).
pub fn cut(s: &str) -> String {
    let n = s.chars().count();
    if n <= SHOWN_CHARS {
        return s.to_string();
    }
    let head: String = s.chars().take(SHOWN_CHARS).collect();
    format!("{head}… ({n} characters)")
}

/// `bytes` in the largest binary unit that keeps it whole-ish: `64 MiB`, `2 GiB`, `512 bytes`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [(&str, u64); 3] = [("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)];
    for (unit, size) in UNITS {
        if bytes >= size && bytes.is_multiple_of(size) {
            return format!("{} {unit}", bytes / size);
        }
        if bytes >= size {
            return format!("{:.1} {unit}", bytes as f64 / size as f64);
        }
    }
    format!("{bytes} bytes")
}

/// The error of an input past its bound: `SIZE bytes: larger than the LIMIT bytes (HUMAN) WHAT
/// may have` (`size` unknown for a stream).
fn too_large(size: Option<u64>, limit: u64, what: &str) -> io::Error {
    let size = size.map_or(String::new(), |n| format!("{n} bytes: "));
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!(
            "{size}larger than the {limit} bytes ({}) {what} may have",
            human_bytes(limit)
        ),
    )
}

/// A reader that fails (`InvalidData`, "larger than the LIMIT bytes … WHAT may have") when its
/// input goes on past `limit` bytes: an input read in a stream (line by line, by a JSON
/// parser) is bounded as one read whole is.
#[derive(Debug)]
pub struct Bounded<R> {
    inner: R,
    left: u64,
    limit: u64,
    what: String,
}

impl<R: Read> Bounded<R> {
    /// At most `limit` bytes of `inner`; `what` names the kind of input ("an events file").
    pub fn new(inner: R, limit: u64, what: &str) -> Self {
        Self {
            inner,
            left: limit,
            limit,
            what: what.to_string(),
        }
    }
}

impl<R: Read> Read for Bounded<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        // One byte more than is left tells a longer input from one of exactly `limit`.
        let want = buf
            .len()
            .min(usize::try_from(self.left.saturating_add(1)).unwrap_or(usize::MAX));
        let n = self.inner.read(&mut buf[..want])?;
        if n as u64 > self.left {
            return Err(too_large(None, self.limit, &self.what));
        }
        self.left -= n as u64;
        Ok(n)
    }
}

/// Open `path` to read at most `limit` bytes of it: a regular file larger than that is refused
/// before anything is read (its size names the error), any other input (a device, a FIFO) fails
/// when it goes on past `limit` ([`Bounded`]). A directory is refused. The error does not name
/// the path (the caller adds its option and path).
pub fn open_bounded(path: &Path, limit: u64, what: &str) -> io::Result<Bounded<fs::File>> {
    let file = fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "a directory, not a file",
        ));
    }
    if meta.is_file() && meta.len() > limit {
        return Err(too_large(Some(meta.len()), limit, what));
    }
    Ok(Bounded::new(file, limit, what))
}

impl<R: Read> Bounded<R> {
    /// Read the rest of the input onto `buf`, whose capacity never passes the bound (plus one
    /// byte): a regular file's size is reserved at once, a stream grows by doubling up to the
    /// bound (`read_to_end` would double past it, up to twice the bound).
    pub fn read_all(&mut self, buf: &mut Vec<u8>, size_hint: Option<u64>) -> io::Result<()> {
        let cap = usize::try_from(self.limit.saturating_add(1)).unwrap_or(usize::MAX);
        if let Some(n) = size_hint {
            let n = usize::try_from(n).unwrap_or(usize::MAX).min(cap);
            buf.reserve_exact(n.saturating_sub(buf.len()) + 1);
        }
        let mut chunk = vec![0u8; 1 << 16];
        loop {
            let n = match self.read(&mut chunk) {
                Ok(0) => return Ok(()),
                Ok(n) => n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if buf.capacity() - buf.len() < n {
                let want = (2 * buf.capacity())
                    .max(1 << 16)
                    .min(cap)
                    .max(buf.len() + n);
                buf.reserve_exact(want - buf.len());
            }
            buf.extend_from_slice(&chunk[..n]);
        }
    }
}

/// The bytes of `path` when it holds at most `limit` of them ([`open_bounded`]: a regular
/// file's size is checked before it is read; a device or FIFO stops one byte past the bound).
/// Memory is the bytes read, never more than the bound ([`Bounded::read_all`]).
pub fn read_bounded(path: &Path, limit: u64, what: &str) -> io::Result<Vec<u8>> {
    let mut input = open_bounded(path, limit, what)?;
    let size = input
        .inner
        .metadata()
        .ok()
        .filter(|m| m.is_file())
        .map(|m| m.len());
    let mut bytes = Vec::new();
    input.read_all(&mut bytes, size)?;
    Ok(bytes)
}

/// [`read_bounded`] of a stream (standard input, say).
pub fn read_stream_bounded(input: impl Read, limit: u64, what: &str) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    Bounded::new(input, limit, what).read_all(&mut bytes, None)?;
    Ok(bytes)
}

/// [`read_bounded`] as UTF-8 text (an error names the first byte that is not).
pub fn read_text_bounded(path: &Path, limit: u64, what: &str) -> io::Result<String> {
    let bytes = read_bounded(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to() + 1),
        )
    })
}

/// An output of a run, named as the user gave it (`--mcap`, `-o`).
#[derive(Clone, Copy, Debug)]
pub enum Output<'a> {
    /// A file (written whole by [`crate::AtomicFile`]: the path is replaced).
    File(&'a str, &'a Path),
    /// A directory (built beside and swapped in whole by [`crate::AtomicDir`]: everything
    /// inside it is replaced).
    Dir(&'a str, &'a Path),
}

/// An input of a run, named as the user gave it (`FILE`, `--times-file`, `--baseline`).
pub type Input<'a> = (&'a str, &'a Path);

/// The device and inode of what `p` names (symbolic links followed); `None` when it does not
/// exist.
fn identity(p: &Path) -> Option<(u64, u64, fs::FileType)> {
    use std::os::unix::fs::MetadataExt;
    fs::metadata(p)
        .ok()
        .map(|m| (m.dev(), m.ino(), m.file_type()))
}

/// How `output` is `input`: "the same file", "a hard link to it", "a symbolic link to it".
fn how_same(output: &Path, input: &Path) -> &'static str {
    let link = |p: &Path| fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink());
    if link(output) || link(input) {
        "a symbolic link to it"
    } else if fs::canonicalize(output).ok() == fs::canonicalize(input).ok() {
        "the same file"
    } else {
        "a hard link to it"
    }
}

/// Where a file output goes: the file it names when it exists (device and inode), else the
/// canonical path of its directory joined with its name; `None` when neither can be known.
#[derive(PartialEq)]
enum Place {
    File(u64, u64),
    Path(PathBuf),
}

fn where_written(p: &Path) -> Option<Place> {
    if let Some((dev, ino, _)) = identity(p) {
        return Some(Place::File(dev, ino));
    }
    let name = p.file_name()?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(Place::Path(canonical(dir)?.join(name)))
}

/// The canonical form of `p` (symbolic links and `..` resolved); `None` when it does not exist.
fn canonical(p: &Path) -> Option<PathBuf> {
    fs::canonicalize(p).ok()
}

fn refused(text: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, text)
}

/// Refuse, before any work, outputs that would replace an input: a file output that is an input
/// (same device and inode: the same path, a hard link, or a symbolic link to it), a directory
/// output that is or holds an input (canonical paths), and two file outputs that are one file.
/// A character device or FIFO (written in place, never replaced) is not refused. Inputs named
/// `-` (standard input) and paths that do not exist are skipped. The error names both, e.g.
/// `--mcap traj.csv is the input FILE traj.csv (the same file): writing it would destroy the
/// input; give another output`.
pub fn check_outputs(inputs: &[Input], outputs: &[Output]) -> io::Result<()> {
    use std::os::unix::fs::FileTypeExt;
    let in_place = |k: &fs::FileType| k.is_char_device() || k.is_fifo();
    let inputs: Vec<&Input> = inputs
        .iter()
        .filter(|(_, p)| *p != Path::new("-"))
        .collect();
    for (k, out) in outputs.iter().enumerate() {
        match *out {
            Output::File(option, path) => {
                // Two outputs that are one file, existing or not (the same place once resolved).
                for other in &outputs[k + 1..] {
                    if let Output::File(option2, path2) = *other {
                        if where_written(path).is_some_and(|w| Some(w) == where_written(path2)) {
                            return Err(refused(format!(
                                "{option} {} and {option2} {} are one file: one output would \
                                 replace the other; give two different files",
                                path.display(),
                                path2.display()
                            )));
                        }
                    }
                }
                let Some((dev, ino, kind)) = identity(path) else {
                    continue;
                };
                if in_place(&kind) {
                    continue;
                }
                for (what, input) in &inputs {
                    if identity(input).is_some_and(|(d, i, _)| (d, i) == (dev, ino)) {
                        return Err(refused(format!(
                            "{option} {} is the input {what} {} ({}): writing it would destroy \
                             the input; give another output",
                            path.display(),
                            input.display(),
                            how_same(path, input)
                        )));
                    }
                }
            }
            Output::Dir(option, dir) => {
                let Some(dir_c) = canonical(dir) else {
                    continue;
                };
                for (what, input) in &inputs {
                    if canonical(input).is_some_and(|i| i.starts_with(&dir_c)) {
                        return Err(refused(format!(
                            "{option} {} holds the input {what} {}: the directory is replaced \
                             whole when it is written and the input would be lost; give another \
                             directory",
                            dir.display(),
                            input.display()
                        )));
                    }
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("rsts-io-in-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    /// The same path, `./` and `..` spellings, a hard link and a symbolic link are the input;
    /// another file, a missing one and a device are not.
    #[test]
    fn an_output_that_is_an_input_is_refused_naming_both() {
        let d = scratch("same");
        let input = d.join("traj.csv");
        fs::write(&input, "t\n").unwrap();
        let hard = d.join("hard.csv");
        fs::hard_link(&input, &hard).unwrap();
        let soft = d.join("soft.mcap");
        std::os::unix::fs::symlink(&input, &soft).unwrap();
        fs::create_dir_all(d.join("sub")).unwrap();
        let dotted = d.join("sub/../traj.csv");
        let inputs = [("FILE", input.as_path())];
        for (out, how) in [
            (&input, "the same file"),
            (&dotted, "the same file"),
            (&hard, "a hard link to it"),
            (&soft, "a symbolic link to it"),
        ] {
            let e = check_outputs(&inputs, &[Output::File("--mcap", out)])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("--mcap {}", out.display()))
                    && e.contains(&format!("the input FILE {}", input.display()))
                    && e.contains(how),
                "{e}"
            );
        }
        let other = d.join("other.mcap");
        fs::write(&other, "x").unwrap();
        check_outputs(&inputs, &[Output::File("--mcap", &other)]).unwrap();
        check_outputs(&inputs, &[Output::File("--mcap", &d.join("new.mcap"))]).unwrap();
        check_outputs(&[("FILE", Path::new("-"))], &[Output::File("-o", &input)]).unwrap();
        let null = Path::new("/dev/null");
        check_outputs(&[("FILE", null)], &[Output::File("-o", null)]).unwrap();
        assert_eq!(fs::read_to_string(&input).unwrap(), "t\n");
    }

    #[test]
    fn a_directory_holding_an_input_and_two_equal_outputs_are_refused() {
        let d = scratch("dir");
        let report = d.join("report");
        fs::create_dir_all(&report).unwrap();
        let base = report.join("report.json");
        fs::write(&base, "{}").unwrap();
        let e = check_outputs(
            &[("--baseline", base.as_path())],
            &[Output::Dir("--report", &report)],
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("--report") && e.contains("holds the input --baseline"),
            "{e}"
        );
        // The directory itself given as an input (a shard of `validate merge`).
        assert!(check_outputs(&[("DIR", &report)], &[Output::Dir("--report", &report)]).is_err());
        check_outputs(&[("DIR", &d)], &[Output::Dir("--report", &report)]).unwrap();
        let svg = d.join("a.svg");
        let spelled = d.join("sub/../a.svg");
        fs::create_dir_all(d.join("sub")).unwrap();
        for exists in [false, true] {
            if exists {
                fs::write(&svg, "x").unwrap();
            }
            let e = check_outputs(
                &[],
                &[
                    Output::File("--svg", &svg),
                    Output::File("--svg-x", &spelled),
                ],
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains("are one file"), "{e}");
        }
        check_outputs(
            &[],
            &[
                Output::File("--svg", &svg),
                Output::File("--svg-x", &d.join("b.svg")),
            ],
        )
        .unwrap();
    }

    /// A regular file is refused from its size (nothing read); a device stops one byte past the
    /// bound.
    #[test]
    fn inputs_read_whole_stop_at_their_bound() {
        let d = scratch("bound");
        let p = d.join("big");
        let f = fs::File::create(&p).unwrap();
        f.set_len(3 << 30).unwrap(); // sparse: 3 GiB that take no room
        let e = read_bounded(&p, 1 << 20, "an events file")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("3221225472 bytes: larger than the 1048576 bytes (1 MiB) an events file"),
            "{e}"
        );
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20, "a times file")
            .unwrap_err()
            .to_string();
        // A stream's buffer never passes the bound (read_to_end doubles past it).
        let mut buf = Vec::new();
        let mut zeros = Bounded::new(io::repeat(0).take(3 << 20), (1 << 20) + 5, "x");
        assert!(zeros.read_all(&mut buf, None).is_err());
        assert!(buf.capacity() <= (1 << 20) + 6, "{}", buf.capacity());
        assert!(
            e.starts_with("larger than the 1048576 bytes (1 MiB) a times file"),
            "{e}"
        );
        fs::write(&p, "0 1 2").unwrap();
        assert_eq!(read_text_bounded(&p, 5, "x").unwrap(), "0 1 2");
        assert!(read_text_bounded(&p, 4, "x").is_err());
        assert_eq!(human_bytes(2 << 30), "2 GiB");
        assert_eq!(human_bytes(1536), "1.5 KiB");
    }
}
