"""``pim event CASE --out DIR``: the whole event from the approach to rest (listed in
:mod:`pim_cli.commands`); the work is :mod:`comparisons.report.event`'s."""

from __future__ import annotations

from pathlib import Path

import click

from pim_cli.main import (
    FiniteFloat,
    case_argument,
    echo_json,
    json_option,
    load_case_for,
    output_units,
    units_option,
)

__all__ = ["event"]


@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Output folder (default: out/CASE-event).")
@click.option("--tyre-friction", "tyre", type=FiniteFloat(0.0, 5.0, "-"), default=None,
              help="Tyre-road friction of both vehicles (default: the case's [evidence], "
                   "else 0.7, dry asphalt; 0: free motion).")
@click.option("--before", "approach", type=FiniteFloat(0.0, 60.0, "s"), default=1.0,
              show_default=True, help="Seconds of the approach before the first impact.")
@click.option("--single-impact", is_flag=True,
              help="PIM's single impact and its run-out (the animation until now), not the "
                   "whole event.")
@click.option("--progress/--no-progress", default=None,
              help="Progress bar of the video on stderr (default: only on a terminal).")
@units_option
@json_option
def event(case_name, out, tyre, approach, single_impact, progress, units, speed_unit,
          as_json):
    """Write CASE's whole event, from the approach to rest, to a folder: every impact,
    the run-out, its video and plan view.

    The folder holds event.mp4 (the pymunk event solid, the analytic event as a ghost),
    plan.png (outlines at a stated interval with their times, CG paths, tyre marks, each
    impact, the rest positions), timeline.csv (every sample in the case's units, each
    column's unit in its header), impacts.csv, report.html and report.md, answer first:
    the impacts in order with their time, delta-V and PDOF per vehicle, and the rest
    positions. The folder is written whole or not at all. --json prints the impacts, the
    rest positions, the approach's duration and the cross-check's differences in the
    case's units (named in its "units").
    """
    from comparisons.report.event import event_json, event_lines, run_event, write_event
    from pim.io.output import output_folder

    case = load_case_for("event", case_name)
    units = output_units(case, units, speed_unit)
    folder = Path(out) if out else Path("out") / f"{case.name or 'case'}-event"
    with output_folder(folder, command="pim event") as tmp:
        run = run_event(case, tyre=tyre, approach=approach, single_impact=single_impact,
                        units=units)
        write_event(run, tmp, units, progress=progress)
    if as_json:
        echo_json({**event_json(run, units), "out": str(folder)})
        return
    for line in event_lines(run, units):
        click.echo(line)
    click.echo(f"wrote {folder / 'report.html'} (event.mp4, plan.png, timeline.csv)")
