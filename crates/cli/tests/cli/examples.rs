//! Every documented example runs as written from a fresh clone: the ```sh (or bash, shell)
//! blocks of README.md and docs/*.md, and the `Examples:` section of `rsts --help` and of every
//! subcommand's `--help`.
//!
//! The examples run in a copy of the checkout's files (what `git ls-files` lists, plus new files
//! not ignored), with nothing in out/. `rsts` is on the PATH there, as README's Quick start tells
//! a user to set it up; `target/` is this build's target directory and `cargo` builds this
//! checkout, so `scripts/run.sh`, `target/release/rsts` and `cargo build --release -p rsts-cli`
//! find the binary already built. Each document (a markdown file, a help text) starts from that
//! fresh state and runs its commands in order, sharing what they write (two documents at a time,
//! each in its own copy, the longest first; one that compiles — `pip install`, `cargo bench` —
//! beside one that does not, see [`Kind`]; `RSTS_EXAMPLES_JOBS=1` runs one at a time); a command
//! that exits non-zero, or that changes a tracked file, fails the test with the file, line and
//! command. Each document's line on stderr names its commands of a second or more.
//!
//! Markers, as comment lines inside a block:
//! - `# needs: heyoka` (or scipy, python, node, chromium, slurm; several separated by commas): the
//!   commands after it, up to the next blank line, run only when that tool is there (a remark in
//!   parentheses may follow: `# needs: slurm (run by sbatch)`); otherwise
//!   they are skipped with a message (`rsts_io::report_skip`, counted by scripts/test.sh).
//! - `# exit: 0, 1`: the exit statuses the next command may end with (default 0), for a command
//!   whose documented outcome may be a failure, e.g. a baseline comparison that a loaded machine
//!   can turn into a timing regression.
//! - `# takes: 5 min`: the next command is long. It is started and stopped after
//!   PROBE_SECONDS (CARGO_PROBE_SECONDS for a cargo command) if still running (it must not fail
//!   before); `RSTS_EXAMPLES_FULL=1` runs it to the end.
//!
//! Bare `scripts/test.sh` (this suite itself) is not run again from here. `slurm` is there when a
//! Slurm controller accepts a job (`sbatch --test-only`), not merely when sbatch is installed;
//! `RSTS_EXAMPLES_NEEDING=TOOL` runs only the examples that need TOOL (scripts/ci_slurm.sh runs
//! the Slurm ones on the Slurm that scripts/slurm_local.sh starts).

use std::collections::BTreeMap;
use std::fs;
use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Optional tools a `# needs:` marker may name.
const TOOLS: [&str; 6] = ["heyoka", "scipy", "python", "node", "chromium", "slurm"];
/// Virtual environments of optional tools, shared with the clone when the checkout has them.
const VENVS: [&str; 2] = [".venv-adapters", ".venv-heyoka"];
/// How long a `# takes:` command runs before it is stopped: long enough to get past argument
/// checks, set-up and the first results (a wrong option or a missing file fails in well under a
/// second).
const PROBE_SECONDS: u64 = 8;
/// The same for a `# takes:` cargo command (`cargo bench`, `cargo test`): cargo rejects a wrong
/// package, target or option in under a second (0.2–0.4 s here), then spends the rest compiling.
const CARGO_PROBE_SECONDS: u64 = 3;
/// Documents run side by side, each in its own copy of the checkout: at most this many at once
/// (fewer on a machine with fewer cores); `RSTS_EXAMPLES_JOBS=1` runs them one after another.
const MAX_JOBS: usize = 2;
/// Longest time one document's examples may take together.
const DOCUMENT_LIMIT: Duration = Duration::from_secs(900);

#[derive(Clone, Debug, PartialEq)]
struct Example {
    /// 1-based line of the command's first line in its source.
    line: usize,
    command: String,
    needs: Vec<String>,
    takes: Option<String>,
    /// Exit statuses that count as success (`# exit: 0, 1`); default 0.
    exit: Vec<i32>,
}

#[derive(Debug)]
struct Document {
    /// A file (`docs/validation.md`) or a help text (`rsts validate --help`).
    source: String,
    examples: Vec<Example>,
}

