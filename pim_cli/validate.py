"""``pim validate``: PIM against the bundled published crash tests (docs/validation.md); the
work and the report are :mod:`comparisons.report.validate`'s."""

from __future__ import annotations

from pathlib import Path

import click

from comparisons.report.validate import run_validation, write_validation
from pim.io.datasets import DATASETS
from pim.io.output import output_folder, rebase
from pim_cli.main import echo_json, json_option, output_units, units_option

__all__ = ["validate"]


@click.command()
@click.argument("dataset", required=False, default="all",
                type=click.Choice(["all", *DATASETS]))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False),
              help="Directory for report.md, the CSV tables and the figures.")
@units_option
@json_option
def validate(dataset, out, units, speed_unit, as_json):
    """Validate PIM on the bundled published crash tests (DATASET: all by default).

    Reproduces the published analyses with their coefficients, checks the momentum balance
    of the measured data and tabulates the coefficients by crash class; writes a Markdown +
    CSV report with figures into OUT and prints one summary line per dataset. Units default
    to those the data are published in: us for the IIHS tests (and all), si for RICSAC.
    """
    units = output_units(None, units, speed_unit, "si" if dataset == "ricsac" else "us")
    with output_folder(out, command="pim validate") as tmp:
        found = run_validation(dataset, units)
        written = rebase(write_validation(found, tmp), tmp, out)
    if as_json:
        echo_json({"dataset": dataset, "units": units.to_json(), "summary": found.summary,
                   "files": [str(p) for p in written]})
        return
    for line in found.summary:
        click.echo(line)
    click.echo(f"wrote {Path(out) / 'report.html'} (and report.md)")
