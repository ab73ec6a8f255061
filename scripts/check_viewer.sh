#!/usr/bin/env bash
# The real-viewer check: every kind of MCAP file rsts writes (compare, check, surfaces scene), opened with the shipped Foxglove
# layouts (docs/foxglove/*.json) in Foxglove Studio's web build (1.48.0, whose MCAP reader is the
# oldest and strictest in use) in headless Chromium, the way a user does it: Layouts > Import
# layout, then Open local file, then Play to the end. Fails when the viewer reports a problem
# (Problems list, error toast, console error, a 3-D panel's topic or frame error) or a panel shows
# no data (a Plot series without a value, a 3-D panel without the scene's colours). Writes a
# screenshot of each case.
#
#   scripts/check_viewer.sh [--out DIR] [--no-self-test] [--docs]
#
#   --out DIR        where the files, screenshots (NAME.png), consoles and report.json go
#                    (default out/viewer)
#   --no-self-test   skip the two cases that must fail (a file with an empty first chunk, as rsts
#                    wrote before; a surfaces scene opened with the compare layout), which show
#                    that the check catches a viewer problem and empty panels
#   --docs           copy the screenshots of the shipped layouts (and of the self-test's file with
#                    an empty first chunk) to docs/img/foxglove/
#
# Installs what it needs, once (a few minutes; later runs reuse it): Debian's chromium (apt-get,
# as root or through sudo), playwright-core (npm, scripts/node_deps.sh viewer; it drives
# /usr/bin/chromium, no browser download), @foxglove/studio-base 1.48.0 and React 17 (npm pack)
# into ${RSTS_NODE_CACHE:-~/.cache/rsts/node}. The viewer is served on 127.0.0.1 only, on a free
# port, and stops with the script. Needs node and npm.
# Exit status: 0 every case as expected; 1 a viewer problem or an empty panel (see the report);
# 2 bad usage, or something could not be installed or built.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="out/viewer"
self_test=1
docs=0
while [ "$#" -gt 0 ]; do
  case "$1" in
    --out) out="${2:?--out wants a directory}"; shift 2 ;;
    --no-self-test) self_test=0; shift ;;
    --docs) docs=1; shift ;;
    -h|--help) sed -n '2,25p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "check_viewer: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"
out="$(cd "$out" && pwd)"
say() { echo "check_viewer: $*" >&2; }
die() { say "$*"; exit 2; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
    die "need root to run: $* (install Debian's chromium yourself)"; fi
}

# 1. Chromium (Debian's; playwright's own browser download does not work here).
chromium="${RSTS_CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium" ]; then
  command -v apt-get >/dev/null 2>&1 || die "$chromium not found and no apt-get to install it (set RSTS_CHROMIUM)"
  say "installing Debian's chromium (apt-get) ..."
  start=$SECONDS
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  [ -x "$chromium" ] || die "chromium was installed but $chromium is missing (set RSTS_CHROMIUM)"
  # scripts/test.sh says once what was downloaded, where, and how long it took.
  [ -z "${RSTS_FETCH_LOG:-}" ] || echo "downloaded: chromium (Debian package, apt-get) into /usr/lib/chromium ($(du -sm /usr/lib/chromium 2>/dev/null | cut -f1) MB, $((SECONDS - start)) s)" >>"$RSTS_FETCH_LOG"
fi

