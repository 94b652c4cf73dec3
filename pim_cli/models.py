"""``pim validate-models`` (PIM against the tuned finite-duration scene on the bundled crash
tests) and ``pim pulses`` (the contact law's crash pulse against NHTSA 10146), registered as
``pim.commands`` entry points in pyproject.toml (``pim validate`` lives in pim/, which never
imports the simulator)."""

from __future__ import annotations

from pathlib import Path

import click
from tqdm.auto import tqdm

from pim_cli.main import echo_json, json_option
from pim.io.files import writable_folder

from comparisons.report.pulses import write_pulses
from comparisons.report.render import markdown_table
from comparisons.studies.pulses import compare_pulses, pulse_table
from comparisons.report.tuned import verdict, write_tuned_study
from comparisons.studies.tuned_scene import COARSE_STEPS, coarse_check, crash_classes, study_class

__all__ = ["validate_models", "pulses"]

_units = click.option("--units", type=click.Choice(["si", "us"]), default="si",
                      show_default=True, help="Units of the tables, plots and messages.")
_progress = click.option("--progress/--no-progress", default=None,
                         help="Progress bar on stderr (default: only on a terminal).")


def _out_option(name: str):
    return click.option("--out", "out", type=click.Path(file_okay=False), default=None,
                        help=f"Output folder (default: out/{name}).")


def _command(name: str, **opts) -> str:
    return " ".join([f"pim {name}"] + [f"--{k.replace('_', '-')} {v}" for k, v in opts.items()
                                       if v is not None])


@click.command("validate-models")
@_out_option("validate-models")
@click.option("--max-tests", type=click.IntRange(3, None), default=None,
              help="Only the first N tests of each class (a quick look), >= 3.")
@click.option("--steps", type=click.IntRange(10, 2000), default=None,
              help="Scene steps per estimated contact time (default 20; checked against "
                   "10x finer).")
@_units
@_progress
@json_option
def validate_models(out, max_tests, steps, units, progress, as_json):
    """PIM against the finite-duration scene tuned to the bundled crash tests.

    Fits both models per test, per crash class and leave-one-out within each class (IIHS
    barrier non-sideswipe and sideswipe, momentum-consistent RICSAC tests) and writes
    tuned-scene.md (one sentence per class on which model predicts the held-out tests
    better), tuned-scene-summary.csv, tuned-scene-predictions.csv and tuned-scene.png.
    """
    folder = writable_folder(Path(out) if out else Path("out") / "validate-models")
    steps = COARSE_STEPS if steps is None else steps
    classes = crash_classes(max_tests)
    studies, checks = [], {}
    with tqdm(desc="validate-models", unit="run", disable=None if progress is None
              else not progress) as bar:
        for name, tests in classes.items():
            st = study_class(name, tests, steps=steps, bar=bar)
            studies.append(st)
            checks[name] = max((coarse_check(t, st.class_fits["scene"].x, steps, 10 * steps)
                                for t in tests[:3]), key=lambda d: d[0])
    files = write_tuned_study(studies, folder, units, _command(
        "validate-models", out=out, max_tests=max_tests, steps=steps if steps != COARSE_STEPS
        else None, units=units if units != "si" else None), checks)
    if as_json:
        echo_json({"files": [str(f) for f in files],
                   "verdicts": [verdict(st, units) for st in studies]})
        return
    for st in studies:
        click.echo(verdict(st, units))
    click.echo(f"wrote {files[0]}")


@click.command("pulses")
@_out_option("pulses")
@click.option("--stiffness", type=click.FloatRange(1e3, 1e9), default=None,
              help="Linear crush stiffness [N/m] (default sim.DEFAULT_STIFFNESS, 7.5e5).")
@click.option("--eps", type=click.FloatRange(0.0, 1.0), default=None,
              help="Restitution of the crush in [0, 1] (default: the test's rebound speed "
                   "over its impact speed).")
@_units
@json_option
def pulses(out, stiffness, eps, units, as_json):
    """The contact law's force-time and delta-V-time against NHTSA test 10146.

    Writes pulses.md (the table of duration, peak force, crush at peak, rebound, each with
    its error), pulses-nhtsa10146.csv and pulses.png.
    """
    folder = writable_folder(Path(out) if out else Path("out") / "pulses")
    c = compare_pulses(stiffness, eps)
    table = pulse_table(c, units)
    cmd = _command("pulses", out=out, stiffness=stiffness, eps=eps,
                   units=units if units != "si" else None)
    files = write_pulses(c, folder, units, cmd)
    if as_json:
        echo_json({"files": [str(f) for f in files], "rows": [dict(zip(table.columns, r,
                                                                        strict=True))
                                                               for r in table.rows]})
        return
    click.echo(markdown_table(table))
    click.echo(f"wrote {files[0]}")
