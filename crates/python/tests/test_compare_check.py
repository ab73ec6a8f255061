"""compare and check against the CLI (rsts compare, rsts check), a scipy integrator written as a
user writes it, and what a bad integrator gets: ValueError naming what was wrong, or its own
exception unchanged."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rsts
from conftest import rhs, save_trajectory


def scipy_dop853(x0, times, a, b, rtol, atol):
    """A user's integrator: scipy's DOP853 through the given times."""
    sol = solve_ivp(rhs(a, b), (times[0], times[-1]), x0, method="DOP853", t_eval=times,
                    rtol=rtol, atol=atol)
    assert sol.success, sol.message
    return sol.y.T


def without_timing(report):
    return {k: v for k, v in report.items()
            if k not in ("integration_seconds", "wall_seconds", "environment")}


def test_compare_builtin_is_the_cli_report(cli_json):
    args = dict(t_end=10.0, samples=101, rtol=1e-8, atol=1e-8)
    expected = cli_json("compare", "--method", "dopri5", "--t-end", 10, "--samples", 101,
                        "--rtol", 1e-8, "--atol", 1e-8)
    got = rsts.compare("dopri5", **args)
    assert list(got) == list(expected)
    assert without_timing(got) == without_timing(expected)
    assert got["method"] == "dopri5" and got["samples_compared"] == 101
    # Another case gives another report (the comparison can fail).
    case_v = rsts.Case(1, 0.5, -0.7092, 1.5643, torus=2)
    other = rsts.compare("dopri5", case=case_v, **args)
    assert other["camera"] == "V" and other["max_state_error"] != got["max_state_error"]


def test_a_scipy_integrator_is_checked_in_process(cli_json, tmp_path):
    calls = []

    def integrator(x0, times, a, b, rtol, atol):
        calls.append((x0.copy(), times.copy(), a, b, rtol, atol))
        return scipy_dop853(x0, times, a, b, rtol, atol)

    # The decimals the CLI reads (a Python float is its exact binary value, another motion).
    case = rsts.Case(1, 0.5, "-0.7092", "1.5643", torus=2)
    report = rsts.compare(integrator, case=case, t_end=20, samples=201, rtol=1e-10, atol=1e-10)
    # Called once, with numpy arrays: the exact start and the whole grid.
    assert len(calls) == 1
    x0, times, a, b, rtol, atol = calls[0]
    assert isinstance(x0, np.ndarray) and isinstance(times, np.ndarray)
    assert x0.tobytes() == case.reference([0.0])[0].tobytes()
    assert times[0] == 0.0 and times[-1] == 20.0
    assert np.allclose(times, np.linspace(0, 20, 201), rtol=1e-15, atol=0)
    assert (a, b, rtol, atol) == (1.0, 0.5, 1e-10, 1e-10)
    assert report["method"] == "test_a_scipy_integrator_is_checked_in_process.<locals>.integrator"
    assert report["samples_compared"] == 201 and report["integration_seconds"] > 0
    # Its steps are not seen from outside: unknown, not 0.
    assert report["steps"] is None and report["rhs_evals"] is None
    assert 1e-13 < report["max_state_error"] < 1e-6, report["max_state_error"]
    # The same states, checked by the CLI from a file, give the same errors.
    states = scipy_dop853(x0, times, a, b, rtol, atol)
    path = tmp_path / "traj.npy"
    save_trajectory(path, times, states)
    expected = cli_json("check", path, "--m", -0.7092, "--h", 1.5643, "--torus", 2)
    for key in ("max_state_error", "final_state_error", "max_orientation_error", "drift"):
        assert report[key] == expected[key], key


def test_check_is_the_cli_report(cli_json, tmp_path):
    case = rsts.Case(1, 0.5, "0.3", "-0.375", phase1="0.7")
    times = np.linspace(0.0, 10.0, 51)
    states = scipy_dop853(case.reference([0.0])[0], times, 1.0, 0.5, 1e-9, 1e-9)
    path = tmp_path / "traj.npy"
    save_trajectory(path, times, states)
    for given in ([], ["--m", 0.3, "--h", -0.375, "--phase1", 0.7]):
        expected = cli_json("check", path, *given)
        kwargs = dict(m="0.3", h="-0.375", phase1="0.7") if given else {}
        got = rsts.check(times, states, 1.0, 0.5, name="traj.npy", **kwargs)
        assert list(got) == list(expected)
        assert got["file"] == "<arrays>"
        assert dict(got, file=None) == dict(expected, file=None)
        assert got["case"]["identified"] == (not given)
    # The user's assertion of docs/python.md, and one that fails on a perturbed trajectory.
    assert rsts.check(times, states)["max_state_error"] < 1e-8
    bad = states.copy()
    bad[-1, 0] += 1e-6
    assert rsts.check(times, bad)["max_state_error"] > 1e-8


def test_check_bad_input_raises_valueerror():
    times = np.linspace(0.0, 1.0, 3)
    states = rsts.Case.default().reference(times)
    nan = states.copy()
    nan[1, 4] = np.nan
    cases = [
        (lambda: rsts.check(times, states[:2]), "states: expected shape (3, 9)"),
        (lambda: rsts.check(times, nan), "states: row 1 (t = 0.5), alpha2: NaN is not a finite number"),
        (lambda: rsts.check(times[::-1], states), "times: times must be strictly increasing"),
        (lambda: rsts.check(times, states, m=0.3), "m/h: give both or neither"),
        (lambda: rsts.check(times, states, m=0.3, h=-100.0), "m/h: (m, h) is outside"),
        (lambda: rsts.check(times, states, a=0.5, b=1.0), "a/b: "),
        (lambda: rsts.check(times, "x"), "states: expected real numbers"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError) as e:
            call()
        assert str(e.value).startswith(message), (message, str(e.value))


class Boom(Exception):
    pass


def test_a_bad_callable_gets_a_clear_error():
    def answer(value):
        return lambda x0, times, a, b, rtol, atol: value(times)

    n = 3
    cases = [
        (answer(lambda t: None), "returned NoneType, not a numpy array of shape (3, 9)"),
        (answer(lambda t: [[0.0] * 9] * len(t)), "returned list, not a numpy array"),
        (answer(lambda t: np.zeros((len(t), 8))), "expected shape (3, 9) (one row of omega, alpha, beta per time), got shape [3, 8]"),
        (answer(lambda t: np.zeros((len(t) + 1, 9))), "got shape [4, 9]"),
        (answer(lambda t: np.full((len(t), 9), np.nan)), "row 0 (t = 0), omega1: NaN is not a finite number"),
        (answer(lambda t: np.array([["a"] * 9] * len(t))), "expected real numbers"),
    ]
    for f, message in cases:
        with pytest.raises(ValueError) as e:
            rsts.compare(f, t_end=1.0, samples=n)
        assert message in str(e.value), str(e.value)
    with pytest.raises(ValueError, match="^integrator: expected a method name"):
        rsts.compare(42)
    with pytest.raises(ValueError, match="^integrator: .*unknown method 'rk5'"):
        rsts.compare("rk5")
    with pytest.raises(ValueError, match="^rtol: .*below the unit round-off"):
        rsts.compare("dop853", rtol=1e-20)
    with pytest.raises(ValueError, match="^samples: must be >= 0"):
        rsts.compare("dop853", samples=-1)


def test_an_exception_of_the_callable_propagates_unchanged():
    raised = Boom("my integrator failed")

    def failing(*args):
        raise raised

    with pytest.raises(Boom) as e:
        rsts.compare(failing, t_end=1.0, samples=3)
    assert e.value is raised
