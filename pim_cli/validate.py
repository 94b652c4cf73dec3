"""``pim validate``: PIM against the bundled published crash tests (docs/validation.md)."""

from __future__ import annotations

import click
import numpy as np

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
from pim.io.output import output_folder, rebase
from pim.io.units import convert
from pim.plotting.validation import (
    barrier_table,
    coefficient_table,
    consistency_table,
    plot_coefficients,
    plot_predicted_vs_measured,
    ricsac_refit_table,
    summary_line,
    write_validation_report,
)
from pim_cli.main import echo_json, json_option, units_option

__all__ = ["validate", "run_validation"]

NOTES = [
    "## Method", "",
    "Barrier tests: each test is a PIM case in Brach's form (theta1 = 0, C at the origin, the "
    "CG at (d1, phi) from C, the normal at Gamma, the barrier a fixed obstacle) solved with "
    "the published (e, mu/mu0). The yaw inertia is not published: the radius of gyration k is "
    "fitted per test (one parameter, residuals scaled by 1 mph and 10 deg/s) and, as a second "
    "run, set to the median of the fitted k of the test's vehicle type ('class k'). 'dV err' "
    "is the length of the delta-V vector error. The refit runs pim.fit on (eps, beta) in "
    "[0, 1] x [0, 1] against the measured dVx, dVy and yaw rate, at the published phi and d1, "
    "with the per-test and the class k. The published method's refit (Brach et al.: eps, beta "
    "and phi at the published d1, phi within +-30 deg of the published value) is the 'fit' "
    "columns (per-test k). The residuals are weighted by the tolerances (1 mph per delta-V "
    "component, 10 deg/s), so the fit minimises the misses the table counts.", "",
    "RICSAC: the CG-to-impact distances are not published, so no reproduction; the momentum "
    "balance of the measured data is checked (pim.analysis.consistency). The refit puts C on "
    "a documented crush edge (each car's rectangular outline, length sqrt(12) k, width "
    "0.39 L, CG at mid-length, where the ray at Brach's phi leaves it) and fits eps, beta and "
    "C's position along the contact plane (+-1 m) to both cars' post-impact velocities and "
    "yaw rates; tests flagged by the momentum check are marked.", "",
    "Sources: Brach R.M., Welsh K.J., Brach R.M., SAE 2014-01-0469 (Appendix 2); RICSAC "
    "compiled from Neades (PhD thesis, De Montfort Univ.) and Vossou & Koulocheris (2018).",
    "",
]


def _barrier_sections(tests, sections: dict, summary: list, units: str) -> None:
    """Add the iihs-barrier table, figure and summary lines (run_validation)."""
    published = reproduce_barrier(tests)
    usable = [r for r in published if r.test.group != "OUTLIER"]
    class_k = class_radius_of_gyration(usable)
    with_class = reproduce_barrier(tests, {t.test_id: class_k[t.vehicle_type] for t in tests})
    per_test_k = {r.test.test_id: r.radius_of_gyration for r in published}
    class_ks = {t.test_id: class_k[t.vehicle_type] for t in tests}
    refitted = refit_barrier(tests, per_test_k)
    refitted_class = refit_barrier(tests, class_ks)
    # the published method (Brach et al.): eps, beta and phi at the published d1
    method = refit_barrier(tests, per_test_k, free_phi=True)
    method_class = refit_barrier(tests, class_ks, free_phi=True)
    sections["barrier"] = barrier_table(published, with_class, method, units=units)
    ks = [r.radius_of_gyration for r in usable]
    lu = convert(1.0, "length", units)[1]
    k_lo, k_hi = (float(convert(x, "length", units)[0]) for x in (min(ks), max(ks)))
    for group, label in (("NS", "non-sideswipe"), ("SS", "sideswipe")):
        rows = [r for r in published if r.test.group == group]
        summary.append(summary_line(f"iihs-barrier {label}, published coefficients, "
                                    f"per-test k", rows, units))
        rows = [r for r in with_class if r.test.group == group]
        summary.append(summary_line(f"iihs-barrier {label}, published coefficients, "
                                    f"class k", rows, units))
        for fits, how in ((method, "per-test k"), (method_class, "class k")):
            rows = [r for r in fits if r.test.group == group]
            summary.append(summary_line(
                f"iihs-barrier {label}, refitted by the published method (eps, beta, phi "
                f"at the published d1), {how}", rows, units))
            dphi = summary_errors([np.degrees(r.phi - r.test.phi) for r in rows])
            summary.append(f"iihs-barrier {label}, published-method refit ({how}) minus "
                           f"published: |d phi| median {dphi['median']:.2f} deg, max "
                           f"{dphi['max']:.2f} deg")
        for fits, how in ((refitted, "per-test k"), (refitted_class, "class k")):
            rows = [r for r in fits if r.test.group == group]
            summary.append(summary_line(f"iihs-barrier {label}, refitted (eps, beta), {how}",
                                        rows, units))
            de = summary_errors([r.restitution - r.test.restitution for r in rows])
            db = summary_errors([r.beta - r.test.beta for r in rows])
            summary.append(f"iihs-barrier {label}, refitted ({how}) minus published: "
                           f"|d eps| median {de['median']:.3f}, max {de['max']:.3f}; "
                           f"|d beta| median {db['median']:.3f}, max {db['max']:.3f}")
    summary.append(f"iihs-barrier: fitted radius of gyration {k_lo:.3f}-{k_hi:.3f} {lu} "
                   f"over {len(ks)} tests; class medians " + ", ".join(
                       f"{c} {float(convert(k, 'length', units)[0]):.3f} {lu}"
                       for c, k in class_k.items()))
    sections["figures"]["predicted_vs_measured"] = plot_predicted_vs_measured(
        {"non-sideswipe, per-test k": [r for r in published if r.test.group == "NS"],
         "sideswipe, per-test k": [r for r in published if r.test.group == "SS"],
         "all, class k": [r for r in with_class if r.test.group != "OUTLIER"],
         "all, refitted (eps, beta, phi)": [r for r in method
                                            if r.test.group != "OUTLIER"]}, units)


