"""Shared helpers of the rsts Python tests: the CLI built from the same crates, run on the same
input, is the reference every function is checked against."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]


def rsts_binary():
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return os.environ.get("RSTS_BIN", str(target / "release" / "rsts"))


@pytest.fixture(scope="session")
def cli():
    """Run `rsts ARGS`; returns (exit code, stdout, stderr)."""
    binary = rsts_binary()
    if not os.access(binary, os.X_OK):
        pytest.fail(f"the rsts binary is not built: {binary} (cargo build --release -p rsts-cli)")

    def run(*args, ok=(0,)):
        p = subprocess.run([binary, *map(str, args)], capture_output=True, text=True, timeout=300)
        assert p.returncode in ok, f"rsts {' '.join(map(str, args))}: exit {p.returncode}\n{p.stderr}"
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    def run(*args, ok=(0,)):
        _, out, _ = cli(*args, "--format", "json", ok=ok)
        return json.loads(out)

    return run


def cli_error(cli, *args):
    """The message of a CLI run refused with exit 2 (after `error: `)."""
    code, _, err = cli(*args, ok=(2,))
    line = err.strip().splitlines()[-1]
    assert line.startswith("error: "), err
    return line[len("error: "):]


def rhs(a, b):
    """The Euler-Poisson equations, inertia diag(2, 2, 1), as a user writes them for scipy."""

    def f(t, y):
        w1, w2, w3, a1, a2, a3, b1, b2, b3 = y
        return [0.5 * w2 * w3 + 0.5 * b * b3, -0.5 * w1 * w3 - 0.5 * a * a3, a * a2 - b * b1,
                a2 * w3 - a3 * w2, a3 * w1 - a1 * w3, a1 * w2 - a2 * w1,
                b2 * w3 - b3 * w2, b3 * w1 - b1 * w3, b1 * w2 - b2 * w1]

    return f


def save_trajectory(path, times, states):
    """The npy layout of `rsts check`: (N, 10), t then the state."""
    np.save(path, np.column_stack([times, states]))
