#!/usr/bin/env bash
# Make the virtual environment .venv-python with maturin, numpy, pytest and scipy, and install
# the Python package rsts (crates/python, docs/python.md) into it: the build is maturin's, in the
# workspace's target directory, so it shares the crates already built there.
#   scripts/install_python.sh          # then: .venv-python/bin/python -c "import rsts"
#   scripts/install_python.sh --env    # only the environment (the packages from PyPI), no build
# Needs python3 (3.9 or later) with its venv module, and PyPI or pip's cache for the packages.
# Exit status: 0 when `import rsts` works afterwards; 1 when Python or the packages cannot be
# had (the reason on the last line of stderr: scripts/test.sh then reports the Python tests as
# skipped); 2 when the package itself failed to build or import (a real failure).
# With RSTS_FETCH_LOG set (scripts/test.sh), a line is appended to that file saying what was
# downloaded into the environment and its size, or that it was there already.
set -uo pipefail
env_only=no
[ "${1:-}" = --env ] && env_only=yes
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv-python"
py="${PYTHON:-python3}"
say() { echo "install_python.sh: $*" >&2; }

if ! command -v "$py" >/dev/null 2>&1; then
  say "no Python 3 interpreter ($py) on the PATH"
  exit 1
fi
if ! "$py" -c 'import sys; sys.exit(sys.version_info < (3, 9))' 2>/dev/null; then
  say "$("$py" --version 2>&1) is older than the 3.9 the package needs"
  exit 1
fi
if [ ! -x "$venv/bin/python" ] && ! "$py" -m venv "$venv" >&2; then
  rm -rf "$venv"
  say "cannot make a virtual environment with '$py -m venv' (on Debian: apt-get install python3-venv)"
  exit 1
fi
fetched() { if [ -n "${RSTS_FETCH_LOG:-}" ]; then echo "$*" >>"$RSTS_FETCH_LOG"; fi; }
if ! "$venv/bin/python" -c 'import maturin, numpy, pytest, scipy' 2>/dev/null; then
  start=$SECONDS
  if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    'maturin>=1.9.4,<2' 'numpy>=1.21' pytest 'scipy>=1.9' >&2; then
    say "cannot install maturin, numpy, pytest and scipy from PyPI into .venv-python"
    exit 1
  fi
  fetched "downloaded: maturin, numpy, pytest, scipy (PyPI, or pip's cache ~/.cache/pip) into $venv ($(du -sm "$venv" | cut -f1) MB, $((SECONDS - start)) s)"
elif [ "$env_only" = yes ]; then
  fetched "already there: maturin, numpy, pytest, scipy in $venv ($(du -sm "$venv" | cut -f1) MB)"
fi
[ "$env_only" = yes ] && exit 0
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
# The documented install (pip install ./crates/python), with the maturin of the venv instead of
# a fresh isolated one, so it works offline once the packages are cached.
start=$SECONDS
if ! PATH="$venv/bin:$PATH" "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
  --no-build-isolation --no-deps --force-reinstall "$root/crates/python" >&2; then
  say "building the package rsts (pip install ./crates/python) failed: see above"
  exit 2
fi
if ! "$venv/bin/python" -c 'import rsts' >&2; then
  say "the package rsts was installed but cannot be imported: see above"
  exit 2
fi
say "rsts built and installed into .venv-python in $((SECONDS - start)) s"
