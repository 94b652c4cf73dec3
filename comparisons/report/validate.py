"""The report of ``pim validate``: PIM against the bundled published crash tests
(docs/validation.md), as typed tables and a :class:`~comparisons.report.document.Document`.

:func:`run_validation` reproduces the published analyses (:mod:`pim.analysis.validation`,
:mod:`pim.analysis.consistency`) and gathers a :class:`Validation` (summary lines, tables of
raw values in the user's units, figures); :func:`write_validation` saves its figures and
writes the report through the one pipeline (report.md, report.html, one CSV per table).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from comparisons.report.document import Bullets, Document, Figure, Paragraph, Section
from comparisons.report.tables import Num, Table
from comparisons.report.write import write_document
from pim.analysis.consistency import check_ricsac
from pim.analysis.validation import (
    class_radius_of_gyration,
    coefficient_stats,
    refit_barrier,
    refit_ricsac,
    reproduce_barrier,
    ricsac_published_errors,
    summary_errors,
)
from pim.io.datasets import DATASETS, load_dataset
from pim.io.files import save_figure
from pim.io.units import convert
from pim.plotting.validation import plot_coefficients, plot_predicted_vs_measured

__all__ = ["Validation", "run_validation", "validation_document", "write_validation",
           "barrier_table", "ricsac_refit_table", "consistency_table", "coefficient_table",
           "summary_line", "METHOD", "BARRIER_GROUPS"]

#: How the validation is done and where the data come from (the report's last sections).
METHOD = {
    "Method": (
        "Barrier tests: each test is a PIM case in Brach's form (theta1 = 0, C at the origin, "
        "the CG at (d1, phi) from C, the normal at Gamma, the barrier a fixed obstacle) solved "
        "with the published (e, mu/mu0). The yaw inertia is not published: the radius of "
        "gyration k is fitted per test (one parameter, residuals scaled by 1 mph and 10 "
        "deg/s) and, as a second run, set to the median of the fitted k of the test's vehicle "
        "type ('class k'). 'dV err' is the length of the delta-V vector error. The refit runs "
        "pim.fit on (eps, beta) in [0, 1] x [0, 1] against the measured dVx, dVy and yaw "
        "rate, at the published phi and d1, with the per-test and the class k. The published "
        "method's refit (Brach et al.: eps, beta and phi at the published d1, phi within +-30 "
        "deg of the published value) is the 'fit' columns (per-test k). The residuals are "
        "weighted by the tolerances (1 mph per delta-V component, 10 deg/s), so the fit "
        "minimises the misses the table counts.",
        "RICSAC: the CG-to-impact distances are not published, so no reproduction; the "
        "momentum balance of the measured data is checked (pim.analysis.consistency). The "
        "refit puts C on a documented crush edge (each car's rectangular outline, length "
        "sqrt(12) k, width 0.39 L, CG at mid-length, where the ray at Brach's phi leaves it) "
        "and fits eps, beta and C's position along the contact plane (+-1 m) to both cars' "
        "post-impact velocities and yaw rates; tests flagged by the momentum check are "
        "marked."),
    "Sources": (
        "Brach R.M., Welsh K.J., Brach R.M., SAE 2014-01-0469 (Appendix 2); RICSAC compiled "
        "from Neades (PhD thesis, De Montfort Univ.) and Vossou & Koulocheris (2018).",),
}

#: The barrier table's columns in groups one screen wide.
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


@dataclass
class Validation:
    """What ``pim validate`` found.

    Attributes
    ----------
    dataset : str
        The dataset validated ("all", "iihs-barrier" or "ricsac").
    units : str
        Unit system of every number shown.
    summary : list of str
        One line per finding.
    tables : list of Table
        Barrier reproduction, RICSAC consistency and refit, coefficients by class.
    figures : dict
        File stem -> matplotlib Figure.
    """

    dataset: str
    units: str
    summary: list = field(default_factory=list)
    tables: list = field(default_factory=list)
    figures: dict = field(default_factory=dict)


def _units(units):
    su = convert(1.0, "speed", units)[1]
    yu = convert(1.0, "angular_velocity", units)[1]
    lu = convert(1.0, "length", units)[1]

    def speed(x, d=2):
        return Num(float(convert(x, "speed", units)[0]), d)

    def yaw(x):
        return Num(float(convert(x, "angular_velocity", units)[0]), 1)

    def length(x, d=3):
        return Num(float(convert(x, "length", units)[0]), d)

    return su, yu, lu, speed, yaw, length


def barrier_table(published, class_k, refitted=None, units="si") -> Table:
    """The barrier tests: measured, published-model (per-test k and class k) and refitted
    values with errors, in ``units``."""
    su, yu, lu, speed, yaw, length = _units(units)
    columns = ["test", "group", "vehicle", f"k [{lu}]", f"k class [{lu}]",
               f"dVx meas [{su}]", f"dVy meas [{su}]", f"Omega meas [{yu}]",
               f"dVx pub [{su}]", f"dVy pub [{su}]", f"Omega pub [{yu}]",
               f"dV err pub [{su}]", f"Omega err pub [{yu}]",
               f"dV err pub, class k [{su}]", f"Omega err pub, class k [{yu}]"]
    if refitted is not None:
        columns += ["e pub", "e fit", "beta pub", "beta fit", "phi pub [deg]",
                    "phi fit [deg]", f"dV err fit [{su}]", f"Omega err fit [{yu}]"]
    rows = []
    for i, (p, c) in enumerate(zip(published, class_k, strict=True)):
        t = p.test
        row = [t.test_id, t.group, f"{t.model_year} {t.vehicle}",
               length(p.radius_of_gyration), length(c.radius_of_gyration),
               *[speed(x) for x in p.measured[:2]], yaw(p.measured[2]),
               *[speed(x) for x in p.predicted[:2]], yaw(p.predicted[2]),
               speed(p.delta_v_error), yaw(p.yaw_error), speed(c.delta_v_error),
               yaw(c.yaw_error)]
        if refitted is not None:
            f = refitted[i]
            row += [Num(t.restitution, 3), Num(f.restitution, 3), Num(t.beta, 3),
                    Num(f.beta, 3), Num(float(np.degrees(t.phi)), 1),
                    Num(float(np.degrees(f.phi)), 1), speed(f.delta_v_error),
                    yaw(f.yaw_error)]
        rows.append(tuple(row))
    return Table("barrier", "IIHS small-overlap barrier tests", tuple(columns), tuple(rows),
                 groups=BARRIER_GROUPS)


def ricsac_refit_table(fits, flagged=(), units="si") -> Table:
    """The RICSAC refit (:func:`pim.analysis.validation.refit_ricsac`): fitted coefficients,
    C's shift along the contact plane, each residual, in ``units``."""
    su, yu, lu, speed, yaw, length = _units(units)
    columns = ("test", "momentum-inconsistent", "eps fit", "beta fit", f"C along [{lu}]",
               *[f"{n} err [{su}]" for n in ("V1x", "V1y", "V2x", "V2y")],
               f"Omega1 err [{yu}]", f"Omega2 err [{yu}]", "within 1 mph, 10 deg/s", "note")
    rows = []
    for f in fits:
        flag = str(f.test.number) in flagged
        if f.message:
            rows.append((f.test.number, flag, *[None] * 10, f.message))
            continue
        r = f.residuals
        rows.append((f.test.number, flag, Num(f.restitution, 3), Num(f.beta, 3),
                     length(f.along),
                     *[speed(r[k]) for k in ("velocity1_x", "velocity1_y", "velocity2_x",
                                             "velocity2_y")],
                     *[yaw(r[k]) for k in ("yaw_rate1", "yaw_rate2")],
                     bool(f.within_tolerance), ", ".join(f"{k} on bound" for k in f.on_bound)))
    return Table("ricsac_refit", "RICSAC refit (eps, beta, C along the crush edge)", columns,
                 tuple(rows))


