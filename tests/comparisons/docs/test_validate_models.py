"""The validate-models docs are what the code gives (comparisons.docs.validate_models):
the statistics recomputed from the per-test errors the docs store, one class refitted in the
default suite, the whole regeneration behind ``slow``."""

import csv
import math
import shutil
from pathlib import Path

import pytest

from comparisons.docs import validate_models as D
from comparisons.docs_numbers import drift
from comparisons.report.tuned import conclusion
from comparisons.studies import contact_time as C
from comparisons.studies import crash_records as R
from comparisons.studies import tuned_scene as T

DOCS = Path(__file__).resolve().parents[3] / "docs"


def _csv(name, folder=DOCS) -> list[dict]:
    with open(folder / name, encoding="utf-8") as f:
        return list(csv.DictReader(f))


def _section() -> str:
    text = (DOCS / "validation.md").read_text(encoding="utf-8")
    assert text.count(D.BEGIN) == 1 and text.count(D.END) == 1
    return text.split(D.BEGIN)[1].split(D.END)[0]


def _row(section: str, cls: str, variant: str) -> list[str]:
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[:2] == [cls, variant]:
            return cells
    raise AssertionError(f"no row for {cls} / {variant}")


def test_the_docs_verdicts_are_what_their_stored_errors_give():
    """Recompute every paired test from the per-test leave-one-out errors in
    tuned-scene-predictions.csv: the verdicts, p-values and intervals of
    tuned-scene-verdicts.csv and of the table in validation.md must be the same."""
    again = D.recomputed_verdicts(DOCS)
    stored = _csv("tuned-scene-verdicts.csv")
    assert all(r["verdict"] == "too few tests to decide" for r in stored if r["tests"] == "0")
    stored = [r for r in stored if r["tests"] != "0"]       # a class of one: no held-out test
    assert len(stored) == len(again["comparisons"]) > 0
    section = _section()
    for row in stored:
        c = again["comparisons"][(row["class"], row["variant"], row["scene"])]
        s = c["score"]
        assert row["verdict"] == s.verdict
        for key, measure in (("p (score)", "score"), ("p (velocity)", "velocity"),
                             ("p (yaw rate)", "yaw")):
            p = c[measure].p_value
            assert (row[key] == "") if p is None else float(row[key]) == pytest.approx(p)
        assert float(row["median score difference [-]"]) == pytest.approx(s.median_difference)
        where = {"scene": (7, 8), "scene-physical": (10, 11)}.get(row["scene"])
        if where:
            cells = _row(section, row["class"], row["variant"])
            assert cells[where[0]] == s.verdict
            assert cells[where[1]] == ("" if s.p_value is None else f"{s.p_value:.2g}")


def test_the_docs_medians_are_what_their_stored_errors_give():
    section = _section()
    again = D.recomputed_verdicts(DOCS)["medians"]
    models = [m.name for m in T.MODELS]
    for (cls, variant, model), (v, yaw) in again.items():
        cell = _row(section, cls, variant)[3 + models.index(model)]
        assert cell == f"{v:.2f} / {math.degrees(yaw):.1f}"


@pytest.fixture(scope="module")
def ricsac():
    (st,) = C.study_classes(classes=["ricsac"])
    return st


def _conclusion(cls: str) -> str:
    """The paragraph of ``cls`` in the conclusion leading docs/tuned-scene.md."""
    text = (DOCS / "tuned-scene.md").read_text(encoding="utf-8")
    head = text.split("## Conclusion", 1)[1].split("\n## ", 1)[0]
    (para,) = [p for p in head.split("\n\n") if p.startswith(f"**{cls}**")]
    return para


def test_the_conclusion_leads_the_docs_and_holds_what_the_code_gives(ricsac):
    """The RICSAC class run again (its study, profile and physical scene): its paragraph of
    the generated conclusion, leading docs/tuned-scene.md and the validation.md section, is
    what the code writes now (numbers within round-off, text word for word)."""
    text = (DOCS / "tuned-scene.md").read_text(encoding="utf-8")
    assert text.index("## Conclusion") < text.index("## Verdicts")
    (generated,) = conclusion([ricsac], D.DOC_UNITS)
    assert drift(_conclusion(R.RICSAC), generated) == []
    assert drift(next(line for line in _section().splitlines()
                      if line.startswith(f"- **{R.RICSAC}**")), f"- {generated}") == []


