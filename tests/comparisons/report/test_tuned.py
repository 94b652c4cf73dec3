"""Tables, verdict sentences, JSON and files of the tuned-scene study
(comparisons.report.tuned), on constructed studies."""

import dataclasses
import json
import math

import numpy as np
import pytest

from comparisons.report import tuned as R
from comparisons.studies.contact_time import (
    MECHANISMS,
    MechanismResult,
    Profile,
    lr_threshold,
)
from comparisons.studies.crash_records import InputVariant
from comparisons.studies.tuned_scene import (
    MODELS,
    ClassStudy,
    MultiStartFit,
    Prediction,
    VariantStudy,
    loo_comparisons,
)
from pim.io.datasets import PIM_OUTPUT


def _rows(errors: dict, kind: str) -> list:
    out = []
    for model, values in errors.items():
        n_par = len(next(m for m in MODELS if m.name == model).parameters)
        for i, v in enumerate(values):
            flags = ("contact time",) if model != "pim" and i == 0 else ()
            out.append(Prediction("class A", f"t{i}", model, kind, "leak-free",
                                  tuple([0.5] * n_par), v / 0.44704, 0.1, v, 0.1 * v,
                                  math.nan if model == "pim" else 0.03,
                                  math.nan if model == "pim" else 0.4, 0.6,
                                  math.nan if model == "pim" else 0.7, flags))
    return out


def _profile(rms, times=(0.02, 0.05, 0.1, 0.15, 0.25)) -> Profile:
    fits = tuple(MultiStartFit((0.1, 2.0, t, 0.5), r, 8, 4, 8, ()) for t, r in
                 zip(times, rms, strict=True))
    free = MultiStartFit((0.1, 2.0, times[int(np.argmin(rms))], 0.5), min(rms), 16, 5, 16, ())
    return Profile(times, fits, free, 48, lr_threshold(min(rms), 48))


def _study(pim_v, scene_v, profile=None, mechanisms=()) -> ClassStudy:
    errors = {"pim": pim_v, "scene": scene_v, "scene-mu0": scene_v,
              "scene-physical": [2 * e for e in pim_v]}
    preds = tuple(_rows(errors, "class fit") + _rows(errors, "leave-one-out"))
    fits = {m.name: MultiStartFit(tuple([0.5] * len(m.parameters)), 1.2, 16, 7, 16, ())
            for m in MODELS}
    loo = {m.name: tuple(MultiStartFit(tuple([0.5] * len(m.parameters)), 1.3, 4, 2, 4, ())
                         for _ in pim_v) for m in MODELS}
    v = VariantStudy(InputVariant("leak-free", "the test's inputs", {"speed": "measured"}),
                     preds, fits, loo, loo_comparisons(preds, 4))
    return ClassStudy("class A", tuple(f"t{i}" for i in range(len(pim_v))),
                      "post-impact velocity and yaw rate", "measured", 4, (v,),
                      (0.01, 0.002), 3.0, profile, mechanisms)


def test_verdict_sentence_states_the_verdict_and_the_medians():
    st = _study([1.0, 2.0, 3.0, 1.5, 2.5, 1.2, 0.9], [0.5, 1.0, 1.5, 0.7, 1.2, 0.6, 0.4])
    text = R.verdict_sentence(st, st.variants[0])
    assert text.startswith("class A (7 tests, leak-free): the scene predicts better.")
    assert "PIM 5.40 km/h" in text and "p = 0.016" in text      # 1.5 m/s x 3.6
    assert "2 of the scenes' 14 held-out predictions lie outside the physical ranges" in text
    small = _study([1.0, 2.0, 3.0], [0.5, 1.0, 1.5])
    text = R.verdict_sentence(small, small.variants[0], "us")
    assert "too few tests to decide" in text and "mph" in text and "no test run" in text