def _ricsac_sections(tests, sections: dict, summary: list, units: str) -> None:
    """Add the RICSAC consistency and refit tables and summary lines (run_validation)."""
    checks = check_ricsac(tests)
    sections["consistency"] = consistency_table(checks)
    flagged = [c.test.split()[1] for c in checks if c.flagged]
    summary.append(f"ricsac: {len(checks)} tests checked, momentum-inconsistent: "
                   f"{', '.join(flagged) or 'none'}")
    fits = refit_ricsac(tests)
    sections["ricsac_refit"] = ricsac_refit_table(fits, flagged, units)
    ok = [f for f in fits if not f.message]
    dv = summary_errors([f.velocity_error for f in ok])
    om = summary_errors([np.degrees(f.yaw_error) for f in ok])
    su = convert(1.0, "speed", units)[1]
    sv = lambda x: float(convert(x, "speed", units)[0])  # noqa: E731
    summary.append(
        f"ricsac refit (eps, beta, C along the contact plane on the crush-edge geometry): "
        f"{len(ok)} tests, worst-car velocity error median {sv(dv['median']):.2f} {su}, "
        f"p90 {sv(dv['p90']):.2f} {su}; yaw-rate error median {om['median']:.1f} deg/s, "
        f"p90 {om['p90']:.1f} deg/s; {sum(f.within_tolerance for f in ok)}/{len(ok)} "
        f"within 1 mph and 10 deg/s (consistent tests only: "
        f"{sum(f.within_tolerance for f in ok if str(f.test.number) not in flagged)}/"
        f"{sum(str(f.test.number) not in flagged for f in ok)})")
    su = convert(1.0, "speed", units)[1]
    for name, errors in ricsac_published_errors(tests).items():
        s = summary_errors([e for _, _, e in errors])
        summary.append(f"ricsac published delta-V {name} vs measured velocities: "
                       f"median {float(convert(s['median'], 'speed', units)[0]):.2f} {su}, "
                       f"p90 {float(convert(s['p90'], 'speed', units)[0]):.2f} {su} "
                       f"({s['n']} vehicles)")


def _coefficient_sections(records: dict, sections: dict, summary: list) -> None:
    """Add the coefficient statistics table, figure and summary lines (run_validation)."""
    stats = coefficient_stats(records)
    if stats:
        sections["coefficients"] = coefficient_table(stats)
        sections["figures"]["coefficients"] = plot_coefficients(stats)
        for s in stats:
            summary.append(f"{s.crash_class} {s.coefficient}: median {s.median:.3f}, "
                           f"mean {s.mean:.3f}, sd {s.sd:.3f} (n = {s.n})")


def run_validation(dataset: str = "all", units: str = "si") -> tuple[dict, list[str]]:
    """Build the report sections and the summary lines of ``pim validate``."""
    names = list(DATASETS) if dataset == "all" else [dataset]
    records = {name: load_dataset(name) for name in names}
    sections, summary = {"notes": list(NOTES), "figures": {}}, []
    if "iihs-barrier" in records:
        _barrier_sections(records["iihs-barrier"], sections, summary, units)
    if "ricsac" in records:
        _ricsac_sections(records["ricsac"], sections, summary, units)
    _coefficient_sections(records, sections, summary)
    sections["summary"] = summary
    return sections, summary


@click.command()
@click.argument("dataset", required=False, default="all",
                type=click.Choice(["all", *DATASETS]))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False),
              help="Directory for report.md, the CSV tables and the figures.")
@units_option
@json_option
def validate(dataset, out, units, as_json):
    """Validate PIM on the bundled published crash tests (DATASET: all by default).

    Reproduces the published analyses with their coefficients, checks the momentum balance
    of the measured data and tabulates the coefficients by crash class; writes a Markdown +
    CSV report with figures into OUT and prints one summary line per dataset. Units default
    to those the data are published in: us for the IIHS tests (and all), si for RICSAC.
    """
    units = units or ("si" if dataset == "ricsac" else "us")
    with output_folder(out, command="pim validate") as tmp:
        sections, summary = run_validation(dataset, units)
        written = rebase(write_validation_report(tmp, sections, units), tmp, out)
    if as_json:
        echo_json({"dataset": dataset, "units": units, "summary": summary,
                   "files": [str(p) for p in written]})
        return
    for line in summary:
        click.echo(line)
    click.echo(f"report: {written[0]}")
