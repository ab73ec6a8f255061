#!/usr/bin/env bash
# The test of scripts/slurm_local.sh (run by scripts/ci_slurm.sh; needs root, installs Slurm):
#  1. `slurm_local.sh true` exits 0 and leaves no daemon and no file behind: the pids it reports
#     are gone, no munged, slurmctld, slurmd or slurmstepd runs that did not run before, its
#     scratch directory is gone and its TMPDIR (a fresh directory) is empty again;
#  2. CMD's exit status is the script's, and a job left running by CMD is cancelled, its
#     processes gone;
#  3. a daemon that does not come up (a slurmd that fails at once, put first on the PATH) is exit
#     2 with the end of its log, and the daemons started before it are stopped as well;
#  4. not root: exit 2 with the reason, nothing started.
# Prints what it checks; exits 1 on the first failure.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
script="$root/scripts/slurm_local.sh"
work="$(mktemp -d "${TMPDIR:-/tmp}/test-slurm-local.XXXXXX")"
trap 'rm -rf "$work"' EXIT

fail() {
  echo "test_slurm_local: FAIL: $*" >&2
  exit 1
}
ok() { echo "test_slurm_local: ok: $*"; }

# The Slurm and munge processes running (a zombie, already ended and waiting for init to reap
# it, does not run).
daemons() {
  ps -eo pid=,stat=,comm= | awk '$2 !~ /^Z/ && $3 ~ /^(munged|slurmctld|slurmd|slurmstepd)$/ {print $1}' | sort
}

# Run slurm_local.sh with a fresh, empty TMPDIR; sets $status, $log, $tmp.
run() {
  tmp="$(mktemp -d "$work/tmp.XXXXXX")"
  log="$work/log.$RANDOM"
  TMPDIR="$tmp" "$script" "$@" 2>"$log"
  status=$?
}

# The pids and scratch directory that slurm_local.sh reported starting.
started() {
  grep -o 'started munged (pid [0-9]*), slurmctld (pid [0-9]*), slurmd (pid [0-9]*) in .*' "$log"
}

# No pid of the list alive, no daemon beyond $before, the directory and $tmp's content gone.
nothing_left() {
  local what="$1" line pids dir pid
  line="$(started)" || fail "$what: no 'started ...' line on stderr:
$(cat "$log")"
  pids="$(grep -o 'pid [0-9]*' <<<"$line" | cut -d' ' -f2)"
  dir="${line##* in }"
  for pid in $pids; do
    if [ -e "/proc/$pid" ] && [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" != Z ]; then
      fail "$what: pid $pid ($(cat "/proc/$pid/comm" 2>/dev/null)) still runs"
    fi
  done
  [ ! -e "$dir" ] || fail "$what: $dir is still there: $(ls -A "$dir")"
  [ -z "$(ls -A "$tmp")" ] || fail "$what: left in its TMPDIR: $(ls -A "$tmp")"
  [ "$(daemons)" = "$before" ] ||
    fail "$what: daemons now $(daemons | tr '\n' ' '), before $(echo "$before" | tr '\n' ' ')"
  ok "$what: pids $(echo "$pids" | tr '\n' ' ')gone, $dir removed, TMPDIR empty, no other daemon"
}

[ "$(id -u)" -eq 0 ] || fail "must run as root (it installs and starts Slurm)"
before="$(daemons)"

# 1.
run true
[ "$status" -eq 0 ] || fail "slurm_local.sh true: exit $status:
$(cat "$log")"
nothing_left "slurm_local.sh true"

# 2.
run sh -c 'sbatch --quiet --output=/dev/null --wrap "sleep 600" && sleep 4 && squeue -h -o "%i %T"; exit 7'
[ "$status" -eq 7 ] || fail "exit status 7 of CMD came back as $status:
$(cat "$log")"
grep -q 'cancelling the jobs left in the queue' "$log" || fail "the running job was not cancelled:
$(cat "$log")"
pgrep -f 'sleep 600' >/dev/null && fail "the job's 'sleep 600' still runs"
nothing_left "CMD exiting 7 with a job running (exit 7 passed on, the job cancelled)"

# 3.
mkdir -p "$work/bin"
printf '#!/bin/sh\necho "slurmd (fake): cannot start: made to fail by test_slurm_local.sh" >&2\nexit 1\n' \
  >"$work/bin/slurmd"
chmod +x "$work/bin/slurmd"
tmp="$(mktemp -d "$work/tmp.XXXXXX")"
log="$work/log.fake"
PATH="$work/bin:$PATH" TMPDIR="$tmp" "$script" true 2>"$log"
status=$?
[ "$status" -eq 2 ] || fail "a slurmd that fails: exit $status, not 2:
$(cat "$log")"
grep -q 'cannot start Slurm: slurmd does not bring node localnode to idle' "$log" &&
  grep -q 'made to fail by test_slurm_local.sh' "$log" ||
  fail "a slurmd that fails: no reason or no log lines:
$(cat "$log")"
[ -z "$(ls -A "$tmp")" ] || fail "a slurmd that fails: left in TMPDIR: $(ls -A "$tmp")"
[ "$(daemons)" = "$before" ] || fail "a slurmd that fails: daemons left: $(daemons | tr '\n' ' ')"
ok "a slurmd that fails: exit 2 with the end of its log, munged and slurmctld stopped, TMPDIR empty"

# 4.
if command -v setpriv >/dev/null 2>&1; then
  tmp="$(mktemp -d "$work/tmp.XXXXXX")" && chmod 777 "$tmp"
  out="$(TMPDIR="$tmp" setpriv --reuid=65534 --regid=65534 --clear-groups bash "$script" true 2>&1)"
  status=$?
  [ "$status" -eq 2 ] && grep -q 'must run as root' <<<"$out" ||
    fail "not root: exit $status: $out"
  [ "$(daemons)" = "$before" ] && [ -z "$(ls -A "$tmp")" ] || fail "not root: something started"
  ok "not root: exit 2 ($out)"
else
  echo "test_slurm_local: skipped: not root (setpriv is not installed)"
fi
echo "test_slurm_local: all checks passed"
