#!/usr/bin/env bash
# Speed against error, rsts against heyoka, in one run: installs heyoka if needed
# (scripts/install_adapters.sh heyoka), builds rsts (release), then measures and prints the
# ratios of the four targets of docs/benchmarks.md (f64, extended, MPFR at 90 digits, closed form) on
# the README's default case (camera I+: a = 1, b = 0.5, m = 0.3, h = -0.375) and two more
# example points (II+, and VI with m < 0), alternating our runs and heyoka's so that load from
# other processes hits both. heyoka runs as an external integrator of `rsts bench --exec`
# (scripts/adapters/heyoka_adapter.py). The machine is usually shared: the load average is
# printed.
#
#   scripts/bench_vs_heyoka.sh                    # all cases, 3 alternated rounds per target
#   scripts/bench_vs_heyoka.sh --rounds 5 --cases I+
#   scripts/bench_vs_heyoka.sh --quick --skip-closed-form
#
# Options are those of `scripts/bench_vs_heyoka.py run --help`. Output: the table on stdout
# (markdown), progress on stderr, every run's rows under out/bench-vs-heyoka/ (--out DIR).
# Takes 10-40 minutes on 2 shared cores; `--cases I+ --rounds 1 --quick --skip-closed-form`
# about 5 (docs/benchmarks.md).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=.venv-adapters/bin/python
if ! { [ -x "$PY" ] && "$PY" -c "import heyoka" 2>/dev/null; }; then
    bash scripts/install_adapters.sh heyoka >&2
fi
bash scripts/setup.sh >&2
cargo build --release -p rsts-cli >&2
exec "$PY" scripts/bench_vs_heyoka.py run --rsts target/release/rsts --python "$PY" "$@"
