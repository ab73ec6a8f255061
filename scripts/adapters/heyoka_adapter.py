#!/usr/bin/env python3
"""heyoka (Taylor method, C++/LLVM) as an external integrator of rsts, protocol rsts-integrator/1.

    rsts compare --exec ".venv-adapters/bin/python scripts/adapters/heyoka_adapter.py f64"
    rsts bench --methods taylor-mp --exec ".venv-adapters/bin/python scripts/adapters/heyoka_adapter.py mpfr" \
        --digits 90 --tolerances 1e-20,1e-40

Argument: the scalar, `f64` (default), `f64-ha` (f64 with high_accuracy: compensated summation
of the state), `real128` (quadruple precision) or `mpfr` (at the request's `digits`). Install
heyoka with scripts/install_adapters.sh heyoka.

A fixed step (`"step"` in the request, `rsts convergence`): every interval between two requested
times is cut into ceil(dt/h) equal steps, each taken by `ta.step(max_delta_t)`; a step that
heyoka shortens below max_delta_t (its own step-size rule asks for less: h is beyond the radius
of convergence at this tolerance) is an error, never a silent change of step. The order is
heyoka's for the tolerance: ceil(-ln(tol)/2) + 1, order 13 at tol 1e-10.

Dense output (`"dense": K` in the request, `rsts compare --dense K`): the run is taken step by
step with `ta.step(max_delta_t, write_tc=True)` (the last step cut at the end time, as
`propagate_grid` does), and the requested times, the K interior times of each step and, in
real128 and MPFR, its end (at the step end's binary64 time) are evaluated by heyoka's continuous
output `ta.update_d_output(t)`: the step's Taylor polynomial, of the method's full order. The
answer carries `stats.step_times` (heyoka's steps' ends) and the dense samples.

The integrator is compiled once (not timed) and `propagate_grid` through the requested times is
timed alone: that is the `integration_seconds` of the answer. rhs_evals counts one evaluation
per Taylor order per step (heyoka's convention; rsts' Taylor methods count one more per step).
"""

import json
import math
import sys
import time

import numpy as np
import heyoka as hy

METHODS = ("f64", "f64-ha", "real128", "mpfr")


def bits_for_digits(digits):
    # The rule of rsts (rsts_dynamics::scalar::bits_for_digits): ceil(digits * log2(10)) + 8.
    return math.ceil(digits * math.log2(10)) + 8


def equations():
    """The Euler-Poisson equations as in crates/dynamics/src/equations.rs (a, b: parameters)."""
    w1, w2, w3, a1, a2, a3, b1, b2, b3 = hy.make_vars("w1", "w2", "w3", "a1", "a2", "a3", "b1", "b2", "b3")
    a, b = hy.par[0], hy.par[1]
    return [
        (w1, 0.5 * w2 * w3 + 0.5 * b * b3),
        (w2, -0.5 * w1 * w3 - 0.5 * a * a3),
        (w3, a * a2 - b * b1),
        (a1, a2 * w3 - a3 * w2),
        (a2, a3 * w1 - a1 * w3),
        (a3, a1 * w2 - a2 * w1),
        (b1, b2 * w3 - b3 * w2),
        (b2, b3 * w1 - b1 * w3),
        (b3, b1 * w2 - b2 * w1),
    ]


def event_expressions():
    """The event functions of `rsts events` that are expressions of the state: the components of
    omega, alpha, beta and of gamma = alpha x beta (s1, s2 turning points are not)."""
    w1, w2, w3, a1, a2, a3, b1, b2, b3 = hy.make_vars("w1", "w2", "w3", "a1", "a2", "a3", "b1", "b2", "b3")
    names = {"omega1": w1, "omega2": w2, "omega3": w3, "alpha1": a1, "alpha2": a2, "alpha3": a3,
             "beta1": b1, "beta2": b2, "beta3": b3}
    names.update({"gamma1": a2 * b3 - a3 * b2, "gamma2": a3 * b1 - a1 * b3, "gamma3": a1 * b2 - a2 * b1})
    return names


def event_list(asked, dtype, found):
    """heyoka non-terminal events for the request's `events`; each detection appends (name, t)
    to `found`. Names heyoka cannot express are skipped with a note on stderr."""
    exprs = event_expressions()
    directions = {"up": hy.event_direction.positive, "down": hy.event_direction.negative,
                  "both": hy.event_direction.any}
    events = []
    for e in asked:
        name, direction = e["name"], e.get("direction", "both")
        if name not in exprs:
            print(f"heyoka_adapter.py: event {name} is not an expression of the state; skipped", file=sys.stderr)
            continue
        def callback(ta, t, d_sgn, name=name):
            found.append((name, t))
        events.append(hy.nt_event(exprs[name], callback, direction=directions[direction], fp_type=dtype))
    return events


