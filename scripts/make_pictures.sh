#!/usr/bin/env bash
# The pictures of docs/geometry.md: P- and Π-surface of torus 0 at the example point of every
# camera (a = 1, b = 0.5), as `rsts surfaces` draws them. Writes DIR/<camera>/torus0_p.png and
# torus0_pi.png; DIR defaults to docs/img (the tracked pictures). Also the README's picture,
# DIR/compare-default.png: out/compare-default.svg of scripts/run.sh as PNG (needs rsvg-convert,
# Debian's librsvg2-bin; said and left out without it).
# Example: scripts/make_pictures.sh out/img    (look at them before replacing docs/img)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${1:-$root/docs/img}"
"$root/scripts/run.sh" --version >/dev/null # builds rsts when needed
rsts="${CARGO_TARGET_DIR:-$root/target}/release/rsts"

while read -r camera m h extra; do
  # shellcheck disable=SC2086 # $extra: zero or more options
  "$rsts" surfaces --a 1 --b 0.5 --m "$m" --h "$h" --torus 0 --no-ply --no-mcap $extra \
    --out "$dir/$camera"
done <<'CAMERAS'
I+ 0.3 -0.375
I- -1.9244 0.4503 --normalize-axes
II+ 0.05 1.058
II- -0.5573 1.463
III -2.9877 1.2605
IV+ 0.05 2.0706
IV- -0.3295 1.7668
V -0.7092 1.5643
VI -2.9877 3.2858
CAMERAS

if command -v rsvg-convert >/dev/null 2>&1; then
  svg="$(mktemp -d)/compare-default.svg"
  "$rsts" compare --svg "$svg" >/dev/null
  rsvg-convert --background-color white -o "$dir/compare-default.png" "$svg"
  rm -r "$(dirname "$svg")"
else
  echo "make_pictures: rsvg-convert not found (apt-get install librsvg2-bin): $dir/compare-default.png not made" >&2
fi
