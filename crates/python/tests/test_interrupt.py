"""Long Rust work releases the GIL, and Ctrl-C (SIGINT) stops it with KeyboardInterrupt: in the
reference, in a built-in comparison, and inside a Python integrator."""

import os
import subprocess
import sys
import signal
import threading
import time

import numpy as np
import pytest

import rsts


def ctrl_c_after(seconds):
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("work", [
    # about 30 s of closed form, 1 min of integration and analysis on an idle machine
    lambda: rsts.Case.default().reference(np.linspace(0.0, 1e4, 1_000_000)),
    lambda: rsts.compare("dop853", t_end=1e5, samples=1_000_001, rtol=1e-12, atol=1e-12),
    lambda: rsts.compare(lambda *args: time.sleep(60), t_end=1.0, samples=3),
    # about a minute of runs, each well under a second: stopped between them
    lambda: rsts.bench(["dop853"], tolerances=list(np.geomspace(1e-8, 1e-13, 100)), t_end=1e4),
    lambda: rsts.bench(["dop853", lambda *args: time.sleep(60)], t_end=1.0, samples=3),
], ids=["reference", "compare", "callable", "bench", "bench-callable"])
def test_ctrl_c_raises_keyboardinterrupt(work):
    # A shell starts background jobs with SIGINT ignored, and Python then installs no handler:
    # give this test Python's own, as an interactive session has.
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = ctrl_c_after(0.5)
    start = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            work()
    finally:
        timer.cancel()
    assert time.monotonic() - start < 10


def test_the_gil_is_released_during_the_reference():
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    time.sleep(0.05)
    try:
        start = time.monotonic()
        rsts.Case.default().reference(np.linspace(0.0, 100.0, 500_000))
        end = time.monotonic()
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if start < t < end]
    # With the GIL held for the whole call the other thread could not run at all.
    assert len(during) >= 50, (len(during), end - start)


# Long pure-Rust calls at high precision (issue 35, defect 7), each in its own interpreter: it
# prints "started" just before the call, gets SIGINT 1 s later and must end with
# KeyboardInterrupt within 2 s of it; killed after 30 s whatever happens.
LONG_CALLS = {
    # about 70 s: 1100 events of s2 at 10000 digits, some 60 ms each
    "events": "rsts.events(['s2'], t_end=4000.0, digits=10000)",
    # about 100 s: 10^4 samples checked at 3000 digits
    "check": "t = np.linspace(0.0, 100.0, 10_000); x = rsts.Case.default().reference(t); "
             "print('started', flush=True); rsts.check(t, x, case=rsts.Case.default(), digits=3000)",
    # more than 8 s: 2000 runs of rk4 at fixed steps, each well under a second
    "convergence": "rsts.convergence(['rk4'], list(np.geomspace(2e-2, 1e-3, 2000)), t_end=1000.0)",
}


@pytest.mark.parametrize("name", sorted(LONG_CALLS))
def test_ctrl_c_stops_a_long_call_within_a_second(name):
    call = LONG_CALLS[name]
    script = "\n".join([
        "import signal, sys, numpy as np, rsts",
        "signal.signal(signal.SIGINT, signal.default_int_handler)",
        "try:",
        f"    {call}" if "started" in call else f"    print('started', flush=True); {call}",
        "except KeyboardInterrupt:",
        "    sys.exit(3)",
        "sys.exit(0)",
    ])
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        line = child.stdout.readline()
        assert line.strip() == "started", line
        time.sleep(1.0)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        try:
            code = child.wait(timeout=30)
        except subprocess.TimeoutExpired:
            code = None
        waited = time.monotonic() - sent
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert code == 3, f"{name}: exit {code} after {waited:.1f} s (3: KeyboardInterrupt)"
    assert waited < 2.0, f"{name}: {waited:.1f} s from SIGINT to KeyboardInterrupt"
