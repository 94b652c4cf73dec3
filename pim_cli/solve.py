"""``pim solve``, ``pim draw`` and ``pim cases``: one case's answer, its drawing, the bundled
cases (listed in :mod:`pim_cli.commands`)."""

from __future__ import annotations

import click

from pim.model.numbers import InputError
from pim_cli.main import (
    allow_inadmissible_option,
    beta_option,
    cap_friction_option,
    case_argument,
    check_answer,
    echo_json,
    eps_option,
    findings_json,
    finish_answer,
    friction_limit_option,
    json_option,
    law_options,
    load_case_for,
    output_units,
    resolve_options,
    solve_choice,
    units_option,
)

__all__ = ["solve", "draw", "cases"]


@click.command()
def cases():
    """List the bundled cases."""
    from pim.io.casefile import list_cases

    items = list_cases()
    width = max(len(name) for name, _ in items)
    for name, description in items:
        click.echo(f"{name:<{width}}  {description}")


@click.command()
@case_argument
@eps_option
@beta_option
@friction_limit_option
@cap_friction_option
@law_options
@units_option
@allow_inadmissible_option
@json_option
def solve(case_name, eps, beta, friction_limit, cap_friction, law, k, mu_c, units, speed_unit,
          allow_inadmissible, as_json):
    """Solve CASE under its impact law (default Brach's PIM) and print the post-impact
    results.

    Prints each vehicle's post-impact velocity, speed and yaw rate, delta-V, PDOF, the
    impulse, Brach's coefficients and the energy loss with its normal/tangential split, then
    warnings; with pre-impact evidence (tyre marks before the impact, a driver table from a
    negative time) each vehicle's speed at their start. Exit code 1 with one line when the
    vehicles do not approach at C (no impact), and after the table when the answer is
    inadmissible (the reasons first; --allow-inadmissible: exit 0).
    """
    from comparisons.report.pre_impact import pre_impact_json, pre_impact_lines, pre_impact_rows
    from pim.analysis.pre_impact_speeds import case_pre_impact
    from pim.model.result_table import format_table, rows_to_json, summarize, table_title

    case = load_case_for("solve", case_name, law)
    units = output_units(case, units, speed_unit)
    choice = resolve_options(case, eps, beta, friction_limit, cap_friction, law, k, mu_c)
    result = solve_choice(case, choice, units)
    pre_impact = pre_impact_rows(case_pre_impact(case), units)     # marks, driver tables
    if result.unsolvable() is not None:
        raise InputError(result.unsolvable())
    found = check_answer(case, result, units, friction_limit, allow_inadmissible, as_json)
    rows = summarize(result, units)
    law = choice.law
    if as_json:
        echo_json({"case": case.name, "units": units.to_json(), "law": law, **findings_json(found),
                   "results": rows_to_json(rows), "pre_impact": pre_impact_json(pre_impact)})
    else:
        click.echo(format_table(rows, table_title(case.name, result, law)))
        if pre_impact:
            click.echo("\nSpeeds before the impact (from the case's impact velocities):")
            for line in pre_impact_lines(pre_impact):
                click.echo(line)
    finish_answer(found, allow_inadmissible)


@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(dir_okay=False), required=True,
              help="Image file to write (.png or .svg).")
@eps_option
@beta_option
@units_option
@allow_inadmissible_option
def draw(case_name, out, eps, beta, units, speed_unit, allow_inadmissible):
    """Draw CASE's geometry and sign conventions to an image file.

    The drawing shows the outlines, C, n, t, Gamma, the arms, the velocities, and the impulse
    when epsilon is known; no label covers another. What is implausible about the scene is
    said first; exit code 1 after drawing an impossible scene or an inadmissible impulse
    (--allow-inadmissible: exit 0).
    """
    from pim.io.files import save_figure
    from pim.model.law import solve
    from pim.plotting.drawing import draw_case

    case = load_case_for("draw", case_name)
    result = None
    if eps is not None or case.impact.restitution is not None:
        result = solve(case, eps, beta)     # under the case's impact law
    units = output_units(case, units, speed_unit)
    found = check_answer(case, result, units, allow=allow_inadmissible)
    path = save_figure(draw_case(case, result, units=units), out)
    click.echo(f"wrote {path}")
    finish_answer(found, allow_inadmissible)
