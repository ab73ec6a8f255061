#!/usr/bin/env python3
"""Speed against error, rsts against heyoka, in one run: the ratios of the four targets of
issue 12 on three motions of N (a = 1, b = 0.5; T = 100, 101 samples), printed as one table.

Run it through scripts/bench_vs_heyoka.sh (installs heyoka, builds rsts). Both sides are
measured by `rsts bench` against the same closed-form reference: ours as built-in methods,
heyoka as an external integrator (`--exec` with scripts/adapters/heyoka_adapter.py, whose
integration_seconds time heyoka's propagate_grid alone, its JIT compilation excluded). Targets:

  f64       max error <= 1e-13 in <= 0.4x heyoka f64's time; error floor <= 1/3 of heyoka's
  extended  taylor-dd reaches <= 1e-31 in <= 0.1x the time heyoka real128 needs for its best
  MPFR      90 digits, max error <= 1e-70 in <= 0.5x heyoka's time (same error)
  closed    one f64 state <= 0.35 us, flat in t; one 100-digit state <= 35 us (criterion)

For each target the tolerances are swept once on both sides (errors are deterministic), the
cheapest tolerance reaching the target error is picked on each side (heyoka real128: its best
error), and then ours and heyoka's runs at those tolerances alternate for --rounds rounds, so
load from other processes hits both; the ratio of each round is ours/heyoka, the median is
reported with the range. Every run's JSON rows are kept under --out.

    bench_vs_heyoka.py run --rsts target/release/rsts --python .venv-adapters/bin/python
    bench_vs_heyoka.py selftest     # the selection and summary logic on made-up rows
"""

import argparse
import json
import math
import os
import re
import shlex
import statistics
import subprocess
import sys
import time

# (name, m, h): the README's default case (camera I+) and two more example points of
# rsts_closed_form::EXAMPLE_POINTS_A1_B05: II+ (stable) and VI (m < 0, the slowest exponential
# growth of the m < 0 points, lambda ~ 0.08, docs/stability.md).
CASES = [("I+", "0.3", "-0.375"), ("II+", "0.05", "1.058"), ("VI", "-2.9877", "3.2858")]

F64_TOLS = [1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15]
EXT_TOLS_OURS = [1e-26, 1e-28, 1e-29, 1e-30, 1e-31, 1e-32]
EXT_TOLS_PEER = [1e-26, 1e-28, 1e-30, 1e-31, 1e-32, 1e-33]
MP_TOLS = [1e-66, 1e-68, 1e-70, 1e-72, 1e-74]
MP_DIGITS = 90

TARGETS = {
    "f64": {"error": 1e-13, "ratio": 0.4, "floor_ratio": 1 / 3},
    "extended": {"error": 1e-31, "ratio": 0.1},
    "mpfr": {"error": 1e-70, "ratio": 0.5},
    "closed-form": {"f64_us": 0.35, "mp_us": 35.0},
}


