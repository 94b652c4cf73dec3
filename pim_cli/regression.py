"""Command line of the regression baselines: ``pim baseline`` and ``pim check`` (listed in
:mod:`pim_cli.commands`)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import click
from tqdm import tqdm

from comparisons.regression.baseline import (
    cases_findings,
    check_baseline,
    dumps_baseline,
    format_report,
    load_references,
    make_baseline,
)
from comparisons.regression.sections import DEFAULT_SECTIONS, DEFAULT_SETTINGS, SECTIONS
from pim.io.files import write_text
from pim.model.plausibility import Findings
from pim_cli.main import (
    SEED,
    allow_inadmissible_option,
    echo_json,
    finish_answer,
    json_option,
    load_case_for,
    say_findings,
    units_option,
)

__all__ = ["baseline", "check", "DRIFT_EXIT_CODE"]

#: Exit code of ``pim check`` when a quantity moved beyond its tolerance.
DRIFT_EXIT_CODE = 1


def _progress(total: int, desc: str):
    bar = tqdm(total=total, desc=desc, disable=not sys.stderr.isatty(), file=sys.stderr)

    def step(name):
        bar.set_postfix_str(str(name))
        bar.update(1)
    return bar, step


@click.command()
@click.argument("cases", nargs=-1, required=True, metavar="CASE...")
@click.option("--out", "out", type=click.Path(dir_okay=False), required=True,
              help="The baseline file to write (JSON).")
@click.option("--with", "extra", multiple=True, type=click.Choice(SECTIONS),
              help="Also record this section (assumptions: PIM's assumptions at their "
                   "typical values, about 1-2 s per case).")
@click.option("--without", "skip", multiple=True, type=click.Choice(SECTIONS),
              help="Leave this section out (e.g. reconstruct of a case with run-out "
                   "evidence takes minutes).")
@click.option("--samples", type=click.IntRange(min=10), default=None,
              help=f"Monte Carlo samples of the uncertainty section (default "
                   f"{DEFAULT_SETTINGS['uncertainty_samples']}).")
@click.option("--reconstruct-samples", type=click.IntRange(min=0), default=None,
              help=f"Monte Carlo samples of reconstruct (default "
                   f"{DEFAULT_SETTINGS['reconstruct_samples']}; 0: the solution only).")
@click.option("--seed", type=SEED, default=None, help="Seed of the Monte Carlo (default 0).")
@click.option("--references", type=click.Path(dir_okay=False), default=None,
              help="TOML file of independent reference values with their source and "
                   "tolerance, held in the baseline beside the recorded values.")
@allow_inadmissible_option
def baseline(cases, out, extra, skip, samples, reconstruct_samples, seed, references,
             allow_inadmissible):
    """Record every output each CASE supports, with its tolerance, in a baseline file.

    Per case: solve, fit (with [measured] motion), the rigid pymunk cross-check, the Monte
    Carlo (with [uncertainty]), reconstruct (with [unknown]) and, with --with assumptions,
    PIM's assumptions at typical values; the SHA-256 of the case file; the versions of the
    project, numpy, scipy, pymunk, numba and pint. Values are SI, each with its unit.
    `pim check OUT` reruns them. Takes about 0.1 s per case without a fit, 1-2 s with one.
    A case whose answer is inadmissible is not recorded: the reasons, exit code 1 and no
    file, unless --allow-inadmissible.
    """
    finish_answer(_cases_findings(cases, allow_inadmissible), allow_inadmissible)
    sections = tuple(s for s in SECTIONS if (s in DEFAULT_SECTIONS or s in extra)
                     and s not in skip)
    settings = dict(DEFAULT_SETTINGS)
    for key, value in (("uncertainty_samples", samples),
                       ("reconstruct_samples", reconstruct_samples), ("seed", seed)):
        if value is not None:
            settings[key] = value
    refs = load_references(references) if references else None
    start = time.perf_counter()
    bar, step = _progress(len(cases), "baseline")
    with bar:
        doc = make_baseline(cases, sections, settings, Path(out).resolve().parent, refs, step)
    write_text(out, dumps_baseline(doc))
    n = sum(len(c["quantities"]) for c in doc["cases"])
    click.echo(f"{out}: {n} quantities of {len(cases)} case(s) in "
               f"{time.perf_counter() - start:.1f} s ({', '.join(sections)})")


def _cases_findings(cases, allow: bool) -> Findings:
    """The errors and warnings about each case and its answer under its own law
    (:func:`comparisons.regression.baseline.cases_findings`), printed
    (:func:`pim_cli.main.say_findings`)."""
    found = cases_findings({name: load_case_for("baseline", name) for name in cases})
    say_findings(found, allow)
    return found


@click.command()
@click.argument("baseline_file", metavar="BASELINE")
@click.option("--case", "only", multiple=True,
              help="Check only this case of the baseline (repeatable).")
@units_option
@json_option
def check(baseline_file, only, units, speed_unit, as_json):
    """Rerun a baseline's cases and list every quantity that moved beyond its tolerance.

    Prints the quantity, its baseline and current values, the difference and the tolerance
    (in each case's units unless --units or --speed-unit says otherwise), whether a case file
    changed since the baseline (its SHA-256) and which dependency versions differ (then the
    seeded Monte Carlo is held to its statistical tolerance instead of bit for bit). Exit code
    0: all within tolerance; 1: drift; 2: bad input (missing or malformed baseline, one line).
    """
    bar, step = _progress(len(only) if only else None, "check")
    with bar:
        report = check_baseline(baseline_file, only or None, step)
    if as_json:
        echo_json(report.to_json(units, speed_unit))
    else:
        click.echo(format_report(report, units, speed_unit))
    return 0 if report.ok else DRIFT_EXIT_CODE
