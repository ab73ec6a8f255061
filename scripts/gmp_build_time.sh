#!/usr/bin/env bash
# The measurement behind "GMP and MPFR are compiled without their own test suites" (docs/setup.md):
# compiles the gmp-mpfr-sys of Cargo.lock twice in a scratch crate under out/gmp-build-time, as
# on a machine without the ~/.cache/gmp-mpfr-sys cache: once as the crate does by default
# (configure, make, make check) and once with its `c-no-tests` feature (configure, make), which
# the workspace uses. Prints the wall-clock and CPU time of each, and the load average.
# Usage: scripts/gmp_build_time.sh          (about 6 min on an idle 2-core machine)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" >&2
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
version="$(grep -A1 '^name = "gmp-mpfr-sys"' "$root/Cargo.lock" | sed -n 's/^version = "\(.*\)"/\1/p')"
[ -n "$version" ] || { echo "gmp_build_time: no gmp-mpfr-sys in Cargo.lock" >&2; exit 2; }
work="$root/out/gmp-build-time"
rm -rf "$work"
mkdir -p "$work/src"
echo 'fn main() {}' >"$work/src/main.rs"
cat >"$work/Cargo.toml" <<EOF
[package]
name = "gmp-build-time"
version = "0.1.0"
edition = "2021"
publish = false

[workspace]

[dependencies]
gmp-mpfr-sys = { version = "=$version", default-features = false, features = ["mpfr"] }

[features]
no-checks = ["gmp-mpfr-sys/c-no-tests"]
EOF
echo "gmp-mpfr-sys $version, GMP and MPFR compiled from its sources, no cache; load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
TIMEFORMAT='%R %U %S'
for variant in with-checks no-checks; do
  features=()
  [ "$variant" = no-checks ] && features=(--features no-checks)
  echo "gmp_build_time: building $variant ..." >&2
  t="$( { time GMP_MPFR_SYS_CACHE=_ CARGO_TARGET_DIR="$work/target-$variant" \
    cargo build --release --quiet --manifest-path "$work/Cargo.toml" "${features[@]}" >&2; } 2>&1 | tail -n 1)"
  read -r real user sys <<<"$t"
  awk -v v="$variant" -v r="$real" -v u="$user" -v s="$sys" \
    'BEGIN { printf "%-12s wall %4.0f s   CPU %4.0f s (user %.0f + sys %.0f)\n", v, r, u + s, u, s }'
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
