"""``pim validate-models`` (PIM against the tuned finite-duration scene on the bundled crash
tests) and ``pim pulses`` (the contact law's crash pulse against NHTSA 10146), listed in
:mod:`pim_cli.commands`."""

from __future__ import annotations

import time
from pathlib import Path

import click
from tqdm.auto import tqdm

from comparisons.report.pulses import pulse_table, write_pulses
from comparisons.report.render import markdown_table
from comparisons.report.tuned import conclusion, study_json, verdict_sentence, write_tuned_study
from comparisons.studies.crash_records import CLASS_KEYS
from comparisons.studies.pulses import compare_pulses
from comparisons.studies.contact_time import study_classes
from comparisons.studies.tuned_scene import COARSE_STEPS
from pim.io.files import writable_folder
from pim.io.output import output_folder, rebase
from pim_cli.main import echo_json, json_option, output_units, units_option

__all__ = ["validate_models", "pulses"]

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
@click.option("--class", "classes", multiple=True, type=click.Choice(list(CLASS_KEYS)),
              help="Only this crash class (repeat for several; default: every class).")
@click.option("--steps", type=click.IntRange(10, 2000), default=None,
              help=f"Scene steps per estimated contact time (default {COARSE_STEPS}; checked "
                   "against 10x finer).")
@units_option
@_progress
@json_option
def validate_models(out, max_tests, classes, steps, units, speed_unit, progress, as_json):
    """Compare PIM with the finite-duration scene tuned to the bundled crash tests, on tests
    held out of each fit, with a verdict.

    Per crash class (IIHS barrier non-sideswipe and sideswipe, RICSAC, NHTSA car-to-car) and
    input variant: multi-start class fits and converged leave-one-out refits of PIM and of
    the compiled scene under two tangential laws, then a paired signed-rank test of the
    held-out errors and one verdict, for the scene fitted freely and held to the physical
    ranges; the class fit's profile over the contact time (20-250 ms) with its
    likelihood-ratio threshold, and on the non-sideswipe class the scene with one mechanism
    switched off at a time. Writes tuned-scene.md and .html (the conclusion first), the
    summary, verdict, profile, mechanism and prediction tables (CSV), tuned-scene.png and
    tuned-scene-profile.png; prints the conclusion, the verdicts and the wall time.
    """
    wall = time.perf_counter()
    shown = output_units(None, units, speed_unit)
    steps = COARSE_STEPS if steps is None else steps
    folder = Path(out) if out else Path("out") / "validate-models"
    command = " ".join([_command("validate-models", out=out, max_tests=max_tests,
                                 steps=steps if steps != COARSE_STEPS else None,
                                 units=units, speed_unit=speed_unit)]
                       + [f"--class {c}" for c in classes])
    with output_folder(folder, command="pim validate-models") as tmp:
        with tqdm(desc="validate-models", unit=" scenes", unit_scale=True,
                  disable=None if progress is None else not progress) as bar:
            studies = study_classes(max_tests, steps=steps, classes=classes or None,
                                    bar=bar)
        files = rebase(write_tuned_study(studies, tmp, shown, command), tmp, folder)
    wall = time.perf_counter() - wall
    if as_json:
        echo_json(study_json(studies, shown, wall) | {"files": [str(f) for f in files]})
        return
    for paragraph in conclusion(studies, shown):
        click.echo(paragraph.replace("**", "") + "\n")
    for st in studies:
        for v in st.variants:
            click.echo(verdict_sentence(st, v, shown))
    click.echo(f"wall time {wall:.1f} s")
    click.echo(f"wrote {files[0]}")


@click.command("pulses")
@_out_option("pulses")
@click.option("--stiffness", type=click.FloatRange(1e3, 1e9), default=None,
              help="Linear crush stiffness [N/m] (default: the full-width frontal barrier "
                   "default, 7.5e5, fitted to this test).")
@click.option("--eps", type=click.FloatRange(0.0, 1.0), default=None,
              help="Restitution of the crush in [0, 1] (default: the test's rebound speed "
                   "over its impact speed).")
@units_option
@json_option
def pulses(out, stiffness, eps, units, speed_unit, as_json):
    """Compare the contact law's force and delta-V pulses with NHTSA test 10146.

    Writes pulses.md and .html (the predicted figures' errors first, then the table of
    duration, peak force, crush at peak, rebound, each with its error and named fitted, when
    it agrees by construction with parameters taken from this test, or predicted),
    pulses-nhtsa10146.csv and pulses.png.
    """
    folder = writable_folder(Path(out) if out else Path("out") / "pulses")
    shown = output_units(None, units, speed_unit)
    c = compare_pulses(stiffness, eps)
    cmd = _command("pulses", out=out, stiffness=stiffness, eps=eps, units=units,
                   speed_unit=speed_unit)
    files = write_pulses(c, folder, shown, cmd)
    table = pulse_table(c, shown)
    if as_json:
        echo_json({"units": shown.to_json(), "files": [str(f) for f in files],
                   "rows": table.records()})
        return
    click.echo(markdown_table(table))
    click.echo(f"wrote {files[0]}")