def clock_ghz():
    """The CPU clock from /proc/cpuinfo (the nominal one in a VM), in GHz; 2.445 if unknown."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("cpu MHz"):
                    return float(line.split(":")[1]) / 1e3
    except OSError:
        pass
    return 2.445


def taylor_order(tol):
    """The Jorba-Zou order of both sides (rsts Taylor::order_for): ceil(-ln(tol)/2) + 1."""
    return math.ceil(-math.log(tol) / 2) + 1


def multiply_adds_per_step(tol):
    """Multiply-adds of one Taylor step of order p: the 14 Cauchy products, 14 p(p+1)/2, and
    the 4 linear terms per order (docs/taylor.md)."""
    p = taylor_order(tol)
    return 14 * p * (p + 1) // 2 + 4 * p


def peak_fraction(kind, tol, us_per_step, ghz):
    """The fraction of the machine's peak a step reaches: f64 and double-double multiply-adds
    against 8 f64 FMAs per cycle (two 256-bit FMA units); MPFR limb products (L^2 per
    multiply-add, L = 5 limbs at 90 digits) against one 64x64-bit multiply per cycle."""
    per_second = 1e6 / us_per_step
    if kind == "mpfr":
        limbs = math.ceil(bits_for_digits(MP_DIGITS) / 64)
        return multiply_adds_per_step(tol) * limbs**2 * per_second / (ghz * 1e9)
    return multiply_adds_per_step(tol) * per_second / (8 * ghz * 1e9)


def bits_for_digits(digits):
    # rsts_dynamics::scalar::bits_for_digits
    return math.ceil(digits * math.log2(10)) + 8


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def loadavg():
    try:
        return " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "?"


class Runner:
    """Runs `rsts bench` for one case: our methods, or heyoka through its adapter (--exec)."""

    def __init__(self, rsts, python, case, out):
        self.rsts, self.python, self.case, self.out = rsts, python, case, out
        name, m, h = case
        self.tag = re.sub(r"[^A-Za-z0-9]+", "_", name)
        self.args = ["--m", m, "--h", h]
        self.count = 0

    def _bench(self, label, what, tols, repeats, digits):
        self.count += 1
        path = os.path.join(self.out, f"{label}-{self.tag}-{self.count}.json")
        cmd = [self.rsts, "bench", *self.args, *what,
               "--tolerances", ",".join(f"{t:g}" for t in tols), "--repeats", str(repeats),
               "--format", "json"]
        if digits:
            cmd += ["--digits", str(digits)]
        log("  $ " + shlex.join(cmd) + f" > {path}")
        with open(path, "w") as f:
            subprocess.run(cmd, check=True, stdout=f)
        with open(path) as f:
            return json.load(f)["rows"]

    def ours(self, method, tols, repeats, digits=None):
        return self._bench(method, ["--methods", method], tols, repeats, digits)

    def peer(self, method, tols, repeats, digits=None):
        adapter = f"{self.python} scripts/adapters/heyoka_adapter.py {method}"
        return self._bench(f"heyoka-{method}", ["--exec", adapter], tols, repeats, digits)


def cheapest_reaching(rows, error):
    """The row of the loosest tolerance whose max error is at most `error` (the cheapest run
    reaching it: time grows as the tolerance tightens), or None."""
    ok = [r for r in rows if r["max_error"] <= error]
    return max(ok, key=lambda r: r["tolerance"]) if ok else None


def best(rows):
    """The row with the smallest max error (ties: the looser tolerance)."""
    return min(rows, key=lambda r: (r["max_error"], -r["tolerance"]))


def ratios(pairs):
    """Per-round ratios ours/peer from [(ours_seconds, peer_seconds)]: their median and range,
    and the ratio of the fastest runs of each side ("best": the least disturbed by load)."""
    rs = [o / p for o, p in pairs]
    return {"median": statistics.median(rs), "min": min(rs), "max": max(rs), "rounds": rs,
            "best": min(o for o, _ in pairs) / min(p for _, p in pairs)}


def alternate(runner, ours_args, peer_args, rounds):
    """Alternate ours and the peer's runs `rounds` times: [(ours_s, peer_s)], and the rows of
    the first round (errors, steps)."""
    pairs, first = [], None
    for k in range(rounds):
        o = runner.ours(*ours_args)[0]
        p = runner.peer(*peer_args)[0]
        if first is None:
            first = (o, p)
        pairs.append((o["integration_seconds"], p["integration_seconds"]))
        log(f"    round {k + 1}: ours {o['integration_seconds']:.4g} s, heyoka "
            f"{p['integration_seconds']:.4g} s, ratio {pairs[-1][0] / pairs[-1][1]:.3f}")
    return pairs, first


def timed(runner, ours_args, peer_args, rounds):
    """The alternated rounds at the chosen tolerances: tolerances, errors, steps, us per step
    (median time / steps) on each side and the ratios."""
    pairs, (ro, rp) = alternate(runner, ours_args, peer_args, rounds)
    return dict(ours_tol=ro["tolerance"], peer_tol=rp["tolerance"], ours_error=ro["max_error"],
                peer_error=rp["max_error"], steps=(ro["steps"], rp["steps"]),
                ours_us_per_step=1e6 * statistics.median(x for x, _ in pairs) / ro["steps"],
                peer_us_per_step=1e6 * statistics.median(y for _, y in pairs) / rp["steps"],
                ratio=ratios(pairs))


def measure_case(runner, rounds, quick):
    result = {"case": runner.case[0], "m": runner.case[1], "h": runner.case[2]}

    # f64: sweep, then the cheapest tolerance reaching 1e-13 on each side, alternated.
    log(f"[{runner.case[0]}] f64 sweep")
    ours = runner.ours("taylor-f64", F64_TOLS, 5)
    peer = runner.peer("f64", F64_TOLS, 5)
    goal = TARGETS["f64"]["error"]
    o, p = cheapest_reaching(ours, goal), cheapest_reaching(peer, goal)
    f64 = {"ours_floor": best(ours)["max_error"], "peer_floor": best(peer)["max_error"],
           "ours_rows": ours, "peer_rows": peer}
    f64["floor_ratio"] = f64["ours_floor"] / f64["peer_floor"]
    if o and p:
        f64.update(timed(runner, ("taylor-f64", [o["tolerance"]], 31),
                         ("f64", [p["tolerance"]], 31), rounds))
    result["f64"] = f64

    # Extended: taylor-dd reaching 1e-31 against heyoka real128 at its best error.
    log(f"[{runner.case[0]}] extended sweep")
    ours = runner.ours("taylor-dd", EXT_TOLS_OURS, 1)
    peer = runner.peer("real128", EXT_TOLS_PEER, 1)
    goal = TARGETS["extended"]["error"]
    o = cheapest_reaching(ours, goal)
    ext = {"ours_floor": best(ours)["max_error"], "peer_floor": best(peer)["max_error"],
           "ours_rows": ours, "peer_rows": peer, "reached": o is not None}
    # Not reached: compare our best error's run instead (and say so).
    o = o or best(ours)
    p = best(peer)
    ext.update(timed(runner, ("taylor-dd", [o["tolerance"]], 5),
                     ("real128", [p["tolerance"]], 5), rounds))
    result["extended"] = ext

    # MPFR at 90 digits: the cheapest tolerance reaching 1e-70 on each side.
    log(f"[{runner.case[0]}] MPFR sweep ({MP_DIGITS} digits)")
    tols = MP_TOLS[1:4] if quick else MP_TOLS
    ours = runner.ours("taylor-mp", tols, 1, MP_DIGITS)
    peer = runner.peer("mpfr", tols, 1, MP_DIGITS)
    goal = TARGETS["mpfr"]["error"]
    o, p = cheapest_reaching(ours, goal), cheapest_reaching(peer, goal)
    mp = {"ours_floor": best(ours)["max_error"], "peer_floor": best(peer)["max_error"],
          "ours_rows": ours, "peer_rows": peer}
    if o and p:
        mp.update(timed(runner, ("taylor-mp", [o["tolerance"]], 3, MP_DIGITS),
                        ("mpfr", [p["tolerance"]], 3, MP_DIGITS), rounds))
    result["mpfr"] = mp
    return result


def closed_form(cargo_args):
    """Per-state times of the closed form from its criterion bench (f64 and 100 digits at
    t = 1, 1e3, 1e6, 1.5e9), in microseconds."""
    cmd = ["cargo", "bench", *cargo_args, "-p", "rsts-closed-form", "--bench", "explicit", "--",
           "--output-format", "bencher", "state/(f64|100-digits)/"]
    log("  $ " + shlex.join(cmd))
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return parse_bencher(text)


def parse_bencher(text):
    """{'f64': {'t=1e0': us, ...}, '100-digits': {...}} from criterion's bencher lines."""
    out = {}
    for line in text.splitlines():
        m = re.match(r"test state/([^/]+)/(\S+)\s+\.\.\. bench:\s+([\d,]+) ns/iter", line)
        if m:
            out.setdefault(m.group(1), {})[m.group(2)] = int(m.group(3).replace(",", "")) / 1e3
    return out


