"""Bad input: every mistake gives a ValueError naming the field (library) or one line and
exit code 2 (command line); and US and SI inputs describe the same physics."""

import math
from importlib import resources

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pim
from pim_cli.main import main

RICSAC = (resources.files("pim.io") / "cases" / "ricsac9.toml").read_text()


def variant(tmp_path, old, new, count=1):
    assert RICSAC.count(old) >= 1, old
    path = tmp_path / "case.toml"
    path.write_text(RICSAC.replace(old, new, count))
    return path


BAD = [
    # (replace this, with this, words the message must contain)
    ('weight = "2255.4 lbf"\n', "", ["vehicle1", "mass", "weight"]),
    ('weight = "2255.4 lbf"', 'mass = "-3 kg"', ["vehicle1.mass", "> 0"]),
    ('weight = "2255.4 lbf"', 'mass = 0', ["vehicle1.mass", "> 0"]),
    ('radius_of_gyration = "3.7313536 ft"', 'yaw_inertia = "-1 kg*m**2"',
     ["vehicle1.yaw_inertia", "> 0"]),
    ('radius_of_gyration = "3.7313536 ft"', 'yaw_inertia = 0', ["vehicle1.yaw_inertia", "> 0"]),
    ('weight = "2255.4 lbf"', "mass = nan", ["vehicle1.mass", "finite"]),
    ('heading = "180 deg"', 'heading = nan', ["vehicle1.heading", "finite"]),
    ('velocity = ["-31.09 ft/s", "0 ft/s"]', 'velocity = ["-31.09 furlongz/s", "0 ft/s"]',
     ["vehicle1.velocity[0]", "unknown unit"]),
    ('velocity = ["-31.09 ft/s", "0 ft/s"]', 'velocity = ["31 kg", "0 ft/s"]',
     ["vehicle1.velocity[0]", "[length] / [time]"]),
    ('velocity = ["-31.09 ft/s", "0 ft/s"]', 'velocity = ["-31.09 ft/s"]',
     ["vehicle1.velocity", "two values"]),
    ('heading = "180 deg"', 'headding = "180 deg"', ["vehicle1", "unknown key 'headding'"]),
    ('normal_angle = "0 deg"', 'normal_angle = "0 deg"\nrestitusion = 0.3',
     ["impact", "unknown key 'restitusion'"]),
    ("restitution = 0.355", "restitution = 1.5", ["impact.restitution", "[0, 1]"]),
    ("restitution = 0.355", "restitution = -0.1", ["impact.restitution", "[0, 1]"]),
    ('normal_angle = "0 deg"', 'normal_angle = "0 m"', ["impact.normal_angle", "expected angle"]),
    ('name = "ricsac9"', 'name = "ricsac9', ["malformed TOML"]),
    ('[impact]', '[impactt]', ["unknown key 'impactt'"]),
    ('vehicle1.yaw_rate = "-180 deg/s"', 'vehicle1.yaw_rat = "-180 deg/s"',
     ["measured.vehicle1", "unknown key 'yaw_rat'"]),
    ('cg = ["4.7737051 ft", "0.5017366 ft"]', 'cg = ["4.7737051 ft", "0.5017366 ft"]\ntheta = 0',
     ["vehicle1", "'theta'", "convention"]),
]


@pytest.mark.parametrize("old, new, words", BAD, ids=[w[-1] for _, _, w in BAD])
def test_library_names_the_field(tmp_path, old, new, words):
    path = variant(tmp_path, old, new)
    with pytest.raises(ValueError) as info:
        pim.load_case(path)
    for word in words:
        assert word in str(info.value), str(info.value)


@pytest.mark.parametrize("old, new, words", BAD[:6] + BAD[10:13] + BAD[15:16],
                         ids=[w[-1] for _, _, w in BAD[:6] + BAD[10:13] + BAD[15:16]])
