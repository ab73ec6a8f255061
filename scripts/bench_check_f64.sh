#!/usr/bin/env bash
# CPU cost per sample of `rsts check` of f64 data (issue 21), this build against an older binary,
# alternated in one run: the reference rows of the README's default case (CSV and npy), a dopri5
# trajectory of the default case (camera I+, its error stays small: every sample has a nearest
# point on N) and one of camera V's third torus (m < 0, its error saturates), rtol = atol = 1e-9,
# CSV, and the reference rows of camera V's third torus (npy and CSV), 10⁵ rows each, --jobs 1.
# User CPU time from bash's `time` (getrusage, to the millisecond: 0.01 µs per sample).
# Prints a markdown table (user CPU µs per sample, the best of the rounds; whether the JSON of
# the two binaries is identical) with the load average; files under out/bench-check-f64/.
# Usage: [BEFORE=path/to/old/rsts] bash scripts/bench_check_f64.sh [ROUNDS]
# (without BEFORE the binary of this build is measured alone).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-2}
cargo build --release -p rsts-cli >&2
D=out/bench-check-f64
mkdir -p "$D"
# A copy of the binary: a build during the run does not change what is measured.
cp target/release/rsts "$D/rsts-after"
A=$D/rsts-after
B=${BEFORE:-}
n=100000
$A reference --m 0.3 --h -0.375 --t-end 1000 --samples $n --format csv -o "$D/ref.csv"
$A reference --m 0.3 --h -0.375 --t-end 1000 --samples $n --format npy -o "$D/ref.npy"
$A integrate --omega=-1.0788400339538464,-0.3702277283006931,0 \
    --alpha=-0.5266712206715436,-0.8500690709091504,0 --beta=-0.8500690709091504,0.5266712206715436,0 \
    --t-end 1000 --samples $n --method dopri5 --rtol 1e-9 --atol 1e-9 --format csv > "$D/dopri5.csv"
$A integrate --omega=-0.17131207221604822,0,1.2580177644422093 \
    --alpha=0.6956521739130435,0,-0.7183787670373176 --beta=0,1,0 \
    --t-end 1000 --samples $n --method dopri5 --rtol 1e-9 --atol 1e-9 --format csv > "$D/dopri5-default.csv"
V="--m -0.7092 --h 1.5643 --torus 2"
# shellcheck disable=SC2086
$A reference $V --t-end 1000 --samples $n --format csv -o "$D/v.csv"
# shellcheck disable=SC2086
$A reference $V --t-end 1000 --samples $n --format npy -o "$D/v.npy"
declare -A args=([ref.csv]="--m 0.3 --h -0.375" [ref.npy]="--m 0.3 --h -0.375" [dopri5-default.csv]="" [dopri5.csv]=""
    [v.npy]="$V" [v.csv]="$V")

# user BINARY FILE TAG: user CPU seconds of one check (its JSON kept as FILE.TAG.json).
user() {
    local TIMEFORMAT=%3U
    # shellcheck disable=SC2086
    { time "$1" check "$D/$2" ${args[$2]} --format json --jobs 1 > "$D/$2.$3.json" 2> /dev/null; } 2>&1
}

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $(date -u +%Y-%m-%dT%H:%MZ)"
echo
echo "| data (10⁵ rows) | before µs/sample (user) | after µs/sample (user) | same JSON |"
echo "|---|---|---|---|"
for f in ref.npy ref.csv dopri5-default.csv dopri5.csv v.npy v.csv; do
    best_a=inf
    best_b=inf
    for ((r = 0; r < rounds; r++)); do
        if [ -n "$B" ]; then
            best_b=$(awk -v x="$(user "$B" "$f" before)" -v m="$best_b" 'BEGIN { print (m == "inf" || x < m) ? x : m }')
        fi
        best_a=$(awk -v x="$(user "$A" "$f" after)" -v m="$best_a" 'BEGIN { print (m == "inf" || x < m) ? x : m }')
    done
    same="-"
    before="-"
    if [ -n "$B" ]; then
        before=$(awk -v u="$best_b" -v n=$n 'BEGIN { printf "%.2f", 1e6 * u / n }')
        same=$(cmp -s "$D/$f.before.json" "$D/$f.after.json" && echo yes || echo NO)
    fi
    after=$(awk -v u="$best_a" -v n=$n 'BEGIN { printf "%.2f", 1e6 * u / n }')
    echo "| $f | $before | $after | $same |"
    echo "done: $f" >&2
done
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
