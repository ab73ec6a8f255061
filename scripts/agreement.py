#!/usr/bin/env python3
"""Do `rsts explicit`, `reference`, `events` and `identify` mean the same motion?

usage: scripts/agreement.py [RSTS]   (default: rsts on the PATH)

Runs the four commands of one binary on decimal inputs (camera V: a = 1.3, b = 0.7, m = -0.52,
h = 2.07, torus 1, phases 0.3, 1.1; and a = 1.9, b = 0.45, m = 0.33, h = 1.21, phase1 = 0.9) and
prints, for each pair, the largest relative difference at 40 digits and the f64 values that
differ. A command that reads another's output reads 45 or 50 of its digits. Values of a state
within 1e-40 of zero (1e-30 in f64: the event's own component, which is zero there) count as
equal. Exit status 1 when a pair disagrees (beyond 1e-40 at 40 digits or in a bit of an f64).
The same comparisons are the tests of crates/flows/src/agreement.rs; docs/numbers.md.
"""

import json
import subprocess
import sys
from decimal import Decimal, getcontext

getcontext().prec = 200
RSTS = sys.argv[1] if len(sys.argv) > 1 else "rsts"
MOTIONS = [
    ["--a", "1.3", "--b", "0.7", "--m", "-0.52", "--h", "2.07", "--torus", "1",
     "--phase1", "0.3", "--phase2", "1.1"],
    ["--a", "1.9", "--b", "0.45", "--m", "0.33", "--h", "1.21", "--torus", "0",
     "--phase1", "0.9", "--phase2", "0"],
]
EVENTS = ["--event", "omega1", "--event", "gamma3", "--event", "alpha2", "--event", "s2",
          "--t-end", "8"]
worst = {}
failed = {}


class Failed(Exception):
    pass


def run(*args):
    p = subprocess.run([RSTS, *args, "--format", "json"], capture_output=True, text=True)
    if p.returncode != 0:
        raise Failed(f"rsts {args[0]} exit {p.returncode}: {p.stderr.strip()}")
    return json.loads(p.stdout)


def dec(x):
    return Decimal(x) if isinstance(x, str) else Decimal(repr(float(x)))


def note(pair, x, y):
    """The relative difference of two 40-digit values (0 when both are zero to 40 digits)."""
    x, y = dec(x), dec(y)
    scale = max(abs(x), abs(y))
    rel = Decimal(0) if scale < Decimal("1e-40") else abs(x - y) / scale
    worst[pair] = max(worst.get(pair, Decimal(0)), rel)


def note_f64(pair, x, y):
    x, y = float(x), float(y)
    same = x == y or (abs(x) < 1e-30 and abs(y) < 1e-30)
    worst.setdefault(pair + " (f64 values that differ)", 0)
    if not same:
        worst[pair + " (f64 values that differ)"] += 1


def state(sample):
    return sample["omega"] + sample["alpha"] + sample["beta"]


def event_state(e):
    return e["state"]["omega"] + e["state"]["alpha"] + e["state"]["beta"]


for motion in MOTIONS:
    grid = ["--t-end", "1.3", "--samples", "6"]
    e40 = run("explicit", *motion, *grid, "--digits", "40")["samples"]
    r40 = run("reference", *motion, *grid, "--digits", "40")["samples"]
    e64 = run("explicit", *motion, *grid)["samples"]
    r64 = run("reference", *motion, *grid)["samples"]
    for a, b, c, d in zip(e40, r40, e64, r64):
        for x, y in zip(state(a), state(b)):
            note("explicit-reference", x, y)
        for x, y in zip(state(c), state(d)):
            note_f64("explicit-reference", x, y)
        for x, y in zip(state(c), state(a)):
            note_f64("explicit f64 = explicit 40 digits rounded", x, float(Decimal(y)))

    ev40 = run("events", *motion, *EVENTS, "--digits", "40")["events"]
    ev50 = run("events", *motion, *EVENTS, "--digits", "50")["events"]
    ev64 = run("events", *motion, *EVENTS)["events"]
    for a, b, c in zip(ev40, ev50, ev64):
        t = b["t"]
        x40 = run("explicit", *motion, "--t-end", t, "--samples", "2", "--digits", "40")["samples"][1]
        x64 = run("explicit", *motion, "--t-end", t, "--samples", "2")["samples"][1]
        y40 = run("reference", *motion, "--times", t, "--digits", "40")["samples"][0]
        y64 = run("reference", *motion, "--times", t)["samples"][0]
        for x, y, u, v, w, z in zip(event_state(a), state(x40), event_state(c), state(x64),
                                    state(y40), state(y64)):
            note("explicit-events", x, y)
            note_f64("explicit-events", u, v)
            note("reference-events", x, w)
            note_f64("reference-events", u, z)
            note_f64("events f64 = events 40 digits rounded", u, float(Decimal(x)))

    def identified(pair, values, exact, at_start):
        fields = motion[0:4]
        vec = lambda v: ",".join(str(x) for x in v)
        args = [*fields, f"--omega={vec(values[0:3])}", f"--alpha={vec(values[3:6])}",
                f"--beta={vec(values[6:9])}", "--tolerance", "1e-30"]
        keys = ["m", "h"] + (["phase1", "phase2"] if at_start else [])
        for digits, f in [(["--digits", "40"], note), ([], note_f64)]:
            try:
                doc = run("identify", *args, *digits)
            except Failed as e:
                failed[pair + (" (f64 values that differ)" if digits == [] else "")] = str(e)
                continue
            for k in keys:
                f(pair, doc[k], exact[k] if digits else float(Decimal(exact[k])))

    exact = dict(zip(["m", "h", "phase1", "phase2"], [motion[5], motion[7], motion[11], motion[13]]))
    for k, s in enumerate(run("explicit", *motion, "--t-end", "2.5", "--samples", "3", "--digits", "45")["samples"]):
        identified("explicit-identify", state(s), exact, k == 0)
    for k, s in enumerate(run("reference", *motion, "--times", "0,0.7", "--digits", "45")["samples"]):
        identified("reference-identify", state(s), exact, k == 0)
    for e in run("events", *motion, *EVENTS, "--digits", "45")["events"][:3]:
        identified("events-identify", event_state(e), exact, False)

bad = False
for pair, why in failed.items():
    print(f"{pair:50s} failed: {why}")
    bad = True
for pair, w in worst.items():
    if "f64" in pair:
        ok = w == 0
        print(f"{pair:50s} {w}")
    else:
        ok = w <= Decimal("1e-40")
        print(f"{pair:50s} {float(w):.1e}")
    bad |= not ok
sys.exit(1 if bad else 0)
