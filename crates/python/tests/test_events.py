"""rsts.events against the CLI (rsts events --format json): the same document, digits as
decimal strings, ValueError naming the argument on bad input."""

import pytest

import rsts


def test_events_are_the_cli_document(cli_json):
    expected = cli_json("events", "--m", -0.7092, "--h", 1.5643, "--torus", 3, "--event", "gamma3:down",
                        "--event", "s1", "--t-end", 10, "--digits", 40)
    # The decimals the CLI reads, as strings (a float is its exact binary value, another motion).
    case = rsts.Case(1, 0.5, "-0.7092", "1.5643", torus=3)
    got = rsts.events(["gamma3:down", "s1"], case=case, t_end=10, digits=40)
    assert got == expected
    assert len(got["events"]) >= 2
    assert all(isinstance(e["t"], str) for e in got["events"])


def test_bad_names_and_windows_raise_value_error():
    with pytest.raises(ValueError, match="names: unknown event 'omega4'"):
        rsts.events(["omega4"])
    with pytest.raises(ValueError, match="t_start/t_end"):
        rsts.events(["s1"], t_start=2.0, t_end=1.0)
