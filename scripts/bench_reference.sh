#!/usr/bin/env bash
# Per-sample cost and peak memory of `rsts reference` and `rsts check` (issue 21): f64 and 30,
# 100, 1000 digits, one thread (--jobs 1) and every core; the f64 runs at 10⁶ samples (and 10⁷
# for reference with --big). Prints a markdown table (stdout), progress on stderr; files under
# out/bench-reference/. Usage: bash scripts/bench_reference.sh [--quick] [--big]
#   --quick: 10⁵ f64 samples instead of 10⁶ (and fewer at 30/100/1000 digits)
#   --big:   also reference of 10⁷ samples (memory at 10⁷)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
big=0
for arg in "$@"; do
    case "$arg" in
        --quick) quick=1 ;;
        --big) big=1 ;;
        *) echo "unknown option $arg (use --quick, --big)" >&2; exit 2 ;;
    esac
done
cargo build --release -p rsts-cli >&2
D=out/bench-reference
mkdir -p "$D"
# A copy of the binary: a build during the run does not change what is measured.
cp target/release/rsts "$D/rsts"
R=$D/rsts
cores=$(nproc)
n=$([ "$quick" = 1 ] && echo 100000 || echo 1000000)
# Samples at D digits: fewer as the cost grows.
declare -A ndig=([30]=$((n / 20)) [100]=$((n / 50)) [1000]=$((n / 1000)))
motion=(--m 0.3 --h -0.375)            # the README's default case, camera I+
motion_neg=(--m -0.7092 --h 1.5643 --torus 2)  # camera V, m < 0

# run LABEL SAMPLES CMD...: wall seconds, µs per sample (wall/N), µs per sample per core
# (user/N), peak memory (MB) of one command.
run() {
    local label=$1 samples=$2
    shift 2
    local log="$D/time-$(echo "$label" | tr -c 'A-Za-z0-9' '_').txt"
    /usr/bin/time -v "$@" > /dev/null 2> "$log"
    local wall user rss
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s}' "$log")
    user=$(awk -F': ' '/User time/ {print $2}' "$log")
    rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$log")
    awk -v l="$label" -v n="$samples" -v w="$wall" -v u="$user" -v r="$rss" \
        'BEGIN { printf "| %s | %d | %.2f | %.3f | %.3f | %.0f |\n", l, n, w, 1e6 * w / n, 1e6 * u / n, r / 1024 }'
    echo "done: $label" >&2
}

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $cores cores; $(date -u +%Y-%m-%dT%H:%MZ)"
echo
echo "| run | samples | wall s | µs/sample (wall) | µs/sample/core (user) | peak MB |"
echo "|---|---|---|---|---|---|"
for m in default negative; do
    if [ "$m" = default ]; then args=("${motion[@]}"); name="I+"; else args=("${motion_neg[@]}"); name="V (m<0)"; fi
    for jobs in 1 "$cores"; do
        run "$name reference f64, --jobs $jobs (npy)" "$n" \
            $R reference "${args[@]}" --t-end 1000 --samples "$n" --format npy --jobs "$jobs" -o "$D/ref-$m.npy"
    done
    $R reference "${args[@]}" --t-end 1000 --samples "$n" --format csv -o "$D/ref-$m.csv"
    run "$name check f64 (CSV of reference)" "$n" $R check "$D/ref-$m.csv" "${args[@]}" --format json
    for jobs in 1 "$cores"; do
        run "$name check f64 (npy of reference), --jobs $jobs" "$n" \
            $R check "$D/ref-$m.npy" "${args[@]}" --format json --jobs "$jobs"
    done
done
for digits in 30 100 1000; do
    k=${ndig[$digits]}
    for jobs in 1 "$cores"; do
        run "I+ reference $digits digits, --jobs $jobs" "$k" \
            $R reference "${motion[@]}" --t-end 1000 --samples "$k" --digits "$digits" --jobs "$jobs" -o "$D/ref-$digits.csv"
    done
    run "I+ check of $digits-digit data" "$k" $R check "$D/ref-$digits.csv" "${motion[@]}" --format json --jobs "$cores"
done
if [ "$big" = 1 ]; then
    run "I+ reference f64, --jobs $cores, 10⁷ (npy)" 10000000 \
        $R reference "${motion[@]}" --t-end 10000 --samples 10000000 --format npy --jobs "$cores" -o "$D/ref-big.npy"
    rm -f "$D/ref-big.npy"
fi
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
