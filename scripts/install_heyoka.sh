#!/usr/bin/env bash
# Install heyoka (Taylor integrator in C++/LLVM with Python bindings) into .venv-heyoka for the
# peer comparison scripts/peer_heyoka.py (rows for `rsts bench --peer`, docs/benchmarks.md).
# Needs python3 (3.11 here: PyPI has manylinux wheels of heyoka for it, with real128 and MPFR
# support) and the venv module. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=.venv-heyoka
PY=${PYTHON:-python3}
if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install --quiet --upgrade pip
"$VENV/bin/python" -m pip install --quiet "heyoka>=7,<8" numpy
"$VENV/bin/python" -c "import heyoka; print('heyoka', heyoka.__version__, 'in $VENV')"
