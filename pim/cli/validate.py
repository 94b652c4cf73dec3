"""``pim validate``: PIM against the bundled published crash tests (docs/validation.md)."""

from __future__ import annotations

import click

from ..analysis.consistency import check_ricsac
from ..analysis.validation import (
    class_radius_of_gyration,
    coefficient_stats,
    refit_barrier,
    reproduce_barrier,
    ricsac_published_errors,
    summary_errors,
)
from ..io.datasets import DATASETS, load_dataset
from ..io.units import convert
from ..plotting.validation import (
    barrier_table,
    coefficient_table,
    consistency_table,
    plot_coefficients,
    plot_predicted_vs_measured,
    summary_line,
    write_validation_report,
)
from .main import echo_json, json_option, units_option

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
    "with the per-test and the class k; 'fit' columns are the per-test-k refit.", "",
    "RICSAC: the CG-to-impact distances are not published, so no reproduction; the momentum "
    "balance of the measured data is checked (pim.analysis.consistency).", "",
    "Sources: Brach R.M., Welsh K.J., Brach R.M., SAE 2014-01-0469 (Appendix 2); RICSAC "
    "compiled from Neades (PhD thesis, De Montfort Univ.) and Vossou & Koulocheris (2018).",
    "",
]


def run_validation(dataset: str = "all", units: str = "si") -> tuple[dict, list[str]]:
    """Build the report sections and the summary lines of ``pim validate``."""
    names = list(DATASETS) if dataset == "all" else [dataset]
    records = {name: load_dataset(name) for name in names}
    sections, summary = {"notes": list(NOTES), "figures": {}}, []
    if "iihs-barrier" in records:
        tests = records["iihs-barrier"]
        published = reproduce_barrier(tests)
        usable = [r for r in published if r.test.group != "OUTLIER"]
        class_k = class_radius_of_gyration(usable)
        with_class = reproduce_barrier(tests, {t.test_id: class_k[t.vehicle_type] for t in tests})
        refitted = refit_barrier(tests, {r.test.test_id: r.radius_of_gyration for r in published})
        refitted_class = refit_barrier(tests, {t.test_id: class_k[t.vehicle_type] for t in tests})
        sections["barrier"] = barrier_table(published, with_class, refitted, units=units)
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
             "all, class k": [r for r in with_class if r.test.group != "OUTLIER"]}, units)
    if "ricsac" in records:
        checks = check_ricsac(records["ricsac"])
        sections["consistency"] = consistency_table(checks)
        flagged = [c.test.split()[1] for c in checks if c.flagged]
        summary.append(f"ricsac: {len(checks)} tests checked, momentum-inconsistent: "
                       f"{', '.join(flagged) or 'none'}")
        su = convert(1.0, "speed", units)[1]
        for name, errors in ricsac_published_errors(records["ricsac"]).items():
            s = summary_errors([e for _, _, e in errors])
            summary.append(f"ricsac published delta-V {name} vs measured velocities: "
                           f"median {float(convert(s['median'], 'speed', units)[0]):.2f} {su}, "
                           f"p90 {float(convert(s['p90'], 'speed', units)[0]):.2f} {su} "
                           f"({s['n']} vehicles)")
    stats = coefficient_stats(records)
    if stats:
        sections["coefficients"] = coefficient_table(stats)
        sections["figures"]["coefficients"] = plot_coefficients(stats)
        for s in stats:
            summary.append(f"{s.crash_class} {s.coefficient}: median {s.median:.3f}, "
                           f"mean {s.mean:.3f}, sd {s.sd:.3f} (n = {s.n})")
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
    sections, summary = run_validation(dataset, units)
    written = write_validation_report(out, sections, units)
    if as_json:
        echo_json({"dataset": dataset, "units": units, "summary": summary,
                   "files": [str(p) for p in written]})
        return
    for line in summary:
        click.echo(line)
    click.echo(f"report: {written[0]}")