/// Commands of one block of (line number, text) lines, with the markers applied.
fn parse_block(lines: &[(usize, String)]) -> Result<Vec<Example>, String> {
    let mut out = Vec::new();
    let mut needs: Vec<String> = Vec::new();
    let mut takes: Option<String> = None;
    let mut exit: Vec<i32> = vec![0];
    let mut k = 0;
    while k < lines.len() {
        let (line, text) = (&lines[k].0, lines[k].1.trim());
        k += 1;
        if text.is_empty() {
            needs.clear();
            takes = None;
            continue;
        }
        if let Some(rest) = text.strip_prefix("# needs:") {
            // Tools, then an optional remark in parentheses.
            let tools = rest.split('(').next().unwrap_or("");
            for tool in tools.split([',', ' ']).filter(|t| !t.is_empty()) {
                if !TOOLS.contains(&tool) {
                    return Err(format!(
                        "line {line}: unknown tool `{tool}` in `# needs:` (known: {})",
                        TOOLS.join(", ")
                    ));
                }
                if !needs.iter().any(|t| t == tool) {
                    needs.push(tool.to_string());
                }
            }
            continue;
        }
        if let Some(rest) = text.strip_prefix("# takes:") {
            takes = Some(rest.trim().to_string());
            continue;
        }
        if let Some(rest) = text.strip_prefix("# exit:") {
            let codes = rest.split('(').next().unwrap_or("");
            exit = codes
                .split([',', ' '])
                .filter(|c| !c.is_empty())
                .map(|c| {
                    c.parse()
                        .map_err(|_| format!("line {line}: bad `# exit:` {c}"))
                })
                .collect::<Result<_, _>>()?;
            continue;
        }
        if text.starts_with('#') {
            continue;
        }
        let mut command = text.to_string();
        while command.ends_with('\\') && k < lines.len() {
            command.push('\n');
            command.push_str(lines[k].1.trim());
            k += 1;
        }
        // A here-document: its lines up to the delimiter belong to the command.
        if let Some(delimiter) = heredoc_delimiter(&command) {
            while k < lines.len() {
                command.push('\n');
                command.push_str(&lines[k].1);
                k += 1;
                if lines[k - 1].1.trim() == delimiter {
                    break;
                }
            }
        }
        out.push(Example {
            line: *line,
            command,
            needs: needs.clone(),
            takes: takes.take(),
            exit: std::mem::replace(&mut exit, vec![0]),
        });
    }
    Ok(out)
}

/// The delimiter of a here-document the command starts (`<<EOF`, `<<'PY'`, `<<-"X"`).
fn heredoc_delimiter(command: &str) -> Option<String> {
    let rest = command.split("<<").nth(1)?;
    let rest = rest.strip_prefix('-').unwrap_or(rest).trim_start();
    let word: String = rest
        .trim_start_matches(['\'', '"'])
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    (!word.is_empty()).then_some(word)
}

