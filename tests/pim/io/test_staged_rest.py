"""The bundled published rest positions (pim/io/staged_rest.py; Day, SAE 2004-01-1207 as
transcribed in pycrash): values as in the file, identified RICSAC tests consistent with
the bundled RICSAC dataset, clear errors on a malformed row."""

import math

import numpy as np
import pytest

from pim.io import staged_rest as S
from pim.io.datasets import data_path, load_ricsac
from pim.model.numbers import InputError

FT, MPH = 0.3048, 0.44704


def test_ricsac10_row_is_the_transcript_in_si():
    """VC11 of the transcript (cells 5, 43, 87 / 0, 99.5, 128.5; 31.35 mph each)."""
    r = S.staged_rest(10)
    assert r.test == "VC11" and r.vehicles == ("1974 Honda CVCC", "1974 Ford Torino")
    assert r.speed == pytest.approx([31.35 * MPH] * 2)
    assert r.rest_range == pytest.approx([math.hypot(5, 43) * FT, 99.5 * FT])
    assert np.degrees(r.heading) == pytest.approx([87.0, 128.5])
    assert len(S.load_staged_rest()) == 5 and S.load_staged_rest()[0].ricsac is None


def test_identified_ricsac_tests_have_the_bundled_measured_speeds():
    """Two published sources agree: Day's impact speeds (0.01 mph) and Neades' measured
    speeds (0.1 m/s) within 0.15 m/s (the coarser rounding, 0.05 m/s, plus a 1 % speed
    trap) for RICSAC 2, 3 and 6. RICSAC 10 does not (14.0 against 14.8 m/s): a discrepancy
    between the sources, kept on record (docs/event.md)."""
    ricsac = {t.number: t for t in load_ricsac()}
    for record in S.load_staged_rest():
        if record.ricsac is None:
            continue
        test = ricsac[record.ricsac]
        diff = np.abs(record.speed - [test.speed1_measured, test.speed2_measured])
        moving = record.speed > 0
        if record.ricsac == 10:
            assert diff.min() > 0.7
        else:
            assert diff[moving].max() <= 0.15, record.test
            assert test.speed2_measured == 0.0 or moving.all()


def test_no_row_for_a_test_without_published_rest():
    with pytest.raises(InputError, match="no published rest positions of RICSAC 9.*2, 3, 6, 10"):
        S.staged_rest(9)


def test_malformed_rows_name_the_line_and_column(monkeypatch):
    lines = data_path(S.DATA_FILE).read_text(encoding="utf-8").splitlines()
    header = next(line for line in lines if not line.startswith("#")).split(",")
    good = dict(zip(header, ["VC9", "oblique", "a", "b", "30", "30", "90", "1", "2",
                                 "3", "4", "5", "6", "7", "8", "10"], strict=True))
    for column, value, message in (("dy2_ft", "1O", "column 'dy2_ft': '1O' is not a number"),
                                   ("speed1_mph", "-3", "'speed1_mph': -3 outside"),
                                   ("ricsac", "13", "not a RICSAC number"),
                                   ("heading1_deg", "nan", "not a finite number")):
        row = dict(good, **{column: value})
        monkeypatch.setattr(S, "bundled_rows", lambda name, columns, row=row: [(7, row)])
        with pytest.raises(InputError, match=f"line 7 {message}" if column == "dy2_ft"
                           else message):
            S.load_staged_rest.__wrapped__()
