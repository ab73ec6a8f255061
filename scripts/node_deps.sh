#!/usr/bin/env bash
# Install the npm packages of one of the project's node tool folders into a cache directory
# and print the path of its node_modules on stdout (for NODE_PATH).
#   scripts/node_deps.sh mcap-readers     # scripts/mcap-readers/package.json (+ package-lock.json)
# The cache is $RSTS_NODE_CACHE (default ${XDG_CACHE_HOME:-~/.cache}/rsts/node)/NAME; nothing is
# written into the checkout. Packages come from the npm registry with `npm ci` (exact versions
# of the lock file, integrity-checked, install scripts not run); a second call with the same lock
# file does nothing.
# Exit status: 0 ready; 3 node or npm is missing; 1 the install failed (e.g. no registry). The
# reason goes to stderr, so a test can skip with it.
# With RSTS_FETCH_LOG set (scripts/test.sh), one line is appended to that file saying what was
# downloaded, where, its size and time, or where the packages already were.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
name="${1:?usage: scripts/node_deps.sh NAME (a folder of scripts/ with a package.json)}"
src="$here/$name"
if [ ! -f "$src/package.json" ] || [ ! -f "$src/package-lock.json" ]; then
  echo "node_deps: $src has no package.json and package-lock.json" >&2
  exit 2
fi
for tool in node npm; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "node_deps: $tool not found (install Node.js >= 18 with npm, e.g. apt-get install nodejs npm)" >&2
    exit 3
  fi
done
dest="${RSTS_NODE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/rsts/node}/$name"
# "N MB" of a directory.
size() { du -sm "$1" 2>/dev/null | cut -f1 | sed 's/$/ MB/'; }
fetched() { if [ -n "${RSTS_FETCH_LOG:-}" ]; then echo "$*" >>"$RSTS_FETCH_LOG"; fi; }
if [ -f "$dest/node_modules/.package-lock.json" ] && cmp -s "$src/package-lock.json" "$dest/package-lock.json"; then
  fetched "already there: npm packages of scripts/$name in $dest ($(size "$dest"))"
  echo "$dest/node_modules"
  exit 0
fi
mkdir -p "$dest"
cp "$src/package.json" "$src/package-lock.json" "$dest/"
echo "node_deps: installing the npm packages of scripts/$name into $dest ..." >&2
start=$(date +%s)
if ! (cd "$dest" && npm ci --no-audit --no-fund --ignore-scripts --loglevel=error >"$dest/npm.log" 2>&1); then
  echo "node_deps: npm ci failed in $dest (no npm registry?); last lines of $dest/npm.log:" >&2
  tail -n 5 "$dest/npm.log" >&2
  rm -f "$dest/package-lock.json"
  exit 1
fi
echo "node_deps: done in $(($(date +%s) - start)) s" >&2
fetched "downloaded: npm packages of scripts/$name (npm registry) into $dest ($(size "$dest"), $(($(date +%s) - start)) s)"
echo "$dest/node_modules"
