"""rsts.bench against the CLI (rsts bench --format json): the built-in rows equal in every field
that is not a time, a Python integrator measured beside them, a raising or wrong callable, and
bad input raising ValueError with the CLI's message."""

import numpy as np
import pytest

import rsts
from conftest import cli_error, rhs

TIMES = ("integration_seconds", "time_min", "time_median", "time_max", "wall_seconds")
SMALL = dict(t_end=10.0, samples=11, repeats=1)
CLI_SMALL = ("--t-end", 10, "--samples", 11, "--repeats", 1)


def untimed(row):
    return {k: v for k, v in row.items() if k not in TIMES}


def scipy_dop853():
    integrate = pytest.importorskip(
        "scipy.integrate", reason="scipy is not installed (scripts/install_python.sh installs it)")

    def solve(x0, times, a, b, rtol, atol):
        sol = integrate.solve_ivp(rhs(a, b), (times[0], times[-1]), x0, method="DOP853",
                                  t_eval=times, rtol=rtol, atol=atol)
        assert sol.success, sol.message
        return sol.y.T

    return solve


def test_builtin_rows_are_the_cli_rows(cli_json):
    expected = cli_json("bench", "--methods", "dop853,taylor-dd", "--tolerances", "1e-6,1e-8,1e-10",
                        *CLI_SMALL)
    got = rsts.bench(["dop853", "taylor-dd"], tolerances=(1e-6, 1e-8, 1e-10), **SMALL)
    assert list(got) == list(expected)
    assert got["case"] == expected["case"] and got["repeats"] == 1
    assert [untimed(r) for r in got["rows"]] == [untimed(r) for r in expected["rows"]]
    assert got["fits"] == expected["fits"]
    assert list(got["environment"]) == list(expected["environment"])
    assert [r["method"] for r in got["rows"]] == ["dop853"] * 3 + ["taylor-dd"] * 3
    errors = [r["max_error"] for r in got["rows"][:3]]
    assert errors[0] > errors[1] > errors[2] > 0, errors
    assert all(r["integration_seconds"] > 0 for r in got["rows"])
    # Another case gives other rows (the comparison can fail).
    other = rsts.bench("dop853", case=rsts.Case(1, 0.5, -0.7092, 1.5643, torus=2),
                       tolerances=[1e-8], **SMALL)
    assert other["rows"][0]["max_error"] != got["rows"][1]["max_error"]


def test_taylor_mp_digits_are_those_of_the_cli(cli_json):
    expected = cli_json("bench", "--methods", "taylor-mp", "--tolerances", "1e-20", "--t-end", 2,
                        "--samples", 3, "--repeats", 1)
    got = rsts.bench(["taylor-mp"], tolerances=[1e-20], t_end=2, samples=3, repeats=1)
    assert got["taylor_mp_digits"] == expected["taylor_mp_digits"] == 30
    assert [untimed(r) for r in got["rows"]] == [untimed(r) for r in expected["rows"]]


def test_a_scipy_integrator_is_measured_beside_the_builtins():
    solve = scipy_dop853()
    calls = []

    def mine(x0, times, a, b, rtol, atol):
        calls.append((rtol, atol, len(times)))
        return solve(x0, times, a, b, rtol, atol)

    tolerances = (1e-6, 1e-9)
    report = rsts.bench([mine, "dop853"], tolerances=tolerances, t_end=10, samples=21, repeats=2)
    rows = report["rows"]
    assert [r["method"] for r in rows] == ["dop853"] * 2 + [mine.__qualname__] * 2
    assert sorted(set(calls)) == [(1e-9, 1e-9, 21), (1e-6, 1e-6, 21)]
    assert len(calls) == 4, "repeats runs per tolerance"
    ours = rows[2:]
    assert [r["tolerance"] for r in ours] == list(tolerances)
    assert ours[1]["max_error"] < 1e-2 * ours[0]["max_error"], ours
    for r in ours:
        # Its steps are not seen from outside: unknown, not 0.
        assert r["steps"] is None and r["rhs_evals"] is None
        assert 0 < r["time_min"] <= r["integration_seconds"] <= r["time_max"]
    # The error is the one rsts.check measures on the callable's own answer.
    case = rsts.Case.default()
    times = np.linspace(0.0, 10.0, 21)
    states = solve(case.reference(times[:1])[0], times, 1.0, 0.5, 1e-9, 1e-9)
    checked = rsts.check(times, states, m=case.m, h=case.h)["max_state_error"]
    assert abs(ours[1]["max_error"] - checked) <= 1e-9 * checked, (ours[1]["max_error"], checked)
    assert [f["method"] for f in report["fits"]] == ["dop853", mine.__qualname__]