def test_json_holds_verdicts_p_values_medians_and_agreement():
    st = _study([1.0, 2.0, 3.0, 1.5, 2.5, 1.2, 0.9], [1.1, 1.9, 3.2, 1.4, 2.6, 1.1, 1.0])
    data = json.loads(json.dumps(R.study_json([st], "si", 12.5)))
    v = data["classes"]["class A"]["variants"]["leak-free"]
    assert v["verdict"].startswith("no significant difference (p = ") and 0 < v["p_value"] <= 1
    assert set(v["models"]) == {"pim", "scene", "scene-mu0", "scene-physical"}
    pim = v["models"]["pim"]
    assert pim["loo_velocity_median"] == 1.5
    assert np.isclose(pim["loo_yaw_median"], math.degrees(0.15))
    assert pim["class_fit"]["agreeing"] == 7 and pim["loo_starts"]["agreeing"] == [2] * 7
    assert v["comparisons"]["scene-mu0"]["p_value_yaw"] is not None
    assert data["wall_time"] == 12.5 and data["speed_unit"] == "km/h"   # "si": km/h


def test_tables_and_files(tmp_path):
    st = _study([1.0, 2.0, 3.0, 1.5, 2.5, 1.2, 0.9], [0.5, 1.0, 1.5, 0.7, 1.2, 0.6, 0.4])
    summary = R.summary_table([st], "us")
    assert len(summary.rows) == 4 and "mph" in summary.columns[10]
    assert summary.rows[1][13] == 1                  # one scene row flagged
    verdicts = R.verdict_table([st])
    assert [r[4] for r in verdicts.rows] == ["the scene predicts better"] * 2 + [
        "PIM predicts better"]
    files = R.write_tuned_study([st], tmp_path, "si", "pim validate-models")
    assert [f.name for f in files] == list(R.FILES)
    md = files[0].read_text()
    assert "pim validate-models" in md and "iihs-car-to-car: not run" in md
    assert "Wilcoxon" in md and "<table" in files[1].read_text()


def test_the_page_leads_with_the_verdicts(tmp_path):
    """Issue 27: tuned-scene.html was built by its own HTML code (no generator, no notes,
    tables without ids); now the pipeline writes it, the verdicts first, each table with its
    id and CSV, the plot inline."""
    st = _study([1.0, 2.0, 3.0, 1.5, 2.5, 1.2, 0.9], [0.5, 1.0, 1.5, 0.7, 1.2, 0.6, 0.4])
    R.write_tuned_study([st], tmp_path, "us", "pim validate-models")
    page = (tmp_path / "tuned-scene.html").read_text()
    assert page.startswith("<!DOCTYPE html>")
    assert '<meta name="generator" content="pim validate-models">' in page
    first = page.index('<section id="verdicts"')
    assert first < page.index('<section id="method"') < page.index('id="table-tuned-scene-')
    verdict = R.verdict_sentence(st, st.variants[0], "us")
    assert page.index("the scene predicts better", first) < page.index('id="method"')
    assert "mph" in verdict and verdict.split(":")[0] in page
    for name in ("verdicts", "summary", "predictions"):
        assert f'id="table-tuned-scene-{name}"' in page and f"tuned-scene-{name}.csv" in page
    assert page.count("data:image/png;base64,") == 2        # the errors and the profile
    md = (tmp_path / "tuned-scene.md").read_text()
    assert md.index("## Verdicts") < md.index("## Method") < md.index("## Every prediction")


_NS = [1.0, 2.0, 3.0, 1.5, 2.5, 1.2, 0.9]


def _mechanisms():
    """The full scene rising with T; the geometry frozen: flat; the others rising more."""
    shapes = ([2.06, 2.12, 2.25, 2.36, 2.57], [2.01, 2.04, 2.04, 2.01, 2.03],
              [2.07, 2.30, 2.89, 3.65, 5.16], [2.24, 2.39, 2.52, 2.56, 2.76])
    return tuple(MechanismResult(m, _profile(r)) for m, r in zip(MECHANISMS, shapes,
                                                                 strict=True))