def consistency_table(checks) -> Table:
    """The momentum checks (:mod:`pim.analysis.consistency`)."""
    def num(x, scale=1.0, d=1):
        return None if x is None else Num(scale * x, d)

    return Table("consistency", "RICSAC momentum consistency",
                 ("test", "m1dV1/(m2dV2)-1 [%]", "linear imbalance [%]", "arm1 [m]",
                  "arm2 [m]", "flagged", "reasons"),
                 tuple((c.test, num(c.impulse_ratio, 100), num(c.linear_imbalance, 100),
                        num(c.arm1, d=2), num(c.arm2, d=2), bool(c.flagged),
                        "; ".join(c.reasons)) for c in checks))


def coefficient_table(stats) -> Table:
    """The coefficient statistics by crash class."""
    return Table("coefficients", "Coefficients by crash class",
                 ("class", "coefficient", "n", "median", "mean", "sd", "p10", "p90", "min",
                  "max"),
                 tuple((s.crash_class, s.coefficient, s.n, *(Num(float(v), 3) for v in (
                     s.median, s.mean, s.sd, s.percentile(10), s.percentile(90),
                     min(s.values), max(s.values)))) for s in stats))


def summary_line(label, rows, units) -> str:
    """``label: n tests, delta-V error median/p90, yaw error median/p90, k within tolerance``."""
    dv = summary_errors([r.delta_v_error for r in rows])
    om = summary_errors([r.yaw_error for r in rows])
    within = sum(r.within_tolerance for r in rows)
    su = convert(1.0, "speed", units)[1]
    yu = convert(1.0, "angular_velocity", units)[1]

    def s(x):
        return float(convert(x, "speed", units)[0])

    def y(x):
        return float(convert(x, "angular_velocity", units)[0])

    return (f"{label}: {dv['n']} tests, delta-V error median {s(dv['median']):.2f} {su}, "
            f"p90 {s(dv['p90']):.2f} {su}; yaw-rate error median {y(om['median']):.1f} {yu}, "
            f"p90 {y(om['p90']):.1f} {yu}; {within}/{dv['n']} within 1 mph and 10 deg/s")


