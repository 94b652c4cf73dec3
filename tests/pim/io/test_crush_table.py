"""The [evidence.vehicleN.crush] table (pim.io.crush_table): SI and US units give the same
profile, vehicle-class defaults, and every bad input named with its field and range."""

import numpy as np
import pytest

from pim.io.crush_table import CRUSH_KEYS, STIFFNESS_CLASS_FILE, load_stiffness_classes, parse_crush
from pim.io.datasets import data_path, source_lines
from pim.io.units import convert, parse

WHERE = "evidence.vehicle1.crush"
US = {"side": "front", "width": "60 in",
      "depths": ["10 in", "12 in", "14 in", "12 in", "9 in", "5 in"],
      "stiffness_a": "300 lbf/in", "stiffness_b": "100 lbf/in^2", "offset": "2 in",
      "depth_sigma": "1 in"}
INCH, LBF_IN, LBF_IN2 = 0.0254, 4.4482216152605 / 0.0254, 4.4482216152605 / 0.0254**2


def _si():
    return {"side": "front", "width": f"{60 * INCH} m",
            "depths": [f"{c * INCH} m" for c in (10, 12, 14, 12, 9, 5)],
            "stiffness_a": f"{300 * LBF_IN} N/m", "stiffness_b": f"{100 * LBF_IN2} N/m^2",
            "offset": f"{2 * INCH * 1000} mm", "depth_sigma": f"{2.54} cm"}


def test_us_and_si_tables_give_the_same_profile():
    us, si = parse_crush(US, WHERE), parse_crush(_si(), WHERE)
    assert us.width == pytest.approx(1.524, rel=1e-12)
    assert us.depths == pytest.approx((0.254, 0.3048, 0.3556, 0.3048, 0.2286, 0.127), rel=1e-12)
    assert us.stiffness_a == pytest.approx(52538.05, rel=1e-6)
    assert us.stiffness_b == pytest.approx(689475.73, rel=1e-6)
    for name in ("width", "stiffness_a", "stiffness_b", "offset", "depth_sigma", "energy"):
        assert getattr(si, name) == pytest.approx(getattr(us, name), rel=1e-9), name
    assert si.depths == pytest.approx(us.depths, rel=1e-12)
    assert us.where == WHERE


def test_energy_round_trips_to_us_units():
    """The CRASH3 six-station energy in ft*lbf computed by hand in US units equals the SI
    energy converted back (A 300 lbf/in, B 100 lbf/in^2, G = A^2 / 2B = 450 lbf)."""
    profile = parse_crush(US, WHERE)
    c, L, a, b = (10, 12, 14, 12, 9, 5), 60.0, 300.0, 100.0
    inch_lbf = L / 5 * (a / 2 * (c[0] + 2 * sum(c[1:5]) + c[5])
                        + b / 6 * (c[0]**2 + 2 * sum(x * x for x in c[1:5]) + c[5]**2
                                   + sum(c[i] * c[i + 1] for i in range(5)))
                        + 5 * a * a / (2 * b))
    value, unit = convert(profile.energy, "energy", "us")
    assert unit == "ft lbf"
    assert value == pytest.approx(inch_lbf / 12, rel=1e-9)


def test_stiffness_units_parse_and_convert():
    assert parse("1 lbf/in", "force_per_length", "a") == pytest.approx(LBF_IN, rel=1e-12)
    assert parse("1 kN/m", "force_per_length", "a") == 1000.0
    assert parse("1 lbf/in**2", "force_per_area", "b") == pytest.approx(LBF_IN2, rel=1e-12)
    value, unit = convert(np.array([LBF_IN]), "force_per_length", "us")
    assert value[0] == pytest.approx(1.0) and unit == "lbf/inch"
    with pytest.raises(ValueError, match=r"x: '300 lbf' is not a force per length"):
        parse("300 lbf", "force_per_length", "x")


def test_optional_keys_and_extra_keys():
    table = dict(US, width_sigma="1 in", stiffness_a_sigma="30 lbf/in",
                 stiffness_b_sigma="10 lbf/in^2", energy_sigma=0.1, stiffness_g="450 lbf",
                 partition="normal")
    p = parse_crush(table, WHERE, extra_keys=("partition",))
    assert p.energy_sigma_relative == 0.1
    assert p.stiffness_g == pytest.approx(450 * 4.4482216152605)
    assert p.energy == pytest.approx(parse_crush(US, WHERE).energy, rel=1e-6)
    assert p.energy_sigma > parse_crush(US, WHERE).energy_sigma > 0
    assert "partition" not in CRUSH_KEYS
    with pytest.raises(ValueError, match=r"unknown key 'partition'"):
        parse_crush(table, WHERE)


def test_side_and_vehicle_dimensions():
    side = dict(US, side="left", width="100 in", offset="-20 in")
    p = parse_crush(side, WHERE, vehicle_length=4.8, vehicle_width=1.8)
    assert p.normal_body.tolist() == [0.0, 1.0] and p.centroid_body[0] == pytest.approx(-0.508)


def _error(table, **kw):
    with pytest.raises(ValueError) as info:
        parse_crush(table, WHERE, **kw)
    return str(info.value)


