"""Figures and the Markdown + CSV report of ``pim validate``.

matplotlib is imported inside the functions (``import pim`` stays fast); every file is
written atomically (:mod:`pim.io.files`). Values are shown in the user's unit system.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ..analysis.validation import SPEED_TOLERANCE, YAW_TOLERANCE, summary_errors
from ..io import html
from ..io.files import save_figure, write_text
from ..io.units import convert

__all__ = ["plot_predicted_vs_measured", "plot_coefficients", "barrier_table",
           "consistency_table", "ricsac_refit_table", "coefficient_table",
           "write_validation_report", "csv_text"]


def _speed(x, units):
    return convert(x, "speed", units)


def _yaw(x, units):
    return convert(x, "angular_velocity", units)


def plot_predicted_vs_measured(series: dict, units: str = "si"):
    """Predicted against measured delta-V magnitude and yaw rate.

    ``series``: label -> list of :class:`pim.analysis.validation.BarrierReproduction` (or
    any rows with ``predicted`` and ``measured`` (dVx, dVy, Omega) [SI]). Returns a Figure.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4.6))
    axes = fig.subplots(1, 2)
    for (label, rows), marker in zip(series.items(), "os^vD", strict=False):
        if not rows:
            continue
        pred = np.array([r.predicted for r in rows])
        meas = np.array([r.measured for r in rows])
        dv_p, su = _speed(np.hypot(pred[:, 0], pred[:, 1]), units)
        dv_m, _ = _speed(np.hypot(meas[:, 0], meas[:, 1]), units)
        om_p, yu = _yaw(pred[:, 2], units)
        om_m, _ = _yaw(meas[:, 2], units)
        axes[0].plot(dv_m, dv_p, marker, ms=5, mfc="none", label=label)
        axes[1].plot(om_m, om_p, marker, ms=5, mfc="none", label=label)
    for ax, what, unit, tol in ((axes[0], "delta-V", su, _speed(SPEED_TOLERANCE, units)[0]),
                                (axes[1], "yaw rate", yu, _yaw(YAW_TOLERANCE, units)[0])):
        lo, hi = ax.get_xlim()
        lo, hi = min(lo, ax.get_ylim()[0]), max(hi, ax.get_ylim()[1])
        x = np.array([lo, hi])
        ax.plot(x, x, "k-", lw=0.8)
        ax.fill_between(x, x - tol, x + tol, color="0.85", zorder=0,
                        label=f"+-{float(tol):.3g} {unit}")
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
        ax.set_xlabel(f"measured {what} [{unit}]")
        ax.set_ylabel(f"PIM {what} [{unit}]")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("IIHS small-overlap barrier tests (Brach et al. 2014): PIM against measured")
    fig.tight_layout()
    return fig


def plot_coefficients(stats):
    """Strip plots of epsilon and beta by crash class (:func:`coefficient_stats` output)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4))
    axes = fig.subplots(1, 2)
    for ax, coefficient in zip(axes, ("epsilon", "beta"), strict=False):
        rows = [s for s in stats if s.coefficient == coefficient]
        for i, s in enumerate(rows):
            jitter = np.linspace(-0.15, 0.15, s.n)
            ax.plot(i + jitter, s.values, "o", ms=4, mfc="none")
            ax.plot([i - 0.25, i + 0.25], [s.median] * 2, "k-", lw=2)
        ax.set_xticks(range(len(rows)), [f"{s.crash_class}\n(n={s.n})" for s in rows], fontsize=8)
        ax.set_ylabel("epsilon [-]" if coefficient == "epsilon" else "beta = mu/mu0 [-]")
        ax.grid(alpha=0.3)
    fig.suptitle("PIM coefficients by crash class (Brach et al. 2014); bar = median")
    fig.tight_layout()
    return fig


def csv_text(header, rows) -> str:
    """CSV text of ``rows`` (lists) under ``header``."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def barrier_table(published, class_k, refitted=None, units="si"):
    """Header and rows of the barrier table: measured, published-model (per-test k and class
    k) and refitted values with errors, in ``units``."""
    su = _speed(1.0, units)[1]
    yu = _yaw(1.0, units)[1]
    lu = convert(1.0, "length", units)[1]
    header = ["test", "group", "vehicle", f"k [{lu}]", f"k class [{lu}]",
              f"dVx meas [{su}]", f"dVy meas [{su}]", f"Omega meas [{yu}]",
              f"dVx pub [{su}]", f"dVy pub [{su}]", f"Omega pub [{yu}]",
              f"dV err pub [{su}]", f"Omega err pub [{yu}]",
              f"dV err pub, class k [{su}]", f"Omega err pub, class k [{yu}]"]
    if refitted is not None:
        header += ["e pub", "e fit", "beta pub", "beta fit", "phi pub [deg]", "phi fit [deg]",
                   f"dV err fit [{su}]", f"Omega err fit [{yu}]"]
    rows = []
    for i, (p, c) in enumerate(zip(published, class_k, strict=True)):
        t = p.test
        row = [t.test_id, t.group, f"{t.model_year} {t.vehicle}",
               *[f"{float(convert(x, 'length', units)[0]):.3f}"
                 for x in (p.radius_of_gyration, c.radius_of_gyration)],
               *[f"{float(_speed(x, units)[0]):.2f}" for x in p.measured[:2]],
               f"{float(_yaw(p.measured[2], units)[0]):.1f}",
               *[f"{float(_speed(x, units)[0]):.2f}" for x in p.predicted[:2]],
               f"{float(_yaw(p.predicted[2], units)[0]):.1f}",
               f"{float(_speed(p.delta_v_error, units)[0]):.2f}",
               f"{float(_yaw(p.yaw_error, units)[0]):+.1f}",
               f"{float(_speed(c.delta_v_error, units)[0]):.2f}",
               f"{float(_yaw(c.yaw_error, units)[0]):+.1f}"]
        if refitted is not None:
            f = refitted[i]
            row += [f"{t.restitution:.3f}", f"{f.restitution:.3f}", f"{t.beta:.3f}",
                    f"{f.beta:.3f}", f"{np.degrees(t.phi):.1f}", f"{np.degrees(f.phi):.1f}",
                    f"{float(_speed(f.delta_v_error, units)[0]):.2f}",
                    f"{float(_yaw(f.yaw_error, units)[0]):+.1f}"]
        rows.append(row)
    return header, rows