def test_the_docs_profile_is_what_the_code_gives(ricsac):
    rows = [r for r in _csv("tuned-scene-profile.csv") if r["class"] == R.RICSAC]
    p = ricsac.profile
    assert [float(r["T [ms]"]) for r in rows] == [t * 1e3 for t in p.times]
    for r, f in zip(rows, p.fits, strict=True):
        assert float(r["class-fit rms [-]"]) == pytest.approx(f.rms, abs=2e-3)
        assert float(r["threshold [-]"]) == pytest.approx(p.threshold, abs=2e-3)


def test_one_class_refitted_gives_the_docs_numbers(ricsac):
    """The RICSAC class (three tests, one variant) run again: every prediction of the docs'
    table within its printed precision."""
    st = ricsac
    stored = {(r["variant"], r["test"], r["model"], r["kind"]): r
              for r in _csv("tuned-scene-predictions.csv") if r["class"] == R.RICSAC}
    rows = [p for v in st.variants for p in v.predictions]
    assert len(rows) == len(stored)
    for p in rows:
        r = stored[(p.variant, p.test, p.model, p.kind)]
        assert float(r["score [-]"]) == pytest.approx(p.score, abs=0.01)
        assert float(r["velocity error [m/s]"]) == pytest.approx(p.velocity_error, abs=0.01)
        assert float(r["yaw error [deg/s]"]) == pytest.approx(math.degrees(p.yaw_error),
                                                              abs=0.1)


def test_the_section_is_replaced_in_place():
    text = "head\n" + D.BEGIN + "\nold\n" + D.END + "\ntail\n"
    assert D.replace_section(text, "NEW") == "head\nNEW\ntail\n"
    with pytest.raises(ValueError, match="markers"):
        D.replace_section("no markers", "NEW")


#: Columns compared as they are printed (text that rounding may move between machines).
_SKIP = ("parameters", "outside the physical ranges", "starts at the best")


def _numbers_close(a: dict, b: dict, key) -> None:
    for column, x in a.items():
        if column in _SKIP:
            continue
        y = b[column]
        try:
            fx, fy = float(x), float(y)
        except ValueError:
            assert x == y, (key, column)
            continue
        tol = 0.2 if "deg" in column else 0.05 if column.startswith("p (") else 0.02
        assert fx == pytest.approx(fy, abs=tol) or (math.isnan(fx) and math.isnan(fy)), (
            key, column, x, y)


@pytest.mark.slow
def test_regenerating_the_docs_reproduces_them(tmp_path):
    """The whole study run again into a copy of docs/: every number of the tables within
    the printed precision, every verdict word for word."""
    shutil.copy(DOCS / "validation.md", tmp_path / "validation.md")
    D.regenerate(tmp_path)
    for name, key in (("tuned-scene-predictions.csv", ("class", "variant", "test", "model",
                                                       "kind")),
                      ("tuned-scene-verdicts.csv", ("class", "variant", "scene")),
                      ("tuned-scene-profile.csv", ("class", "variant", "T [ms]")),
                      ("tuned-scene-mechanisms.csv", ("class", "mechanism"))):
        new = {tuple(r[k] for k in key): r for r in _csv(name, tmp_path)}
        old = {tuple(r[k] for k in key): r for r in _csv(name)}
        assert new.keys() == old.keys()
        for k, row in new.items():
            _numbers_close(row, old[k], k)
    new = (tmp_path / "tuned-scene.md").read_text(encoding="utf-8")
    old = (DOCS / "tuned-scene.md").read_text(encoding="utf-8")
    assert drift(old.split("## Verdicts")[0], new.split("## Verdicts")[0]) == []
