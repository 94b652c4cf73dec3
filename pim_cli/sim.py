"""``pim sim CASE``: analytic PIM versus the pymunk simulation, side by side."""

from __future__ import annotations

import math
import sys

import click

from pim_cli.main import (
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
    units_option,
)
from pim.model.impact_laws import solve_law
from pim.model.numbers import InputError

from sim.crosscheck import crosscheck
from sim.failures import SimulationError
from sim.kudlich_slibar import crosscheck_kudlich_slibar, simulate_kudlich_slibar
from sim.secondary import WATCH_AFTER, find_secondary_impact, watch_after_impact
from sim.settings import Settings

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
@allow_inadmissible_option
@json_option
def sim(case_name, eps, beta, dt, iterations, contact, start, units, allow_inadmissible,
        as_json):
    """Simulate CASE with pymunk and compare with the analytic answer (pim solve) under the
    case's impact law (Brach's PIM, friction-capped Brach or Kudlich-Slibar).

    Prints analytic and simulated post-impact velocities and yaw rates with absolute and
    relative errors, and the wall time of the simulation; before them, a note when the
    outlines run into each other again within 2 s after the impact (a secondary contact,
    with its time and place). Exit code 1 if the simulation fails (no contact, never
    separated, multiple contacts, energy gained, not converged), and after the table when
    the analytic answer is inadmissible (the reasons first; --allow-inadmissible: exit 0).
    """
    from pim.io.casefile import load_case

    kwargs = {"iterations": iterations, "contact": contact, "start": start}
    if dt is not None:
        kwargs["dt"] = dt
    settings = Settings(**kwargs)
    case = load_case(case_name)
    units = units or case.units
    try:
        check = _crosscheck_law(case, eps, beta, settings)
    except SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {exc}", err=True)
        sys.exit(1)
    found = check_answer(case, check.analytic, units, allow=allow_inadmissible,
                         as_json=as_json)
    secondary, why = _secondary(case, check)
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


def _secondary(case, check):
    """(The secondary contact within :data:`sim.secondary.WATCH_AFTER` s after the impact
    or None, why it could not be watched or ""): the rigid scene of the check played on,
    or the Kudlich-Slibar two-phase run."""
    try:
        if (case.impact.law or "brach") != "kudlich-slibar":
            return watch_after_impact(case, check.eps, check.beta), ""
        settings = Settings(dt=1e-3, record=True, duration=WATCH_AFTER + 2e-3)
        mu_c = check.mu_c if math.isfinite(check.mu_c) else 1e6    # always stick
        run = simulate_kudlich_slibar(case, check.k, mu_c, settings)
        return find_secondary_impact(run.trajectory), ""
    except SimulationError as exc:
        return None, (f"a secondary contact after the impact was not checked: the run on "
                      f"after the impact failed ({exc.kind})")


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
        capped = solve_law(case, law, eps, beta)
        eps, beta = float(capped.eps), float(capped.beta)
    return crosscheck(case, eps, beta, settings)

