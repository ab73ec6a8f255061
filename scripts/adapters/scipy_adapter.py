#!/usr/bin/env python3
"""scipy.integrate.solve_ivp as an external integrator of rsts, protocol rsts-integrator/1.

    rsts compare --exec ".venv-adapters/bin/python scripts/adapters/scipy_adapter.py DOP853" --rtol 1e-10 --atol 1e-10

Argument: the method of solve_ivp, RK45 (default), DOP853, Radau or LSODA. Install scipy with
scripts/install_adapters.sh scipy.

A fixed step (`"step"` in the request, `rsts convergence`): RK45 and DOP853 take every step of
length h with their step-size control off -- first_step = max_step = h (h shortened so that each
interval between two requested times is a whole number of steps) and atol = 1e300, so every
step is accepted and the next step is capped at h; each interval is its own solve_ivp call and
its sample is the end of its last step (not the dense output, whose order is lower). Radau
(implicit, its Newton iterations depend on the tolerance) and LSODA (it switches methods and
orders) have no honest fixed-step mode: they refuse.
"""

import json
import math
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

METHODS = ("RK45", "DOP853", "Radau", "LSODA")
FIXED_STEP = ("RK45", "DOP853")

# Event functions of `rsts events` that are functions of the state (docs/events.md).
STATE_EVENTS = {name: k for k, name in enumerate(
    ["omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3"])}


def event_functions(asked):
    """solve_ivp event callables (with .direction) for the request's `events`, and their names."""
    def gamma(k):
        def g(t, y):
            al, be = y[3:6], y[6:9]
            return [al[1] * be[2] - al[2] * be[1], al[2] * be[0] - al[0] * be[2], al[0] * be[1] - al[1] * be[0]][k]
        return g
    funcs, names = [], []
    for e in asked:
        name, direction = e["name"], e.get("direction", "both")
        if name in STATE_EVENTS:
            k = STATE_EVENTS[name]
            f = (lambda k: lambda t, y: y[k])(k)
        elif name in ("gamma1", "gamma2", "gamma3"):
            f = gamma(int(name[-1]) - 1)
        else:
            print(f"scipy_adapter.py: event {name} is not a function of the state; skipped", file=sys.stderr)
            continue
        f.direction = {"up": 1.0, "down": -1.0}.get(direction, 0.0)
        funcs.append(f)
        names.append(name)
    return funcs, names


def main():
    method = sys.argv[1] if len(sys.argv) > 1 else "RK45"
    if method not in METHODS:
        sys.exit(f"scipy_adapter.py: unknown method {method!r} (known: {', '.join(METHODS)})")
    req = json.load(sys.stdin)
    a, b = float(req["a"]), float(req["b"])
    init = req["initial"]
    y0 = np.array([float(x) for x in init["omega"] + init["alpha"] + init["beta"]])
    times = np.array(req["times"], dtype=float)

    def rhs(t, y):  # Euler-Poisson equations, inertia diag(2, 2, 1), fields a (alpha) and b (beta)
        w1, w2, w3, a1, a2, a3, b1, b2, b3 = y
        return [0.5 * w2 * w3 + 0.5 * b * b3, -0.5 * w1 * w3 - 0.5 * a * a3, a * a2 - b * b1,
                a2 * w3 - a3 * w2, a3 * w1 - a1 * w3, a1 * w2 - a2 * w1,
                b2 * w3 - b3 * w2, b3 * w1 - b1 * w3, b1 * w2 - b2 * w1]

    funcs, names = event_functions(req.get("events", []))
    found = []
    step = req.get("step")
    if step is not None and method not in FIXED_STEP:
        sys.exit(f"scipy_adapter.py: {method} cannot take a fixed step (asked: step = {step}); "
                 f"use {' or '.join(FIXED_STEP)}")
    start = time.perf_counter()
    steps = None
    if len(times) == 1:  # no time passes
        ts, ys, nfev = times, y0[:, None], 0
    elif step is not None:
        ts, ys, nfev, steps = fixed_steps(rhs, times, y0, method, float(step))
    else:
        sol = solve_ivp(rhs, (times[0], times[-1]), y0, method=method, t_eval=times,
                        rtol=req["rtol"], atol=req["atol"], events=funcs or None)
        # Events located by solve_ivp's own root finder (brentq on its dense output).
        if funcs:
            found = sorted((float(t), n) for n, ts_n in zip(names, sol.t_events) for t in ts_n if t > times[0])
        if not sol.success:
            sys.exit(f"scipy_adapter.py: solve_ivp failed: {sol.message}")
        ts, ys, nfev = sol.t, sol.y, sol.nfev
    seconds = time.perf_counter() - start
    samples = [{"t": float(t), "omega": list(y[0:3]), "alpha": list(y[3:6]), "beta": list(y[6:9])}
               for t, y in zip(ts, ys.T)]
    # solve_ivp does not count steps when it samples at t_eval: only evaluations are reported.
    stats = {"rhs_evals": int(nfev), "integration_seconds": seconds}
    if steps is not None:
        stats["steps"] = int(steps)
    answer = {"name": f"scipy-{method}", "version": f"scipy {scipy.__version__}", "samples": samples, "stats": stats}
    # At a fixed step solve_ivp's events are not used: no "events" (rsts then locates them in
    # the samples).
    if "events" in req and step is None:
        answer["events"] = [{"name": n, "t": t} for t, n in found]
    json.dump(answer, sys.stdout)


def fixed_steps(rhs, times, y0, method, step):
    """Every interval in ceil(dt/step) equal steps, the step control off (see the module doc)."""
    ys, nfev, steps = [y0], 0, 0
    y = y0
    for t0, t1 in zip(times[:-1], times[1:]):
        n = max(1, math.ceil((t1 - t0) / step))
        h = (t1 - t0) / n
        sol = solve_ivp(rhs, (t0, t1), y, method=method, first_step=h, max_step=h,
                        rtol=1e-3, atol=1e300)
        if not sol.success:
            sys.exit(f"scipy_adapter.py: solve_ivp failed: {sol.message}")
        # n steps, one more when the rounding of t leaves a sliver before t1.
        if not n <= len(sol.t) - 1 <= n + 1:
            sys.exit(f"scipy_adapter.py: {len(sol.t) - 1} steps over [{t0}, {t1}], not {n}")
        y = sol.y[:, -1]
        ys.append(y)
        nfev += sol.nfev
        steps += len(sol.t) - 1
    return times, np.array(ys).T, nfev, steps


if __name__ == "__main__":
    main()
