"""The Python face refuses what the CLI refuses (issue 35): state components beyond the CLI's
bound (|x| <= 1e8, docs/output.md) in arrays and in a callable's answer, with ValueError naming
the row and the column; ints too large for any argument named, not a bare OverflowError; times
counted before they are copied; an event asked for twice."""

import numpy as np
import pytest

import rsts
from conftest import cli_error, save_trajectory

BOUND = "is outside the range of a state component (|x| <= 1e8, docs/output.md)"


def trajectory(n=200, t_end=1.0):
    times = np.linspace(0.0, t_end, n)
    return times, rsts.Case.default().reference(times)


def test_arrays_beyond_the_bound_are_refused_naming_row_and_column(cli, tmp_path):
    times, states = trajectory()
    big = states.copy()
    big[1:101, 0] = 1e200
    with pytest.raises(ValueError) as e:
        rsts.check(times, big, case=rsts.Case.default())
    assert str(e.value) == f"states: row 1 (t = {float(times[1])!r}), omega1: 1e200 {BOUND}", str(e.value)
    # The CLI refuses the same rows in a file: the same bound, the same words.
    path = tmp_path / "big.npy"
    save_trajectory(path, times, big)
    assert cli_error(cli, "check", path).endswith(f"row 2, column 2 (omega1): 1e200 {BOUND}")
    # At the bound itself the values are analysed (and found wrong), as the CLI does.
    edge = states.copy()
    edge[5, 7] = -1e8
    report = rsts.check(times, edge, case=rsts.Case.default())
    assert report["max_state_error"] > 1e7
    for bad, shown in [(np.inf, "inf is not a finite number"), (-2e8, "-2e8 " + BOUND)]:
        wrong = states.copy()
        wrong[7, 5] = bad
        with pytest.raises(ValueError, match=rf"^states: row 7 \(t = .*\), alpha3: {shown}"):
            rsts.check(times, wrong)


def test_a_callables_answer_beyond_the_bound_is_refused():
    case = rsts.Case.default()

    def overflowing(x0, times, a, b, rtol, atol):
        answer = case.reference(times)
        answer[1:101, 0] = 1e200
        return answer

    for call in [lambda: rsts.compare(overflowing, case=case, t_end=1.0, samples=200),
                 lambda: rsts.bench([overflowing], case=case, t_end=1.0, samples=200, repeats=1)]:
        with pytest.raises(ValueError) as e:
            call()
        assert "row 1 (t = " in str(e.value) and f"omega1: 1e200 {BOUND}" in str(e.value), str(e.value)


@pytest.mark.parametrize("call, name", [
    (lambda: rsts.compare("rk4", samples=10**30), "samples"),
    (lambda: rsts.compare("rk4", pieces=10**30), "pieces"),
    (lambda: rsts.compare("taylor-mp", digits=-10**30), "digits"),
    (lambda: rsts.compare("rk4", dense=10**30), "dense"),
    (lambda: rsts.Case(1, 0.5, 0.3, -0.375, torus=10**30), "torus"),
    (lambda: rsts.Case.default().reference([0.0, 1.0], digits=10**30), "digits"),
    (lambda: rsts.events(["omega1"], digits=10**30), "digits"),
    (lambda: rsts.identify([0.0] * 9, digits=10**30), "digits"),
    (lambda: rsts.convergence(["rk4"], [0.1, 0.05, 0.025], samples=10**30), "samples"),
    (lambda: rsts.convergence(["taylor-mp"], [0.1, 0.05, 0.025], order=10**30), "order"),
    (lambda: rsts.convergence(["rk4"], [0.1, 0.05, 0.025], digits=10**30), "digits"),
    (lambda: rsts.check([0.0, 1.0], np.zeros((2, 9)), digits=10**30), "digits"),
    (lambda: rsts.check([0.0, 1.0], np.zeros((2, 9)), m=0.3, h=-0.375, torus=10**30), "torus"),
    (lambda: rsts.bench(["rk4"], samples=10**30), "samples"),
    (lambda: rsts.bench(["rk4"], repeats=10**30), "repeats"),
    (lambda: rsts.bench(["rk4"], digits=10**30), "digits"),
])
def test_huge_ints_are_refused_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=rf"^{name}: -?1000000000000000000000.* is out of range$"):
        call()


def test_a_huge_int_is_shown_cut():
    with pytest.raises(ValueError) as e:
        rsts.compare("rk4", samples=10**1000)
    assert str(e.value) == "samples: 10000000000000000000… (1001 characters) is out of range"


class Huge:
    """A sequence of 10⁸ times that counts its reads: refused before any is copied."""

    reads = 0

    def __len__(self):
        return 100_000_000

    def __getitem__(self, k):
        Huge.reads += 1
        if k >= 100_000_000:
            raise IndexError
        return float(k)


def test_too_many_times_are_refused_before_they_are_copied():
    message = "^times: at most 10000000 times are supported, got 100000000$"
    with pytest.raises(ValueError, match=message):
        rsts.Case.default().reference(Huge())
    with pytest.raises(ValueError, match=message):
        rsts.compare("rk4", times=Huge())
    assert Huge.reads == 0


def test_an_event_asked_for_twice_is_refused_as_the_cli_refuses_it(cli):
    with pytest.raises(ValueError) as e:
        rsts.events(["omega1", "omega1:up"])
    assert str(e.value) == "names: omega1 is asked for twice"
    assert cli_error(cli, "events", "--event", "omega1", "--event", "omega1:up").endswith(
        "omega1 is asked for twice")