def verdict(ok):
    return "met" if ok else "MISSED"


def fmt_ratio(r):
    return f"{r['median']:.3f} ({r['min']:.3f}-{r['max']:.3f}; fastest runs {r['best']:.3f})"


def summary(results, cf, load):
    """The table printed at the end (markdown)."""
    ghz = clock_ghz()
    lines = [f"load average (1, 5, 15 min) before/after: {load[0]} / {load[1]}; clock "
             f"{ghz:.3f} GHz (peaks: 8 f64 FMAs or one 64-bit multiply per cycle)", ""]

    def step(res, side, kind):
        us = res[f"{side}_us_per_step"]
        frac = peak_fraction(kind, res[f"{side}_tol"], us, ghz)
        return f"{us:.3g} us/step, {100 * frac:.2g} % of peak"

    lines.append("| case | target | ours | heyoka | ratio ours/heyoka: median (range; fastest "
                 "runs) | goal | |")
    lines.append("|---|---|---|---|---|---|---|")
    for r in results:
        c = r["case"]
        f = r["f64"]
        if "ratio" in f:
            ok = f["ratio"]["median"] <= TARGETS["f64"]["ratio"]
            lines.append(
                f"| {c} | f64 error <= 1e-13 | {f['ours_error']:.2e} at tol {f['ours_tol']:g}, "
                f"{step(f, 'ours', 'f64')} | {f['peer_error']:.2e} at tol {f['peer_tol']:g}, "
                f"{step(f, 'peer', 'f64')} | {fmt_ratio(f['ratio'])} | <= 0.4 | {verdict(ok)} |")
        else:
            lines.append(f"| {c} | f64 error <= 1e-13 | floor {f['ours_floor']:.2e} | floor "
                         f"{f['peer_floor']:.2e} | not reached | <= 0.4 | MISSED |")
        ok = f["floor_ratio"] <= TARGETS["f64"]["floor_ratio"]
        lines.append(f"| {c} | f64 error floor | {f['ours_floor']:.2e} | {f['peer_floor']:.2e} | "
                     f"{f['floor_ratio']:.3f} | <= 0.333 | {verdict(ok)} |")
        e = r["extended"]
        ok = e["reached"] and e["ratio"]["median"] <= TARGETS["extended"]["ratio"]
        what = "reaches <= 1e-31" if e["reached"] else "best error (1e-31 not reached)"
        lines.append(
            f"| {c} | extended: {what} vs real128 best | {e['ours_error']:.2e} at tol "
            f"{e['ours_tol']:g}, {step(e, 'ours', 'dd')} | {e['peer_error']:.2e} at "
            f"tol {e['peer_tol']:g}, {step(e, 'peer', 'dd')} | "
            f"{fmt_ratio(e['ratio'])} | <= 0.1 | {verdict(ok)} |")
        m = r["mpfr"]
        if "ratio" in m:
            ok = m["ratio"]["median"] <= TARGETS["mpfr"]["ratio"]
            lines.append(
                f"| {c} | MPFR {MP_DIGITS} digits, error <= 1e-70 | {m['ours_error']:.2e} at tol "
                f"{m['ours_tol']:g}, {step(m, 'ours', 'mpfr')} | {m['peer_error']:.2e}"
                f" at tol {m['peer_tol']:g}, {step(m, 'peer', 'mpfr')} | "
                f"{fmt_ratio(m['ratio'])} | <= 0.5 | {verdict(ok)} |")
        else:
            lines.append(f"| {c} | MPFR {MP_DIGITS} digits, error <= 1e-70 | floor "
                         f"{m['ours_floor']:.2e} | floor {m['peer_floor']:.2e} | not reached | "
                         f"<= 0.5 | MISSED |")
    if cf:
        for label, goal_key, goal in [("f64", "f64_us", "<= 0.35 us"),
                                      ("100-digits", "mp_us", "<= 35 us")]:
            times = cf.get(label, {})
            if not times:
                continue
            worst = max(times.values())
            flat = times.get("t=1.5e9", worst) / times.get("t=1e0", worst)
            ok = worst <= TARGETS["closed-form"][goal_key]
            cells = ", ".join(f"{k}: {v:.3g} us" for k, v in times.items())
            lines.append(f"| closed form | one {label} state (ExplicitMotion::at) | {cells} | "
                         f"(no peer) | t=1.5e9 / t=1: {flat:.2f} | {goal} | {verdict(ok)} |")
    return "\n".join(lines)


