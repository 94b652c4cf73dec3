"""``pim sim CASE``: analytic PIM versus the pymunk simulation, side by side."""

from __future__ import annotations

import sys

import click

from pim.cli import (
    FiniteFloat,
    beta_option,
    case_argument,
    echo_json,
    eps_option,
    json_option,
    units_option,
)

from .crosscheck import crosscheck

__all__ = ["sim"]


@click.command()
@case_argument
@eps_option
@beta_option
@click.option("--dt", type=FiniteFloat(), default=None, help="Time step [s] (default: Settings()).")
@click.option("--iterations", type=int, default=None,
              help="Solver iterations per step (default: automatic from the contact).")
@click.option("--contact", type=click.Choice(["point", "outline"]), default="point",
              show_default=True, help="Collide a point at C, or the vehicle outlines.")
@click.option("--start", type=click.Choice(["exact", "detected"]), default="exact",
              show_default=True, help="Place the contact at C, or let the engine find it.")
@units_option
@json_option
def sim(case_name, eps, beta, dt, iterations, contact, start, units, as_json):
    """Simulate CASE with pymunk and compare with Brach's PIM (pim solve).

    Prints analytic and simulated post-impact velocities and yaw rates with absolute and
    relative errors, and the wall time of the simulation. Exit code 1 if the simulation
    fails (no contact, never separated, multiple contacts, energy gained, not converged).
    """
    from pim.io.casefile import load_case

    from .failures import SimulationError
    from .settings import Settings

    kwargs = {"iterations": iterations, "contact": contact, "start": start}
    if dt is not None:
        kwargs["dt"] = dt
    settings = Settings(**kwargs)
    case = load_case(case_name)
    units = units or case.units
    try:
        check = crosscheck(case, eps, beta, settings)
    except SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {exc}", err=True)
        sys.exit(1)
    if as_json:
        echo_json(check.to_json(units))
        return
    for text in check.limitations:     # before the table, where a reader sees them
        click.echo(f"note: {text}", err=True)
    click.echo(check.format_table(units))

