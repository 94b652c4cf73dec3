"""Cell formats of the comparison tables (comparisons.report.tables)."""

import math

from comparisons.report.tables import fmt_error, fmt_value


def test_values():
    assert fmt_value(None) == "" and fmt_value(math.nan) == ""
    assert fmt_value(True) == "yes" and fmt_value(3) == "3"
    assert fmt_value(1234567.891) == "1.23457e+06" and fmt_value(0.1234567) == "0.123457"
    assert fmt_value("text") == "text"


def test_errors():
    assert fmt_error(None) == "—" and fmt_error(math.nan) == "—"
    assert fmt_error(0) == "0" and fmt_error(1.234e-7) == "1.23e-07"
