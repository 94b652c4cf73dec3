"""Bundled crash-test data: values as published, malformed copies rejected with a clear error."""

import math

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