def cmd_run(args):
    os.makedirs(args.out, exist_ok=True)
    load = [loadavg()]
    log(f"load average: {load[0]} (2 shared cores: ratios come from alternated runs)")
    start = time.time()
    names = args.cases.split(",") if args.cases else [c[0] for c in CASES]
    unknown = set(names) - {c[0] for c in CASES}
    if unknown:
        sys.exit(f"unknown case(s) {sorted(unknown)}; known: {[c[0] for c in CASES]}")
    results = []
    for case in CASES:
        if case[0] in names:
            results.append(measure_case(Runner(args.rsts, args.python, case, args.out),
                                        args.rounds, args.quick))
    cf = None if args.skip_closed_form else closed_form(args.cargo_arg or [])
    load.append(loadavg())
    table = summary(results, cf, load)
    doc = {"results": results, "closed_form_us": cf, "load": load,
           "wall_seconds": time.time() - start, "rounds": args.rounds}
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(doc, f, indent=1)
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(table + "\n")
    print(table)
    log(f"wall time {time.time() - start:.0f} s; rows and summary in {args.out}")


def sweep_tables(doc):
    """Markdown tables of the sweeps in a results.json: per case and precision, each
    tolerance's max error and time on both sides (the first, unrepeated sweep: errors and
    steps are exact, the times are single runs)."""
    out = []
    labels = {"f64": ("taylor-f64", "heyoka f64"), "extended": ("taylor-dd", "heyoka real128"),
              "mpfr": (f"taylor-mp {MP_DIGITS} digits", f"heyoka MPFR {MP_DIGITS} digits")}
    for r in doc["results"]:
        for key, (ours_name, peer_name) in labels.items():
            res = r[key]
            ours = {x["tolerance"]: x for x in res["ours_rows"]}
            peer = {x["tolerance"]: x for x in res["peer_rows"]}
            out.append(f"{r['case']} (m = {r['m']}, h = {r['h']}), {key}:\n")
            out.append(f"| tolerance | {ours_name} | {peer_name} | steps (ours / heyoka) |")
            out.append("|---|---|---|---|")
            for tol in sorted(set(ours) | set(peer), reverse=True):
                cell = lambda x: (f"{x['max_error']:.2e} in {x['integration_seconds'] * 1e3:.3g} ms"
                                  if x else "—")
                o, p = ours.get(tol), peer.get(tol)
                steps = f"{o['steps'] if o else '—'} / {p['steps'] if p else '—'}"
                out.append(f"| {tol:g} | {cell(o)} | {cell(p)} | {steps} |")
            out.append("")
    return "\n".join(out)


