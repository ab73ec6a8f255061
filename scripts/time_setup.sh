#!/usr/bin/env bash
# Time a newcomer's two README commands (scripts/run.sh, then scripts/test.sh) on a fresh clone of
# this repository's committed HEAD, with nothing built: a new target directory and no cached
# GMP/MPFR (GMP_MPFR_SYS_CACHE=_ makes gmp-mpfr-sys compile them as on a new machine instead of
# reusing ~/.cache/gmp-mpfr-sys). Crates already downloaded in ~/.cargo are reused (downloading is a
# few seconds here). Prints the wall-clock and CPU time of each command and the load average before
# and after (the machine may be shared: compare CPU time, or run it on an idle machine).
#
# Usage: scripts/time_setup.sh [DIR]    (DIR: where to clone; default a new /tmp/rsts-fresh-XXXX)
# Logs: DIR.run.log and DIR.test.log. Exit code: 0 when both commands succeeded, else 1.
set -euo pipefail

src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${1:-$(mktemp -u /tmp/rsts-fresh-XXXXXX)}"
if [ -e "$dir" ]; then
  echo "time_setup: $dir exists; give a new directory" >&2
  exit 2
fi
git clone -q "$src" "$dir"
export GMP_MPFR_SYS_CACHE=_
unset CARGO_TARGET_DIR RUSTC_WRAPPER

load() { cut -d' ' -f1-3 /proc/loadavg; }
echo "time_setup: clone of $(git -C "$dir" rev-parse --short HEAD) in $dir; $(nproc) cores; load $(load)"

status=0
for cmd in run test; do
  log="$dir.$cmd.log"
  before="$(load)"
  # bash's `time` reports real, user and sys of the whole command, children included.
  TIMEFORMAT="%R %U %S"
  { time (cd "$dir" && "scripts/$cmd.sh" >"$log" 2>&1); } 2>"$dir.$cmd.time" || status=1
  read -r real user sys <"$dir.$cmd.time"
  printf 'time_setup: scripts/%s.sh: %dm%02ds wall, %dm%02ds CPU (user+sys); load %s -> %s; log %s\n' \
    "$cmd" "$((${real%.*} / 60))" "$((${real%.*} % 60))" \
    "$(((${user%.*} + ${sys%.*}) / 60))" "$(((${user%.*} + ${sys%.*}) % 60))" \
    "$before" "$(load)" "$log"
  echo "  last line: $(tail -n 1 "$log")"
done
exit "$status"
