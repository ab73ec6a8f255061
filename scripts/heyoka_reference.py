#!/usr/bin/env python3
"""An independent reference trajectory from heyoka in MPFR (any state, not only on N), in the
`rsts-reference-1` format read by the ignored test `external_reference_agrees` of
crates/dynamics/tests/dynamics/taylor.rs (docs/taylor.md):

    {"format": "rsts-reference-1", "a": "1", "b": "0.5",
     "times": ["0", "0.25", ...], "states": [["w1", "w2", "w3", "al1", ..., "be3"], ...]}

    .venv-adapters/bin/python scripts/heyoka_reference.py --a 1 --b 0.5 \
        --state w1,w2,w3,al1,al2,al3,be1,be2,be3 --t-end 20 --samples 41 [--digits 50] --out REF.json

Install heyoka first: scripts/install_adapters.sh heyoka. To measure heyoka itself against the
closed form, use the adapter: `rsts bench --exec ".venv-adapters/bin/python
scripts/adapters/heyoka_adapter.py f64"` (docs/benchmarks.md).
"""

import argparse
import os
import json
import statistics
import sys
import tempfile
import time
from decimal import Decimal, getcontext

import numpy as np

try:
    import heyoka as hy
except ImportError:  # pragma: no cover - message for the user
    sys.exit("heyoka is not installed: run scripts/install_adapters.sh heyoka and use .venv-adapters/bin/python")

getcontext().prec = 80
FORMAT = "rsts-reference-1"


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "adapters"))
from heyoka_adapter import bits_for_digits, equations  # noqa: E402  (the equations written once)


def converter(method, bits):
    """(numpy dtype, function decimal string -> scalar) of a method."""
    if method == "f64":
        return np.float64, lambda s: np.float64(float(s))
    if method == "real128":
        return hy.real128, lambda s: hy.real128(s)
    if method == "mpfr":
        return hy.real, lambda s: hy.real(s, bits)
    raise SystemExit(f"unknown method {method!r} (known: f64, f64-ha, real128, mpfr)")


def integrate(method, a, b, state, times, tol, bits, repeats=1):
    """States at `times` (decimal strings) and stats of `repeats` heyoka runs from the same
    integrator object (JIT-compiled once, reset to t = 0 and the initial state before each run):
    the states and steps of the first run, the median of the run times.

    Methods: f64, f64-ha (f64 with heyoka's high_accuracy mode: compensated summation of the
    state, like rsts' taylor-f64), real128, mpfr (at `bits` bits)."""
    scalar = "f64" if method == "f64-ha" else method
    dtype, conv = converter(scalar, bits)
    init = np.array([conv(x) for x in state], dtype=dtype)
    pars = np.array([conv(a), conv(b)], dtype=dtype)
    grid = np.array([conv(t) for t in times], dtype=dtype)
    kwargs = dict(tol=conv(repr(tol)) if scalar != "f64" else tol, pars=pars, fp_type=dtype)
    if scalar == "mpfr":
        kwargs["prec"] = bits
    if method == "f64-ha":
        kwargs["high_accuracy"] = True
    ta = hy.taylor_adaptive(equations(), init, **kwargs)
    first, seconds = None, []
    for _ in range(max(1, repeats)):
        ta.time = grid[0]
        ta.state[:] = init
        start = time.perf_counter()
        result = ta.propagate_grid(grid)
        seconds.append(time.perf_counter() - start)
        outcome, steps, states = result[0], result[3], result[-1]
        if outcome != hy.taylor_outcome.time_limit:
            raise SystemExit(f"{method} at tol {tol}: heyoka stopped with {outcome}")
        if first is None:
            first = (np.array(states, copy=True), int(steps))
    states, steps = first
    return states, {"steps": steps, "rhs_evals": steps * int(ta.order), "seconds": statistics.median(seconds)}


def cmd_make_reference(args):
    state = args.state.split(",")
    if len(state) != 9:
        raise SystemExit("--state needs 9 comma-separated numbers")
    if args.samples < 2 or not Decimal(args.t_end) > 0:
        raise SystemExit("need --samples >= 2 and --t-end > 0")
    t_end = Decimal(args.t_end)
    times = [str(t_end * k / (args.samples - 1)) for k in range(args.samples)]
    times[0] = "0"
    bits = bits_for_digits(args.digits)
    states, _ = integrate("mpfr", args.a, args.b, state, times, 10.0 ** (-args.digits), bits)
    out = {
        "format": FORMAT,
        "a": args.a,
        "b": args.b,
        "times": times,
        "states": [[str(x) for x in row] for row in states],
    }
    # Written whole or not at all: a temporary beside the target, renamed over it at the end.
    parent = os.path.dirname(os.path.abspath(args.out))
    os.makedirs(parent, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".ref.tmp-", dir=parent)
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(out, f, indent=1)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, args.out)
    except BaseException:
        os.unlink(tmp)
        raise


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--a", default="1")
    p.add_argument("--b", default="0.5")
    p.add_argument("--state", required=True)
    p.add_argument("--t-end", default="20")
    p.add_argument("--samples", type=int, default=41)
    p.add_argument("--digits", type=int, default=50)
    p.add_argument("--out", required=True)
    cmd_make_reference(p.parse_args())


if __name__ == "__main__":
    main()
