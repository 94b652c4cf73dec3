"""pim/io/toml_tables.py: the one table-and-keys check of the case file's parsers."""

import pytest

from pim.io.toml_tables import check_keys


def test_known_keys_pass_and_the_table_comes_back():
    table = {"mass": 1.0, "cg": [0, 0]}
    assert check_keys(table, {"mass", "cg", "heading"}, "vehicle1") is table


@pytest.mark.parametrize("table, words", [
    ([1, 2], "vehicle1 must be a table"),
    ({"mas": 1.0}, "vehicle1: unknown key 'mas'; did you mean 'mass'? (allowed: cg, mass)"),
    ({"colour": 1.0}, "vehicle1: unknown key 'colour' (allowed: cg, mass)"),
])
def test_errors_name_the_table_the_key_and_the_allowed_ones(table, words):
    with pytest.raises(ValueError) as info:
        check_keys(table, ("mass", "cg"), "vehicle1")
    assert str(info.value) == words
