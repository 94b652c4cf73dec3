"""docs/tuned-scene.md (with its CSV tables and plot) and the ``pim validate-models`` section
of docs/validation.md, written from the study's output (``python -m comparisons.docs
validate-models``).

The section sits between :data:`BEGIN` and :data:`END` in docs/validation.md; everything in
it, prose included, is rendered here from a run of
:func:`comparisons.studies.tuned_scene.study_all` (the same run and report functions as the
command), so no figure in it is typed by hand. :func:`stored_rows` and
:func:`recomputed_verdicts` read the per-test leave-one-out errors back from the docs' CSV
and recompute the statistics, which the default test suite compares with what the docs say.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from comparisons.report.render import markdown_table
from comparisons.report.tables import Table
from comparisons.report.tuned import (
    FILES,
    conclusion,
    median_errors,
    origins_table,
    verdict_sentence,
    write_tuned_study,
)
from comparisons.studies.contact_time import study_classes
from comparisons.report.write import replace_block, write_block
from comparisons.studies.paired_verdict import ALPHA, CONFIDENCE, compare_paired, minimum_tests
from comparisons.studies.tuned_scene import (
    AGREEMENT,
    CLASS_STARTS,
    COARSE_STEPS,
    LOO_STARTS,
    MEASURES,
    MODELS,
    PHYSICAL_RANGES,
    SCENE_MODELS,
    SCENE_PHYSICAL_MODEL,
    SCREEN,
)
from pim.io.output import output_folder, rebase
from pim.io.units import DisplayUnits, convert

#: The docs' units: SI with speeds in m/s (the units of the study's JSON medians).
DOC_UNITS = DisplayUnits("si", "m/s")

__all__ = ["BEGIN", "END", "COMMAND", "DOCS_FILES", "regenerate", "section",
           "replace_section", "results_table", "fits_table", "stored_rows",
           "recomputed_verdicts"]

COMMAND = "python -m comparisons.docs validate-models"
BEGIN = (f"<!-- validate-models: begin (written by `{COMMAND}`; edit "
         "comparisons/docs/validate_models.py, not this text) -->")
END = "<!-- validate-models: end -->"
#: The files of the study kept in docs/ (the HTML report stays with the command's output).
DOCS_FILES = tuple(f for f in FILES if not f.endswith(".html"))
_STARTS = f"{CLASS_STARTS['scene']} / {LOO_STARTS['scene']}"


def _medians(rows) -> str:
    """'velocity [m/s] / yaw rate [deg/s]' medians of prediction rows ('' without rows)."""
    m = median_errors(rows)
    if not m["n"] or math.isnan(m["v"]):
        return ""
    return f"{m['v']:.2f} / {math.degrees(m['yaw']):.1f}"


def results_table(studies) -> Table:
    """Per class and variant: the leave-one-out medians of each model and the verdicts."""
    rows = []
    for st in studies:
        for v in st.variants:
            loo = {m.name: v.rows(m.name, "leave-one-out") for m in MODELS}
            cells = [_medians(loo[m.name]) for m in MODELS]
            c, c0 = v.comparisons["scene"]["score"], v.comparisons["scene-mu0"]["score"]
            cp = v.comparisons[SCENE_PHYSICAL_MODEL.name]["score"]
            rows.append((st.crash_class, v.variant.name, len(st.tests), *cells, c.verdict,
                         _p(c.p_value), c0.verdict, cp.verdict, _p(cp.p_value)))
    return Table("validate-models-results", "Leave-one-out medians (velocity [m/s] / yaw rate "
                 "[deg/s]) and verdicts",
                 ("class", "input variant", "tests", "PIM", "scene, Coulomb mu_c",
                  "scene, mu_c = b abs(mu0)", "scene in physical ranges",
                  "verdict: PIM against the scene (Coulomb)", "p",
                  "verdict with mu_c = b abs(mu0)", "verdict: PIM against the scene in "
                  "physical ranges", "p (physical)"), tuple(rows))


def _p(p) -> str:
    return "" if p is None else f"{p:.2g}"


def fits_table(studies) -> Table:
    """Per class, variant and model: the class fit's rms, parameters, how many starts
    reached it and which parameters sit on a bound or leave the physical ranges."""
    rows = []
    for st in studies:
        for v in st.variants:
            for m in MODELS:
                fit = v.class_fits[m.name]
                flags = sorted({f for p in v.rows(m.name, "class fit") for f in p.flags})
                rows.append((st.crash_class, v.variant.name, m.name, f"{fit.rms:.3f}",
                             f"{fit.agreeing}/{fit.starts}",
                             ", ".join(f"{n} {x:.3g}" for n, x in zip(m.parameters, fit.x,
                                                                        strict=True)),
                             ", ".join(fit.on_bound), ", ".join(flags)))
    return Table("validate-models-fits", "Class fits",
                 ("class", "input variant", "model", "rms [-]", "starts at the best",
                  "parameters", "on a bound", "outside the physical ranges"), tuple(rows))


def _method() -> list[str]:
    ranges = ", ".join(f"{k} {lo:g}-{hi:g} {u}" for k, (lo, hi, u, _) in
                       PHYSICAL_RANGES.items())
    return [
        "`pim validate-models` asks whether relaxing PIM's assumptions predicts real crashes "
        "better. Models of the same case: PIM (epsilon, beta; mu = beta mu0); the "
        "finite-duration point contact on the compiled integrator with the crush's "
        "epsilon, the contact time T, tyre friction during the contact, and one of two "
        "tangential laws with one parameter each: Coulomb mu_c, or mu_c = b |mu0| with mu0 "
        "PIM's critical impulse ratio of the test's own inputs (never its outcome); and the "
        "Coulomb scene held to the physical ranges (T, mu_c, mu_tyre boxed, the contact's "
        "duration and crush kept inside theirs), with its own paired test. The class fit's "
        "profile over the contact time (20-250 ms, the others refitted at each T, a "
        "likelihood-ratio threshold) and the scene with one mechanism switched off at a "
        "time are in [tuned-scene.md](tuned-scene.md).",
        "",
        "Every fit is a least-squares fit of the observed values scaled by 1 mph and 10 deg/s "
        "on the project's batched Levenberg-Marquardt engine: a "
        f"{SCREEN}-point Sobol screen of the parameter box, its best {_STARTS} points "
        "(class fit / each leave-one-out refit; scene) refined to convergence, a start "
        f"counted as reaching the best when its rms is within {AGREEMENT:.0%}. Leave-one-out "
        "refits start from the same screen for every fold (independent of the held-out "
        "test) and take inputs no PIM fit of the held-out test touched (input variants "
        "below). A test's score is the root-mean-square of its scaled residuals; the verdict "
        f"is the paired Wilcoxon signed-rank test of the scores at level {ALPHA:g} with the "
        f"{CONFIDENCE:.0%} bootstrap interval of the median difference, and no verdict below "
        f"{minimum_tests(max(len(m.parameters) for m in MODELS))} tests (the larger model's "
        f"parameters + 2). Fitted scenes outside {ranges} are flagged. The scene steps "
        f"{COARSE_STEPS} times per estimated contact time.",
        "",
        "Input variants: **leak-free** (barrier tests: phi the median of the class's other "
        "tests' published phi, the radius of gyration the median per vehicle type of the "
        "other tests' fitted ones); **published PIM-fitted phi** (each test's own phi, which "
        "Brach et al. fitted with PIM to that test's motion: it leaks the outcome, shown "
        "beside); **published inputs** (the other classes, none of whose inputs the harness "
        "fits). The NHTSA car-to-car outcome is Rose et al.'s PIM output, not measured "
        "motion (`tests/pim/analysis/test_validation.py`): PIM fits it by construction."]


def section(studies) -> str:
    """The validate-models section of docs/validation.md, markers included."""
    lines = [BEGIN, "## The finite-duration scene tuned to the crash tests, against PIM "
             "(`pim validate-models`)", "", "**Conclusion**, per class:", "",
             *[f"- {p}" for p in conclusion(studies, DOC_UNITS)], "", *_method(), "",
             f"Full output: [tuned-scene.md](tuned-scene.md) (`{COMMAND}`).", "",
             markdown_table(results_table(studies)), "", *[
                 f"- {verdict_sentence(st, v, DOC_UNITS)}" for st in studies for v in st.variants],
             "", markdown_table(fits_table(studies)), "",
             "![leave-one-out: scene against PIM](tuned-scene.png)", "",
             "Where each input of the study comes from (`pim.io.datasets` origins; the "
             "variants' replacements of the outcome-derived inputs):", "",
             markdown_table(origins_table(studies)), "", END]
    return "\n".join(lines)


def replace_section(text: str, new: str) -> str:
    """``text`` with its :data:`BEGIN` ... :data:`END` block replaced by ``new``."""
    return replace_block(text, BEGIN, END, new, "docs/validation.md")


def regenerate(docs_dir, studies=None, bar=None) -> list[Path]:
    """Run the study (unless ``studies`` are given) and rewrite its files in ``docs_dir``
    and the section of ``docs_dir/validation.md``."""
    docs = Path(docs_dir)
    studies = study_classes(bar=bar) if studies is None else studies
    with output_folder(docs, "--docs", command=COMMAND, merge=True) as tmp:
        written = write_tuned_study(studies, tmp, DOC_UNITS, COMMAND)
        for path in written:
            if path.name not in DOCS_FILES:
                path.unlink()
        md = write_block(tmp / "validation.md", BEGIN, END, section(studies),
                         source=docs / "validation.md")
        kept = [p for p in written if p.name in DOCS_FILES] + [md]
    return rebase(kept, tmp, docs)


def stored_rows(docs_dir) -> list[dict]:
    """The leave-one-out rows of docs/tuned-scene-predictions.csv, typed."""
    with open(Path(docs_dir) / "tuned-scene-predictions.csv", encoding="utf-8") as f:
        rows = [r for r in csv.DictReader(f) if r["kind"] == "leave-one-out"]
    su = convert(1.0, "speed", DOC_UNITS)[1]
    num = lambda s: math.nan if s == "" else float(s)  # noqa: E731
    return [{"class": r["class"], "variant": r["variant"], "test": r["test"],
             "model": r["model"], "score": num(r["score [-]"]),
             "velocity": num(r[f"velocity error [{su}]"]),
             "yaw": math.radians(num(r["yaw error [deg/s]"]))} for r in rows]


def recomputed_verdicts(docs_dir) -> dict:
    """(class, variant, scene model) -> measure -> :class:`PairedComparison` recomputed from
    the stored per-test errors (:func:`stored_rows`), and (class, variant, model) ->
    median velocity [m/s] and yaw rate [rad/s]."""
    rows = stored_rows(docs_dir)
    groups = {(r["class"], r["variant"]) for r in rows}
    n_parameters = max(len(m.parameters) for m in MODELS)
    out, medians = {}, {}
    for cls, variant in sorted(groups):
        pick = {m.name: sorted((r for r in rows if (r["class"], r["variant"], r["model"])
                                == (cls, variant, m.name)), key=lambda r: r["test"])
                for m in MODELS}
        for m in MODELS:
            medians[(cls, variant, m.name)] = tuple(
                float(np.median([r[k] for r in pick[m.name]])) for k in ("velocity", "yaw"))
        for s in SCENE_MODELS:
            out[(cls, variant, s.name)] = {
                k: compare_paired([r[k] for r in pick["pim"]], [r[k] for r in pick[s.name]],
                                  n_parameters) for k in MEASURES}
    return {"comparisons": out, "medians": medians}
