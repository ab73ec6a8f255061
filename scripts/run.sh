#!/usr/bin/env bash
# Build (release) and run rsts with the given arguments; with none, run the built-in default
# comparison: camera I+ (a=1, b=0.5, m=0.3, h=-0.375), Dop853 at 1e-12 against the closed form over
# T=100, printing the report and writing out/compare-default.mcap.
# Example: scripts/run.sh integrate --t-end 100 --format csv
# The binary is target/release/rsts: put that directory on your PATH to call `rsts` directly.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

if [ "$#" -eq 0 ]; then
  set -- compare --mcap out/compare-default.mcap
fi
bin="${CARGO_TARGET_DIR:-$root/target}/release/rsts"
first=no
[ -x "$bin" ] || first=yes
start=$SECONDS
# No cd: relative paths in the arguments stay relative to the caller's directory.
cargo build --release --manifest-path "$root/Cargo.toml" -p rsts-cli --bin rsts
if [ "$first" = yes ]; then
  echo "run.sh: first build took $(((SECONDS - start) / 60)) min $(((SECONDS - start) % 60)) s;" \
    "later runs start at once. The binary: $bin" >&2
fi
exec "$bin" "$@"
