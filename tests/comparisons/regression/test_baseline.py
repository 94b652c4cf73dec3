"""comparisons.regression.baseline: baselines record, check finds planted drift, bad files are one
line, versions and inputs that changed are reported, references hold to their sources."""

import json
import shutil
from importlib import resources

import numpy as np
import pytest

import pim
import sim
from comparisons.regression.baseline import (
    FORMAT,
    agreement,
    assert_agrees,
    check_baseline,
    dumps_baseline,
    format_report,
    load_baseline,
    load_references,
    make_baseline,
)

RICSAC9 = resources.files("pim.io") / "cases" / "ricsac9.toml"


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A baseline of a copy of ricsac9 (solve, fit, cross-check, Monte Carlo) and hard-pole."""
    folder = tmp_path_factory.mktemp("baseline")
    shutil.copy(RICSAC9, folder / "mine.toml")
    doc = make_baseline([str(folder / "mine.toml"), "hard-pole"], base=folder)
    (folder / "b.json").write_text(json.dumps(doc))
    return folder, doc


def _copy(recorded, tmp_path, edit=None, case_text=None):
    folder, doc = recorded
    doc = json.loads(json.dumps(doc))
    if edit:
        edit(doc)
    (tmp_path / "b.json").write_text(json.dumps(doc))
    (tmp_path / "mine.toml").write_text(case_text or (folder / "mine.toml").read_text())
    return tmp_path / "b.json"


def test_a_fresh_baseline_checks_clean(recorded, tmp_path):
    folder, doc = recorded
    assert doc["format"] == FORMAT and doc["versions"]["numpy"] == np.__version__
    entry = doc["cases"][0]
    assert entry["case"] == "mine.toml"            # relative to the baseline's folder
    assert entry["sections"] == ["solve", "fit", "crosscheck", "uncertainty"]
    assert "reconstruct" in entry["skipped"]
    q = entry["quantities"]["solve.velocity1_x"]
    assert q["unit"] == "m/s" and q["tolerance"]["relative"] == 1e-12
    # the stored value is the closed form's, in SI (the sheet prints -6.126 ft/s)
    assert q["value"] == pytest.approx(-6.126 * 0.3048, rel=2e-3)
    report = check_baseline(_copy(recorded, tmp_path))
    assert report.ok and report.checked > 100 and not report.input_changes
    assert "all" in format_report(report)


def test_changing_a_mass_in_the_case_file_is_drift_and_an_input_change(recorded, tmp_path,
                                                                        monkeypatch):
    monkeypatch.chdir(tmp_path)      # the case is shown by its path from the current folder
    text = (recorded[0] / "mine.toml").read_text().replace("2255.4 lbf", "2300 lbf")
    report = check_baseline(_copy(recorded, tmp_path, case_text=text))
    assert not report.ok
    assert report.input_changes and "SHA-256" in report.input_changes[0]
    names = {d.quantity for d in report.drifts}
    assert {"solve.velocity1_x", "fit.eps", "crosscheck.velocity1_x"} <= names
    table = format_report(report)
    assert "input changed: mine.toml" in table and "solve.velocity1_x" in table
    assert "mph" in table and "ft/s" not in table     # the case's own units (ricsac9: US)
    assert all(d.case == "mine.toml" for d in report.drifts)   # hard-pole did not move


def _set(name, factor=None, shift=None, case=0):
    def edit(doc):
        q = doc["cases"][case]["quantities"][name]
        q["value"] = q["value"] * factor if factor is not None else q["value"] + shift
    return edit


def test_a_planted_drift_beyond_tolerance_is_the_only_row(recorded, tmp_path):
    report = check_baseline(_copy(recorded, tmp_path, _set("solve.impulse_n", 1 + 1e-9)))
    assert [d.quantity for d in report.drifts] == ["solve.impulse_n"]
    d = report.drifts[0]
    assert d.unit == "N*s" and abs(d.difference) > d.tolerance


def test_a_quantity_new_since_the_baseline_is_a_note_not_drift(recorded, tmp_path):
    def forget(doc):
        del doc["cases"][1]["quantities"]["solve.mu0"]
    report = check_baseline(_copy(recorded, tmp_path, forget))
    assert report.ok and "hard-pole: 1 quantities are new" in report.notes[0]
    assert "solve.mu0" in format_report(report)


def test_a_change_within_tolerance_passes(recorded, tmp_path):
    # 1e-13 relative: below the closed form's round-off tolerance of 1e-12
    assert check_baseline(_copy(recorded, tmp_path, _set("solve.impulse_n", 1 + 1e-13))).ok


def test_monte_carlo_is_bit_for_bit_on_the_same_versions_statistical_across(recorded,
                                                                             tmp_path):
    name = "uncertainty.speed1.p50"
    q = recorded[1]["cases"][0]["quantities"][name]
    half = q["tolerance"]["absolute"] / 2          # half its statistical tolerance
    assert half > 0
    same = check_baseline(_copy(recorded, tmp_path, _set(name, shift=half)))
    assert [d.quantity for d in same.drifts] == [name]      # same versions: bit for bit

    def older_numpy(doc):
        _set(name, shift=half)(doc)
        doc["versions"]["numpy"] = "0.0.1"
    across = check_baseline(_copy(recorded, tmp_path, older_numpy))
    assert across.ok and across.version_changes["numpy"][0] == "0.0.1"
    assert "version differs: numpy 0.0.1" in format_report(across)


def test_the_seeded_monte_carlo_repeats_exactly():
    a = make_baseline(["ricsac9"], sections=["uncertainty"])["cases"][0]["quantities"]
    b = make_baseline(["ricsac9"], sections=["uncertainty"])["cases"][0]["quantities"]
    assert a == b


@pytest.mark.parametrize("text, why", [
    ("{", "unreadable JSON"),
    ('{"format": "other"}', "format"),
    (json.dumps({"format": FORMAT, "cases": []}), "no cases"),
    (json.dumps({"format": FORMAT, "cases": [{"case": "ricsac9"}]}), "lacks"),
    (json.dumps({"format": FORMAT, "cases": [{"case": "ricsac9", "sha256": "x", "quantities": {
        "solve.q": {"value": "1.0", "kind": "dimensionless", "tolerance": {}}}}]}),
     "malformed"),
])
def test_a_malformed_baseline_is_one_line(tmp_path, text, why):
    path = tmp_path / "b.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=why) as err:
        load_baseline(path)
    assert "\n" not in str(err.value)


def test_a_missing_baseline_names_the_file(tmp_path):
    with pytest.raises(ValueError, match="no such baseline file"):
        check_baseline(tmp_path / "none.json")


def test_unknown_section_and_unknown_case_are_errors(recorded, tmp_path):
    with pytest.raises(ValueError, match="unknown section 'solver'"):
        make_baseline(["ricsac9"], sections=["solver"])
    with pytest.raises(ValueError, match="holds no case"):
        check_baseline(_copy(recorded, tmp_path), ["ricsac9-brach"])


REFS = '''
[[reference]]
case = "ricsac9"
quantity = "solve.speed1"
kind = "speed"
value = "{speed}"
relative = 2e-3
source = "design sheet"

[[reference]]
case = "ricsac9"
quantity = "solve.yaw_rate1"
kind = "angular_velocity"
at_most = "{limit}"
source = "a bound"
'''


def test_references_hold_todays_values_to_an_independent_source(tmp_path):
    # the sheet prints 9.669 mph for vehicle 1's final speed (ricsac9.md)
    path = tmp_path / "refs.toml"
    path.write_text(REFS.format(speed="9.669 mph", limit="-199 deg/s"))
    refs = load_references(path)
    r = refs["ricsac9"]["solve.speed1"]
    assert r["value"] == pytest.approx(9.669 * 0.44704) and r["unit"] == "m/s"
    doc = make_baseline(["ricsac9"], sections=["solve"], references=refs)
    (tmp_path / "b.json").write_text(json.dumps(doc))
    assert check_baseline(tmp_path / "b.json").ok
    # a wrong published value (10 mph) and a violated bound: both named with their source
    path.write_text(REFS.format(speed="10 mph", limit="-200 deg/s"))
    doc["cases"][0]["references"] = load_references(path)["ricsac9"]
    (tmp_path / "b.json").write_text(json.dumps(doc))
    report = check_baseline(tmp_path / "b.json")
    assert [(d.quantity, d.against) for d in report.drifts] == [
        ("solve.speed1", "design sheet"), ("solve.yaw_rate1", "at most: a bound")]


@pytest.mark.parametrize("text", ['[[reference]]\ncase = "x"\n', "[[reference]\n",
                                  '[[reference]]\ncase="x"\nquantity="q"\nkind="speed"\n'
                                  'source="s"\nvalue="fast"\n'])
def test_bad_references_are_one_line(tmp_path, text):
    path = tmp_path / "refs.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as err:
        load_references(path)
    assert "\n" not in str(err.value) and "refs.toml" in str(err.value)


def test_agreement_is_the_projects_one_error_measure(ricsac9):
    analytic = pim.solve(ricsac9)
    simulated = sim.simulate(ricsac9)
    # docs/sim.md: RICSAC 9 agrees with the rigid scene to round-off (about 1e-15)
    assert assert_agrees(analytic, simulated, 1e-9) < 1e-9
    assert agreement(simulated, analytic) == agreement(analytic, simulated)
    other = pim.solve(ricsac9, 0.5, 1.0)
    error = agreement(analytic, other)
    # independent: largest change error over largest change, by hand
    k1 = np.sqrt(ricsac9.vehicle1.yaw_inertia / ricsac9.vehicle1.mass)
    k2 = np.sqrt(ricsac9.vehicle2.yaw_inertia / ricsac9.vehicle2.mass)
    d = [*(other.velocity1 - analytic.velocity1), *(other.velocity2 - analytic.velocity2),
         k1 * (other.yaw_rate1 - analytic.yaw_rate1), k2 * (other.yaw_rate2 - analytic.yaw_rate2)]
    c = [*(analytic.velocity1 - ricsac9.vehicle1.velocity),
         *(analytic.velocity2 - ricsac9.vehicle2.velocity),
         k1 * analytic.yaw_rate1, k2 * analytic.yaw_rate2]
    assert error == pytest.approx(np.max(np.abs(d)) / np.max(np.abs(c)), rel=1e-12)
    with pytest.raises(AssertionError, match="largest error in the velocity changes"):
        assert_agrees(analytic, other, 1e-3)
    with pytest.raises(TypeError):
        agreement(simulated, simulated)


def test_the_file_has_one_line_per_quantity_and_reads_back(recorded):
    doc = recorded[1]
    text = dumps_baseline(doc)
    assert json.loads(text) == json.loads(json.dumps(doc))
    line = next(x for x in text.splitlines() if '"solve.velocity1_x"' in x)
    assert json.loads(line.strip().rstrip(",").split(": ", 1)[1])["unit"] == "m/s"


def test_energy_loss_percent_is_shown_in_percent(tmp_path):
    """Issue 28: `check` gave energy_loss_percent the unit "-" (a percent share)."""
    doc = make_baseline(["hard-pole"], sections=["solve"])
    q = doc["cases"][0]["quantities"]["solve.energy_loss_percent"]
    assert (q["kind"], q["unit"]) == ("percent", "percent")
    # a baseline recorded before kind "percent" existed reads the same
    old = json.loads(json.dumps(doc))
    old["cases"][0]["quantities"]["solve.energy_loss_percent"].update(
        kind="dimensionless", unit="dimensionless")
    for name, data in (("new.json", doc), ("old.json", old)):
        data["cases"][0]["quantities"]["solve.energy_loss_percent"]["value"] += 1.0
        (tmp_path / name).write_text(json.dumps(data))
        text = format_report(check_baseline(tmp_path / name))
        row = next(line for line in text.splitlines() if line.startswith("hard-pole"))
        assert row.split()[-2:] == ["%", "baseline"], row


# Issue 28: `pim baseline cases/my-case.toml --out baselines/mine.json` stored the case's
# absolute path; the documented pim_check("cases/my-case.toml", ...) failed ("holds no
# case") and a moved copy failed ("neither a file nor a bundled case").
@pytest.fixture(scope="module")
def project(tmp_path_factory):
    """A project: cases/my-case.toml (a copy of hard-pole), baselines/mine.json."""
    root = tmp_path_factory.mktemp("project")
    (root / "cases").mkdir()
    (root / "baselines").mkdir()
    shutil.copy(resources.files("pim.io") / "cases" / "hard-pole.toml",
                root / "cases" / "my-case.toml")
    doc = make_baseline([str(root / "cases" / "my-case.toml"), "hard-barrier"],
                        sections=["solve"], base=root / "baselines")
    (root / "baselines" / "mine.json").write_text(json.dumps(doc))
    return root, doc


def test_case_paths_are_stored_relative_to_the_baseline(project):
    _, doc = project
    assert [e["case"] for e in doc["cases"]] == ["../cases/my-case.toml", "hard-barrier"]


def test_a_moved_project_checks_clean(project, tmp_path, monkeypatch):
    moved = tmp_path / "clone"
    shutil.copytree(project[0], moved)
    monkeypatch.chdir(moved)
    shutil.rmtree(project[0] / "cases")         # the original is gone: nothing reads it
    try:
        report = check_baseline("baselines/mine.json")
        assert report.ok and not report.input_changes
        for name in ("cases/my-case.toml", "my-case.toml", str(moved / "cases" / "my-case.toml"),
                     "../cases/my-case.toml", "hard-pole"):      # as typed, as stored, by name
            report = check_baseline("baselines/mine.json", [name])
            assert report.ok and report.checked == len(doc_quantities(project, 0)), name
        monkeypatch.chdir(tmp_path)             # another folder: the path's tail still names it
        assert check_baseline(moved / "baselines" / "mine.json", ["cases/my-case.toml"]).ok
        with pytest.raises(ValueError, match=r"holds no case cases/other.toml \(it holds "):
            check_baseline(moved / "baselines" / "mine.json", ["cases/other.toml"])
    finally:
        shutil.copytree(moved / "cases", project[0] / "cases")


def doc_quantities(project, i):
    return project[1]["cases"][i]["quantities"]


def test_an_old_baseline_with_an_absolute_path_works_while_the_file_is_there(project, tmp_path):
    root, doc = project
    old = json.loads(json.dumps(doc))
    old["cases"][0]["case"] = str(root / "cases" / "my-case.toml")   # as recorded before
    (tmp_path / "old.json").write_text(json.dumps(old))
    assert check_baseline(tmp_path / "old.json").ok
    old["cases"][0]["case"] = str(tmp_path / "gone" / "my-case.toml")
    (tmp_path / "old.json").write_text(json.dumps(old))
    with pytest.raises(ValueError) as err:
        check_baseline(tmp_path / "old.json")
    assert str(err.value) == (
        f"case {str(tmp_path / 'gone' / 'my-case.toml')!r}: no such file; the baseline stores "
        "this absolute path (recorded before pim stored case paths relative to the baseline "
        "file): restore the file there, or record the baseline again with pim baseline (it "
        "then moves with its cases)")


def test_cases_findings_prefix_each_case_and_take_a_case_without_coefficients(tmp_path):
    from comparisons.regression.baseline import cases_findings
    from pim.model.plausibility import findings

    good, rec = pim.load_case("ricsac9"), pim.load_case("ricsac9-reconstruct")
    text = resources.files("pim.io.cases").joinpath("ricsac9.toml").read_text()
    path = tmp_path / "gains.toml"
    path.write_text(text.replace("restitution = 0.355\nbeta = 1\n",
                                 "restitution = 1\nbeta = 3\n"))
    bad = pim.load_case(str(path))
    found = cases_findings({"a": good, "b": rec, "c": bad})
    assert all(t.startswith(("a: ", "b: ", "c: ")) for t in found.all)
    own = findings(good, pim.solve(good))
    assert [t for t in found.warnings if t.startswith("a: ")] == [f"a: {t}" for t in own.warnings]
    assert found.errors and all(t.startswith("c: ") for t in found.errors)
