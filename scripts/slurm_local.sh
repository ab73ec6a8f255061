#!/usr/bin/env bash
# scripts/slurm_local.sh CMD [ARGS...]: run CMD beside a single-node Slurm started for it alone.
#
# Installs slurmctld, slurmd, slurm-client and munge with apt-get when they are missing, then in
# a scratch directory (mktemp -d under $TMPDIR or /tmp): a munge key and munged on its own socket,
# a slurm.conf generated for this machine (one node with `nproc` CPUs and 95 % of MemTotal, root
# as SlurmUser, ProctrackType=proctrack/linuxproc, TaskPlugin=task/none, no cgroup.conf, free
# ports), slurmctld and slurmd in the foreground. When the node is idle it runs CMD with
# SLURM_CONF pointing at that configuration (sbatch, squeue, scontrol... in CMD talk to this
# Slurm), then cancels what is left in the queue, stops every daemon it started (by pid, TERM
# then KILL after 10 s), removes the scratch directory, and exits with CMD's status.
#
# It tells on stderr what it starts: `slurm_local.sh: started munged (pid P) ... in DIR`.
# Exit 2, with a message, when it cannot: not root, packages missing and no apt-get, a daemon
# that does not come up (the last lines of its log are shown).
#
# Environment: SLURM_LOCAL_TIMEOUT (seconds to wait for each daemon, default 60).
set -uo pipefail

me="slurm_local.sh"
timeout="${SLURM_LOCAL_TIMEOUT:-60}"
PATH="$PATH:/usr/sbin:/sbin"

say() { echo "$me: $*" >&2; }

if [ "$#" -eq 0 ]; then
  say "usage: scripts/slurm_local.sh CMD [ARGS...] (runs CMD beside a single-node Slurm)"
  exit 2
fi
if [ "$(id -u)" -ne 0 ]; then
  say "cannot start Slurm: must run as root (the daemons run as root, SlurmUser=root)"
  exit 2
fi