def test_command_line_prints_one_line_and_exits_2(tmp_path, capsys, old, new, words):
    path = variant(tmp_path, old, new)
    assert main(["solve", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1 and "Traceback" not in err
    assert words[0] in err


@pytest.mark.parametrize("args, words", [
    (["solve", "ricsac9", "--eps", "1.5"], ["eps", "[0, 1]"]),
    (["solve", "ricsac9", "--eps", "nan"], ["eps", "[0, 1]"]),
    (["solve", "no-such-case"], ["no-such-case", "ricsac9"]),
    (["solve", "ricsac9", "--units", "furlongs"], ["furlongs"]),
])
def test_command_line_options(capsys, args, words):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    for word in words:
        assert word in err


def test_library_rejects_bad_arrays():
    v = dict(mass=1000.0, yaw_inertia=1500.0, cg=(0.0, 0.0), velocity=(1.0, 0.0))
    with pytest.raises(ValueError, match="mass must be > 0"):
        pim.Vehicle(**{**v, "mass": np.array([1000.0, -1.0])})
    with pytest.raises(ValueError, match="velocity must be finite"):
        pim.Vehicle(**{**v, "velocity": (np.nan, 0.0)})
    with pytest.raises(ValueError, match=r"cg must be an \[x, y\] pair"):
        pim.Vehicle(**{**v, "cg": (0.0, 0.0, 0.0)})
    with pytest.raises(ValueError, match="fixed obstacle must be 0"):
        pim.Vehicle(**{**v, "mass": np.inf, "yaw_inertia": np.inf})
    with pytest.raises(ValueError, match="only vehicle2"):
        pim.Case(pim.Vehicle.obstacle((0, 0)), pim.Vehicle(**v), pim.Impact((0, 0), 0))
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match=r"eps .* \[0, 1\]"):
        pim.solve(case, np.array([0.2, 1.2]))
    with pytest.raises(ValueError, match="beta"):
        pim.solve(case, 0.3, np.inf)


def test_fixed_obstacle_from_a_case_file(tmp_path):
    text = (resources.files("pim.io") / "cases" / "hard-barrier.toml").read_text()
    path = tmp_path / "wall.toml"
    path.write_text(text.replace("fixed = true", 'fixed = true\nmass = "1000 kg"'))
    with pytest.raises(ValueError, match="vehicle2.mass: a fixed obstacle has no mass"):
        pim.load_case(path)


US_CASE = """
name = "units"
[vehicle1]
weight = "{w1} lbf"
yaw_inertia = "{i1} slug*ft**2"
cg = ["{x1} ft", "{y1} ft"]
heading = "{h1} deg"
velocity = ["{vx1} mph", "{vy1} mph"]
yaw_rate = "{w} deg/s"
[vehicle2]
weight = "{w2} lbf"
radius_of_gyration = "{k2} in"
cg = ["{x2} ft", "{y2} ft"]
heading = "{h2} deg"
velocity = ["{vx2} ft/s", "{vy2} ft/s"]
[impact]
point = ["{cx} ft", "{cy} ft"]
normal_angle = "{g} deg"
"""

SI_CASE = """
name = "units"
[vehicle1]
mass = {m1}
yaw_inertia = {I1}
cg = [{x1}, {y1}]
heading = {h1}
velocity = [{vx1}, {vy1}]
yaw_rate = {w}
[vehicle2]
mass = {m2}
yaw_inertia = {I2}
cg = [{x2}, {y2}]
heading = {h2}
velocity = [{vx2}, {vy2}]
[impact]
point = [{cx}, {cy}]
normal_angle = {g}
"""

# Exact definitions (NIST SP 811): 1 ft = 0.3048 m, 1 lb = 0.45359237 kg, g0 = 9.80665 m/s^2,
# 1 mph = 0.44704 m/s, 1 in = 0.0254 m. These are written out here, in the test only, as an
# independent check of the unit parsing (the library itself delegates to pint).
FT, LB, G0, MPH, INCH = 0.3048, 0.45359237, 9.80665, 0.44704, 0.0254


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.5, 5.0), min_size=20, max_size=20))
def test_us_and_si_inputs_give_the_same_physics(tmp_path_factory, xs):
    us = dict(w1=2000 * xs[0], i1=500 * xs[1], x1=-xs[2], y1=xs[3] - 2.5, h1=36 * xs[4],
              vx1=10 * xs[5], vy1=xs[6] - 2.5, w=20 * (xs[7] - 2.5), w2=3000 * xs[8],
              k2=20 * xs[9], x2=xs[10], y2=xs[11] - 2.5, h2=72 * xs[12], vx2=-5 * xs[13],
              vy2=xs[14], cx=xs[15] - 2.5, cy=xs[16] - 2.5, g=180 + 10 * (xs[17] - 2.5))
    si = dict(m1=us["w1"] * LB, I1=us["i1"] * LB * G0 / FT * FT ** 2, x1=us["x1"] * FT,
              y1=us["y1"] * FT, h1=np.radians(us["h1"]), vx1=us["vx1"] * MPH,
              vy1=us["vy1"] * MPH, w=np.radians(us["w"]), m2=us["w2"] * LB,
              I2=us["w2"] * LB * (us["k2"] * INCH) ** 2, x2=us["x2"] * FT, y2=us["y2"] * FT,
              h2=np.radians(us["h2"]), vx2=us["vx2"] * FT, vy2=us["vy2"] * FT,
              cx=us["cx"] * FT, cy=us["cy"] * FT, g=np.radians(us["g"]))
    folder = tmp_path_factory.mktemp("units")
    (folder / "us.toml").write_text(US_CASE.format(**us))
    (folder / "si.toml").write_text(SI_CASE.format(**{k: repr(float(v)) for k, v in si.items()}))
    a, b = pim.load_case(folder / "us.toml"), pim.load_case(folder / "si.toml")
    ra, rb = pim.solve(a, 0.3, 0.8), pim.solve(b, 0.3, 0.8)
    np.testing.assert_allclose(ra.velocity1, rb.velocity1, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(ra.velocity2, rb.velocity2, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(ra.yaw_rate1, rb.yaw_rate1, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(ra.energy_loss, rb.energy_loss, rtol=1e-9, atol=1e-6)


# --- Issue 22: inputs accepted that should not be -------------------------------------


@pytest.mark.parametrize("old, new, field", [
    ('weight = "2255.4 lbf"', 'weight = "2255.4 lbf # comment"', "vehicle1.weight"),
    ('heading = "180 deg"', 'heading = "180 deg;"', "vehicle1.heading"),
    ('yaw_rate = "0 deg/s"', 'yaw_rate = "30 deg/s !"', "vehicle1.yaw_rate"),
    ('weight = "2255.4 lbf"', "weight = \"2255.4 lbf 'x'\"", "vehicle1.weight"),
    ('normal_angle = "0 deg"', "normal_angle = -90", "impact.normal_angle"),
    ('weight = "2255.4 lbf"', 'weight = "4800 lbs"', "4800 lbf"),
])
def test_trailing_text_and_bare_degrees_exit_2_naming_the_field(tmp_path, capsys, old, new,
                                                                 field):
    """Before: each solved with exit 0."""
    assert main(["solve", str(variant(tmp_path, old, new))]) == 2
    err = capsys.readouterr().err
    assert field in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("nested", [
    "a = " + "{b = " * 500 + "1" + "}" * 500,
    "a = " + "[" * 500 + "]" * 500,
    "[" + ".".join(["evidence"] + ["x"] * 500) + "]",
])
def test_deep_nesting_is_one_line(tmp_path, capsys, nested):
    """Before: 500 nested tables raised RecursionError."""
    path = tmp_path / "case.toml"
    path.write_text(RICSAC + "\n" + nested + "\n")
    assert main(["solve", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and ("nest" in err or "unknown key" in err), err


def test_a_huge_description_is_refused_at_once(tmp_path, capsys):
    """Before: a 150 000-character description took over 60 s (the unit-system scan)."""
    import time

    path = variant(tmp_path, 'description = "RICSAC',
                   'description = "1 m' + " " * 150_000 + 'x RICSAC')
    start = time.perf_counter()
    assert main(["solve", str(path)]) == 2
    assert time.perf_counter() - start < 5
    assert "description has 15" in capsys.readouterr().err


def test_cg_to_front_places_the_outline(tmp_path):
    """The vehicle table's cg_to_front: the outline spans [a - length, a] along the heading
    (before: outlines were always centred on the CG)."""
    case = pim.load_case(variant(tmp_path, 'length = "13.0 ft"',
                                 'length = "13.0 ft"\ncg_to_front = "5 ft"'))
    assert case.vehicle1.cg_to_front == pytest.approx(5 * 0.3048)
    from pim.plotting.drawing import outline

    corners = outline(case.vehicle1)
    # heading 180 deg: the front is at cg_x - 5 ft, the rear at cg_x + 8 ft
    cg_x = case.vehicle1.cg[0]
    assert corners[:, 0].min() == pytest.approx(cg_x - 5 * 0.3048)
    assert corners[:, 0].max() == pytest.approx(cg_x + 8 * 0.3048)


@pytest.mark.parametrize("new, words", [
    ('length = "13.0 ft"\ncg_to_front = "14 ft"',
     ["vehicle1.cg_to_front = '14 ft'", "between 0 and vehicle1.length = '13.0 ft'"]),
    ('cg_to_front = "5 ft"', ["cg_to_front", "needs vehicle1.length"]),
])
def test_cg_to_front_outside_the_outline_is_refused(tmp_path, capsys, new, words):
    assert main(["solve", str(variant(tmp_path, 'length = "13.0 ft"', new))]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err


def test_flipped_normal_hints_at_its_direction_in_the_case_units(tmp_path, capsys):
    """Before: "no impact ... (u_n = 9.476 m/s > 0)" for a US case, no hint."""
    path = variant(tmp_path, 'normal_angle = "0 deg"', 'normal_angle = "180 deg"')
    assert main(["solve", str(path)]) == 1
    err = capsys.readouterr().err
    # u_n = 31.09 ft/s = 21.2 mph (the staged speed), in the field's unit
    assert "u_n = 21.2 mph" in err and "m/s" not in err and "ft/s" not in err
    assert "from vehicle 2 toward vehicle 1" in err and "try 0 deg" in err


@pytest.mark.parametrize("psi", ["90 deg", "-90 deg", "270 deg"])
def test_contact_plane_angle_gives_the_normal_toward_vehicle_1(tmp_path, psi):
    """PC-Crash's contact plane by its direction psi: Gamma = psi +- 90 deg, the normal
    pointing toward vehicle 1's CG (RICSAC 9: the plane is the y axis, vehicle 1 at +x)."""
    path = variant(tmp_path, 'normal_angle = "0 deg"', f'contact_plane_angle = "{psi}"')
    gamma = float(pim.load_case(str(path)).impact.normal_angle)
    assert (math.cos(gamma), math.sin(gamma)) == pytest.approx((1.0, 0.0), abs=1e-15)


@pytest.mark.parametrize("new,words", [
    ('point = [0, 0]\nnormal_angle = "0 deg"\ncontact_plane_angle = "90 deg"', "not both"),
    ('point = ["0 ft", "0.5017366 ft"]\ncontact_plane_angle = "0 deg"', "through vehicle 1"),
    ('point = [0, 0]\ncontact_plane_angle = "ninety"', "impact.contact_plane_angle"),
])
def test_contact_plane_angle_errors_name_the_field(tmp_path, new, words):
    text = RICSAC.replace('point = ["0 ft", "0 ft"]\nnormal_angle = "0 deg"', new)
    path = tmp_path / "case.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=words):
        pim.load_case(str(path))


# --- Issue 28: the [units] table chooses the units results are presented in -------------

@pytest.mark.parametrize("table, system, speed", [
    ("", "us", None),                                   # written in ft: us, mph by default
    ('[units]\nspeed = "m/s"\n', "us", "m/s"),
    ('[units]\nsystem = "si"\n', "si", None),
    ('[units]\nsystem = "si"\nspeed = "ft/s"\n', "si", "ft/s"),
])
def test_the_units_table_sets_the_presentation(tmp_path, table, system, speed):
    path = tmp_path / "case.toml"
    path.write_text(RICSAC + "\n" + table)
    case = pim.load_case(path)
    assert (case.units, case.speed_unit) == (system, speed)
    assert case.vehicle1.velocity[0] == pytest.approx(-31.09 * 0.3048)   # read as before


def test_a_units_table_in_mph_does_not_make_an_si_file_us(tmp_path):
    text = RICSAC.replace("lbf", "N").replace(" ft", " m").replace("slug", "kg")
    path = tmp_path / "case.toml"
    path.write_text(text.replace("ft/s", "km/h") + '\n[units]\nspeed = "mph"\n')
    case = pim.load_case(path)
    assert (case.units, case.speed_unit) == ("si", "mph")


@pytest.mark.parametrize("table, words", [
    ('[units]\nspeed = "kph"\n', ["units.speed", "'km/h', 'mph', 'm/s', 'ft/s'", "'kph'"]),
    ('[units]\nsystem = "metric"\n', ["units.system", "'si', 'us'"]),
    ('[units]\nsped = "mph"\n', ["units", "unknown key 'sped'"]),
    ('units = "mph"\n', ["units must be a table"]),
])
def test_a_bad_units_table_names_the_key(tmp_path, capsys, table, words):
    path = tmp_path / "case.toml"
    path.write_text(table + RICSAC if not table.startswith("[") else RICSAC + "\n" + table)
    with pytest.raises(ValueError) as info:
        pim.load_case(path)
    assert all(w in str(info.value) for w in words), str(info.value)
    assert main(["solve", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1 and words[0] in err
# Issue 28: what a new user wrote, and what the message says.
def test_a_missing_table_is_named_apart_from_the_file_name(tmp_path):
    """Before: "bad2/noimpact.toml.impact is missing" (the file name glued to the key)."""
    folder = tmp_path / "bad2"
    folder.mkdir()
    path = folder / "noimpact.toml"
    path.write_text(RICSAC[:RICSAC.index("[impact]")] + RICSAC[RICSAC.index("[measured]"):])
    with pytest.raises(ValueError) as info:
        pim.load_case(path)
    assert str(info.value) == f"{path}: table [impact] is missing"


def test_an_unknown_key_gets_the_closest_known_one(tmp_path):
    """Before: no "did you mean" for a key (the units had one)."""
    path = variant(tmp_path, 'yaw_rate = "0 deg/s"\nlength = "13.0 ft"',
                   'yawrate = "0 deg/s"\nlength = "13.0 ft"')
    with pytest.raises(ValueError, match=r"vehicle1: unknown key 'yawrate'; did you mean "
                                         r"'yaw_rate'\? \(allowed: body, cg, "):
        pim.load_case(path)


def test_a_negative_brach_distance_is_quoted_as_written(tmp_path):
    """Before: "vehicle1.d (distance CG to C) must be >= 0 [m]" for a case written in ft."""
    text = (resources.files("pim.io") / "cases" / "ricsac9-brach.toml").read_text()
    assert 'd = "4.800 ft"' in text
    path = tmp_path / "case.toml"
    path.write_text(text.replace('d = "4.800 ft"', "d = '-4.8 ft'", 1))
    with pytest.raises(ValueError) as info:
        pim.load_case(path)
    assert str(info.value) == ("vehicle1.d = '-4.8 ft' must be >= 0 (the distance from the CG "
                               "to C)")


def test_degree_and_percent_signs_in_a_case_file(tmp_path):
    """"10°", "35.5 %" and "100 %" read as 10 deg, 0.355 and 1 (refused before)."""
    path = variant(tmp_path, 'normal_angle = "0 deg"\nrestitution = 0.355\nbeta = 1',
                   'normal_angle = "10°"\nrestitution = "35.5 %"\nbeta = "100 %"')
    case = pim.load_case(path)
    assert float(case.impact.normal_angle) == pytest.approx(math.pi / 18, rel=1e-15)
    assert float(case.impact.restitution) == pytest.approx(0.355, rel=1e-15)
    assert float(case.impact.beta) == 1.0


@pytest.mark.parametrize("table, old, new, words", [
    ("ricsac9", 'vehicle1.mass = {normal = "1.4 slug"}', 'vehicle1.mas = {normal = "1.4 slug"}',
     "uncertainty: unknown input 'vehicle1.mas'; did you mean 'vehicle1.mass'? (allowed: "),
    ("ricsac9-reconstruct", 'vehicle1.speed = {bounds', 'vehicle1.sped = {bounds',
     "unknown: 'vehicle1.sped' cannot be solved for; did you mean 'vehicle1.speed'? "
     "(allowed: "),
])
def test_every_unknown_name_of_a_case_file_gets_the_closest_known_one(tmp_path, table, old,
                                                                      new, words):
    """Issue 28: "did you mean" for keys (the units had one) in every table."""
    text = (resources.files("pim.io") / "cases" / f"{table}.toml").read_text()
    assert old in text
    path = tmp_path / "case.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(ValueError) as info:
        pim.load_case(path)
    assert str(info.value).startswith(words), str(info.value)


def test_a_case_name_too_long_for_a_file_is_an_input_error():
    """pim.load_case('x' * 5000) raised OSError ("File name too long") from the file
    system's look-up (issue 33 point 11): an input error naming the case, cut short."""
    from pim.model.numbers import InputError

    for name in ("x" * 5000, "a\x00b"):
        with pytest.raises(InputError, match="is neither a file nor a bundled case") as info:
            pim.load_case(name)
        assert len(str(info.value)) < 1000
    assert "... (5000 characters)" in str(pytest.raises(InputError, pim.load_case,
                                                        "x" * 5000).value)