class Boom(Exception):
    pass


def test_an_exception_of_the_callable_propagates_unchanged():
    raised = Boom("my integrator failed")

    def failing(*args):
        raise raised

    with pytest.raises(Boom) as e:
        rsts.bench(["dop853", failing], tolerances=[1e-8], **SMALL)
    assert e.value is raised


def test_a_wrong_answer_raises_valueerror_naming_it():
    def short(x0, times, a, b, rtol, atol):
        return np.zeros((len(times), 8))

    def nan(x0, times, a, b, rtol, atol):
        return np.full((len(times), 9), np.nan)

    with pytest.raises(ValueError, match=r"got shape \[11, 8\]"):
        rsts.bench([short], tolerances=[1e-8], **SMALL)
    with pytest.raises(ValueError, match=r"row 0 \(t = 0\), omega1: NaN is not a finite number"):
        rsts.bench([nan], tolerances=[1e-8], **SMALL)


def test_bad_input_raises_valueerror_with_the_cli_message(cli):
    def same(python_call, *cli_args):
        message = cli_error(cli, "bench", *cli_args)
        assert message.startswith("--")
        with pytest.raises(ValueError) as e:
            python_call()
        python_words = message[2:].replace("--", "").replace("methods", "integrators")
        assert str(e.value) == python_words.replace("t-end", "t_end"), (str(e.value), message)

    same(lambda: rsts.bench(["dop853"], tolerances=[-1e-3]), "--tolerances=-1e-3")
    with pytest.warns(UserWarning, match="skipping dop853 at tolerance 1e-30"):
        same(lambda: rsts.bench(["dop853"], tolerances=[1e-30]), "--methods", "dop853",
             "--tolerances", "1e-30")
    same(lambda: rsts.bench(["dop853"], repeats=2000), "--repeats", 2000)
    same(lambda: rsts.bench(["taylor-mp"], digits=5), "--methods", "taylor-mp", "--digits", 5)
    same(lambda: rsts.bench(["dop853"], samples=2_000_000), "--samples", 2_000_000)
    same(lambda: rsts.bench(["dop853"], tolerances=[1e-8], t_end=2.5e8, repeats=20),
         "--methods", "dop853", "--tolerances", "1e-8", "--t-end", 2.5e8, "--repeats", 20)
    with pytest.raises(ValueError, match=r"^integrators: give at least one method"):
        rsts.bench([])
    with pytest.raises(ValueError, match=r"^integrators: .*unknown method 'rk5'"):
        rsts.bench(["dop853", "rk5"])
    with pytest.raises(ValueError, match=r"^integrators: expected method names .* got int"):
        rsts.bench(["dop853", 42])
    with pytest.raises(ValueError, match=r"^tolerances: give at least one tolerance"):
        rsts.bench(["dop853"], tolerances=[])


def test_a_tolerance_below_round_off_is_skipped_with_a_warning():
    with pytest.warns(UserWarning, match=r"^skipping dop853 at tolerance 1e-18: below its unit round-off"):
        report = rsts.bench(["dop853"], tolerances=[1e-8, 1e-18], **SMALL)
    assert [r["tolerance"] for r in report["rows"]] == [1e-8]