# 2. The driver (playwright-core) and Foxglove Studio's web build.
node_path="$("$root/scripts/node_deps.sh" viewer)" || die "cannot install the npm packages of scripts/viewer"
cache="${RSTS_NODE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/rsts/node}/studio-1.48.0"
if [ ! -f "$cache/www/assets/index.js" ]; then
  say "fetching Foxglove Studio's web build (@foxglove/studio-base 1.48.0, 36 MB) and React 17 with npm pack ..."
  rm -rf "$cache" && mkdir -p "$cache/pack" "$cache/www"
  (cd "$cache/pack" && npm pack --silent @foxglove/studio-base@1.48.0 react@17.0.2 react-dom@17.0.2 >/dev/null 2>npm.log) \
    || die "npm pack failed (no npm registry?): $(tail -n 3 "$cache/pack/npm.log")"
  for t in "$cache"/pack/*.tgz; do
    d="${t%.tgz}"; mkdir -p "$d"; tar -xzf "$t" -C "$d"; rm "$t"
  done
  mv "$cache/pack/foxglove-studio-base-1.48.0/package/assets" "$cache/www/assets"
  cp "$cache/pack/react-17.0.2/package/umd/react.production.min.js" "$cache/www/"
  cp "$cache/pack/react-dom-17.0.2/package/umd/react-dom.production.min.js" "$cache/www/"
  rm -rf "$cache/pack"
fi
cp "$root/scripts/viewer/index.html" "$root/scripts/viewer/boot.js" "$cache/www/"

# 3. One file of each kind, from the current build.
cd "$root"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
say "building rsts ..."
cargo build --release -q -p rsts-cli || die "the build failed"
cargo build --release -q -p rsts-mcap --example empty_first_chunk || die "the build failed"
rsts=target/release/rsts
files="$out/files"
rm -rf "$files" && mkdir -p "$files"
# with events: the Log panel lists them and the errors plot draws their time errors
$rsts compare --t-end 20 --samples 401 --event omega1 --event gamma2 --format json --mcap "$files/compare.mcap" >"$files/compare.json"
# rsts check logs like compare (here: the compare log's integrated channel against the closed form)
$rsts check "$files/compare.mcap" --format json --mcap "$files/check.mcap" >"$files/check.json"
$rsts surfaces --m 0.3 --h -0.375 --torus 0 --periods 1 --samples 1000 --scene-grid 32 --no-ply \
  --out "$files/surfaces" >/dev/null
cases=(
  --case compare "$files/compare.mcap" docs/foxglove/compare.json "#338cff,#ff731a"
  --case check "$files/check.mcap" docs/foxglove/compare.json "#338cff,#ff731a"
  --case surfaces "$files/surfaces/torus0_scene.mcap" docs/foxglove/surfaces.json
  "#8c001a,#00268c,#6585b5/60/3000,#b47848/50/200"
)
if [ "$self_test" -eq 1 ]; then
  target/release/examples/empty_first_chunk "$files/compare.mcap" "$files/compare-empty-first-chunk.mcap"
  cases+=(
    --case self-test-empty-first-chunk "$files/compare-empty-first-chunk.mcap" docs/foxglove/compare.json
    "#338cff,#ff731a" --expect-failure "Chunks without message indexes|problem"
    --case self-test-wrong-layout "$files/surfaces/torus0_scene.mcap" docs/foxglove/compare.json
    "#338cff,#ff731a" --expect-failure "no data|scene data not shown"
  )
fi

# 4. The viewer.
set +e
NODE_PATH="$node_path" node "$root/scripts/viewer/check_viewer.cjs" --www "$cache/www" --out "$out" \
  --chromium "$chromium" "${cases[@]}" >"$out/report.json"
code=$?
set -e
if [ "$code" -eq 2 ]; then
  die "the viewer check could not run (see above)"
fi
if [ "$docs" -eq 1 ] && [ "$code" -eq 0 ]; then
  mkdir -p docs/img/foxglove
  cp "$out/compare.png" "$out/surfaces.png" docs/img/foxglove/
  if [ -f "$out/self-test-empty-first-chunk_problems.png" ]; then
    cp "$out/self-test-empty-first-chunk_problems.png" docs/img/foxglove/empty-first-chunk.png
  fi
  say "copied the screenshots to docs/img/foxglove/"
fi
say "screenshots in $out: $(cd "$out" && ls -- *.png | tr '\n' ' ')"
say "report: $out/report.json"
if [ "$code" -eq 0 ]; then
  say "OK: every kind of rsts MCAP opens in Foxglove Studio 1.48 with the shipped layouts, no problem reported, every panel shows data"
else
  say "FAILED: see the problems above and $out/report.json"
fi
exit "$code"
