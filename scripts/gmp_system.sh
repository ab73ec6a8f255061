#!/usr/bin/env bash
# The measurement behind "GMP and MPFR are compiled, not taken from the system" (docs/setup.md):
# 1. which GMP/MPFR the system offers (Debian's libgmp-dev and libmpfr-dev, installed with apt-get
#    when missing) and which GMP the crate gmp-mpfr-sys in Cargo.lock accepts with its
#    `use-system-libs` feature;
# 2. nanoseconds per MPFR operation at 336 bits (the precision of --digits 100) for the libraries
#    the build compiled (target/release) and for the system's, run alternately three times
#    (scripts/gmp-system/mpfr_ops.c; best of 5 rounds of CPU time each).
# Usage: scripts/gmp_system.sh [BITS]     (run scripts/run.sh first: it builds the bundled ones)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bits="${1:-336}"
say() { echo "gmp_system: $*" >&2; }

if [ ! -f /usr/include/mpfr.h ] || [ ! -f /usr/include/x86_64-linux-gnu/gmp.h ] && [ ! -f /usr/include/gmp.h ]; then
  command -v apt-get >/dev/null 2>&1 || { say "no system GMP/MPFR headers and no apt-get"; exit 2; }
  say "installing Debian's libgmp-dev and libmpfr-dev (apt-get) ..."
  as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libgmp-dev libmpfr-dev >/dev/null
fi
bundled="$(ls -d "${CARGO_TARGET_DIR:-$root/target}"/release/build/gmp-mpfr-sys-*/out 2>/dev/null | head -n 1)"
if [ -z "$bundled" ] || [ ! -f "$bundled/lib/libmpfr.a" ]; then
  say "no GMP/MPFR built by gmp-mpfr-sys under target/release: run scripts/run.sh first"
  exit 2
fi
version="$(grep -A1 '^name = "gmp-mpfr-sys"' "$root/Cargo.lock" | sed -n 's/^version = "\(.*\)"/\1/p')"
src="$(ls -d "$HOME"/.cargo/registry/src/*/gmp-mpfr-sys-"$version" 2>/dev/null | head -n 1)"
echo "gmp-mpfr-sys $version (Cargo.lock) compiles: $(grep -h 'define __GNU_MP_VERSION\b\|define __GNU_MP_VERSION_MINOR\|define __GNU_MP_VERSION_PATCHLEVEL' "$bundled/include/gmp.h" | awk '{printf "%s%s", sep, $3; sep="."}') (GMP)"
if [ -n "$src" ]; then
  need="$(sed -n 's/^const GMP_VER: (i32, i32, i32) = (\([0-9]*\), \([0-9]*\), [0-9]*);/\1.\2/p' "$src/build.rs")"
  echo "its use-system-libs feature accepts a system GMP ${need:-?} or newer of the same major version (build.rs: GMP_VER, compatible_version)"
fi
echo "system: GMP $(dpkg-query -W -f '${Version}' libgmp-dev 2>/dev/null || echo '?'), MPFR $(dpkg-query -W -f '${Version}' libmpfr-dev 2>/dev/null || echo '?') (Debian packages)"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cc -O2 -Wall -o "$tmp/bundled" "$root/scripts/gmp-system/mpfr_ops.c" -I"$bundled/include" \
  "$bundled/lib/libmpfr.a" "$bundled/lib/libgmp.a"
cc -O2 -Wall -o "$tmp/system" "$root/scripts/gmp-system/mpfr_ops.c" -lmpfr -lgmp
for round in 1 2 3; do
  "$tmp/bundled" "$bits" >"$tmp/b$round"
  "$tmp/system" "$bits" >"$tmp/s$round"
done
# Best of the three runs per operation, and the ratio system / bundled.
awk '
  FNR == 1 { lib = (FILENAME ~ /\/b[0-9]$/) ? "b" : "s"; if (FNR == 1 && $1 == "#") { hdr[lib] = $0; next } }
  $1 != "#" { k = lib SUBSEP $1; if (!(k in best) || $2 < best[k]) best[k] = $2; ops[$1] = 1; order[++n] = $1 }
  END {
    print hdr["b"] "  |  " substr(hdr["s"], 3)
    printf "%-8s %14s %14s %8s\n", "op", "bundled ns", "system ns", "sys/bun"
    for (i = 1; i <= n; i++) { o = order[i]; if (o in done) continue; done[o] = 1
      printf "%-8s %14.1f %14.1f %8.2f\n", o, best["b", o], best["s", o], best["s", o] / best["b", o] }
  }' "$tmp"/b1 "$tmp"/s1 "$tmp"/b2 "$tmp"/s2 "$tmp"/b3 "$tmp"/s3
