#!/usr/bin/env bash
# Run every test of the workspace in release mode: the same build as scripts/run.sh, so after
# run.sh only the tests themselves are compiled (crates/cli/tests/cli/one_build.rs checks it).
# The last line is the summary `N passed, M failed, K skipped`:
#   N  tests that passed, less those that skipped all their work for a missing optional tool
#      (they call rsts_io::report_skip, which appends a line to $RSTS_SKIP_LOG);
#   M  tests that failed;
#   K  lines in $RSTS_SKIP_LOG (a whole test, or one part such as the examples of a document
#      that need heyoka: one line per document and missing tool, not per command) plus the
#      tests marked #[ignore].
# The Python package's tests (pytest, crates/python/tests) run after cargo's, in .venv-python
# (scripts/install_python.sh builds the package there); their counts are added to N, M, K. When
# Python 3 or the packages cannot be had they are one skip, `SKIPPED: python: REASON`.
# The exit status is cargo's, or pytest's when cargo's is 0. Every test binary runs even when
# one fails (--no-fail-fast).
# Extra arguments go to cargo test; --workspace is added unless they pick packages:
#   scripts/test.sh --test dynamics conservation::   # one test file, no recompilation
#   scripts/test.sh -p rsts-cli -- --nocapture
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" || exit
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
cd "$root" || exit

args=("$@")
pick_packages=no
for a in "$@"; do
  case "$a" in
    --) break ;;
    -p | -p* | --package | --package=* | --workspace | --all | --manifest-path | --manifest-path=*)
      pick_packages=yes ;;
  esac
done
if [ "$pick_packages" = no ]; then
  # The Python extension is built by maturin below (scripts/install_python.sh), not here: cargo
  # and maturin configure PyO3 differently (maturin names the venv's interpreter), and building
  # it both ways would recompile PyO3 and the extension on every run.
  args=(--workspace --exclude rsts-python "${args[@]}")
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/rsts-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
export RSTS_SKIP_LOG="$work/skipped"
# The tests' scratch files (each test process's rsts-*-tests-PID directory, pytest's tmp_path)
# go under $work and leave with it: a run leaves nothing in the system's temporary directory.
mkdir "$work/tmp" && export TMPDIR="$work/tmp"
: >"$RSTS_SKIP_LOG"

start=$SECONDS
cargo test --release --no-run "${args[@]}"
status=$?
if [ "$status" -ne 0 ]; then
  echo "test.sh: the build failed (cargo exit status $status): see above"
  echo "0 passed, 0 failed, 0 skipped"
  exit "$status"
fi
if [ $((SECONDS - start)) -ge 10 ]; then
  echo "test.sh: build took $(((SECONDS - start) / 60)) min $(((SECONDS - start) % 60)) s"
fi

cargo test --release --no-fail-fast "${args[@]}" 2>&1 | tee "$work/log"
status=${PIPESTATUS[0]}

# The Python package: built by maturin in the same target directory (the crates above are
# reused), tested against the CLI just built. Only in a run of everything (no arguments) or with
# `-p rsts-python`.
py_passed=0 py_failed=0 py_skipped=0
if [ "$#" -eq 0 ] || [[ " $* " == *" rsts-python "* ]]; then
  py_start=$SECONDS
  "$root/scripts/install_python.sh" 2>"$work/python-install"
  py_install=$?
  if [ "$py_install" -eq 0 ]; then
    echo "test.sh: Python package built and installed in $((SECONDS - py_start)) s"
    "$root/.venv-python/bin/python" -m pytest -q -rs -p no:cacheprovider "$root/crates/python/tests" \
      2>&1 | tee "$work/pytest"
    py_status=${PIPESTATUS[0]}
    last="$(grep -E '(passed|failed|error|skipped)' "$work/pytest" | tail -n 1)"
    count() { echo "$last" | grep -oE "[0-9]+ $1" | grep -oE '[0-9]+' || echo 0; }
    py_passed=$(count passed)
    py_failed=$(($(count failed) + $(count error)))
    py_skipped=$(count skipped)
    if [ "$py_status" -ne 0 ] && [ "$py_failed" -eq 0 ]; then py_failed=1; fi
  elif [ "$py_install" -eq 1 ]; then
    # Python 3 or the packages cannot be had: one skip, with the reason.
    echo "SKIPPED: python: the Python package's tests ($(tail -n 1 "$work/python-install" | sed 's/^install_python.sh: //'))" >>"$RSTS_SKIP_LOG"
    py_status=0
  else
    cat "$work/python-install"
    echo "test.sh: the Python package failed to build or import (scripts/install_python.sh exit $py_install)"
    py_status=$py_install
    py_failed=1
  fi
  if [ "$status" -eq 0 ]; then status=$py_status; fi
fi

# Skipped: the lines `SKIPPED: NAME: REASON`; a NAME that is a passed test's name (or the last
# part of its path) means that test did none of its work.
awk -v skipfile="$RSTS_SKIP_LOG" -v py_passed="$py_passed" -v py_failed="$py_failed" \
  -v py_skipped="$py_skipped" '
  BEGIN {
    while ((getline line < skipfile) > 0) {
      if (line !~ /^SKIPPED: /) continue
      skips++
      name = substr(line, 10); sub(/: .*/, "", name)
      skipped_name[name] = 1
    }
  }
  /^test result: / {
    for (i = 1; i <= NF; i++) {
      if ($(i + 1) ~ /^passed/) passed += $i
      if ($(i + 1) ~ /^failed/) failed += $i
      if ($(i + 1) ~ /^ignored/) ignored += $i
    }
  }
  /^test .* \.\.\. ok$/ {
    name = $2; short = name; sub(/.*::/, "", short)
    if ((name in skipped_name) || (short in skipped_name)) whole++
  }
  END {
    printf "%d passed, %d failed, %d skipped\n", passed - whole + py_passed, failed + py_failed,
      skips + ignored + py_skipped
  }
' "$work/log" >"$work/summary"

if [ "$status" -ne 0 ]; then
  echo "test.sh: cargo test or pytest exited with status $status (failed tests, a test binary that crashed, or a build error: see above)"
fi
if [ -s "$RSTS_SKIP_LOG" ]; then
  echo "test.sh: skipped:"
  sed 's/^SKIPPED: /  /' "$RSTS_SKIP_LOG"
fi
cat "$work/summary"
exit "$status"
