#!/usr/bin/env bash
# Install the Python adapters' packages (scipy, numpy, heyoka) into .venv-adapters, for
# scripts/adapters/*.py (external integrators of `rsts compare|bench|validate --exec`,
# docs/own-integrator.md). Needs python3 with the venv module and PyPI. Idempotent.
#   scripts/install_adapters.sh            scipy and heyoka
#   scripts/install_adapters.sh scipy      scipy only (numpy comes with it)
#   scripts/install_adapters.sh heyoka     heyoka only
# Exit status 0 when every package asked for is importable afterwards.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=.venv-adapters
PY=${PYTHON:-python3}
want=("$@")
[ ${#want[@]} -eq 0 ] && want=(scipy heyoka)
if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV"
fi
status=0
for pkg in "${want[@]}"; do
    case "$pkg" in
        scipy) spec=("scipy>=1.9" numpy) ;;
        heyoka) spec=("heyoka>=7,<8" numpy) ;;
        *) echo "install_adapters.sh: unknown package '$pkg' (scipy, heyoka)" >&2; exit 2 ;;
    esac
    if "$VENV/bin/python" -c "import $pkg" 2>/dev/null; then
        continue
    fi
    if ! "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check "${spec[@]}"; then
        echo "install_adapters.sh: could not install ${spec[*]} into $VENV" >&2
        status=1
    fi
done
for pkg in "${want[@]}"; do
    "$VENV/bin/python" -c "import $pkg; print('$pkg', $pkg.__version__, 'in $VENV')" || status=1
done
exit $status