/// The ```sh / ```bash / ```shell blocks of a markdown text (other fences — text, toml, json,
/// yaml — are not commands).
fn markdown_examples(text: &str) -> Result<Vec<Example>, String> {
    enum State {
        Outside,
        Shell(Vec<(usize, String)>),
        Other,
    }
    let mut out = Vec::new();
    let mut state = State::Outside;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```").map(str::trim);
        state = match (state, fence) {
            (State::Outside, Some(lang)) if ["sh", "bash", "shell"].contains(&lang) => {
                State::Shell(Vec::new())
            }
            (State::Outside, Some(_)) => State::Other,
            (State::Shell(block), Some(_)) => {
                out.extend(parse_block(&block)?);
                State::Outside
            }
            (State::Other, Some(_)) => State::Outside,
            (State::Shell(mut block), None) => {
                block.push((i + 1, line.to_string()));
                State::Shell(block)
            }
            (s, None) => s,
        };
    }
    match state {
        State::Outside => Ok(out),
        _ => Err("a code block is not closed".into()),
    }
}

/// The `Examples:` section of a help text: the indented lines after it.
fn help_examples(text: &str) -> Result<Option<Vec<Example>>, String> {
    let lines: Vec<&str> = text.lines().collect();
    let Some(start) = lines.iter().position(|l| l.trim_end() == "Examples:") else {
        return Ok(None);
    };
    let mut block = Vec::new();
    for (i, line) in lines.iter().enumerate().skip(start + 1) {
        if !line.is_empty() && !line.starts_with(' ') {
            break;
        }
        block.push((i + 1, line.to_string()));
    }
    parse_block(&block).map(Some)
}

/// Subcommand names listed under `Commands:` in a help text (without `help`).
fn subcommands(help: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in help.lines() {
        if line.trim_end() == "Commands:" {
            inside = true;
            continue;
        }
        if inside {
            if !line.starts_with("  ") {
                break;
            }
            if let Some(name) = line.split_whitespace().next() {
                if name != "help" {
                    out.push(name.to_string());
                }
            }
        }
    }
    out
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .unwrap()
        .to_path_buf()
}

fn rsts_help(path: &[String]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(path)
        .arg("--help")
        .output()
        .expect("run rsts --help");
    assert!(out.status.success(), "rsts {path:?} --help failed");
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// Every document with examples; problems found while extracting them.
fn documents() -> (Vec<Document>, Vec<String>) {
    let mut docs = Vec::new();
    let mut problems = Vec::new();
    let mut files = vec![repo().join("README.md")];
    let mut md: Vec<PathBuf> = fs::read_dir(repo().join("docs"))
        .expect("docs/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    md.sort();
    files.extend(md);
    for f in files {
        let source = f
            .strip_prefix(repo())
            .unwrap()
            .to_string_lossy()
            .into_owned();
        match markdown_examples(&fs::read_to_string(&f).unwrap()) {
            Ok(examples) => docs.push(Document { source, examples }),
            Err(e) => problems.push(format!("{source}: {e}")),
        }
    }
    // Help texts: the top level, each subcommand, and their subcommands.
    let mut queue: Vec<Vec<String>> = vec![vec![]];
    while let Some(path) = queue.pop() {
        let text = rsts_help(&path);
        let source = format!(
            "rsts {}{}--help",
            path.join(" "),
            if path.is_empty() { "" } else { " " }
        );
        for sub in subcommands(&text) {
            let mut p = path.clone();
            p.push(sub);
            queue.push(p);
        }
        match help_examples(&text) {
            Ok(Some(examples)) => docs.push(Document { source, examples }),
            // A nested command (validate merge) may leave its examples to its parent.
            Ok(None) if path.len() > 1 => {}
            Ok(None) => problems.push(format!("{source}: no Examples: section")),
            Err(e) => problems.push(format!("{source}: {e}")),
        }
    }
    (docs, problems)
}

fn tool_available(tool: &str) -> bool {
    let ok = |program: &str, args: &[&str]| {
        Command::new(program)
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    match tool {
        // The Python packages live in the adapters' virtual environments
        // (scripts/install_adapters.sh), which the documented commands use.
        "heyoka" | "scipy" => VENVS.iter().any(|venv| {
            ok(
                &repo().join(venv).join("bin/python").to_string_lossy(),
                &["-c", &format!("import {tool}")],
            )
        }),
        // Python 3.9 or later that can make a virtual environment (docs/python.md makes one and
        // installs the package into it).
        "python" => ok(
            "python3",
            &[
                "-c",
                "import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 9))",
            ],
        ),
        "node" => ok("node", &["--version"]),
        "chromium" => ok("chromium", &["--version"]),
        // A controller that would take a job now, not only the client installed.
        "slurm" => ok(
            "timeout",
            &["20", "sbatch", "--test-only", "--wrap", "true"],
        ),
        _ => false,
    }
}

/// The files of a fresh clone of the checkout: tracked ones and new ones not ignored.
fn checkout_files() -> Vec<PathBuf> {
    let out = Command::new("git")
        .args([
            "ls-files",
            "-z",
            "--cached",
            "--others",
            "--exclude-standard",
        ])
        .current_dir(repo())
        .output()
        .expect("git ls-files (the examples test needs git)");
    assert!(out.status.success(), "git ls-files failed");
    out.stdout
        .split(|&b| b == 0)
        .filter(|p| !p.is_empty())
        .map(|p| PathBuf::from(String::from_utf8_lossy(p).into_owned()))
        .filter(|p| repo().join(p).is_file())
        .collect()
}

struct Sandbox {
    root: PathBuf,
    clone: PathBuf,
    /// Relative path → content of every file of the fresh clone.
    files: BTreeMap<PathBuf, Vec<u8>>,
    path: String,
}

impl Sandbox {
    /// The copy of worker `index` (each worker of the test has its own).
    fn new(index: usize) -> Self {
        let root =
            std::env::temp_dir().join(format!("rsts-examples-{}-{index}", std::process::id()));
        let _ = fs::remove_dir_all(&root);
        let clone = root.join("clone");
        let mut files = BTreeMap::new();
        for rel in checkout_files() {
            let (from, to) = (repo().join(&rel), clone.join(&rel));
            fs::create_dir_all(to.parent().unwrap()).unwrap();
            fs::copy(&from, &to).unwrap();
            files.insert(rel, fs::read(&from).unwrap());
        }
        let bin = PathBuf::from(env!("CARGO_BIN_EXE_rsts"));
        let target = bin.parent().unwrap().parent().unwrap();
        std::os::unix::fs::symlink(target, clone.join("target")).unwrap();
        for venv in VENVS {
            if repo().join(venv).is_dir() {
                std::os::unix::fs::symlink(repo().join(venv), clone.join(venv)).unwrap();
            }
        }
        // `rsts` on the PATH; `cargo` builds this checkout (the clone's sources are its files).
        let shims = root.join("bin");
        fs::create_dir_all(&shims).unwrap();
        std::os::unix::fs::symlink(&bin, shims.join("rsts")).unwrap();
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let shim = format!(
            r#"#!/usr/bin/env bash
# cargo for the examples test: paths into the clone are the checkout's paths, except under the
# clone's out/, where examples make their own files (a scratch crate, say).
clone='{clone}'
repo='{repo}'
args=()
for a in "$@"; do
  case "$a" in
    "$clone"/out/* | *="$clone"/out/*) args+=("$a") ;;
    *) args+=("${{a//"$clone"/"$repo"}}") ;;
  esac
done
case " ${{args[*]}} " in
  *" --manifest-path"*) exec "{cargo}" "${{args[@]}}" ;;
esac
# An option first (`cargo --version`, as maturin asks): no subcommand to add a manifest to.
case "${{args[0]:-}}" in
  -*) exec "{cargo}" "${{args[@]}}" ;;
esac
case "$PWD/" in
  "$clone"/out/*) exec "{cargo}" "${{args[@]}}" ;;
esac
exec "{cargo}" "${{args[0]}}" --manifest-path "$repo/Cargo.toml" "${{args[@]:1}}"
"#,
            clone = clone.display(),
            repo = repo().display(),
        );
        fs::write(shims.join("cargo"), shim).unwrap();
        Command::new("chmod")
            .arg("+x")
            .arg(shims.join("cargo"))
            .status()
            .unwrap();
        let path = format!(
            "{}:{}",
            shims.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        Self {
            root,
            clone,
            files,
            path,
        }
    }

    /// Back to a fresh clone: tracked files as they were, nothing else. Returns the tracked files
    /// that had been changed or removed.
    fn reset(&self) -> Vec<String> {
        let mut changed = Vec::new();
        for (rel, content) in &self.files {
            let p = self.clone.join(rel);
            if fs::read(&p).ok().as_deref() != Some(content.as_slice()) {
                changed.push(rel.display().to_string());
                let _ = fs::remove_file(&p);
                fs::create_dir_all(p.parent().unwrap()).unwrap();
                fs::write(&p, content).unwrap();
            }
        }
        self.remove_new(&self.clone.clone(), Path::new(""));
        changed
    }

    fn remove_new(&self, dir: &Path, rel: &Path) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let (p, r) = (e.path(), rel.join(e.file_name()));
            let kind = fs::symlink_metadata(&p).unwrap().file_type();
            if rel.as_os_str().is_empty()
                && (r == Path::new("target") || VENVS.iter().any(|v| r == Path::new(v)))
            {
                continue;
            }
            if kind.is_dir() {
                if self.files.keys().any(|f| f.starts_with(&r)) {
                    self.remove_new(&p, &r);
                } else {
                    let _ = fs::remove_dir_all(&p);
                }
            } else if !self.files.contains_key(&r) {
                let _ = fs::remove_file(&p);
            }
        }
    }
}

impl Drop for Sandbox {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.root);
    }
}

fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The skipped examples of one document grouped by the tools they miss: one skip each (a block
/// under `# needs: heyoka` is one thing skipped, not one per command line).
fn skip_groups(skipped: Vec<(Example, Vec<String>)>) -> Vec<(Vec<String>, Vec<Example>)> {
    let mut groups: Vec<(Vec<String>, Vec<Example>)> = Vec::new();
    for (ex, missing) in skipped {
        match groups.iter_mut().find(|(m, _)| *m == missing) {
            Some((_, v)) => v.push(ex),
            None => groups.push((missing, vec![ex])),
        }
    }
    groups
}

#[test]
fn a_skipped_block_counts_once() {
    let block = "```sh\n# needs: heyoka\nrsts a\nrsts b\nrsts c\n```\n";
    let lines: Vec<(usize, String)> = block
        .lines()
        .enumerate()
        .skip(1)
        .take(4)
        .map(|(k, l)| (k + 1, l.to_string()))
        .collect();
    let examples = parse_block(&lines).unwrap();
    assert_eq!(examples.len(), 3, "{examples:?}");
    let heyoka = vec!["heyoka".to_string()];
    let mut skipped: Vec<_> = examples.into_iter().map(|e| (e, heyoka.clone())).collect();
    let scipy = Example {
        needs: vec!["scipy".into()],
        ..skipped[0].0.clone()
    };
    skipped.push((scipy, vec!["scipy".into()]));
    let groups = skip_groups(skipped);
    assert_eq!(groups.len(), 2, "one skip per missing tool set");
    assert_eq!(groups[0].1.len(), 3);
}

/// What became of one document's examples.
struct Outcome {
    failures: Vec<String>,
    skipped: Vec<(Example, Vec<String>)>,
    ran: usize,
}

/// Packages whose `cargo build --release -p …` finds every unit fresh after the test build (the
/// same features: tests/cli/one_build.rs) and so re-links nothing.
const FRESH_PACKAGES: [&str; 2] = ["rsts-cli", "example-adapter-rk4"];

/// `cargo build --release -p P [-p Q …]` of [`FRESH_PACKAGES`] only.
fn fresh_build(command: &str) -> bool {
    let words: Vec<&str> = command.split_whitespace().collect();
    let Some(rest) = words.strip_prefix(&["cargo", "build", "--release"][..]) else {
        return false;
    };
    !rest.is_empty()
        && rest
            .chunks(2)
            .all(|c| c.len() == 2 && c[0] == "-p" && FRESH_PACKAGES.contains(&c[1]))
}

/// How a document's commands use the shared target/, which decides what may run beside it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    /// Runs what the test build made (a fresh `cargo build -p` of [`FRESH_PACKAGES`] and
    /// `scripts/run.sh` included): beside anything but a [`Kind::Relinks`] document.
    Runs,
    /// Compiles in target/ without touching the binaries the others run — `cargo test`, `bench`
    /// or `run` of a package other than [`FRESH_PACKAGES`], `pip install` of the Python package:
    /// one such document at a time (their cargo runs would wait for each other on target/'s
    /// lock), beside [`Kind::Runs`] documents.
    Builds,
    /// May re-link `rsts` or `example-adapter-rk4` in target/release, which vanish for an
    /// instant (a cargo build of the workspace, of rsts-cli with other features or in another
    /// profile…): runs alone.
    Relinks,
}

