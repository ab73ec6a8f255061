"""rsts.convergence against the CLI (rsts convergence --format json): the same document; bad
input raises ValueError naming the argument."""

import pytest

import rsts

STEPS = [0.5, 0.25, 0.125, 0.0625, 0.03125]


def test_convergence_is_the_cli_document(cli_json):
    expected = cli_json("convergence", "--methods", "rk4,taylor-f64", "--order", 5,
                        "--steps", ",".join(map(str, STEPS)))
    got = rsts.convergence(["rk4", "taylor-f64"], STEPS, order=5)
    assert got == expected
    orders = {f["method"]: f["order"] for f in got["fits"]}
    assert abs(orders["rk4"] - 4) < 0.1 and abs(orders["taylor-f64-p5"] - 5) < 0.2
    # Another case, another document.
    case_v = rsts.Case(1, 0.5, -0.7092, 1.5643, torus=2)
    other = rsts.convergence(["rk4"], STEPS, case=case_v)
    assert other["rows"][0]["max_error"] != got["rows"][0]["max_error"]


@pytest.mark.parametrize("kwargs, name", [
    (dict(methods=["rk4"], steps=[0.5, 0.25]), "steps"),
    (dict(methods=["taylor-f64"], steps=STEPS), "methods/order"),
    (dict(methods=["rk4"], steps=STEPS, order=4), "order"),
    (dict(methods=["euler"], steps=STEPS), "methods"),
    (dict(methods=[], steps=STEPS), "methods"),
])
def test_bad_input_names_the_argument(kwargs, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        rsts.convergence(**kwargs)