def cmd_tables(args):
    with open(args.results) as f:
        print(sweep_tables(json.load(f)))


def cmd_selftest(_args):
    rows = [{"tolerance": t, "max_error": e, "integration_seconds": s, "steps": 1}
            for t, e, s in [(1e-10, 3e-11, 1.0), (1e-12, 4e-13, 2.0), (1e-13, 9e-14, 3.0),
                            (1e-14, 8e-14, 4.0)]]
    assert cheapest_reaching(rows, 1e-13)["tolerance"] == 1e-13
    assert cheapest_reaching(rows, 1e-15) is None
    assert best(rows)["tolerance"] == 1e-14
    r = ratios([(1.0, 4.0), (3.0, 4.0), (1.0, 2.0)])
    assert (r["median"], r["min"], r["max"], r["best"]) == (0.5, 0.25, 0.75, 0.5), r
    text = ("test state/f64/t=1e0 ... bench:         212 ns/iter (+/- 3)\n"
            "test state/100-digits/t=1.5e9 ... bench:      31,012 ns/iter (+/- 90)\n")
    assert parse_bencher(text) == {"f64": {"t=1e0": 0.212}, "100-digits": {"t=1.5e9": 31.012}}
    assert taylor_order(1e-13) == 16 and taylor_order(1e-70) == 82
    assert multiply_adds_per_step(1e-13) == 14 * 16 * 17 // 2 + 64
    # 1904 + 64 multiply-adds in 1 us at 1 GHz with 8 FMAs per cycle: 24.6 % of peak.
    assert abs(peak_fraction("f64", 1e-13, 1.0, 1.0) - 1968 / 8000) < 1e-12
    assert abs(peak_fraction("mpfr", 1e-70, 1.0, 1.0) - (14 * 82 * 83 // 2 + 328) * 25 / 1000) < 1e-9
    class Fake:  # a runner whose runs take 2 s (ours) and 4 s (heyoka) for 100 steps
        def ours(self, method, tols, repeats, digits=None):
            return [{"tolerance": tols[0], "max_error": 1e-14, "integration_seconds": 2e-4,
                     "steps": 100}]

        def peer(self, method, tols, repeats, digits=None):
            return [{"tolerance": tols[0], "max_error": 3e-14, "integration_seconds": 4e-4,
                     "steps": 100}]
    t = timed(Fake(), ("taylor-f64", [1e-13], 1), ("f64", [1e-12], 1), 2)
    assert (t["ours_tol"], t["peer_tol"], t["steps"]) == (1e-13, 1e-12, (100, 100)), t
    assert abs(t["ours_us_per_step"] - 2.0) < 1e-12 and abs(t["peer_us_per_step"] - 4.0) < 1e-12
    assert t["ratio"]["median"] == 0.5 and len(t["ratio"]["rounds"]) == 2, t
    print("selftest ok")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="measure and print the ratios")
    r.add_argument("--rsts", default="target/release/rsts")
    r.add_argument("--python", default=".venv-adapters/bin/python")
    r.add_argument("--rounds", type=int, default=3, help="alternated rounds per target")
    r.add_argument("--cases", help="comma-separated subset of " + ",".join(c[0] for c in CASES))
    r.add_argument("--quick", action="store_true", help="fewer MPFR tolerances")
    r.add_argument("--skip-closed-form", action="store_true")
    r.add_argument("--cargo-arg", action="append", help="extra argument for cargo bench")
    r.add_argument("--out", default="out/bench-vs-heyoka")
    t = sub.add_parser("tables", help="markdown tables of the sweeps of a results.json")
    t.add_argument("results")
    sub.add_parser("selftest", help="check the selection and summary logic")
    args = p.parse_args()
    if args.cmd == "run" and args.rounds < 1:
        sys.exit("--rounds must be at least 1")
    {"run": cmd_run, "tables": cmd_tables, "selftest": cmd_selftest}[args.cmd](args)


if __name__ == "__main__":
    main()
