#!/usr/bin/env bash
# CI's Slurm part (run by .ci/run after scripts/test.sh; needs root, installs Slurm with apt):
#  1. scripts/test_slurm_local.sh: scripts/slurm_local.sh leaves no daemon and no file behind;
#  2. on a Slurm started by scripts/slurm_local.sh (this script again, with --inside):
#     a. the quick suite as a 4-task job array and its `afterany` merge, the merged report
#        compared with an unsharded run (equal up to timings);
#     b. the same array with task 3 given a suite that does not exist: the merge names shard 3/4
#        and exits 2;
#     c. an ensemble of 40 motions of `rsts bench` as a 4-task array and its merge, compared with
#        the unsharded run (rows and bands equal up to the times);
#     d. the documented blocks that need Slurm (docs/validation.md, docs/benchmarks.md), through
#        the examples test: RSTS_EXAMPLES_NEEDING=slurm.
# Each step says what it runs; the job ids, the task logs and the merges' output are shown.
# Exit 0 when all pass, 1 on the first failure, 2 when Slurm cannot be started.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if ! command -v cargo >/dev/null 2>&1; then export PATH="$HOME/.cargo/bin:$PATH"; fi
step() { printf '\n== ci_slurm: %s\n' "$*"; }
fail() {
  echo "ci_slurm: FAIL: $*" >&2
  exit 1
}

if [ "${1:-}" != --inside ]; then
  started=$SECONDS
  step "scripts/test_slurm_local.sh (no daemon, no file left behind)"
  scripts/test_slurm_local.sh
  step "cargo build --release -p rsts-cli (fresh after scripts/test.sh)"
  cargo build --release -p rsts-cli
  command -v python3 >/dev/null 2>&1 || fail "python3 is needed to compare the reports"
  step "scripts/slurm_local.sh $0 --inside (the jobs, on a real single-node Slurm)"
  scripts/slurm_local.sh "$0" --inside
  echo "ci_slurm: all passed in $((SECONDS - started)) s"
  exit 0
fi

rsts="$root/target/release/rsts"
work="$(mktemp -d "${TMPDIR:-/tmp}/ci-slurm.XXXXXX")"
trap 'rm -rf "$work"' EXIT
sinfo
echo "ci_slurm: work directory $work"

# Compare two JSON reports with the clock's figures removed; prints what was compared.
same_up_to_timings() {
  python3 - "$1" "$2" "$3" <<'PY'
import json, sys
kind, a_path, b_path = sys.argv[1:]
a, b = (json.load(open(p)) for p in (a_path, b_path))
TIMES = {"integration_seconds", "time_min", "time_median", "time_max", "wall_seconds",
         "time_p05", "time_p95", "timing"}
# Provenance, not results: when the report was made and the shards a merge was made of.
PROVENANCE = {"created", "parts"}
def strip(v, top=True):
    if isinstance(v, dict):
        return {k: strip(x, False) for k, x in v.items()
                if k not in TIMES and not (top and k in PROVENANCE)}
    if isinstance(v, list):
        return [strip(x, False) for x in v]
    return v
def no_time_regressions(r):
    if r.get("baseline"):
        r["baseline"]["regressions"] = [x for x in r["baseline"]["regressions"] if x["kind"] != "time"]
    return r
a, b = strip(no_time_regressions(a)), strip(no_time_regressions(b))
if a != b:
    for key in sorted(set(a) | set(b)):
        if a.get(key) != b.get(key):
            print(f"differs: {key}", file=sys.stderr)
    sys.exit(f"{kind}: {a_path} and {b_path} differ beyond timings")
if kind == "validate":
    s = a["summary"]
    print(f"equal up to timings: {s['runs']} runs ({s['passed']} passed, {s['failed']} failed, {s['errors']} errors), suite digest {a['suite_digest']}")
else:
    bands = ", ".join(f"{x['method']}@{x['tolerance']:g} median {x['error_median']!r}" for x in a["bands"])
    print(f"equal up to timings: {len(a['rows'])} rows of {a['ensemble']['n']} motions; error bands to the bit ({bands})")
PY
}

# The logs of a job array's tasks and of its merge (the glob patterns given).
show_logs() {
  local f
  for f in $1; do
    echo "---- $(basename "$f")"
    sed 's/^/  /' "$f"
  done
}

cat >"$work/validate-array.sh" <<'EOF'
#!/bin/bash
# validate-array.sh SUITE DIR [BAD_TASK]: shard K of N of SUITE into DIR/shard-K; task BAD_TASK
# is given a suite that does not exist (bad input: exit 2, no report).
#SBATCH --job-name=ci-validate
#SBATCH --array=1-4
#SBATCH --time=00:30:00
set -euo pipefail
suite="$1"
if [ "$SLURM_ARRAY_TASK_ID" = "${3:-}" ]; then suite=validation/no-such-suite.toml; fi
echo "task $SLURM_ARRAY_TASK_ID of $SLURM_ARRAY_TASK_COUNT (job $SLURM_ARRAY_JOB_ID) on $(hostname): $suite"
target/release/rsts validate --suite "$suite" --report "$2/shard-$SLURM_ARRAY_TASK_ID" \
  --shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT" --jobs "${SLURM_CPUS_PER_TASK:-1}" || [ $? -eq 1 ]