def _barrier_group_lines(label, group, fits, units) -> list[str]:
    """The summary lines of one group (non-sideswipe or sideswipe) of barrier tests."""
    published, with_class, method, method_class, refitted, refitted_class = fits
    lines = [summary_line(f"iihs-barrier {label}, published coefficients, {how}",
                          [r for r in rows if r.test.group == group], units)
             for rows, how in ((published, "per-test k"), (with_class, "class k"))]
    for rows, how in ((method, "per-test k"), (method_class, "class k")):
        rows = [r for r in rows if r.test.group == group]
        lines.append(summary_line(f"iihs-barrier {label}, refitted by the published method "
                                  f"(eps, beta, phi at the published d1), {how}", rows, units))
        dphi = summary_errors([np.degrees(r.phi - r.test.phi) for r in rows])
        lines.append(f"iihs-barrier {label}, published-method refit ({how}) minus "
                     f"published: |d phi| median {dphi['median']:.2f} deg, max "
                     f"{dphi['max']:.2f} deg")
    for rows, how in ((refitted, "per-test k"), (refitted_class, "class k")):
        rows = [r for r in rows if r.test.group == group]
        lines.append(summary_line(f"iihs-barrier {label}, refitted (eps, beta), {how}", rows,
                                  units))
        de = summary_errors([r.restitution - r.test.restitution for r in rows])
        db = summary_errors([r.beta - r.test.beta for r in rows])
        lines.append(f"iihs-barrier {label}, refitted ({how}) minus published: "
                     f"|d eps| median {de['median']:.3f}, max {de['max']:.3f}; "
                     f"|d beta| median {db['median']:.3f}, max {db['max']:.3f}")
    return lines


def _barrier(tests, v: Validation) -> None:
    """The iihs-barrier table, figure and summary lines."""
    units = v.units
    published = reproduce_barrier(tests)
    usable = [r for r in published if r.test.group != "OUTLIER"]
    class_k = class_radius_of_gyration(usable)
    with_class = reproduce_barrier(tests, {t.test_id: class_k[t.vehicle_type] for t in tests})
    per_test_k = {r.test.test_id: r.radius_of_gyration for r in published}
    class_ks = {t.test_id: class_k[t.vehicle_type] for t in tests}
    # the published method (Brach et al.): eps, beta and phi at the published d1
    method = refit_barrier(tests, per_test_k, free_phi=True)
    fits = (published, with_class, method, refit_barrier(tests, class_ks, free_phi=True),
            refit_barrier(tests, per_test_k), refit_barrier(tests, class_ks))
    v.tables.append(barrier_table(published, with_class, method, units=units))
    for group, label in (("NS", "non-sideswipe"), ("SS", "sideswipe")):
        v.summary += _barrier_group_lines(label, group, fits, units)
    ks = [r.radius_of_gyration for r in usable]
    lu = convert(1.0, "length", units)[1]
    k_lo, k_hi = (float(convert(x, "length", units)[0]) for x in (min(ks), max(ks)))
    v.summary.append(f"iihs-barrier: fitted radius of gyration {k_lo:.3f}-{k_hi:.3f} {lu} "
                     f"over {len(ks)} tests; class medians " + ", ".join(
                         f"{c} {float(convert(k, 'length', units)[0]):.3f} {lu}"
                         for c, k in class_k.items()))
    v.figures["predicted_vs_measured"] = plot_predicted_vs_measured(
        {"non-sideswipe, per-test k": [r for r in published if r.test.group == "NS"],
         "sideswipe, per-test k": [r for r in published if r.test.group == "SS"],
         "all, class k": [r for r in with_class if r.test.group != "OUTLIER"],
         "all, refitted (eps, beta, phi)": [r for r in method if r.test.group != "OUTLIER"]},
        units)


