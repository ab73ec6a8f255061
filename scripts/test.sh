#!/usr/bin/env bash
# Run every test of the workspace in release mode (the first build compiles GMP/MPFR: ~5 min).
# Extra arguments go to cargo test, e.g. scripts/test.sh -p rsts-cli
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

cd "$root"
if [ "$#" -eq 0 ]; then
  set -- --workspace
fi
exec cargo test --release "$@"