# ---- packages -------------------------------------------------------------------------------
missing=()
command -v slurmctld >/dev/null 2>&1 || missing+=(slurmctld)
command -v slurmd >/dev/null 2>&1 || missing+=(slurmd)
command -v sbatch >/dev/null 2>&1 || missing+=(slurm-client)
command -v munged >/dev/null 2>&1 || missing+=(munge)
if [ "${#missing[@]}" -gt 0 ]; then
  if ! command -v apt-get >/dev/null 2>&1; then
    say "cannot start Slurm: ${missing[*]} missing and no apt-get to install them"
    exit 2
  fi
  say "installing ${missing[*]} with apt-get"
  # No service may start from the packages' scripts: the only daemons are the ones started
  # below (a policy-rc.d that forbids starting services, only while installing, unless the
  # system has one).
  policy=""
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    policy=/usr/sbin/policy-rc.d
    printf '#!/bin/sh\nexit 101\n' >"$policy" && chmod +x "$policy"
  fi
  started=$SECONDS
  log="$(mktemp)"
  if ! { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    >"$log" 2>&1; then
    [ -n "$policy" ] && rm -f "$policy"
    say "cannot start Slurm: apt-get could not install ${missing[*]}:"
    tail -n 15 "$log" >&2
    rm -f "$log"
    exit 2
  fi
  [ -n "$policy" ] && rm -f "$policy"
  rm -f "$log"
  say "installed in $((SECONDS - started)) s"
fi

# ---- scratch directory and clean-up ----------------------------------------------------------
scratch="$(mktemp -d "${TMPDIR:-/tmp}/slurm-local.XXXXXX")" || {
  say "cannot start Slurm: cannot make a scratch directory"
  exit 2
}
chmod 700 "$scratch"
pids=()   # every daemon started, in order
names=()

# The pids of the slurmstepd processes of this Slurm still running.
job_steps() {
  local p
  for p in /proc/[0-9]*; do
    [ "$(cat "$p/comm" 2>/dev/null)" = slurmstepd ] || continue
    { tr '\0' '\n' <"$p/environ"; } 2>/dev/null | grep -qxF "SLURM_CONF=$scratch/slurm.conf" &&
      echo "${p#/proc/}"
  done
}

# Stop every daemon started (last first): TERM, then KILL after 10 s; remove the scratch directory.
cleanup() {
  trap - EXIT INT TERM HUP
  if [ -n "${ctld_up:-}" ] && kill -0 "${pids[1]:-0}" 2>/dev/null; then
    # Jobs left by CMD: cancelled, and their steps given time to end with slurmd still there.
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
      say "cancelling the jobs left in the queue: $(squeue -h -o %i | tr '\n' ' ')"
      scancel --full --quiet --user=root 2>/dev/null
      for _ in $(seq 1 50); do
        [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
        sleep 0.2
      done
    fi
    # The jobs' slurmstepd processes (reparented to init, known by this SLURM_CONF in their
    # environment) end shortly after their jobs.
    for _ in $(seq 1 50); do
      [ -z "$(job_steps)" ] && break
      sleep 0.2
    done
    if [ -n "$(job_steps)" ]; then
      say "killing job steps that outlived their jobs: $(job_steps)"
      kill -KILL $(job_steps) 2>/dev/null
    fi
  fi
  local i pid
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid="${pids[$i]}"
    kill -TERM "$pid" 2>/dev/null || continue
    for _ in $(seq 1 100); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    if kill -0 "$pid" 2>/dev/null; then
      say "${names[$i]} (pid $pid) did not stop on TERM within 10 s: killed"
      kill -KILL "$pid" 2>/dev/null
    fi
    wait "$pid" 2>/dev/null
  done
  rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP

# A daemon that did not come up: what its log says, then exit 2 (the clean-up runs).
fail() {
  local what="$1" log="$2"
  say "cannot start Slurm: $what; the end of $(basename "$log"):"
  if [ -s "$log" ]; then tail -n 20 "$log" | sed 's/^/  | /' >&2; else say "  (the log is empty)"; fi
  exit 2
}

# Wait until `check` succeeds (true) or the daemon `pid` ends or the time is up (false).
wait_for() {
  local pid="$1"
  shift
  local deadline=$((SECONDS + timeout))
  until "$@" >/dev/null 2>&1; do
    kill -0 "$pid" 2>/dev/null || return 1
    [ "$SECONDS" -lt "$deadline" ] || return 1
    sleep 0.5
  done
}

# A TCP port nothing listens on, from $1 upwards.
free_port() {
  local port="$1"
  local used
  used="$(ss -Htan 2>/dev/null | awk '{n = split($4, a, ":"); print a[n]}')"
  while grep -qx "$port" <<<"$used"; do port=$((port + 1)); done
  echo "$port"
}

# ---- munge ----------------------------------------------------------------------------------
mkdir -p "$scratch/munge" "$scratch/state" "$scratch/spool" && chmod 700 "$scratch/munge"
dd if=/dev/urandom of="$scratch/munge/munge.key" bs=1024 count=1 status=none &&
  chmod 400 "$scratch/munge/munge.key"
socket="$scratch/munge/munge.socket"
munged --foreground --force --socket="$socket" --key-file="$scratch/munge/munge.key" \
  --pid-file="$scratch/munge/munged.pid" --log-file="$scratch/munge/munged.log" \
  --seed-file="$scratch/munge/munged.seed" >>"$scratch/munge/munged.log" 2>&1 &
pids+=($!) names+=(munged)
munge_works() { munge --socket="$socket" -n | unmunge --socket="$socket"; }
wait_for "${pids[0]}" munge_works || fail "munged does not answer on its socket" "$scratch/munge/munged.log"

# ---- slurm.conf -----------------------------------------------------------------------------
cpus="$(nproc)"
mem_mb=$(($(awk '/^MemTotal:/ {print $2}' /proc/meminfo) / 1024 * 95 / 100))
host="$(hostname -s)"
ctld_port="$(free_port 6817)"
d_port="$(free_port $((ctld_port + 1)))"
export SLURM_CONF="$scratch/slurm.conf"
cat >"$SLURM_CONF" <<CONF
# Written by scripts/slurm_local.sh: one node, this machine, for one command.
ClusterName=rstslocal
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$scratch/state
SlurmdSpoolDir=$scratch/spool
SlurmctldPidFile=$scratch/slurmctld.pid
SlurmdPidFile=$scratch/slurmd.pid
SlurmctldLogFile=$scratch/slurmctld.log
SlurmdLogFile=$scratch/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
NodeName=localnode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=local Nodes=localnode Default=YES MaxTime=INFINITE State=UP
CONF

# ---- slurmctld, slurmd ----------------------------------------------------------------------
slurmctld -D -i -f "$SLURM_CONF" >>"$scratch/slurmctld.log" 2>&1 &
pids+=($!) names+=(slurmctld)
ctld_ping() { scontrol ping | grep -q UP; }
wait_for "${pids[1]}" ctld_ping || fail "slurmctld does not answer (port $ctld_port)" "$scratch/slurmctld.log"
ctld_up=1

slurmd -D -N localnode -f "$SLURM_CONF" >>"$scratch/slurmd.log" 2>&1 &
pids+=($!) names+=(slurmd)
node_idle() { [ "$(sinfo -h -n localnode -o %t)" = idle ]; }
wait_for "${pids[2]}" node_idle || {
  say "node state: $(sinfo -h -n localnode -o '%t %E' 2>&1)"
  fail "slurmd does not bring node localnode to idle" "$scratch/slurmd.log"
}

say "started munged (pid ${pids[0]}), slurmctld (pid ${pids[1]}), slurmd (pid ${pids[2]}) in $scratch"
say "node localnode idle: $cpus CPUs, $mem_mb MB, partition local; SLURM_CONF=$SLURM_CONF"
say "running: $*"

# ---- the command ----------------------------------------------------------------------------
"$@"
status=$?
say "$1 exited with status $status; stopping Slurm"
exit "$status"
