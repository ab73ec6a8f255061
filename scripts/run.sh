#!/usr/bin/env bash
# Build (release) and run rsts with the given arguments; with none, run the built-in default
# comparison: camera I+ (a=1, b=0.5, m=0.3, h=-0.375), Dop853 at 1e-12 against the closed form over
# T=100, printing the report, writing out/compare-default.svg (state error and drifts of H, K, G
# against time) and out/compare-default.mcap, and saying on stderr what to open next.
# Example: scripts/run.sh integrate --t-end 100 --format csv
# The binary is target/release/rsts: put that directory on your PATH to call `rsts` directly.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi

default=no
if [ "$#" -eq 0 ]; then
  default=yes
  set -- compare --mcap out/compare-default.mcap --svg out/compare-default.svg
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
if [ "$default" = no ]; then
  exec "$bin" "$@"
fi
"$bin" "$@" || exit
cat >&2 <<'NEXT'

run.sh: what to open next:
  out/compare-default.svg   the state error and the drifts of H, K, G against time (any browser)
  out/compare-default.mcap  the whole run: Foxglove or Lichtblick, "Open local file" (docs/mcap.md),
                            or scripts/run.sh inspect out/compare-default.mcap
  docs/compare.md           what each line of the report means; docs/own-integrator.md to check yours
  scripts/test.sh           every test (docs/setup.md: how long it takes)
NEXT