def ricsac_refit_table(fits, flagged=(), units="si"):
    """Header and rows of the RICSAC refit (:func:`pim.analysis.validation.refit_ricsac`):
    fitted coefficients, C's shift along the contact plane, each residual, in ``units``."""
    su = _speed(1.0, units)[1]
    yu = _yaw(1.0, units)[1]
    lu = convert(1.0, "length", units)[1]
    header = ["test", "momentum-inconsistent", "eps fit", "beta fit", f"C along [{lu}]",
              *[f"{n} err [{su}]" for n in ("V1x", "V1y", "V2x", "V2y")],
              f"Omega1 err [{yu}]", f"Omega2 err [{yu}]", "within 1 mph, 10 deg/s", "note"]
    rows = []
    for f in fits:
        flag = "yes" if str(f.test.number) in flagged else "no"
        if f.message:
            rows.append([f.test.number, flag, *[""] * 10, f.message])
            continue
        r = f.residuals
        rows.append([f.test.number, flag, f"{f.restitution:.3f}", f"{f.beta:.3f}",
                     f"{float(convert(f.along, 'length', units)[0]):+.3f}",
                     *[f"{float(_speed(r[k], units)[0]):+.2f}" for k in
                       ("velocity1_x", "velocity1_y", "velocity2_x", "velocity2_y")],
                     *[f"{float(_yaw(r[k], units)[0]):+.1f}" for k in ("yaw_rate1", "yaw_rate2")],
                     "yes" if f.within_tolerance else "no",
                     ", ".join(f"{k} on bound" for k in f.on_bound)])
    return header, rows


def consistency_table(checks):
    """Header and rows of the momentum checks (:mod:`pim.analysis.consistency`)."""
    header = ["test", "m1dV1/(m2dV2)-1 [%]", "linear imbalance [%]", "arm1 [m]", "arm2 [m]",
              "flagged", "reasons"]
    fmt = lambda x, s=1.0, p=1: "" if x is None else f"{s * x:.{p}f}"  # noqa: E731
    return header, [[c.test, fmt(c.impulse_ratio, 100), fmt(c.linear_imbalance, 100),
                     fmt(c.arm1, p=2), fmt(c.arm2, p=2), "yes" if c.flagged else "no",
                     "; ".join(c.reasons)] for c in checks]


def coefficient_table(stats):
    """Header and rows of the coefficient statistics by crash class."""
    header = ["class", "coefficient", "n", "median", "mean", "sd", "p10", "p90", "min", "max"]
    return header, [[s.crash_class, s.coefficient, s.n, *(f"{v:.3f}" for v in (
        s.median, s.mean, s.sd, s.percentile(10), s.percentile(90), min(s.values),
        max(s.values)))] for s in stats]