@pytest.mark.parametrize("change, message", [
    ({"depths": ["10 in", "-2 in", "3 in"]},
     r"evidence\.vehicle1\.crush\.depths\[1\] = '-2 in': a crush depth must be >= 0"),
    ({"depths": ["10 in"]}, r"crush\.depths: 1 depth given; at least 2 are needed"),
    ({"depths": "10 in"}, r"crush\.depths must be a list"),
    ({"depths": ["10 in", "12 kg"]}, r"crush\.depths\[1\]: '12 kg' is not a length"),
    ({"side": "roof"}, r"crush\.side = 'roof' is not a side \(allowed: front, rear, left, "
                       r"right\)"),
    ({"stiffness_a": "-300 lbf/in"}, r"crush\.stiffness_a must be > 0"),
    ({"stiffness_b": "0 lbf/in^2"}, r"crush\.stiffness_b must be > 0"),
    ({"stiffness_b": "100 lbf/in"}, r"crush\.stiffness_b: '100 lbf/in' is not a force per "
                                    r"area"),
    ({"width": "0 in"}, r"crush\.width must be > 0"),
    ({"depth_sigma": "-1 in"}, r"crush\.depth_sigma = -0\.0254 m must be finite and >= 0"),
    ({"energy_sigma": -0.1}, r"crush\.energy_sigma_relative = -0\.1 - must be finite"),
    ({"colour": "red"}, r"crush: unknown key 'colour'"),
])
def test_bad_tables_name_the_field(change, message):
    table = {k: v for k, v in dict(US, **change).items()}
    with pytest.raises(ValueError, match=message):
        parse_crush(table, WHERE)


@pytest.mark.parametrize("missing", ["side", "width", "depths"])
def test_missing_keys(missing):
    table = {k: v for k, v in US.items() if k != missing}
    assert _error(table) == f"{WHERE}: missing {missing}"


def test_stiffness_must_be_given_one_way():
    assert "not both" in _error(dict(US, **{"class": "midsize car"}))


def test_damage_must_fit_on_the_vehicle():
    msg = _error(US, vehicle_length=4.5, vehicle_width=1.4)
    assert msg == (f"{WHERE}.width = 1.52 m is longer than the damaged front side (the "
                   f"vehicle's width, 1.4 m); allowed: (0, 1.4 m]")
    side = dict(US, side="right", width="200 in")
    assert "longer than the damaged right side (the vehicle's length, 4.5 m)" in _error(
        side, vehicle_length=4.5)
    deep = dict(US, side="left", width="50 in", depths=["10 in", "80 in"])
    assert _error(deep, vehicle_width=1.8) == (
        f"{WHERE}.depths: a crush of 2.03 m is deeper than the vehicle (width 1.8 m); "
        f"allowed: [0, 1.8 m]")
    front_deep = dict(US, depths=["10 in", "200 in"])
    assert "deeper than the vehicle (length 4.5 m)" in _error(front_deep, vehicle_length=4.5)
    shifted = dict(US, offset="20 in")
    assert "beyond the end of the front side; allowed: |offset| + width/2 <= 0.9 m" in _error(
        shifted, vehicle_width=1.8)
    assert parse_crush(US, WHERE, vehicle_length=4.5, vehicle_width=1.8).width == 1.524


def test_class_defaults_from_the_bundled_table():
    """CRASH3 Table 8-2 category 4 (the bundled "midsize car"): front 356 lb/in, 34 lb/in^2,
    G 1874 lb; side 143 lb/in, 50 lb/in^2, G 203 lb."""
    table = {k: v for k, v in US.items() if not k.startswith("stiffness")}
    front = parse_crush(dict(table, **{"class": "Midsize Car"}), WHERE)
    assert front.stiffness_a == pytest.approx(356 * LBF_IN, rel=1e-9)
    assert front.stiffness_b == pytest.approx(34 * LBF_IN2, rel=1e-9)
    assert front.stiffness_g == pytest.approx(1874 * 4.4482216152605, rel=1e-9)
    side = parse_crush(dict(table, side="right", **{"class": "midsize car"}), WHERE)
    assert side.stiffness_a == pytest.approx(143 * LBF_IN, rel=1e-9)
    classes = load_stiffness_classes()
    assert classes["midsize car", "left"].stiffness_b == pytest.approx(50 * LBF_IN2)
    assert "CRASH3" in " ".join(source_lines(data_path(STIFFNESS_CLASS_FILE)))
    assert _error(dict(table, **{"class": "bus"})) == (
        f"{WHERE}.class = 'bus' has no front stiffness (known classes: midsize car)")
    assert _error(dict(table, side="rear", **{"class": "midsize car"})) == (
        f"{WHERE}.class = 'midsize car' has no rear stiffness (known classes: none)")
    assert "or a class (known: midsize car)" in _error(
        {k: v for k, v in US.items() if k != "stiffness_b"})


def test_class_table_errors_name_file_line_and_column(tmp_path):
    path = tmp_path / "classes.csv"
    header = "class,side,A_lbf_per_in,B_lbf_per_in2,G_lbf,A_sd_lbf_per_in,B_sd_lbf_per_in2,source"
    for row, message in [("x,top,1,1,,,,s", "classes.csv line 3: side 'top' is not one of"),
                         ("x,front,-1,1,,,,s", "line 3 column 'A_lbf_per_in': '-1' must be a "
                                               "finite number > 0"),
                         ("x,front,1,b,,,,s", "column 'B_lbf_per_in2': 'b' is not a number"),
                         ("x,front,1,1,,,s", "line 3: 7 fields, expected 8")]:
        path.write_text(f"# source\n{header}\n{row}\n")
        with pytest.raises(ValueError, match=message):
            load_stiffness_classes(path)
    path.write_text("# source\nclass,side\n")
    with pytest.raises(ValueError, match="header must be"):
        load_stiffness_classes(path)
    with pytest.raises(ValueError, match="cannot read the stiffness classes"):
        load_stiffness_classes(tmp_path / "missing.csv")
