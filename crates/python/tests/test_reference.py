"""Case, Case.reference and identify against the CLI (rsts reference, rsts identify)."""

import decimal

import numpy as np
import pytest

import rsts
from conftest import cli_error

# The decimals the CLI reads, as strings: a Python float is its exact binary value (another
# motion, 1e-17 away), a str the decimal it writes.
CAMERA_V = dict(a="1", b="0.5", m="-0.7092", h="1.5643", torus=2, phase1="0.4", phase2="1.3")
TIMES = [0.0, 0.5, 2.0, 10.25, 99.875, 1000.0]


def case_args(c):
    return ["--a", c["a"], "--b", c["b"], "--m", c["m"], "--h", c["h"], "--torus", c["torus"],
            "--phase1", c["phase1"], "--phase2", c["phase2"]]


def test_case_attributes_and_default():
    c = rsts.Case(**CAMERA_V)
    assert (c.a, c.b, c.m, c.h, c.torus, c.phase1, c.phase2) == tuple(
        v if isinstance(v, int) else float(v) for v in CAMERA_V.values())
    assert c.camera == "V"
    d = rsts.Case.default()
    assert (d.a, d.b, d.m, d.h, d.torus, d.camera) == (1.0, 0.5, 0.3, -0.375, 0, "I+")
    assert d == rsts.Case(1, 0.5, "0.3", -0.375) and d != rsts.Case(**CAMERA_V)
    # The float 0.3 is another motion than the decimal 0.3.
    assert d != rsts.Case(1, 0.5, 0.3, -0.375)


def test_reference_is_bit_identical_to_the_cli(cli, tmp_path):
    out = tmp_path / "ref.npy"
    cli("reference", *case_args(CAMERA_V), "--times", ",".join(map(repr, TIMES)),
        "--format", "npy", "-o", out)
    expected = np.load(out)[:, 1:10]
    got = rsts.Case(**CAMERA_V).reference(np.array(TIMES))
    assert got.dtype == np.float64 and got.shape == (len(TIMES), 9)
    assert got.tobytes() == np.ascontiguousarray(expected).tobytes()
    # A list works as well as an array; a moved start changes the values (the check can fail).
    assert rsts.Case(**CAMERA_V).reference(TIMES).tobytes() == got.tobytes()
    moved = rsts.Case(**dict(CAMERA_V, phase1=0.41)).reference(TIMES)
    assert moved.tobytes() != got.tobytes()


def test_reference_digits_are_the_cli_digits(cli):
    _, out, _ = cli("reference", *case_args(CAMERA_V), "--times", "0,2.5", "--digits", "40")
    rows = [line.split(",")[1:10] for line in out.strip().splitlines()[1:]]
    got = rsts.Case(**CAMERA_V).reference([0, 2.5], digits=40)
    assert got == rows
    assert all(len(v.lstrip("-").split("e")[0].replace(".", "")) == 40 for v in got[1])


@pytest.mark.parametrize("bad, args", [
    (dict(h=-100.0), ["--h", "-100"]),                     # outside the admissible region
    (dict(torus=3), ["--torus", "3"]),                     # no such torus
    (dict(a=0.5, b=1.0), ["--a", "0.5", "--b", "1"]),      # b > a
    (dict(a=1e300), ["--a", "1e300"]),                     # outside the documented range
])
def test_bad_cases_raise_the_cli_message(cli, bad, args):
    c = dict(a=1.0, b=0.5, m="0.3", h=-0.375, torus=0)
    c.update(bad)
    with pytest.raises(ValueError) as e:
        rsts.Case(**c)
    message = cli_error(cli, "reference", "--times", "0", *args)
    # The same message; the CLI names its options (--m/--h), Python its arguments (m/h).
    options, text = message.split(": ", 1)
    assert str(e.value) == options.replace("--", "") + ": " + text


@pytest.mark.parametrize("times, digits, what", [
    ([1.0, 0.0], None, "times: times must be strictly increasing: time 2 (0) does not come after 1"),
    ([], None, "times: no times"),
    ([0.0, float("nan")], None, "times: element 1 is not a finite number (NaN)"),
    ([[0.0, 1.0]], None, "times: expected a 1-D array, got shape [1, 2]"),
    (["x"], None, "times: 'x' is not a number"),             # a str is a decimal, as on the CLI
    ([0.0], 17, "digits: must be between 18 and 10000 (without it: f64), got 17"),
])
def test_reference_bad_input_raises_valueerror(times, digits, what):
    with pytest.raises(ValueError) as e:
        rsts.Case.default().reference(times, digits=digits)
    assert str(e.value).startswith(what), str(e.value)


def test_identify_is_the_cli_document(cli_json):
    state = rsts.Case(**CAMERA_V).reference([3.0])[0]
    # The floats' exact binary values written out, so the CLI reads the same numbers.
    vectors = [",".join(str(decimal.Decimal(float(x))) for x in state[k:k + 3]) for k in (0, 3, 6)]
    expected = cli_json("identify", f"--omega={vectors[0]}", f"--alpha={vectors[1]}",
                        f"--beta={vectors[2]}")
    got = rsts.identify(state, 1.0, 0.5)
    assert got == expected
    assert list(got) == list(expected)  # the same keys in the same order
    assert got["camera"] == "V" and got["torus"] == 2 and abs(got["m"] + 0.7092) < 1e-12
    # Off N: the CLI's document too (it exits with 1).
    off = [0.3, -0.2, 0.5, 1, 0, 0, 0, 1, 0]
    expected = cli_json("identify", "--omega=0.3,-0.2,0.5", "--alpha=1,0,0", "--beta=0,1,0",
                        ok=(1,))
    assert rsts.identify(off) == expected and expected["on_N"] is False


def test_identify_bad_input_raises_valueerror(cli):
    with pytest.raises(ValueError, match=r"^a/b: need a > b > 0"):
        rsts.identify([0.3, -0.2, 0.5, 1, 0, 0, 0, 1, 0], 0.5, 1.0)
    with pytest.raises(ValueError, match=r"^state: expected 9 numbers"):
        rsts.identify([1, 0, 0])
    with pytest.raises(ValueError) as e:
        rsts.identify([0.3, -0.2, 0.5, 2, 0, 0, 0, 1, 0])
    message = cli_error(cli, "identify", "--omega=0.3,-0.2,0.5", "--alpha=2,0,0", "--beta=0,1,0")
    assert str(e.value) == "state: " + message.split(": ", 1)[1]
