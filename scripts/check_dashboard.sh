#!/usr/bin/env bash
# The real-browser check of a validation dashboard (`rsts dashboard`): opens its pages from the
# file system in headless Chromium and fails on a page error, a console error, a request for
# anything but a local file, or a missing element; writes a full-page screenshot of each page.
#
#   scripts/check_dashboard.sh --out DIR [--first-screen] --page NAME FILE.html [--expect CSS-SELECTOR]... ...
#
# --first-screen: screenshots of the first 1400×1000 pixels of each page, not the whole page.
#
# Installs what it needs, once, as scripts/check_viewer.sh does: Debian's chromium (apt-get, as
# root or through sudo; RSTS_CHROMIUM names another) and playwright-core (npm, scripts/node_deps.sh
# viewer: it drives /usr/bin/chromium, no browser download). Needs node and npm.
# Prints the check's JSON report on stdout. Exit status: 0 every page fine; 1 a problem (see the
# report); 2 bad usage, or the browser or its driver could not be had (the reason on stderr).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
say() { echo "check_dashboard: $*" >&2; }
die() { say "$*"; exit 2; }
case "${1:-}" in -h|--help) sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;; esac

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
    die "need root to run: $* (install Debian's chromium yourself)"; fi
}

chromium="${RSTS_CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium" ]; then
  command -v apt-get >/dev/null 2>&1 || die "$chromium not found and no apt-get to install it (set RSTS_CHROMIUM)"
  say "installing Debian's chromium (apt-get) ..."
  start=$SECONDS
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null || die "apt-get update failed"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null || die "apt-get install chromium failed"
  [ -x "$chromium" ] || die "chromium was installed but $chromium is missing (set RSTS_CHROMIUM)"
  # scripts/test.sh says once what was downloaded, where, and how long it took.
  [ -z "${RSTS_FETCH_LOG:-}" ] || echo "downloaded: chromium (Debian package, apt-get) into /usr/lib/chromium ($(du -sm /usr/lib/chromium 2>/dev/null | cut -f1) MB, $((SECONDS - start)) s)" >>"$RSTS_FETCH_LOG"
fi
node_path="$("$root/scripts/node_deps.sh" viewer)" || die "cannot install playwright-core (scripts/node_deps.sh viewer)"
NODE_PATH="$node_path" exec node "$root/scripts/dashboard/check_dashboard.cjs" --chromium "$chromium" "$@"