/// What one command does to the shared target/ (see [`Kind`]).
fn kind(command: &str) -> Kind {
    if fresh_build(command) || command.contains("scripts/run.sh") {
        // run.sh: `cargo build --release -p rsts-cli --bin rsts`, a fresh build.
        return Kind::Runs;
    }
    if [
        "scripts/setup.sh",
        "pip install",
        "maturin",
        "install_python.sh",
    ]
    .iter()
    .any(|b| command.contains(b))
    {
        return Kind::Builds;
    }
    let words: Vec<&str> = command.split_whitespace().collect();
    let Some(at) = words.iter().position(|w| *w == "cargo") else {
        return Kind::Runs;
    };
    let args = &words[at + 1..];
    // Only what builds: `cargo tree`, `fmt`, `metadata`… do not.
    let compiles = [
        "build", "run", "test", "bench", "rustc", "install", "b", "r", "t",
    ];
    if !args.first().is_some_and(|sub| compiles.contains(sub)) {
        return Kind::Runs;
    }
    // Up to `--`: what follows goes to the program.
    let args: Vec<&str> = args.iter().take_while(|a| **a != "--").copied().collect();
    let mut packages = Vec::new();
    for (i, a) in args.iter().enumerate() {
        if *a == "-p" || *a == "--package" {
            packages.extend(args.get(i + 1).copied());
        } else if let Some(p) = a.strip_prefix("--package=").or(a.strip_prefix("-p")) {
            if !p.is_empty() {
                packages.push(p);
            }
        } else if ["--workspace", "--all", "--manifest-path"].contains(a) {
            return Kind::Relinks;
        }
    }
    if packages.is_empty() || packages.iter().any(|p| FRESH_PACKAGES.contains(p)) {
        Kind::Relinks
    } else {
        Kind::Builds
    }
}