def _markdown(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(x) for x in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def summary_line(label, rows, units) -> str:
    """``label: n tests, delta-V error median/p90, yaw error median/p90, k within tolerance``."""
    dv = summary_errors([r.delta_v_error for r in rows])
    om = summary_errors([r.yaw_error for r in rows])
    within = sum(r.within_tolerance for r in rows)
    su, yu = _speed(1.0, units)[1], _yaw(1.0, units)[1]
    s = lambda x: float(_speed(x, units)[0])  # noqa: E731
    y = lambda x: float(_yaw(x, units)[0])  # noqa: E731
    return (f"{label}: {dv['n']} tests, delta-V error median {s(dv['median']):.2f} {su}, "
            f"p90 {s(dv['p90']):.2f} {su}; yaw-rate error median {y(om['median']):.1f} {yu}, "
            f"p90 {y(om['p90']):.1f} {yu}; {within}/{dv['n']} within 1 mph and 10 deg/s")


#: The report's tables: (key of ``sections``, title).
TABLES = (("barrier", "IIHS small-overlap barrier tests"),
          ("consistency", "RICSAC momentum consistency"),
          ("ricsac_refit", "RICSAC refit (eps, beta, C along the crush edge)"),
          ("coefficients", "Coefficients by crash class"))


#: The barrier table's columns in groups one screen wide (:func:`pim.io.html.split_table`).
BARRIER_GROUPS = (
    ("Measured, and the radius of gyration k (per test and per class)",
     ("group", "vehicle", "k", "k class", "dVx meas", "dVy meas", "Omega meas")),
    ("PIM with the published coefficients",
     ("dVx pub", "dVy pub", "Omega pub", "dV err pub", "Omega err pub", "dV err pub, class k",
      "Omega err pub, class k")),
    ("The published method's refit (eps, beta, phi) against the published values",
     ("e pub", "e fit", "beta pub", "beta fit", "phi pub", "phi fit", "dV err fit",
      "Omega err fit")),
)


def write_validation_report(out, sections: dict, units: str = "si") -> list[Path]:
    """Write ``report.md``, ``report.html`` and the CSVs/PNGs of ``sections`` into directory
    ``out``.

    ``sections`` may hold: ``summary`` (list of lines), ``barrier`` ((header, rows)),
    ``consistency`` ((header, rows)), ``ricsac_refit`` ((header, rows)), ``coefficients``
    ((header, rows)), ``notes`` (list of Markdown paragraphs), ``figures`` (name ->
    Figure). Returns the written paths, report.md first.
    """
    out = Path(out)
    written = []
    md = ["# PIM validation on published crash tests", "",
          f"Units: {units}. Generated by `pim validate`.", ""]
    if sections.get("summary"):
        md += ["## Summary", ""] + [f"- {line}" for line in sections["summary"]] + [""]
    for key, title in TABLES:
        if key not in sections:
            continue
        header, rows = sections[key]
        written.append(write_text(out / f"{key}.csv", csv_text(header, rows)))
        md += [f"## {title}", "", f"CSV: `{key}.csv`", "", _markdown(header, rows)]
    for name, fig in sections.get("figures", {}).items():
        written.append(save_figure(fig, out / f"{name}.png"))
        md += [f"![{name}]({name}.png)", ""]
    md += sections.get("notes", [])
    written.append(write_text(out / "report.html", validation_html(out, sections, units)))
    written.insert(0, write_text(out / "report.md", "\n".join(md) + "\n"))
    return written


def validation_html(out, sections: dict, units: str = "si") -> str:
    """The report as one self-contained HTML page (:mod:`pim.io.html`); the figures are read
    from ``out``, where :func:`write_validation_report` saved them."""
    out = Path(out)
    parts = []                                          # (id, title, body)
    if sections.get("summary"):
        parts.append(("summary", "Summary", html.bullets(sections["summary"])))
    for key, title in TABLES:
        if key in sections:
            header, rows = sections[key]
            cells = [[str(x) for x in r] for r in rows]
            note = f"CSV: `{key}.csv`"
            parts.append((key, title, html.split_table(
                header, cells, BARRIER_GROUPS, header[0], note=note, id=f"table-{key}")
                if key == "barrier" else html.table(header, cells, note=note,
                                                    id=f"table-{key}")))
    figures = [html.figure(out / f"{name}.png", alt=name, caption=f"`{name}.png`")
               for name in sections.get("figures", {})]
    if figures:
        parts.append(("figures", "Figures", '<div class="grid">' + "".join(figures) + "</div>"))
    notes, title = [], None
    for line in [*sections.get("notes", []), "## "]:
        if line.startswith("## "):
            if title is not None:
                parts.append((f"notes-{len(parts)}", title, notes))
            title, notes = line[3:], []
        elif line.strip():
            notes.append(html.paragraph(line))
    return html.page("PIM validation on published crash tests",
                     [html.section(t, body, id=i, cls="keep" if i == "summary" else "")
                      for i, t, body in parts],
                     subtitle=f"Units: {units}. Generated by `pim validate` (the same as "
                              "text: `report.md`).",
                     contents=[(i, t) for i, t, _ in parts], generator="pim validate")
