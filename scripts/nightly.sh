#!/usr/bin/env bash
# The nightly validation: run validation/nightly.toml (every camera on every torus, five integrators,
# the hard cases, T = 1e4 runs) against the previous night's report as the baseline.
#
# Reports go to $RSTS_NIGHTLY_DIR (default out/nightly)/<UTC time>/; out/nightly/baseline is the
# report the next night is compared with: this night's report when it passed, else the previous
# baseline stays (a regression keeps being reported until it is fixed, not accepted by rerunning).
# Extra arguments go to `rsts validate`, e.g. scripts/nightly.sh --jobs 2; RSTS_NIGHTLY_SUITE picks
# another suite file.
# Every night is recorded in the validation history $out/history.sqlite (rsts validate --history),
# and the dashboard $out/dashboard/index.html (rsts dashboard) is rebuilt from it; `rsts history
# regressions $out/history.sqlite` lists what regressed (docs/validation.md, History and dashboard).
# Then the real-viewer check (scripts/check_viewer.sh, screenshots in <run>/viewer/): every kind
# of MCAP file with the shipped layouts in Foxglove Studio; RSTS_NIGHTLY_VIEWER=0 leaves it out.
# Exit code: that of `rsts validate` (0 pass, 1 a run failed or regressed, 2 bad input); when it
# passed, that of the viewer check (1 a viewer problem or an empty panel, 2 it could not run).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
cd "$root"

out="${RSTS_NIGHTLY_DIR:-out/nightly}"
run="$out/$(date -u +%Y%m%dT%H%M%SZ)"
mkdir -p "$out"
cargo build --release -q -p rsts-cli

suite="${RSTS_NIGHTLY_SUITE:-validation/nightly.toml}"
args=(validate --suite "$suite" --report "$run" --history "$out/history.sqlite")
if [ -f "$out/baseline/report.json" ]; then
  args+=(--baseline "$out/baseline/report.json")
else
  echo "no baseline yet ($out/baseline/report.json): this run becomes the first one" >&2
fi

set +e
target/release/rsts "${args[@]}" "$@"
code=$?
set -e

if [ "$code" -eq 0 ]; then
  rm -rf "$out/baseline.new"
  cp -r "$run" "$out/baseline.new"
  rm -rf "$out/baseline"
  mv "$out/baseline.new" "$out/baseline"
  echo "baseline for the next run: $out/baseline (from $run)"
elif [ "$code" -eq 1 ]; then
  echo "runs failed or regressed: see $run/report.md; the baseline stays $out/baseline" >&2
fi

if [ -f "$out/history.sqlite" ]; then
  set +e
  target/release/rsts dashboard --history "$out/history.sqlite" --out "$out/dashboard"
  dashboard=$?
  set -e
  if [ "$dashboard" -ne 0 ] && [ "$code" -eq 0 ]; then code=$dashboard; fi
fi

if [ "${RSTS_NIGHTLY_VIEWER:-1}" != 0 ]; then
  set +e
  "$root/scripts/check_viewer.sh" --out "$run/viewer"
  viewer=$?
  set -e
  if [ "$viewer" -ne 0 ]; then
    echo "the real-viewer check failed: see $run/viewer/report.json" >&2
    if [ "$code" -eq 0 ]; then code=$viewer; fi
  fi
fi
exit "$code"
