"""``pim sim CASE``: analytic PIM versus the pymunk simulation, side by side."""

from __future__ import annotations

import click

from pim.model.numbers import InputError
from pim_cli.main import (
    OPTION_NAMES,
    FiniteFloat,
    allow_inadmissible_option,
    beta_option,
    case_argument,
    check_answer,
    echo_json,
    eps_option,
    findings_json,
    finish_answer,
    json_option,
    load_case_for,
    output_units,
    units_option,
)
from sim.crosscheck import crosscheck_law
from sim.failures import SimulationError
from sim.secondary import watch_after_check
from sim.settings import Settings

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
@allow_inadmissible_option
@json_option
def sim(case_name, eps, beta, dt, iterations, contact, start, units, speed_unit,
        allow_inadmissible, as_json):
    """Simulate CASE with pymunk and compare the result with the analytic answer (pim
    solve).

    Both run under the case's impact law (Brach's PIM, friction-capped Brach or
    Kudlich-Slibar).

    Prints analytic and simulated post-impact velocities and yaw rates with absolute and
    relative errors, and the wall time of the simulation; before them, a note when the
    outlines run into each other again within 2 s after the impact (a secondary contact,
    with its time and place). Exit code 1 if the simulation fails (no contact, never
    separated, multiple contacts, energy gained, not converged), and after the table when
    the analytic answer is inadmissible (the reasons first; --allow-inadmissible: exit 0).
    """

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
        check = crosscheck_law(case, eps, beta, settings, names=OPTION_NAMES)
    except SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {in_options(str(exc))}", err=True)
        raise click.exceptions.Exit(1) from None
    found = check_answer(case, check.analytic, units, allow=allow_inadmissible,
                         as_json=as_json)
    secondary, why = watch_after_check(case, check)
    if as_json:
        echo_json(check.to_json(units) | findings_json(found) | {
            "secondary_impact": None if secondary is None else secondary.to_json(units)})
    else:
        # before the table, where a reader sees them; PIM's own flags are said above
        for text in getattr(check, "limitations", ()):
            if not text.startswith("PIM: "):
                click.echo(f"note: {text}", err=True)
        if secondary is not None or why:
            click.echo(f"note: {why or secondary.message(units)}", err=True)
        click.echo(check.format_table(units))
    finish_answer(found, allow_inadmissible)


#: The simulator's settings that ``pim sim`` sets from an option: its messages name the option.
SETTING_OPTIONS = {"settings.iterations": "--iterations", "settings.dt": "--dt",
                   "settings.contact": "--contact", "settings.start": "--start"}


def in_options(message: str) -> str:
    """A message of the simulator as a command-line user reads it: each setting of
    :data:`SETTING_OPTIONS` named by its option (``settings.iterations`` -> ``--iterations``)."""
    for setting, option in SETTING_OPTIONS.items():
        message = message.replace(setting, option)
    return message
