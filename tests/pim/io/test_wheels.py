"""pim/io/wheels.py: the wheel states shared by the run-out evidence and the pre-impact marks."""

import tomllib
from importlib import resources

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pim.io.evidence_table import parse_evidence
from pim.io.wheels import WHEEL_WORDS, braking_fraction, wheel_fractions


def test_words_numbers_and_one_or_four_states():
    assert wheel_fractions("locked", "w") == (1.0,) * 4
    assert wheel_fractions(["locked", "free", "free-rolling", 0.3], "w") == (1, 0, 0, 0.3)
    assert wheel_fractions([1, "0.5", 0, 0.25], "w") == (1, 0.5, 0, 0.25)
    assert braking_fraction(" locked ", "w") == 1.0


@given(st.floats(0.0, 1.0))
def test_any_fraction_in_0_1_is_kept(f):
    assert braking_fraction(f, "w") == f and wheel_fractions(f, "w") == (f,) * 4


@pytest.mark.parametrize("value, words", [
    ("skidding", ["evidence.vehicle1.wheels", "'locked', 'free'"]),
    (1.5, ["evidence.vehicle1.wheels", "[0, 1]"]),
    (["locked", "free"], ["evidence.vehicle1.wheels", "one state or four"]),
    (["locked", "free", "free", "sliding"], ["evidence.vehicle1.wheels[3]", "'locked'"]),
    ("nan", ["evidence.vehicle1.wheels"]),
])
def test_bad_states_name_the_field(value, words):
    with pytest.raises(ValueError) as info:
        wheel_fractions(value, "evidence.vehicle1.wheels")
    assert all(w in str(info.value) for w in words), str(info.value)


def test_both_tables_read_the_same_states():
    """The run-out's ``wheels`` and the marks' ``braking`` were parsed by two copies of the
    word table; a word one of them knew the other refused ('free-rolling' as braking)."""
    table = {"vehicle1": {"rest_position": ["1 m", "1 m"], "rest_heading": 0, "wheelbase": "2.7 m",
                          "track": "1.5 m", "friction": 0.7,
                          "wheels": ["free-rolling", "locked", "0.5", 0.5],
                          "pre_impact": {"skid_length": "10 m", "friction": 0.7,
                                         "braking": ["free-rolling", "locked", "0.5", 0.5]}}}
    ev = parse_evidence(table).vehicle1
    assert ev.braking == (0.0, 1.0, 0.5, 0.5)
    assert set(WHEEL_WORDS) == {"locked", "free", "free-rolling"}


def test_a_quoted_fraction_is_the_fraction_for_every_command():
    """Issue 28 (fault harness): `wheels = '0.3'` was accepted by `pim solve` while `pim
    reconstruct` ran past 60 s. One parser reads it for every command: 0.3 on all four
    wheels, the same as the number 0.3 (the time was the run-outs' Monte Carlo, not the
    string: pim reconstruct now measures it first, tests/pim_cli/test_reconstruct.py)."""
    import pim

    text = (resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text()
    old = 'wheels = ["locked", "locked", 0.3, 0.3]'
    assert text.count(old) == 2
    quoted = pim.io.casefile.parse_case(tomllib.loads(text.replace(old, "wheels = '0.3'")))
    number = pim.io.casefile.parse_case(tomllib.loads(text.replace(old, "wheels = 0.3")))
    for case in (quoted, number):
        assert case.evidence.vehicle1.braking == case.evidence.vehicle2.braking == (0.3,) * 4
