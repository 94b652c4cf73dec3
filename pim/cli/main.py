"""The ``pim`` command line.

pim's own commands are defined here; commands of the layers above it (``pim sim``,
``pim compare`` ...) are registered by their packages under the ``pim.commands`` entry-point
group and loaded only when used, so that ``pim/`` never imports ``sim/`` or
``comparisons/``. Any ``ValueError`` (bad input) becomes a one-line message and exit code 2.
"""

from __future__ import annotations

import json
import sys
from importlib.metadata import entry_points

import click

__all__ = ["main", "cli", "case_argument", "eps_option", "beta_option", "units_option",
           "json_option", "echo_json"]

ENTRY_POINT_GROUP = "pim.commands"


class _Commands(click.Group):
    """A click group that also offers the commands registered as entry points."""

    def _plugins(self) -> dict:
        return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | set(self._plugins()))

    def get_command(self, ctx, name):
        command = super().get_command(ctx, name)
        if command is None and name in self._plugins():
            command = self._plugins()[name].load()
        return command


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="pim-harness")
def cli():
    """Brach's Planar Impact Mechanics for vehicle collisions, with a pymunk cross-check.

    CASE is a bundled case name (see `pim cases`) or a path to a TOML case file.
    """


case_argument = click.argument("case_name", metavar="CASE")
eps_option = click.option("--eps", type=float, default=None,
                          help="Coefficient of restitution epsilon in [0, 1] "
                               "(default: the case's).")
beta_option = click.option("--beta", type=float, default=None,
                           help="Fraction of the critical impulse ratio, mu = beta mu0 "
                                "(default: the case's, else 1).")
units_option = click.option("--units", type=click.Choice(["si", "us"]), default="si",
                            show_default=True, help="Units of the printed results.")
json_option = click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")


def echo_json(data) -> None:
    """Print ``data`` as indented JSON (NaN and inf become null)."""
    def clean(x):
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, list | tuple):
            return [clean(v) for v in x]
        if isinstance(x, float) and (x != x or x in (float("inf"), float("-inf"))):
            return None
        return x

    click.echo(json.dumps(clean(data), indent=2))


@cli.command()
def cases():
    """List the bundled cases."""
    from ..io.casefile import list_cases

    items = list_cases()
    width = max(len(name) for name, _ in items)
    for name, description in items:
        click.echo(f"{name:<{width}}  {description}")


@cli.command()
@case_argument
@eps_option
@beta_option
@units_option
@json_option
def solve(case_name, eps, beta, units, as_json):
    """Solve CASE with Brach's PIM and print the post-impact results."""
    from ..io.casefile import load_case
    from ..model.solver import solve as solve_case
    from ..plotting.tables import format_table, rows_to_json, summarize

    case = load_case(case_name)
    result = solve_case(case, eps, beta)
    problems = result.problems()
    if result.q_singular.any():
        raise ValueError(problems[0] if problems else "q is singular")
    rows = summarize(result, units)
    if as_json:
        echo_json({"case": case.name, "units": units, "admissible": bool(result.admissible),
                   "problems": problems, "results": rows_to_json(rows)})
        return
    title = f"{case.name}: epsilon = {float(result.eps):g}, beta = {float(result.beta):g}"
    click.echo(format_table(rows, title))
    for text in problems:
        click.echo(f"warning: {text}", err=True)


@cli.command()
@case_argument
@click.option("--out", "out", type=click.Path(dir_okay=False), required=True,
              help="Image file to write (.png or .svg).")
@eps_option
@beta_option
def draw(case_name, out, eps, beta):
    """Draw CASE's geometry and sign conventions (outlines, C, n, t, Gamma, arms, velocities)."""
    from ..io.casefile import load_case
    from ..io.files import save_figure
    from ..model.solver import solve as solve_case
    from ..plotting.drawing import draw_case

    case = load_case(case_name)
    result = None
    if eps is not None or case.impact.restitution is not None:
        result = solve_case(case, eps, beta)
    path = save_figure(draw_case(case, result), out)
    click.echo(f"wrote {path}")


def main(argv=None) -> int:
    """Entry point of the ``pim`` console script; returns the exit code."""
    try:
        cli.main(args=argv, prog_name="pim", standalone_mode=False)
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except click.exceptions.Abort:
        click.echo("aborted", err=True)
        return 130
    except ValueError as exc:
        click.echo(f"error: {exc}", err=True)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


def run() -> None:
    """Console-script wrapper: exit with :func:`main`'s code."""
    sys.exit(main())