def _ricsac(tests, v: Validation) -> None:
    """The RICSAC consistency and refit tables and summary lines."""
    units = v.units
    checks = check_ricsac(tests)
    v.tables.append(consistency_table(checks))
    flagged = [c.test.split()[1] for c in checks if c.flagged]
    v.summary.append(f"ricsac: {len(checks)} tests checked, momentum-inconsistent: "
                     f"{', '.join(flagged) or 'none'}")
    fits = refit_ricsac(tests)
    v.tables.append(ricsac_refit_table(fits, flagged, units))
    ok = [f for f in fits if not f.message]
    dv = summary_errors([f.velocity_error for f in ok])
    om = summary_errors([np.degrees(f.yaw_error) for f in ok])
    su = convert(1.0, "speed", units)[1]

    def sv(x):
        return float(convert(x, "speed", units)[0])

    v.summary.append(
        f"ricsac refit (eps, beta, C along the contact plane on the crush-edge geometry): "
        f"{len(ok)} tests, worst-car velocity error median {sv(dv['median']):.2f} {su}, "
        f"p90 {sv(dv['p90']):.2f} {su}; yaw-rate error median {om['median']:.1f} deg/s, "
        f"p90 {om['p90']:.1f} deg/s; {sum(f.within_tolerance for f in ok)}/{len(ok)} "
        f"within 1 mph and 10 deg/s (consistent tests only: "
        f"{sum(f.within_tolerance for f in ok if str(f.test.number) not in flagged)}/"
        f"{sum(str(f.test.number) not in flagged for f in ok)})")
    for name, errors in ricsac_published_errors(tests).items():
        s = summary_errors([e for _, _, e in errors])
        v.summary.append(f"ricsac published delta-V {name} vs measured velocities: "
                         f"median {sv(s['median']):.2f} {su}, p90 {sv(s['p90']):.2f} {su} "
                         f"({s['n']} vehicles)")


def _coefficients(records: dict, v: Validation) -> None:
    """The coefficient statistics table, figure and summary lines."""
    stats = coefficient_stats(records)
    if stats:
        v.tables.append(coefficient_table(stats))
        v.figures["coefficients"] = plot_coefficients(stats)
        for s in stats:
            v.summary.append(f"{s.crash_class} {s.coefficient}: median {s.median:.3f}, "
                             f"mean {s.mean:.3f}, sd {s.sd:.3f} (n = {s.n})")


def run_validation(dataset: str = "all", units: str = "si") -> Validation:
    """Reproduce the published analyses of ``dataset`` ("all" or one of
    :data:`pim.io.datasets.DATASETS`) in ``units``."""
    names = list(DATASETS) if dataset == "all" else [dataset]
    records = {name: load_dataset(name) for name in names}
    v = Validation(dataset, units)
    if "iihs-barrier" in records:
        _barrier(records["iihs-barrier"], v)
    if "ricsac" in records:
        _ricsac(records["ricsac"], v)
    _coefficients(records, v)
    return v


def validation_document(v: Validation) -> Document:
    """The report: the summary first, each table, the figures, the method and sources."""
    sections = []
    if v.summary:
        sections.append(Section("summary", "Summary", (Bullets(tuple(v.summary)),),
                                keep=True))
    sections += [Section(t.name, t.title, (t,)) for t in v.tables]
    if v.figures:
        sections.append(Section("figures", "Figures", tuple(
            Figure(f"{name}.png", alt=name.replace("_", " ")) for name in v.figures)))
    sections += [Section(title.lower(), title, tuple(Paragraph(p) for p in paragraphs))
                 for title, paragraphs in METHOD.items()]
    return Document("PIM validation on published crash tests", "pim validate",
                    tuple(sections), subtitle=f"Units: {v.units}. Generated by `pim "
                                              "validate` (the same as text: `report.md`).")


def write_validation(v: Validation, folder) -> list[Path]:
    """Save the figures (PNG) and write the report (report.md first, report.html, the
    CSVs) into ``folder``; return the paths, report.md first."""
    folder = Path(folder)
    figures = [save_figure(fig, folder / f"{name}.png") for name, fig in v.figures.items()]
    written = write_document(validation_document(v), folder)
    return [written[-1], *written[:-1], *figures]
