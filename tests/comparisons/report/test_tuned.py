"""Tables, verdicts and files of the tuned-scene study (comparisons.report.tuned)."""

import math

from comparisons.report import tuned as R
from comparisons.studies.tuned_scene import ClassStudy, FitResult, Prediction


def _study(pim_v, scene_v, kind="leave-one-out"):
    preds = []
    for i, (a, b) in enumerate(zip(pim_v, scene_v, strict=True)):
        preds.append(Prediction("c", f"t{i}", "PIM", kind, (0.2, 0.9), 0.1, a, 0.05, 1e-4))
        preds.append(Prediction("c", f"t{i}", "scene", kind, (0.2, 1.0, 0.1, 0.7), -0.1, b,
                                0.1, 2e-2))
    fits = {"PIM": FitResult((0.2, 0.9), 1.0, 10, 0.1),
            "scene": FitResult((0.2, 1.0, 0.1, 0.7), 1.0, 10, 1.0)}
    return ClassStudy("class A", tuple(f"t{i}" for i in range(len(pim_v))), tuple(preds),
                      fits, 3.0)


def test_verdict_names_the_better_model_and_the_ratio():
    text = R.verdict(_study([1.0, 2.0, 3.0], [0.5, 1.0, 1.5]))
    assert "the tuned scene predicts" in text and "(2x)" in text
    assert "1.00 against 2.00 m/s" in text
    text = R.verdict(_study([1.0, 1.0, 1.0], [3.0, 3.0, math.nan]), "us")
    assert "PIM predicts" in text and "ft/s" in text and "failed on 1" in text


def test_a_class_of_one_reports_its_fits():
    text = R.verdict(_study([0.4], [0.2], kind="per-test fit"))
    assert "too few for leave-one-out" in text and "0.40 m/s" in text


def test_files(tmp_path):
    st = _study([1.0, 2.0, 3.0], [0.5, 1.0, 1.5])
    files = R.write_tuned_study([st], tmp_path, "si", "pim validate-models",
                                {"class A": (0.01, 0.002)})
    assert [f.name for f in files] == ["tuned-scene.md", "tuned-scene-summary.csv",
                                       "tuned-scene-predictions.csv", "tuned-scene.html",
                                       "tuned-scene.png"]
    md = files[0].read_text()
    assert "pim validate-models" in md and "iihs-car-to-car: not run" in md
    summary = R.summary_table([st]).rows
    assert len(summary) == 2 and summary[0][3] == 3