/// The kind of a document: that of its most demanding command.
fn document_kind(doc: &Document) -> Kind {
    doc.examples
        .iter()
        .map(|e| kind(&e.command))
        .max()
        .unwrap_or(Kind::Runs)
}

/// How long a `# takes:` command runs before it is stopped: a cargo command checks its
/// arguments (package, target and test names) in well under a second, then only compiles.
fn probe_seconds(command: &str) -> u64 {
    if command.split_whitespace().any(|w| w == "cargo") {
        CARGO_PROBE_SECONDS
    } else {
        PROBE_SECONDS
    }
}

fn run_document(doc: &Document, sandbox: &Sandbox, full: bool) -> Outcome {
    let mut script = String::from("set -a\n");
    let mut skipped = Vec::new();
    let mut ran = 0;
    for (k, ex) in doc.examples.iter().enumerate() {
        let missing: Vec<String> = ex
            .needs
            .iter()
            .filter(|t| !tool_available(t))
            .cloned()
            .collect();
        if !missing.is_empty() {
            skipped.push((ex.clone(), missing));
            continue;
        }
        if ex.command.trim() == "scripts/test.sh" {
            eprintln!(
                "examples: {}:{}: `scripts/test.sh` is the suite running this test; not run again",
                doc.source, ex.line
            );
            continue;
        }
        ran += 1;
        script.push_str(&format!(
            "printf '\\n@@start {k}\\n'\n__t0=$EPOCHREALTIME\n"
        ));
        match &ex.takes {
            Some(_) if !full => script.push_str(&format!(
                "timeout -k 5 {} bash -c {}\n__s=$?\n\
                 if [ $__s -eq 124 ] || [ $__s -eq 137 ]; then printf '\\n@@stopped {k}\\n'; __s=0; fi\n",
                probe_seconds(&ex.command),
                quote(&ex.command)
            )),
            _ => script.push_str(&format!("{}\n__s=$?\n", ex.command)),
        }
        let accepted: Vec<String> = ex
            .exit
            .iter()
            .map(|c| format!("[ $__s -ne {c} ]"))
            .collect();
        script.push_str(&format!(
            "if {}; then printf '\\n@@failed {k} %s\\n' $__s; exit 97; fi\n\
             printf '\\n@@took {k} %s %s\\n' $__t0 $EPOCHREALTIME\n",
            accepted.join(" && ")
        ));
    }
    let log_path = sandbox.root.join("log");
    let log = fs::File::create(&log_path).unwrap();
    let start = Instant::now();
    let mut child = Command::new("bash")
        .arg("-c")
        .arg(&script)
        .current_dir(&sandbox.clone)
        .env("PATH", &sandbox.path)
        // Tools that run cargo by $CARGO (maturin, under `pip install ./crates/python`) use the
        // shim too, so that they build this checkout like every other command.
        .env("CARGO", sandbox.root.join("bin").join("cargo"))
        .env("RSTS_EXAMPLES_RUNNING", "1")
        .stdin(Stdio::null())
        .stdout(log.try_clone().unwrap())
        .stderr(log)
        .process_group(0)
        .spawn()
        .expect("run bash");
    let mut timed_out = false;
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > DOCUMENT_LIMIT {
            let _ = Command::new("kill")
                .args(["-KILL", &format!("-{}", child.id())])
                .status();
            timed_out = true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let mut text = String::new();
    let _ = fs::File::open(&log_path).unwrap().read_to_string(&mut text);
    let mut failures = Vec::new();
    let tail = |text: &str| {
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len().saturating_sub(40)..].join("\n")
    };
    let mut last_started = None;
    // (seconds, line) of each command that finished.
    let mut took: Vec<(f64, usize)> = Vec::new();
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["@@start", k] => last_started = k.parse::<usize>().ok(),
            ["@@took", k, t0, t1] => {
                if let (Ok(k), Ok(t0), Ok(t1)) =
                    (k.parse::<usize>(), t0.parse::<f64>(), t1.parse::<f64>())
                {
                    took.push((t1 - t0, doc.examples[k].line));
                }
            }
            ["@@stopped", k] => {
                let ex = &doc.examples[k.parse::<usize>().unwrap()];
                eprintln!(
                    "examples: {}:{}: stopped after {} s as marked \
                     (`# takes: {}`; RSTS_EXAMPLES_FULL=1 runs it to the end)",
                    doc.source,
                    ex.line,
                    probe_seconds(&ex.command),
                    ex.takes.as_deref().unwrap_or("")
                );
            }
            ["@@failed", k, status] => {
                let ex = &doc.examples[k.parse::<usize>().unwrap()];
                let output = text.split(&format!("@@start {k}\n")).nth(1).unwrap_or("");
                let output = output.split("\n@@failed").next().unwrap_or("");
                failures.push(format!(
                    "{}:{}: `{}` exited with status {status}; its output (end):\n{}",
                    doc.source,
                    ex.line,
                    ex.command,
                    tail(output)
                ));
            }
            _ => {}
        }
    }
    if timed_out {
        let which = last_started
            .map(|k| {
                format!(
                    "{}:{}: `{}`",
                    doc.source, doc.examples[k].line, doc.examples[k].command
                )
            })
            .unwrap_or_default();
        failures.push(format!(
            "{}: the examples took more than {} s; running at the time: {which}\n{}",
            doc.source,
            DOCUMENT_LIMIT.as_secs(),
            tail(&text)
        ));
    }
    // Where the time went: the commands of a second or more, longest first.
    took.sort_by(|a, b| b.0.total_cmp(&a.0));
    let slow: Vec<String> = took
        .iter()
        .filter(|(t, _)| *t >= 1.0)
        .map(|(t, line)| format!(":{line} {t:.1} s"))
        .collect();
    eprintln!(
        "examples: {}: {ran} run, {} skipped, {:.1} s{}",
        doc.source,
        skipped.len(),
        start.elapsed().as_secs_f64(),
        if slow.is_empty() {
            String::new()
        } else {
            format!(" ({})", slow.join(", "))
        }
    );
    Outcome {
        failures,
        skipped,
        ran,
    }
}

