#!/usr/bin/env python3
"""scipy.integrate.solve_ivp as an external integrator of rsts, protocol rsts-integrator/1.

    rsts compare --exec ".venv-adapters/bin/python scripts/adapters/scipy_adapter.py DOP853" --rtol 1e-10 --atol 1e-10

Argument: the method of solve_ivp, RK45 (default), DOP853, Radau or LSODA. Install scipy with
scripts/install_adapters.sh scipy.
"""

import json
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

METHODS = ("RK45", "DOP853", "Radau", "LSODA")

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
    start = time.perf_counter()
    if len(times) == 1:  # no time passes
        ts, ys, nfev = times, y0[:, None], 0
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
    answer = {"name": f"scipy-{method}", "samples": samples,
              "stats": {"rhs_evals": int(nfev), "integration_seconds": seconds}}
    if "events" in req:
        answer["events"] = [{"name": n, "t": t} for t, n in found]
    json.dump(answer, sys.stdout)


if __name__ == "__main__":
    main()
