#!/usr/bin/env python3
"""Peer integrator: the same Euler–Poisson system (Kowalevski top, inertia diag(2,2,1), two
constant fields a, b) integrated by heyoka's Taylor method in f64, real128 and MPFR, measured
against a reference trajectory.

Install heyoka first: scripts/install_heyoka.sh, then run with .venv-heyoka/bin/python.

Reference trajectory file (JSON, written by `make-reference` below or by any other tool):

    {
      "format": "rsts-reference-1",
      "a": "1", "b": "0.5",                 # field strengths, decimal strings
      "times": ["0", "0.25", ...],           # sample times, decimal strings, times[0] = "0"
      "states": [["w1", "w2", "w3", "al1", "al2", "al3", "be1", "be2", "be3"], ...]
    }

`states[k]` is the state (omega, alpha, beta in the body frame) at `times[k]`, as decimal strings
carrying as many digits as the reference has; `states[0]` is the initial state of every run.

    compare:        peer_heyoka.py compare REF.json --tolerances 1e-10,1e-15 \
                        [--methods f64,f64-ha,real128,mpfr] [--mp-digits 40] [--repeats 3] \
                        [--out rows.json]
    make-reference: peer_heyoka.py make-reference --a 1 --b 0.5 \
                        --state w1,w2,w3,al1,al2,al3,be1,be2,be3 --t-end 20 --samples 41 \
                        [--digits 50] --out REF.json

`rsts bench --write-reference REF.json` writes such a file from the closed-form motion (exact
reference: the same one `rsts bench` measures against); `make-reference` below integrates one
with heyoka in MPFR instead.

`compare` prints (or writes) {"rows": [{"method", "tolerance", "max_error",
"integration_seconds", "steps", "rhs_evals"}]}, the rows `rsts bench --peer FILE` reads:
max_error is the largest |x - x_ref| over all samples and components (evaluated in decimal
arithmetic 20 digits beyond the reference); integration_seconds is the median over --repeats
runs of the wall time of propagate_grid alone (not the JIT compilation of the integrator, done
once; the integrator is reset to t = 0 and the initial state before each run); rhs_evals is
steps x order (one per Taylor coefficient order, the convention of rsts' Taylor integrators,
which add one per step for their compensation).
"""

import argparse
import json
import statistics
import sys
import time
from decimal import Decimal, getcontext

import numpy as np

try:
    import heyoka as hy
except ImportError:  # pragma: no cover - message for the user
    sys.exit("heyoka is not installed: run scripts/install_heyoka.sh and use .venv-heyoka/bin/python")

getcontext().prec = 80
FORMAT = "rsts-reference-1"


def bits_for_digits(digits):
    # Same rule as rsts_dynamics::scalar::bits_for_digits: ceil(digits * log2(10)) + 8.
    import math

    return math.ceil(digits * math.log2(10)) + 8


def equations():
    """The right-hand side, component by component as in crates/dynamics/src/equations.rs."""
    w1, w2, w3, a1, a2, a3, b1, b2, b3 = hy.make_vars("w1", "w2", "w3", "a1", "a2", "a3", "b1", "b2", "b3")
    pa, pb = hy.par[0], hy.par[1]
    return [
        (w1, 0.5 * w2 * w3 + 0.5 * pb * b3),
        (w2, -0.5 * w1 * w3 - 0.5 * pa * a3),
        (w3, pa * a2 - pb * b1),
        (a1, a2 * w3 - a3 * w2),
        (a2, a3 * w1 - a1 * w3),
        (a3, a1 * w2 - a2 * w1),
        (b1, b2 * w3 - b3 * w2),
        (b2, b3 * w1 - b1 * w3),
        (b3, b1 * w2 - b2 * w1),
    ]


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


def to_decimal(x):
    """Exact value of an f64; the full decimal text of real128 and MPFR numbers."""
    if isinstance(x, (float, np.float64)):
        return Decimal(float(x))
    return Decimal(str(x))


def max_error(states, reference):
    worst = Decimal(0)
    for row, ref in zip(states, reference):
        for x, r in zip(row, ref):
            worst = max(worst, abs(to_decimal(x) - Decimal(r)))
    return float(worst)


def cmd_compare(args):
    with open(args.reference) as f:
        ref = json.load(f)
    if ref.get("format") != FORMAT:
        raise SystemExit(f"{args.reference}: not a {FORMAT} file")
    if Decimal(ref["times"][0]) != 0:
        raise SystemExit(f"{args.reference}: times[0] must be 0")
    if len(ref["times"]) != len(ref["states"]) or any(len(s) != 9 for s in ref["states"]):
        raise SystemExit(f"{args.reference}: need one 9-component state per time")
    # Decimal arithmetic wider than the reference's digits, so the error is not the subtraction's.
    digits = max(len(x.lstrip("-").split("e")[0]) for row in ref["states"] for x in row)
    getcontext().prec = max(80, digits + 20)
    tols = [float(t) for t in args.tolerances.split(",")]
    methods = args.methods.split(",")
    for method in methods:
        converter("f64" if method == "f64-ha" else method, 64)  # unknown names fail before any run
    bits = bits_for_digits(args.mp_digits)
    rows = []
    for method in methods:
        for tol in tols:
            states, stats = integrate(
                method, ref["a"], ref["b"], ref["states"][0], ref["times"], tol, bits, args.repeats
            )
            print(f"heyoka {method} tol {tol:g}: {stats['seconds']:.3e} s", file=sys.stderr)
            name = f"heyoka-{method}" + (f"-{args.mp_digits}d" if method == "mpfr" else "")
            rows.append(
                {
                    "method": name,
                    "tolerance": tol,
                    "max_error": max_error(states, ref["states"]),
                    "integration_seconds": stats["seconds"],
                    "steps": stats["steps"],
                    "rhs_evals": stats["rhs_evals"],
                }
            )
    text = json.dumps({"rows": rows}, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    else:
        print(text)


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
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("compare", help="run heyoka against a reference file")
    c.add_argument("reference")
    c.add_argument("--tolerances", default="1e-15")
    c.add_argument("--methods", default="f64,real128,mpfr")
    c.add_argument("--mp-digits", type=int, default=40)
    c.add_argument("--repeats", type=int, default=3, help="runs per tolerance; the time is their median")
    c.add_argument("--out")
    r = sub.add_parser("make-reference", help="write a reference file with heyoka in MPFR")
    r.add_argument("--a", default="1")
    r.add_argument("--b", default="0.5")
    r.add_argument("--state", required=True)
    r.add_argument("--t-end", default="20")
    r.add_argument("--samples", type=int, default=41)
    r.add_argument("--digits", type=int, default=50)
    r.add_argument("--out", required=True)
    args = p.parse_args()
    {"compare": cmd_compare, "make-reference": cmd_make_reference}[args.cmd](args)


if __name__ == "__main__":
    main()
