#!/usr/bin/env bash
# Build (release) and run rsts with the given arguments; with none, run the built-in default
# case (`rsts integrate`). Example: scripts/run.sh integrate --t-end 100 --format csv
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

if [ "$#" -eq 0 ]; then
  set -- integrate
fi
# No cd: relative paths in the arguments stay relative to the caller's directory.
exec cargo run --release --manifest-path "$root/Cargo.toml" -p rsts-cli --bin rsts -- "$@"