def main():
    method = sys.argv[1] if len(sys.argv) > 1 else "f64"
    if method not in METHODS:
        sys.exit(f"heyoka_adapter.py: unknown scalar {method!r} (known: {', '.join(METHODS)})")
    req = json.load(sys.stdin)
    if req.get("protocol") != "rsts-integrator/1":
        sys.exit(f"heyoka_adapter.py: unsupported protocol {req.get('protocol')!r}")
    bits = bits_for_digits(int(req["digits"]))
    if method in ("f64", "f64-ha"):
        dtype, num = np.float64, float
    elif method == "real128":
        dtype, num = hy.real128, hy.real128
    else:
        dtype, num = hy.real, lambda s: hy.real(s, bits)
    init = req["initial"]
    state = np.array([num(x) for x in init["omega"] + init["alpha"] + init["beta"]], dtype=dtype)
    pars = np.array([num(req["a"]), num(req["b"])], dtype=dtype)
    # Times are binary64 values: convert them exactly (not through their decimal text).
    exact = (lambda t: hy.real(float(t), bits)) if method == "mpfr" else (lambda t: num(float(t)))
    times = np.array([exact(t) for t in req["times"]], dtype=dtype)
    tol = min(req["rtol"], req["atol"])
    opts = dict(pars=pars, fp_type=dtype, tol=tol if dtype is np.float64 else num(repr(tol)))
    if method == "mpfr":
        opts["prec"] = bits
    if method == "f64-ha":
        opts["high_accuracy"] = True
    found = []
    events = event_list(req.get("events", []), dtype, found)
    if events:
        opts["nt_events"] = events
    ta = hy.taylor_adaptive(equations(), state, **opts)
    start = time.perf_counter()
    dense = req.get("dense")
    if dense and req.get("step") is not None:
        sys.exit("heyoka_adapter.py: dense output is not available with a fixed step")
    if dense:
        steps, states, step_times, dense_samples = dense_steps(ta, times, int(dense), exact, dtype)
    elif req.get("step") is not None:
        steps, states = fixed_steps(ta, times, float(req["step"]), num)
    else:
        outcome, _, _, steps, _, states = ta.propagate_grid(times)
        if outcome != hy.taylor_outcome.time_limit:
            sys.exit(f"heyoka_adapter.py: heyoka stopped with {outcome}")
    seconds = time.perf_counter() - start
    # Numbers keep all their digits: f64 as JSON numbers, real128 and MPFR as decimal strings.
    out = (lambda x: float(x)) if dtype is np.float64 else str
    samples = [
        {"t": float(t), "omega": [out(x) for x in s[0:3]], "alpha": [out(x) for x in s[3:6]], "beta": [out(x) for x in s[6:9]]}
        for t, s in zip(req["times"], states)
    ]
    # Events located by heyoka's own machinery (nt_event), in time order, in (0, t_end].
    t_end = float(req["times"][-1]) if req["times"] else 0.0
    answer_events = [
        {"name": n, "t": out(t)} for n, t in sorted(found, key=lambda e: e[1]) if 0 < float(t) <= t_end
    ]
    name = f"heyoka-{method}" + (f"-{req['digits']}d" if method == "mpfr" else "")
    extra = {"events": answer_events} if "events" in req else {}
    stats = {"steps": int(steps), "rhs_evals": int(steps) * int(ta.order), "integration_seconds": seconds}
    if dense:
        stats["step_times"] = step_times
        extra["dense"] = [sample(t, y, out) for t, y in dense_samples]
    json.dump(
        {"name": name, "version": f"heyoka {hy.__version__}", "samples": samples, **extra, "stats": stats},
        sys.stdout,
    )


def sample(t, y, out):
    return {"t": t, "omega": [out(x) for x in y[0:3]], "alpha": [out(x) for x in y[3:6]],
            "beta": [out(x) for x in y[6:9]]}


def dense_steps(ta, times, k, exact, dtype):
    """The run step by step with heyoka's continuous output (see the module doc): the states at
    `times`, heyoka's step ends (binary64) and, per step, K interior samples and its end."""
    if times[0] != ta.time:
        sys.exit("heyoka_adapter.py: a dense run starts at the first requested time")
    states, step_times, dense = [np.array(ta.state)], [float(ta.time)], []
    t_end, nxt, steps = times[-1], 1, 0
    while nxt < len(times):
        t0 = step_times[-1]
        outcome, _ = ta.step(t_end - ta.time, write_tc=True)
        if outcome not in (hy.taylor_outcome.success, hy.taylor_outcome.time_limit):
            sys.exit(f"heyoka_adapter.py: heyoka stopped with {outcome} at t = {float(ta.time)}")
        steps += 1
        t1 = float(ta.time)
        while nxt < len(times) and times[nxt] <= ta.time:
            states.append(np.array(ta.update_d_output(times[nxt])))
            nxt += 1
        for j in range(1, k + 1):
            t = t0 + (t1 - t0) * j / (k + 1)
            dense.append((t, np.array(ta.update_d_output(exact(t)))))
        end = np.array(ta.state) if dtype is np.float64 else np.array(ta.update_d_output(exact(t1)))
        dense.append((t1, end))
        step_times.append(t1)
    return steps, states, step_times, dense


def fixed_steps(ta, times, step, num):
    """Steps of exactly dt/ceil(dt/step) through `times` (see the module doc)."""
    states, steps = [np.array(ta.state)], 0
    for t0, t1 in zip(times[:-1], times[1:]):
        n = max(1, math.ceil(float(t1 - t0) / step))
        h = (t1 - t0) / n
        for k in range(n):
            # The last step ends exactly at t1.
            dt = h if k < n - 1 else t1 - ta.time
            outcome, taken = ta.step(dt)
            if outcome != hy.taylor_outcome.time_limit:
                sys.exit(f"heyoka_adapter.py: heyoka took a step of {float(taken)} < {float(dt)} at "
                         f"t = {float(ta.time)}: the fixed step is too large for its order")
            steps += 1
        states.append(np.array(ta.state))
    return steps, states


if __name__ == "__main__":
    main()
