"""Bundled crash-test data: values as published, malformed copies rejected with a clear error."""

import math
from pathlib import Path

import pytest

from pim.io.datasets import (
    BARRIER_FILE,
    CAR_TO_CAR_FILE,
    RICSAC_FILE,
    data_path,
    load_barrier,
    load_car_to_car,
    load_dataset,
    load_ricsac,
    source_lines,
)


def test_counts_and_groups():
    barrier = load_barrier()
    assert len(barrier) == 41
    groups = [t.group for t in barrier]
    assert groups.count("NS") == 16 and groups.count("SS") == 24 and groups.count("OUTLIER") == 1
    assert len(load_car_to_car()) == 18
    ricsac = load_ricsac()
    assert [t.number for t in ricsac] == [1] + list(range(2, 13))
    assert [t.number for t in ricsac if not t.has_motion] == [2]


def test_values_follow_the_paper_not_the_workbook():
    """brach_matrix_vs_paper_discrepancies.csv: the paper has CF11002 mu 85.2 %, CEN1212
    Gamma 74.4 deg, CF10020 dV 46.9 ft/s and CF11001 (not CF11011) as an ID."""
    by_id = {t.test_id: t for t in load_barrier()}
    assert by_id["CF11002"].beta == pytest.approx(0.852)
    assert by_id["CEN1212"].normal_angle == pytest.approx(math.radians(74.4))
    assert by_id["CF10020"].delta_v == pytest.approx(46.9 * 0.3048)
    assert "CF11001" in by_id and "CF11011" not in by_id
    assert by_id["CF10017"].group == "NS" and by_id["CF10028"].group == "SS"


def test_si_conversion():
    t = load_barrier()[0]   # CEN1212: d1 3.7 ft, v0 58.60 ft/s, Omega 205.96 deg/s
    assert t.d == pytest.approx(3.7 * 0.3048)
    assert t.speed == pytest.approx(58.60 * 0.3048)
    assert t.yaw_rate == pytest.approx(math.radians(205.96))
    r = load_ricsac()[8]    # RICSAC 9
    assert r.number == 9 and r.velocity1_pre == (-9.48, 0.0) and r.yaw_rate2_post == 0.79


def test_source_lines_kept():
    for name in (BARRIER_FILE, CAR_TO_CAR_FILE, RICSAC_FILE):
        assert source_lines(data_path(name))
    assert "2014-01-0469" in source_lines(data_path(BARRIER_FILE))[0]


def _copy(tmp_path, name, edit):
    text = data_path(name).read_text(encoding="utf-8")
    path = tmp_path / name
    path.write_text(edit(text), encoding="utf-8")
    return path


@pytest.mark.parametrize("edit, match", [
    (lambda s: s.replace("CEN1212,NS,2012,Audi A4,Sedan,Flat 150 barrier,25,0.103",
                         "CEN1212,NS,2012,Audi A4,Sedan,Flat 150 barrier,25,0.1o3"),
     r"line 4 column 'e': '0\.1o3' is not a number"),
    (lambda s: s.replace(",0.103,100.0,", ",1.103,100.0,"), r"line 4 column 'e': 1\.103 outside"),
    (lambda s: s.replace("CEN1204,NS", "CEN1204,XX"), r"line 5 column 'group': 'XX' is not one"),
    (lambda s: s.replace("Omega_dps", "Omega"), r"line 3: header .*missing \['Omega_dps'\]"),
    (lambda s: s.replace(",205.96\n", "\n"), r"line 4: 16 fields, expected 17"),
    (lambda s: s.replace("CEN1204", "CEN1212"), r"line 5: duplicate test_id 'CEN1212'"),
    (lambda s: s.replace(",58.60,52.79,", ",nan,52.79,"),
     r"column 'v0_fps': 'nan' is not a finite"),
    (lambda s: s.replace(",58.60,52.79,", ",,52.79,"), r"column 'v0_fps': empty"),
])
def test_malformed_barrier_file_rejected(tmp_path, edit, match):
    path = _copy(tmp_path, BARRIER_FILE, edit)
    with pytest.raises(ValueError, match=match) as info:
        load_barrier(path)
    assert BARRIER_FILE in str(info.value)


def test_malformed_car_to_car_file_rejected(tmp_path):
    path = _copy(tmp_path, CAR_TO_CAR_FILE,
                 lambda s: s.replace("CF09009b,SS,2001 Ford Taurus,28%,0.009",
                                     "CF09009b,SS,2001 Ford Taurus,28%,0.010"))
    with pytest.raises(ValueError, match="restitution of CF09009b differs"):
        load_car_to_car(path)
    path = _copy(tmp_path, CAR_TO_CAR_FILE, lambda s: s.replace("CF09009b,", "CF09009c,"))
    with pytest.raises(ValueError, match="must end in a or b"):
        load_car_to_car(path)


