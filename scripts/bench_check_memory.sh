#!/usr/bin/env bash
# Peak memory of `rsts check` at 10⁵, 10⁶ and 10⁷ samples (issue 21, item 4: check streams its
# input). The data: `rsts reference` of the README's default case (camera I+) as npy, T = 10⁴;
# the 10⁷ file takes 1.04 GB of disk (deleted after); with .venv-python (scripts/install_python.sh),
# rsts.check of the same arrays up to 10⁶ (its peak above the interpreter holding them). Prints a
# markdown table (stdout).
# Usage: bash scripts/bench_check_memory.sh [--quick]   (--quick: 10⁵ and 10⁶ only)
set -euo pipefail
cd "$(dirname "$0")/.."
sizes=(100000 1000000 10000000)
[ "${1:-}" = --quick ] && sizes=(100000 1000000)
cargo build --release -p rsts-cli >&2
D=out/bench-check-memory
mkdir -p "$D"
cp target/release/rsts "$D/rsts"
R=$D/rsts
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; $(date -u +%Y-%m-%dT%H:%MZ)"
echo
echo "| samples | input | peak MB | wall s | user s |"
echo "|---|---|---|---|---|"
for n in "${sizes[@]}"; do
    f="$D/ref-$n.npy"
    $R reference --m 0.3 --h -0.375 --t-end 10000 --samples "$n" --format npy -o "$f"
    /usr/bin/time -f "%M %e %U" -o "$D/time.txt" $R check "$f" --m 0.3 --h -0.375 --format json > /dev/null
    read -r kb wall user < "$D/time.txt"
    echo "| $n | npy, $(du -h "$f" | cut -f1) | $((kb / 1024)) | $wall | $user |"
    # The Python face (issue 35, defect 3): rsts.check of the same rows as numpy arrays, read a
    # chunk at a time where they are; its peak less that of the interpreter holding the arrays.
    if [ -x .venv-python/bin/python ] && [ "$n" -le 1000000 ]; then
        load="import numpy as np, rsts; a = np.load('$f'); t = np.ascontiguousarray(a[:, 0]); x = np.ascontiguousarray(a[:, 1:]); del a"
        /usr/bin/time -f "%M" -o "$D/base.txt" .venv-python/bin/python -c "$load"
        /usr/bin/time -f "%M %e %U" -o "$D/time.txt" .venv-python/bin/python -c "$load; rsts.check(t, x, m='0.3', h='-0.375')"
        read -r base < "$D/base.txt"
        read -r kb wall user < "$D/time.txt"
        echo "| $n | Python rsts.check(times, states): $((base / 1024)) MB with the arrays loaded | +$(((kb - base) / 1024)) | $wall | $user |"
    fi
    rm -f "$f"
done
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
