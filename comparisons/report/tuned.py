"""Tables, plot, verdicts and report of the tuned-scene study (``pim validate-models``,
:mod:`comparisons.studies.tuned_scene`), written through the one report pipeline.

Consumes :class:`comparisons.studies.tuned_scene.ClassStudy` objects; speaks the user's units
(``units`` "si" or "us" through :func:`pim.io.units.convert`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from comparisons.report.document import Bullets, Document, Figure, Paragraph, Section
from comparisons.report.tables import Table, fmt_value
from comparisons.report.write import write_document
from comparisons.studies.tuned_scene import UNRUNNABLE, ClassStudy
from pim.io.files import save_figure
from pim.io.units import convert

__all__ = ["KINDS", "predictions_table", "summary_table", "verdict", "plot_tuned_study",
           "tuned_document", "write_tuned_study", "median_errors"]

KINDS = ("per-test fit", "class fit", "leave-one-out")


def _speed(x, units):
    return float(convert(x, "speed", units)[0])


def median_errors(rows) -> dict:
    """Median |delta-V error|, velocity error [m/s], yaw error [rad/s], time [s] of rows
    (NaN rows, failed scenes, are counted as failures)."""
    ok = [r for r in rows if math.isfinite(r.velocity_error)]
    if not ok:
        return {"n": len(rows), "failed": len(rows), "dv": math.nan, "v": math.nan,
                "yaw": math.nan, "time": math.nan}
    return {"n": len(rows), "failed": len(rows) - len(ok),
            "dv": float(np.median([abs(r.delta_v_error) for r in ok])),
            "v": float(np.median([r.velocity_error for r in ok])),
            "yaw": float(np.median([r.yaw_error for r in ok])),
            "time": float(np.median([r.wall_time for r in rows]))}


def predictions_table(studies, units: str = "si") -> Table:
    """Every prediction: class, test, model, kind, parameters and errors."""
    su = convert(1.0, "speed", units)[1]
    rows = []
    for st in studies:
        for p in st.predictions:
            rows.append((st.crash_class, p.test, p.model, p.kind,
                         " ".join(f"{v:.3g}" for v in p.x), _speed(p.delta_v_error, units),
                         _speed(p.velocity_error, units), math.degrees(p.yaw_error),
                         p.wall_time * 1e3))
    f2 = lambda x: "" if x != x else f"{x:.2f}"  # noqa: E731
    return Table("tuned-scene-predictions",
                 "Each test predicted by each model: own parameters, class parameters, and "
                 "class parameters fitted without the test (leave-one-out)",
                 ("class", "test", "model", "kind", "parameters",
                  f"delta-V error [{su}]", f"velocity error [{su}]", "yaw error [deg/s]",
                  "time [ms]"), tuple(rows),
                 {f"delta-V error [{su}]": f2, f"velocity error [{su}]": f2,
                  "yaw error [deg/s]": lambda x: "" if x != x else f"{x:.1f}",
                  "time [ms]": fmt_value})


def summary_table(studies, units: str = "si") -> Table:
    """Medians per class, model and kind."""
    su = convert(1.0, "speed", units)[1]
    rows = []
    for st in studies:
        for kind in KINDS:
            for model in ("PIM", "scene"):
                m = median_errors(st.rows(model, kind))
                if m["n"]:
                    params = st.class_fits[model].x if kind == "class fit" else ()
                    rows.append((st.crash_class, model, kind, m["n"], m["failed"],
                                 _speed(m["dv"], units), _speed(m["v"], units),
                                 math.degrees(m["yaw"]), m["time"] * 1e3,
                                 " ".join(f"{v:.3g}" for v in params)))
    f2 = lambda x: "" if x != x else f"{x:.2f}"  # noqa: E731
    return Table("tuned-scene-summary", "Median errors per class, model and kind",
                 ("class", "model", "kind", "tests", "failed",
                  f"median abs delta-V error [{su}]", f"median velocity error [{su}]",
                  "median yaw error [deg/s]", "time per prediction [ms]",
                  "class parameters"), tuple(rows),
                 {f"median abs delta-V error [{su}]": f2, f"median velocity error [{su}]": f2,
                  "median yaw error [deg/s]": lambda x: "" if x != x else f"{x:.1f}",
                  "time per prediction [ms]": fmt_value})


def verdict(study: ClassStudy, units: str = "si") -> str:
    """One sentence: which model predicts the held-out tests better, by how much."""
    a = median_errors(study.rows("PIM", "leave-one-out"))
    b = median_errors(study.rows("scene", "leave-one-out"))
    su = convert(1.0, "speed", units)[1]
    if not a["n"]:
        a = median_errors(study.rows("PIM", "per-test fit"))
        b = median_errors(study.rows("scene", "per-test fit"))
        return (f"{study.crash_class} ({a['n']} test(s), too few for leave-one-out): fitted "
                f"with its own parameters, PIM misses the post-impact velocity by "
                f"{_speed(a['v'], units):.2f} {su} and the yaw rate by "
                f"{math.degrees(a['yaw']):.1f} deg/s, the tuned scene by "
                f"{_speed(b['v'], units):.2f} {su} and {math.degrees(b['yaw']):.1f} deg/s.")
    better = "the tuned scene" if b["v"] < a["v"] else "PIM"
    ratio = max(a["v"], b["v"]) / max(min(a["v"], b["v"]), 1e-12)
    return (f"{study.crash_class} ({a['n']} tests, leave-one-out): {better} predicts the "
            f"held-out post-impact velocity better, median error "
            f"{_speed(min(a['v'], b['v']), units):.2f} against "
            f"{_speed(max(a['v'], b['v']), units):.2f} {su} ({ratio:.2g}x); yaw rate "
            f"PIM {math.degrees(a['yaw']):.1f}, scene {math.degrees(b['yaw']):.1f} deg/s; "
            f"one prediction costs {a['time'] * 1e3:.2g} ms (PIM) and "
            f"{b['time'] * 1e3:.2g} ms (scene)"
            + (f"; the scene failed on {b['failed']} test(s)" if b["failed"] else "") + ".")


def plot_tuned_study(studies, units: str = "si"):
    """Leave-one-out errors, scene against PIM, per class: velocity (top) and yaw rate
    (bottom); points below the diagonal are tests the scene predicts better. A Figure."""
    from matplotlib.figure import Figure

    su = convert(1.0, "speed", units)[1]
    fig = Figure(figsize=(4.2 * len(studies), 7.6), layout="constrained")
    axes = np.atleast_2d(fig.subplots(2, len(studies), squeeze=False))
    for j, st in enumerate(studies):
        kind = "leave-one-out" if st.rows("PIM", "leave-one-out") else "per-test fit"
        pim_rows = {r.test: r for r in st.rows("PIM", kind)}
        pairs = [(pim_rows[r.test], r) for r in st.rows("scene", kind) if r.test in pim_rows]
        for i, (attr, scale, label) in enumerate(
                (("velocity_error", lambda x: _speed(x, units), f"velocity error [{su}]"),
                 ("yaw_error", math.degrees, "yaw-rate error [deg/s]"))):
            ax = axes[i, j]
            xs = [scale(getattr(a, attr)) for a, _ in pairs]
            ys = [scale(getattr(b, attr)) for _, b in pairs]
            ax.scatter(xs, ys, s=26, color="C0", edgecolors="k", linewidths=0.3)
            top = max([v for v in xs + ys if v == v] + [1e-3]) * 1.1
            ax.plot([0, top], [0, top], color="0.5", ls="--", lw=1)
            ax.set_xlim(0, top)
            ax.set_ylim(0, top)
            ax.set_xlabel(f"PIM, {label}")
            ax.set_ylabel(f"tuned scene, {label}")
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title(f"{st.crash_class}\n{kind}, {len(pairs)} test(s)", fontsize=9)
    return fig


def tuned_document(studies, units: str = "si", command: str = "",
                   checks: dict | None = None) -> Document:
    """The study as a report: one verdict per class, what was not run, the coarse scene's
    check against a finer one, the plot, the medians and every prediction.

    ``checks``: class -> (speed, yaw-rate) difference of the coarse scene against the fine
    one at the class parameters [m/s, rad/s].
    """
    su = convert(1.0, "speed", units)[1]
    notes = [f"{name}: not run ({why})." for name, why in UNRUNNABLE.items()]
    for name, (dv, dw) in (checks or {}).items():
        notes.append(f"{name}: the coarse scene differs from a 10x finer one by "
                     f"{_speed(dv, units):.3f} {su} and {math.degrees(dw):.2f} deg/s at the "
                     f"class parameters.")
    notes.append(f"study time {sum(st.wall_time for st in studies):.0f} s.")
    blocks = ([Paragraph(f"Regenerate with `{command}`.")] if command else []) + [
        *(Paragraph(verdict(st, units)) for st in studies), Bullets(tuple(notes)),
        Paragraph("PIM parameters: epsilon, beta. Scene parameters: epsilon, mu_c (between "
                  "the vehicles), T [s] (contact duration), mu_tyre. Errors: |delta-V| "
                  "predicted minus measured, length of the post-impact velocity error, "
                  "|yaw-rate error|, the largest over the moving vehicles."),
        Figure("tuned-scene.png", alt="leave-one-out")]
    return Document("The finite-duration scene tuned to crash tests, against PIM",
                    "pim validate-models", (
                        Section("verdicts", "Verdicts", tuple(blocks), keep=True),
                        Section("medians", "Medians", (summary_table(studies, units),)),
                        Section("predictions", "Every prediction",
                                (predictions_table(studies, units),))),
                    name="tuned-scene")


def write_tuned_study(studies, out_dir, units: str = "si", command: str = "",
                      checks: dict | None = None) -> list[Path]:
    """Write tuned-scene.md (first in the list), tuned-scene.html, the two CSV tables and
    tuned-scene.png into ``out_dir`` through the one report pipeline (:func:`tuned_document`)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    png = save_figure(plot_tuned_study(studies, units), out / "tuned-scene.png")
    written = write_document(tuned_document(studies, units, command, checks), out)
    return [written[-1], *written[:-2], written[-2], png]