/// The documents still to run (by cost, the longest last) and the kinds of those running.
struct Schedule<'a> {
    queue: Vec<(u64, usize, &'a Document, Kind)>,
    running: Vec<Kind>,
}

impl<'a> Schedule<'a> {
    /// Whether a document of this kind may start beside those running (see [`Kind`]).
    fn may_start(&self, kind: Kind) -> bool {
        match kind {
            _ if self.running.contains(&Kind::Relinks) => false,
            Kind::Relinks => self.running.is_empty(),
            Kind::Builds => !self.running.contains(&Kind::Builds),
            Kind::Runs => true,
        }
    }

    /// The longest document that may start now (waiting until one may); `None` when none is
    /// left.
    fn next(
        schedule: &std::sync::Mutex<Self>,
        finished: &std::sync::Condvar,
    ) -> Option<(usize, &'a Document, Kind)> {
        let mut s = schedule.lock().unwrap();
        loop {
            if s.queue.is_empty() {
                return None;
            }
            if let Some(at) = s.queue.iter().rposition(|(.., kind)| s.may_start(*kind)) {
                let (_, order, doc, kind) = s.queue.remove(at);
                s.running.push(kind);
                return Some((order, doc, kind));
            }
            s = finished.wait(s).unwrap();
        }
    }
}