def test_the_physical_variant_has_its_own_verdict_p_and_interval_in_json_and_tables():
    st = _study(_NS, _NS, _profile([2.06, 2.12, 2.25, 2.36, 2.57]))
    data = json.loads(json.dumps(R.study_json([st], "si")))
    phys = data["classes"]["class A"]["physical"]
    assert phys["verdict"] == "PIM predicts better" and 0 < phys["p_value"] < 0.05
    assert phys["median_score_difference"] > 0 and len(phys["interval"]) == 2
    assert phys["box"]["T [s]"] == [0.05, 0.25] and phys["box"]["mu_c"] == [0.0, 1.0]
    assert "physical" in data["classes"]["class A"]["variants"]["leak-free"]
    rows = [r for r in R.verdict_table([st]).rows if r[2] == "scene-physical"]
    assert len(rows) == 1 and rows[0][4] == "PIM predicts better"
    assert "held to the physical ranges" in R.verdict_sentence(st, st.variants[0])


def test_the_profile_in_json_holds_t_in_seconds_scores_parameters_and_threshold():
    st = _study(_NS, _NS, _profile([2.06, 2.12, 2.25, 2.36, 2.57]))
    prof = json.loads(json.dumps(R.study_json([st], "si")))["classes"]["class A"]["profile"]
    assert prof["T"] == [0.02, 0.05, 0.1, 0.15, 0.25]
    assert prof["score"] == [2.06, 2.12, 2.25, 2.36, 2.57]
    assert prof["parameters"][2] == {"epsilon": 0.1, "mu_c": 2.0, "T [s]": 0.1,
                                     "mu_tyre": 0.5}
    # chi2_1(0.95) = 3.841 (any chi-square table): 2.06 exp(3.841 / 96) = 2.1441
    assert prof["threshold"] == pytest.approx(2.1441, abs=2e-4)
    assert prof["kept_T"] == [0.02, 0.05] and prof["physical_T_excluded"] is True
    table = R.profile_table([st])
    assert [r[5] for r in table.rows] == [True, True, False, False, False]


def test_the_conclusion_leads_the_page_and_names_the_mechanism(tmp_path):
    st = _study(_NS, _NS, _profile([2.06, 2.12, 2.25, 2.36, 2.57]), _mechanisms())
    flat = _study(_NS, _NS, _profile([3.75, 3.72, 3.72, 3.73, 3.74]))
    first, second = R.conclusion([st, flat])
    assert "exclude the full-scale contact time 70-150 ms" in first
    assert "threshold 2.144 (48 residuals) keeps 20-50 ms" in first
    assert "PIM predicts better (p = " in first                   # the physical verdict
    assert ("with the geometry change during contact (rotation and the moving contact "
            "point) switched off the profile stays within its threshold") in first
    assert "do not constrain the contact time" in second
    finite = _study(_NS, _NS, _profile([3.5, 3.1, 2.7, 2.69, 2.66]))
    (third,) = R.conclusion([finite])
    assert "exclude a near-instant contact (T up to 50 ms) and keep the full-scale" in third
    assert "does not reproduce these tests as well as PIM" in first
    assert "Caveat" not in first
    output = dataclasses.replace(finite, outcome_origin=PIM_OUTPUT)
    assert "PIM fits it by construction" in R.conclusion([output])[0]
    R.write_tuned_study([st], tmp_path, "si", "pim validate-models")
    md = (tmp_path / "tuned-scene.md").read_text()
    assert md.index("## Conclusion") < md.index("## Verdicts")
    assert "the geometry change during contact" in md.split("## Verdicts")[0]
    mech = (tmp_path / "tuned-scene-mechanisms.csv").read_text()
    assert "no geometry change" in mech and (tmp_path / "tuned-scene-profile.png").is_file()
