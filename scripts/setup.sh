#!/usr/bin/env bash
# Check for what the build needs and install what is missing; say what the first build does.
#
# Needs: cargo (Rust toolchain), and for the GMP and MPFR that rug builds from source (crate
# gmp-mpfr-sys) a C compiler, make and m4. Installs missing system packages with apt-get (through
# sudo only when not root and sudo exists). Quiet when everything is there and built.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
have() { command -v "$1" >/dev/null 2>&1; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then
    "$@"
  elif have sudo; then
    sudo "$@"
  else
    echo "setup: need root privileges to run: $*" >&2
    return 1
  fi
}

# Rust: not installed from here (no network besides crates.io); say how to get it.
if ! have cargo && [ -x "$HOME/.cargo/bin/cargo" ]; then
  export PATH="$HOME/.cargo/bin:$PATH"
fi
if ! have cargo; then
  echo "setup: cargo not found; install Rust >= 1.80 (https://rustup.rs) and retry" >&2
  exit 1
fi

missing=()
have m4 || missing+=(m4)
have make || missing+=(make)
have cc || have gcc || missing+=(gcc)
# SQLite for the validation history (crate rsts-history links the system library: docs/validation.md
# says why not the bundled one). Checked by compiling its header.
if have cc && ! printf '#include <sqlite3.h>\n' | cc -E -x c - >/dev/null 2>&1; then
  missing+=(libsqlite3-dev)
fi

if [ "${#missing[@]}" -gt 0 ]; then
  if ! have apt-get; then
    echo "setup: missing ${missing[*]}; install them with your package manager" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]} with apt-get (to build GMP and MPFR from source, and link SQLite)" >&2
  start=$SECONDS
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
  echo "setup: installed in $((SECONDS - start)) s" >&2
  [ -z "${RSTS_FETCH_LOG:-}" ] || echo "downloaded: ${missing[*]} (Debian packages, apt-get; $((SECONDS - start)) s)" >>"$RSTS_FETCH_LOG"
fi

if [ ! -x "${CARGO_TARGET_DIR:-$root/target}/release/rsts" ]; then
  cat >&2 <<'MSG'
setup: first build (release): GMP 6.3.0 and MPFR 4.2.2 from the sources bundled in the crate
setup: gmp-mpfr-sys (configure and make, without their own test suites: the longest step, about
setup: two minutes; docs/setup.md says why not Debian's libgmp-dev), then about 150 Rust crates.
setup: Measured on a fresh clone with 2 cores: see docs/setup.md. Later builds take
setup: seconds.
MSG
fi