#[test]
fn every_documented_example_runs_as_written() {
    if std::env::var_os("RSTS_EXAMPLES_RUNNING").is_some() {
        // An example ran the test suite (scripts/test.sh with arguments that include this
        // test): running every example again from inside would recurse.
        return;
    }
    if cfg!(debug_assertions) {
        rsts_io::report_skip(
            "every_documented_example_runs_as_written",
            "a debug test run; the examples use the release build (run scripts/test.sh)",
        );
        return;
    }
    let full = std::env::var_os("RSTS_EXAMPLES_FULL").is_some();
    let (mut docs, mut failures) = documents();
    let total: usize = docs.iter().map(|d| d.examples.len()).sum();
    assert!(total > 20, "only {total} examples found");
    // Only the examples that need one tool (their blocks stand alone: scripts/ci_slurm.sh).
    if let Ok(tool) = std::env::var("RSTS_EXAMPLES_NEEDING") {
        assert!(
            TOOLS.contains(&tool.as_str()),
            "RSTS_EXAMPLES_NEEDING={tool}: not a tool"
        );
        for d in &mut docs {
            d.examples.retain(|e| e.needs.contains(&tool));
        }
        let left: usize = docs.iter().map(|d| d.examples.len()).sum();
        assert!(left > 0, "no example needs {tool}");
        eprintln!("examples: only the {left} that need {tool} (RSTS_EXAMPLES_NEEDING)");
    }
    let total: usize = docs.iter().map(|d| d.examples.len()).sum();
    // The longest documents first, so that the workers finish together: a command costs about
    // a second, a `# takes:` probe its probe_seconds, a build (`pip install`, `cargo run` of
    // another package's example) about a minute.
    let cost = |d: &Document| {
        d.examples
            .iter()
            .map(|e| match (&e.takes, kind(&e.command)) {
                (Some(_), _) => probe_seconds(&e.command),
                (None, Kind::Builds | Kind::Relinks) => 60,
                (None, Kind::Runs) => 1,
            })
            .sum::<u64>()
    };
    let mut queue: Vec<(u64, usize, &Document, Kind)> = docs
        .iter()
        .enumerate()
        .filter(|(_, d)| !d.examples.is_empty())
        .map(|(order, d)| (cost(d), order, d, document_kind(d)))
        .collect();
    queue.sort_by_key(|(cost, order, ..)| (*cost, std::cmp::Reverse(*order)));
    let jobs = std::env::var("RSTS_EXAMPLES_JOBS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
        .unwrap_or(MAX_JOBS)
        .clamp(1, MAX_JOBS)
        .min(std::thread::available_parallelism().map_or(1, |n| n.get()));
    let schedule = std::sync::Mutex::new(Schedule {
        queue,
        running: Vec::new(),
    });
    let finished = std::sync::Condvar::new();
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for index in 0..jobs {
            let (schedule, finished, results) = (&schedule, &finished, &results);
            scope.spawn(move || {
                let sandbox = Sandbox::new(index);
                while let Some((order, doc, kind)) = Schedule::next(schedule, finished) {
                    let outcome = run_document(doc, &sandbox, full);
                    let changed = sandbox.reset();
                    results.lock().unwrap().push((order, doc, outcome, changed));
                    let mut s = schedule.lock().unwrap();
                    let at = s.running.iter().position(|k| *k == kind).unwrap();
                    s.running.remove(at);
                    finished.notify_all();
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|(order, ..)| *order);
    let mut ran = 0;
    for (_, doc, outcome, changed) in results {
        ran += outcome.ran;
        failures.extend(outcome.failures);
        for (missing, examples) in skip_groups(outcome.skipped) {
            let first = &examples[0];
            let more = match examples.len() {
                1 => String::new(),
                n => format!(" and {} more command(s) of the document", n - 1),
            };
            let hint = match missing.iter().any(|t| t == "slurm") {
                true => "; slurm: no controller accepts `sbatch --test-only` (scripts/slurm_local.sh CMD starts one)",
                false => "",
            };
            rsts_io::report_skip(
                &format!("example {}:{}", doc.source, first.line),
                &format!(
                    "needs {} (`{}`{more}{hint})",
                    missing.join(", "),
                    first.command.lines().next().unwrap_or("")
                ),
            );
        }
        for file in changed {
            failures.push(format!(
                "{}: its examples changed the tracked file {file} (examples write under out/)",
                doc.source
            ));
        }
    }
    eprintln!("examples: {ran} of {total} run ({jobs} at a time)");
    assert!(
        failures.is_empty(),
        "{} documented example(s) failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn only_builds_that_may_re_link_run_alone() {
    for (command, expected) in [
        ("rsts compare --t-end 20", Kind::Runs),
        ("cargo build --release -p example-adapter-rk4", Kind::Runs),
        (
            "cargo build --release -p rsts-cli -p example-adapter-rk4",
            Kind::Runs,
        ),
        ("scripts/run.sh compare", Kind::Runs),
        ("cargo tree -p rsts-cli", Kind::Runs),
        (".venv/bin/pip install ./crates/python", Kind::Builds),
        (
            "cargo run --release -p rsts-harness --example own_integrator",
            Kind::Builds,
        ),
        (
            "cargo bench -p rsts-closed-form --bench explicit -- 'state/'",
            Kind::Builds,
        ),
        (
            "X=1 cargo test --release -p rsts-harness --test t -- -p rsts-cli",
            Kind::Builds,
        ),
        ("cargo build --release", Kind::Relinks),
        ("cargo build -p rsts-cli", Kind::Relinks),
        (
            "cargo build --release -p rsts-cli --features x",
            Kind::Relinks,
        ),
        (
            "cargo test --release -p rsts-cli --test cli jobs::",
            Kind::Relinks,
        ),
        (
            "cargo test --release --workspace --test dynamics taylor::",
            Kind::Relinks,
        ),
        (
            "cargo build --release --package=example-adapter-rk4 --bin x",
            Kind::Relinks,
        ),
    ] {
        assert_eq!(kind(command), expected, "{command}");
    }
    // Who may start beside whom.
    let doc = Document {
        source: String::new(),
        examples: Vec::new(),
    };
    let beside = |running: &[Kind], kind: Kind| {
        Schedule {
            queue: vec![(1, 0, &doc, kind)],
            running: running.to_vec(),
        }
        .may_start(kind)
    };
    assert!(beside(&[Kind::Builds], Kind::Runs));
    assert!(beside(&[Kind::Runs, Kind::Runs], Kind::Builds));
    assert!(!beside(&[Kind::Builds], Kind::Builds));
    assert!(!beside(&[Kind::Runs], Kind::Relinks));
    assert!(!beside(&[Kind::Relinks], Kind::Runs));
    assert!(beside(&[], Kind::Relinks));
}

#[test]
fn extraction_follows_blocks_markers_and_continuations() {
    let md = "text\n```sh\n# a comment\nrsts a \\\n    --x 1\n\n# needs: heyoka\nrsts b\nrsts c\n\n# takes: 2 min\nrsts d\nrsts e\n```\n```text\nrsts not-a-command\n```\n";
    let ex = markdown_examples(md).unwrap();
    let codes = markdown_examples("```sh\n# exit: 0, 1 (why)\na\nb\n```\n").unwrap();
    assert_eq!(
        (codes[0].exit.clone(), codes[1].exit.clone()),
        (vec![0, 1], vec![0])
    );
    let summary: Vec<(usize, &str, usize, bool)> = ex
        .iter()
        .map(|e| (e.line, e.command.as_str(), e.needs.len(), e.takes.is_some()))
        .collect();
    assert_eq!(
        summary,
        [
            (4, "rsts a \\\n--x 1", 0, false),
            (8, "rsts b", 1, false),
            (9, "rsts c", 1, false),
            (12, "rsts d", 0, true),
            (13, "rsts e", 0, false),
        ]
    );
    let here = markdown_examples("```sh\npython - <<'PY'\nimport x\n\nprint(1)\nPY\nrsts y\n```\n")
        .unwrap();
    assert_eq!(here.len(), 2, "{here:?}");
    assert_eq!(here[0].command, "python - <<'PY'\nimport x\n\nprint(1)\nPY");
    let remark = markdown_examples("```sh\n# needs: slurm, node (why)\nx\n```\n").unwrap();
    assert_eq!(remark[0].needs, ["slurm", "node"]);
    let twice = markdown_examples("```sh\n# needs: scipy\na\n# needs: scipy\nb\n```\n").unwrap();
    assert_eq!(
        (&twice[0].needs[..], &twice[1].needs[..]),
        (&["scipy".to_string()][..], &["scipy".to_string()][..])
    );
    assert!(markdown_examples("```sh\n# needs: magic\nrsts x\n```\n")
        .unwrap_err()
        .contains("unknown tool `magic`"));
    assert!(markdown_examples("```sh\nrsts x\n").is_err());
    let help = "Usage: rsts x\n\nExamples:\n  # one\n  rsts x --a 1\n\n  rsts x --b 2 \\\n      --c 3\n\nSee docs.\n";
    let ex = help_examples(help).unwrap().unwrap();
    assert_eq!(ex.len(), 2);
    assert_eq!((ex[0].line, ex[0].command.as_str()), (5, "rsts x --a 1"));
    assert_eq!(ex[1].command, "rsts x --b 2 \\\n--c 3");
    assert_eq!(help_examples("no examples").unwrap(), None);
    assert_eq!(
        subcommands("Commands:\n  one  x\n  help  y\n\nOptions:\n"),
        ["one"]
    );
}