EOF

# ---- a. ----
step "a. unsharded run: rsts validate --suite validation/quick.toml --report $work/quick --jobs 2"
"$rsts" validate --suite validation/quick.toml --report "$work/quick" --jobs 2
step "a. sbatch the quick suite as a 4-task array, then the afterany merge (sbatch --wait)"
array=$(sbatch --parsable --output="$work/validate-%A_%a.log" "$work/validate-array.sh" \
  validation/quick.toml "$work/quick-array")
echo "array job $array submitted"
squeue
set +e
sbatch --wait --dependency="afterany:$array" --job-name=ci-merge --output="$work/merge-%j.log" \
  --wrap "echo merge job \$SLURM_JOB_ID after array $array; target/release/rsts validate merge $work/quick-array/shard-* --report $work/quick-merged"
status=$?
set -e
show_logs "$work/validate-${array}_*.log $work/merge-*.log"
[ "$status" -eq 0 ] || fail "the merge job exited $status"
same_up_to_timings validate "$work/quick-merged/report.json" "$work/quick/report.json"
rm -f "$work"/merge-*.log

# ---- b. ----
step "b. the same array with task 3 given a suite that does not exist; the merge must name shard 3/4"
array=$(sbatch --parsable --output="$work/bad-%A_%a.log" "$work/validate-array.sh" \
  validation/quick.toml "$work/bad-array" 3)
echo "array job $array submitted"
set +e
sbatch --wait --dependency="afterany:$array" --job-name=ci-merge --output="$work/merge-%j.log" \
  --wrap "echo merge job \$SLURM_JOB_ID after array $array; target/release/rsts validate merge $work/bad-array/shard-* --report $work/bad-merged"
status=$?
set -e
show_logs "$work/bad-${array}_*.log $work/merge-*.log"
[ "$status" -eq 2 ] || fail "the merge after a failed shard exited $status, not 2"
grep -q 'missing shard(s) 3/4' "$work"/merge-*.log || fail "the merge does not name shard 3/4"
[ ! -e "$work/bad-merged" ] || fail "the merge wrote a report"
echo "ci_slurm: the merge exited 2 naming the failed shard: $(grep -h 'missing shard' "$work"/merge-*.log)"
rm -f "$work"/merge-*.log

# ---- c. ----
ensemble=(--ensemble 40 --t-end 20 --repeats 1 --methods dop853,taylor-f64 --tolerances 1e-8,1e-12)
step "c. unsharded run: rsts bench ${ensemble[*]} --json $work/ensemble.json"
"$rsts" bench "${ensemble[@]}" --json "$work/ensemble.json" >/dev/null
step "c. sbatch the ensemble as a 4-task array (--shard K/4 --json), then the afterany bench merge"
cat >"$work/bench-array.sh" <<EOF
#!/bin/bash
#SBATCH --job-name=ci-bench
#SBATCH --array=1-4
#SBATCH --time=00:30:00
set -euo pipefail
echo "task \$SLURM_ARRAY_TASK_ID of \$SLURM_ARRAY_TASK_COUNT (job \$SLURM_ARRAY_JOB_ID)"
target/release/rsts bench ${ensemble[*]} --shard "\$SLURM_ARRAY_TASK_ID/\$SLURM_ARRAY_TASK_COUNT" \\
  --json "$work/ensemble-array/shard-\$SLURM_ARRAY_TASK_ID.json"
EOF
array=$(sbatch --parsable --output="$work/bench-%A_%a.log" "$work/bench-array.sh")
echo "array job $array submitted"
set +e
sbatch --wait --dependency="afterany:$array" --job-name=ci-merge --output="$work/merge-%j.log" \
  --wrap "echo merge job \$SLURM_JOB_ID after array $array; target/release/rsts bench merge $work/ensemble-array/shard-*.json --json $work/ensemble-merged.json"
status=$?
set -e
show_logs "$work/bench-${array}_*.log $work/merge-*.log"
[ "$status" -eq 0 ] || fail "the bench merge job exited $status"
same_up_to_timings bench "$work/ensemble-merged.json" "$work/ensemble.json"

# ---- d. ----
step "d. the documented Slurm blocks: RSTS_EXAMPLES_NEEDING=slurm cargo test --release -p rsts-cli --test cli examples::"
set +e
RSTS_EXAMPLES_NEEDING=slurm cargo test --release -p rsts-cli --test cli -- \
  examples::every_documented_example_runs_as_written --nocapture >"$work/examples.log" 2>&1
status=$?
set -e
grep -E '^(examples:|test examples::every|SKIPPED|test result)' "$work/examples.log" || true
if [ "$status" -ne 0 ]; then
  tail -n 60 "$work/examples.log"
  fail "the examples test exited $status"
fi
squeue
echo "ci_slurm: every Slurm check passed"