def test_malformed_ricsac_file_rejected(tmp_path):
    path = _copy(tmp_path, RICSAC_FILE, lambda s: s.replace("-30,0,60,-19.8", ",0,60,-19.8"))
    with pytest.raises(ValueError, match=r"line 4 column 'Gamma_deg': empty, but other motion"):
        load_ricsac(path)
    path = _copy(tmp_path, RICSAC_FILE,
                 lambda s: s.replace("1,Chevrolet Chevelle Malibu,Ford Pinto,2096",
                                     "1,Chevrolet Chevelle Malibu,Ford Pinto,-2096"))
    with pytest.raises(ValueError, match=r"column 'm1_kg': -2096 outside"):
        load_ricsac(path)


def test_missing_file_and_unknown_dataset(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        load_barrier(tmp_path / "none.csv")
    with pytest.raises(ValueError, match="unknown dataset 'x'"):
        load_dataset("x")


def test_nhtsa_car_to_car_as_transcribed():
    """SAE 2006-01-0908 via pycrash's transcription: test 4364 (Accord and Trailblazer)."""
    from pim.io.datasets import LB, MPH, NHTSA_FILE, SLUG_FT2, load_nhtsa_car_to_car

    tests = {t.test: t for t in load_nhtsa_car_to_car()}
    assert list(tests) == ["4363", "4364", "4438", "4474"]
    t = tests["4364"]
    assert "Trailblazer" in t.vehicle2 and t.mass2 == pytest.approx(5192.5 * LB)
    assert t.yaw_inertia2 == pytest.approx(3563 * SLUG_FT2)
    assert t.speed2 == pytest.approx(34.9 * MPH) and t.d2 == pytest.approx(7.1 * 0.3048)
    assert t.normal_angle == pytest.approx(math.radians(51.9)) and t.restitution == 0.089
    assert t.delta_v1 == pytest.approx(40.1 * MPH)
    assert t.yaw_change2 == pytest.approx(math.radians(148))
    assert "2006-01-0908" in source_lines(data_path(NHTSA_FILE))[0]
    assert load_dataset("nhtsa-car-to-car")[0].test == "4363"


def test_every_input_names_its_origin():
    """The origins on the records: the barrier tests' phi, e and mu were fitted with PIM to
    their own motion; the NHTSA table's outcome is a PIM analysis's output."""
    from pim.io.datasets import (
        FITTED_BY_PIM,
        MEASURED,
        ORIGIN_KINDS,
        PIM_OUTPUT,
        PUBLISHED_GEOMETRY,
        load_nhtsa_car_to_car,
    )

    b = load_barrier()[0]
    assert b.origins["phi"] == FITTED_BY_PIM and b.origins["d"] == PUBLISHED_GEOMETRY
    assert b.origins["yaw_rate"] == MEASURED
    n = load_nhtsa_car_to_car()[0]
    assert n.origins["delta_v1"] == PIM_OUTPUT and n.origins["speed1"] == MEASURED
    for records in (load_barrier(), load_car_to_car(), load_ricsac(), load_nhtsa_car_to_car()):
        r = records[0]
        assert set(r.origins.values()) <= set(ORIGIN_KINDS)
        fields = set(r.__dataclass_fields__)
        assert set(r.origins) <= fields          # every origin names a field


def test_malformed_nhtsa_file_rejected(tmp_path):
    from pim.io.datasets import NHTSA_FILE, load_nhtsa_car_to_car

    path = _copy(tmp_path, NHTSA_FILE, lambda s: s.replace(",0.126,", ",1.126,"))
    with pytest.raises(ValueError, match=r"column 'cor': 1.126 outside"):
        load_nhtsa_car_to_car(path)
    path = _copy(tmp_path, NHTSA_FILE, lambda s: s.replace("4364,", "4363,"))
    with pytest.raises(ValueError, match="duplicate test '4363'"):
        load_nhtsa_car_to_car(path)


def test_bundled_rows_skip_the_source_lines_and_check_the_header():
    from pim.io.datasets import bundled_rows
    from pim.io.inertia_data import DATA_FILE
    from pim.model.numbers import InputError

    text = (Path(__file__).resolve().parents[3] / "pim" / "io" / "data" / DATA_FILE).read_text()
    lines = text.splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    columns = tuple(lines[header].split(","))
    rows = bundled_rows(DATA_FILE, columns)
    first_line, first_row = rows[0]
    assert first_line == header + 2                      # 1-based, after the header
    assert lines[first_line - 1].startswith(first_row["year"])
    with pytest.raises(InputError, match="columns must be"):
        bundled_rows(DATA_FILE, columns[:-1])
