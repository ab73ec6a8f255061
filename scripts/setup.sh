#!/usr/bin/env bash
# Check for what the build needs and install what is missing.
#
# Needs: cargo (Rust toolchain), and for rug's bundled GMP/MPFR build a C compiler, make and m4.
# Idempotent and silent when everything is there; installs system packages with apt-get (through
# sudo only when not root and sudo exists).
set -euo pipefail

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

if [ "${#missing[@]}" -gt 0 ]; then
  if ! have apt-get; then
    echo "setup: missing ${missing[*]}; install them with your package manager" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]} (needed to build GMP/MPFR for rug)" >&2
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi
