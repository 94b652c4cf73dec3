"""Cells of the report tables (comparisons.report.tables): the one number format, typed
cells that state their digits, raw values for the CSV."""

import math

from comparisons.report.tables import Num, Table, cell_text, fmt_error, fmt_value, raw_value


def test_values():
    assert fmt_value(None) == "" and fmt_value(math.nan) == ""
    assert fmt_value(True) == "yes" and fmt_value(3) == "3"
    assert fmt_value(1234567.891) == "1.235e+06" and fmt_value(0.1234567) == "0.1235"
    assert fmt_value("text") == "text" and fmt_value(Num(28.0467, 1)) == "28.0"


def test_errors():
    assert fmt_error(None) == "—" and fmt_error(math.nan) == "—"
    assert fmt_error(0) == "0" and fmt_error(1.234e-7) == "1.2e-07"


def test_a_num_keeps_its_value_for_the_csv_and_its_digits_for_the_page():
    t = Table("t", "T", ("a", "b"), ((Num(1.23456, 2), 1e-3),), {"b": fmt_error})
    assert raw_value(t.rows[0][0]) == 1.23456 and t.column("a") == [1.23456]
    assert t.cells() == [["1.23", "0.001"]] and t.numeric() == [True, True]
    assert cell_text(t, "b", Num(2e-7)) == "2e-07"


def test_a_row_of_the_wrong_length_is_refused():
    try:
        Table("t", "T", ("a", "b"), ((1,),))
    except ValueError as exc:
        assert "1 cells for 2 columns" in str(exc)
    else:
        raise AssertionError("accepted")


def test_records_are_the_rows_by_column_with_raw_values():
    from comparisons.report.tables import Num, Table

    table = Table("t", "T", ("name", "value [m]"), (("a", Num(1.25, 1)), ("b", None)))
    assert table.records() == [{"name": "a", "value [m]": 1.25},
                               {"name": "b", "value [m]": None}]
