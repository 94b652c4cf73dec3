"""``pim sim CASE``: analytic PIM versus the pymunk simulation, side by side."""

from __future__ import annotations

import click

from pim.model.law import solve as solve_under_law
from pim.model.numbers import InputError
from pim_cli.main import (
    FiniteFloat,
    beta_option,
    case_argument,
    echo_json,
    eps_option,
    json_option,
    load_case_for,
    output_units,
    units_option,
)
from sim.crosscheck import crosscheck
from sim.kudlich_slibar import crosscheck_kudlich_slibar

__all__ = ["sim", "in_options", "SETTING_OPTIONS"]


@click.command()
@case_argument
@eps_option
@beta_option
@click.option("--dt", type=FiniteFloat(0.0, 1.0, "s"), default=None,
              help="Time step [s] in (0, 1] (default: Settings()).")
@click.option("--iterations", type=click.IntRange(1, 100_000), default=None,
              help="Solver iterations per step (default: automatic from the contact).")
@click.option("--contact", type=click.Choice(["point", "outline"]), default="point",
              show_default=True, help="Collide a point at C, or the vehicle outlines.")
@click.option("--start", type=click.Choice(["exact", "detected"]), default="exact",
              show_default=True, help="Place the contact at C, or let the engine find it.")
@units_option
@json_option
def sim(case_name, eps, beta, dt, iterations, contact, start, units, speed_unit, as_json):
    """Simulate CASE with pymunk and compare with the analytic answer (pim solve) under the
    case's impact law (Brach's PIM, friction-capped Brach or Kudlich-Slibar).

    Prints analytic and simulated post-impact velocities and yaw rates with absolute and
    relative errors, and the wall time of the simulation. Exit code 1 if the simulation
    fails (no contact, never separated, multiple contacts, energy gained, not converged).
    """

    from sim.failures import SimulationError
    from sim.settings import Settings

    kwargs = {"iterations": iterations, "contact": contact, "start": start}
    if dt is not None:
        kwargs["dt"] = dt
    try:
        settings = Settings(**kwargs)
    except InputError as exc:
        raise InputError(in_options(str(exc))) from None
    case = load_case_for("sim", case_name)
    units = output_units(case, units, speed_unit)
    try:
        check = _crosscheck_law(case, eps, beta, settings)
    except SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {in_options(str(exc))}", err=True)
        raise click.exceptions.Exit(1) from None
    if as_json:
        echo_json(check.to_json(units))
        return
    for text in getattr(check, "limitations", ()):     # before the table, where a reader sees them
        click.echo(f"note: {text}", err=True)
    click.echo(check.format_table(units))


#: The simulator's settings that ``pim sim`` sets from an option: its messages name the option.
SETTING_OPTIONS = {"settings.iterations": "--iterations", "settings.dt": "--dt",
                   "settings.contact": "--contact", "settings.start": "--start"}


def in_options(message: str) -> str:
    """A message of the simulator as a command-line user reads it: each setting of
    :data:`SETTING_OPTIONS` named by its option (``settings.iterations`` -> ``--iterations``)."""
    for setting, option in SETTING_OPTIONS.items():
        message = message.replace(setting, option)
    return message


def _crosscheck_law(case, eps, beta, settings):
    """The cross-check of the case's impact law: Brach's (at the effective beta for the
    friction-capped law) or the two-phase Kudlich-Slibar run (docs/impact-laws.md)."""
    law = case.impact.law or "brach"
    if law == "kudlich-slibar":
        if eps is not None or beta is not None:
            raise InputError("--eps and --beta do not apply to law kudlich-slibar (set "
                             "impact.restitution and impact.contact_friction in the case)")
        return crosscheck_kudlich_slibar(case, settings=settings)
    if law == "brach-capped":
        capped = solve_under_law(case, eps, beta)
        eps, beta = float(capped.eps), float(capped.beta)
    return crosscheck(case, eps, beta, settings)

