"""The ``pim`` command line: its group, the options its commands share, its exit codes.

The commands are listed in :mod:`pim_cli.commands` (name, "module:function", group, one-line
summary): ``pim --help`` prints that table without importing a command module, numpy or
pim, and a command's module is imported when the command runs. No package imports the
command line; it imports them all.

A command runs with SIGINT and SIGTERM handled by :class:`pim.io.process.Interrupts`:
temporary files are removed and the exit code is 130 (Ctrl-C) or 143 (SIGTERM), with one
line. A :class:`pim.InputError` (bad input), an output folder or file that cannot be
written, or a click usage error becomes a one-line message and exit code 2; any other
exception is a bug and keeps its traceback.
"""

from __future__ import annotations

import importlib
import json
import math
import signal
import sys
from typing import TYPE_CHECKING

import click

from pim_cli.commands import COMMANDS, GROUPS, LOOK_ALIKES, by_name

if TYPE_CHECKING:
    from pim.model.plausibility import Findings

__all__ = ["main", "cli", "FiniteFloat", "Beta", "SEED",
           "case_argument", "eps_option", "beta_option", "units_option", "output_units",
           "json_option", "echo_json", "friction_limit_option", "cap_friction_option",
           "solve_with_options", "NO_IMPACT_EXIT_CODE", "law_options",
           "load_case_for", "OPTION_NAMES", "resolve_options", "solve_choice",
           "allow_inadmissible_option", "INADMISSIBLE_EXIT_CODE", "allow_inconsistent_option",
           "say_contradiction", "finish_evidence",
           "check_answer", "say_findings", "finish_answer", "findings_json"]


class _Commands(click.Group):
    """pim's group: its commands from the table of :mod:`pim_cli.commands`, listed by their
    group without importing them, each imported when it runs, and run with SIGINT and
    SIGTERM as exceptions."""

    def list_commands(self, ctx):
        return [command.name for command in COMMANDS]

    def get_command(self, ctx, name):
        row = by_name(name)
        if row is None:
            return None
        module, _, function = row.target.partition(":")
        return getattr(importlib.import_module(module), function)

    def format_commands(self, ctx, formatter):
        """One section per group of :data:`pim_cli.commands.GROUPS`, each summary whole."""
        for group in GROUPS:
            with formatter.section(group):
                formatter.write_dl([(c.name, c.summary) for c in COMMANDS if c.group == group])

    def format_epilog(self, ctx, formatter):
        """Which of the commands that sound alike to use: each set of names on a line, how
        to choose below it."""
        with formatter.section("Which command to use"):
            for names, choice in LOOK_ALIKES:
                formatter.write_text(names)
                with formatter.indentation():
                    formatter.write_text(choice)

    def invoke(self, ctx):
        """Run the command with SIGINT and SIGTERM as exceptions
        (:class:`pim.io.process.Interrupts`). An interrupt ends the run with one line and
        exit code 130 or 143; so does an error that follows one (ffmpeg or a worker in the
        same process group may fail first, with a broken pipe) and a run that ends after one
        was swallowed on its way (its output folder was not swapped in)."""
        from pim.io.process import Interrupts  # a command runs: pim loads with it

        interrupts = Interrupts()
        with interrupts.installed():
            try:
                outcome = super().invoke(ctx)
            except (click.exceptions.Exit, click.ClickException):
                if interrupts.last() is None:
                    raise
            except BaseException:
                if interrupts.last() is None:
                    raise
            else:
                if interrupts.last() is None:
                    return outcome
        _interrupted(interrupts.last())


def _interrupted(signum: int):
    """End the run interrupted by ``signum``: one line, exit code 130 (SIGINT) or 143."""
    from pim.io.process import INTERRUPT_EXIT_CODES

    click.echo("terminated" if signum == signal.SIGTERM else "aborted", err=True)
    raise click.exceptions.Exit(INTERRUPT_EXIT_CODES[signum])


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="pim-harness")
def cli():
    """Brach's Planar Impact Mechanics for vehicle collisions, with a pymunk cross-check.

    CASE is a bundled case name (see `pim cases`) or a path to a TOML case file; `pim
    COMMAND --help` gives a command's options.
    """


class FiniteFloat(click.ParamType):
    """A finite float (``nan`` and ``inf`` are usage errors), optionally in [low, high]
    (``unit`` is named with the range in the message)."""

    name = "float"

    def __init__(self, low: float | None = None, high: float | None = None, unit: str = ""):
        self.low, self.high, self.unit = low, high, unit

    def _range(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        if self.low is not None and self.high is not None:
            return f" in [{self.low:g}, {self.high:g}]{unit}"
        return f" >= {self.low:g}{unit}" if self.low is not None else ""

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            number = value
        else:
            try:
                number = float(value)
            except (TypeError, ValueError):
                self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(number) or (self.low is not None and number < self.low) or (
                self.high is not None and number > self.high):
            self.fail(f"{value!r} is not a finite number{self._range()}", param, ctx)
        return number


#: Type of every --seed option: numpy's seeds are integers >= 0 (a negative one is a usage
#: error naming the option, exit 2, not numpy's traceback).
SEED = click.IntRange(min=0)


class Beta(FiniteFloat):
    """A beta option: a finite float >= 0 (:data:`pim.model.case.BETA_RANGE_TEXT`; the
    library's formula takes any beta, e.g. the Kudlich-Slibar law's Brach equivalent)."""

    def convert(self, value, param, ctx):
        from pim.model.case import BETA_RANGE_TEXT

        number = super().convert(value, param, ctx)
        if number < 0:
            self.fail(f"{value!r}: beta {BETA_RANGE_TEXT}", param, ctx)
        return number


case_argument = click.argument("case_name", metavar="CASE")
eps_option = click.option("--eps", type=FiniteFloat(0.0, 1.0), default=None,
                          help="Coefficient of restitution epsilon in [0, 1] "
                               "(default: the case's impact.restitution).")
beta_option = click.option("--beta", type=Beta(), default=None,
                           help="Fraction of the critical impulse ratio, mu = beta mu0 "
                                "(default: the case's impact.beta, else 1).")
def units_option(command):
    """--units (the unit system) and --speed-unit (the unit of speeds and delta-V): the
    command's parameters ``units`` and ``speed_unit``, resolved by :func:`output_units`."""
    from pim.model.case import SPEED_UNITS

    command = click.option(
        "--speed-unit", "speed_unit", type=click.Choice(SPEED_UNITS), default=None,
        help="Unit of every speed, velocity and delta-V in the results (default: the case "
             "file's [units] speed, else km/h in SI units and mph in US units).")(command)
    return click.option(
        "--units", type=click.Choice(["si", "us"]), default=None,
        help="Units of the printed and written results: si (m, kg, N, kJ; speeds in km/h) "
             "or us (ft, slug, lbf, ft lbf; speeds in mph); angles in deg, yaw rates in "
             "deg/s (default: the case file's [units] system, else the units it is written "
             "in).")(command)


def output_units(case=None, units=None, speed_unit=None, default: str = "si"):
    """The :class:`pim.io.units.DisplayUnits` of a command's output from --units and
    --speed-unit (each default: the case file's choice, else ``default`` and its field speed
    unit); the model's messages print speeds in them until the command ends."""
    from pim.io.units import display_units, messages_in

    shown = display_units(units or (None if case is not None else default), speed_unit, case)
    ctx = click.get_current_context(silent=True)
    if ctx is not None:
        ctx.with_resource(messages_in(shown))
    return shown


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


friction_limit_option = click.option(
    "--friction-limit", type=FiniteFloat(low=0.0), default=None,
    help="Warn when |mu| = |Pt/Pn| exceeds this friction coefficient (default: no limit).")
cap_friction_option = click.option(
    "--cap-friction", is_flag=True,
    help="Friction-capped Brach (law brach-capped): mu = sign(mu0) min(beta |mu0|, "
         "--friction-limit). A variant of Brach's law, not PC-Crash's: for the PC-Crash / "
         "Virtual CRASH law use --law kudlich-slibar.")


def law_options(command):
    """--law, --k and --mu-c: the impact law and its parameters (docs/impact-laws.md)."""
    from pim.model.case import LAWS

    command = click.option(
        "--mu-c", "mu_c", type=FiniteFloat(), default=None,
        help="Contact friction mu_c >= 0 between the vehicles (kudlich-slibar), or the cap "
             "of brach-capped (default: the case's impact.contact_friction).")(command)
    command = click.option(
        "--k", "k", type=FiniteFloat(), default=None,
        help="Restitution k in [0, 1] of the kudlich-slibar law (the restitution impulse is "
             "k times the compression impulse; default: the case's impact.restitution).")(
        command)
    return click.option(
        "--law", type=click.Choice(LAWS), default=None,
        help="Impact law: brach (eps, beta), brach-capped (eps, beta, capped at --mu-c) or "
             "kudlich-slibar (PC-Crash / Virtual CRASH: --k, --mu-c); default: the case's "
             "impact.law, else brach.")(command)


#: The command line's names of the law options, for the model's messages.
OPTION_NAMES = {"eps": "--eps", "beta": "--beta", "law": "--law", "k": "--k", "mu_c": "--mu-c",
                "cap_friction": "--cap-friction", "friction_limit": "--friction-limit"}


def resolve_options(case, eps, beta, friction_limit=None, cap_friction=False, law=None, k=None,
                    mu_c=None):
    """The :class:`pim.model.law.LawChoice` the law options make of ``case``
    (:func:`pim.resolve_law`; its messages name the options)."""
    from pim.model.law import resolve_law

    return resolve_law(case, eps, beta, law=law, k=k, mu_c=mu_c, cap_friction=cap_friction,
                       friction_limit=friction_limit, names=OPTION_NAMES)


def solve_choice(case, choice, units=None):
    """Solve ``case`` under the :class:`pim.model.law.LawChoice` ``choice``
    (:func:`pim.solve`).

    Raises click's Exit(1) after one line on stderr when the vehicles do not approach at C
    (no impact), with the approach velocity in ``units`` (default: the case's;
    :func:`pim.io.units.display_units`).
    """
    from pim.io.units import display_units, unit_scale
    from pim.model.law import solve
    from pim.model.plausibility import no_impact_message

    result = solve(case, choice.restitution, choice.beta, law=choice.law,
                   mu_c=choice.contact_friction)
    scale, label = unit_scale("velocity", display_units(units, case=case))
    message = no_impact_message(result, label, scale)
    if message:
        click.echo(message, err=True)
        raise click.exceptions.Exit(NO_IMPACT_EXIT_CODE)
    return result


def solve_with_options(case, eps, beta, *, friction_limit=None, cap_friction=False,
                       law=None, k=None, mu_c=None, units=None):
    """Solve ``case`` as the commands do: :func:`solve_choice` of :func:`resolve_options`.

    Raises InputError for a bad or contradictory option, click's Exit(1) when there is no
    impact.
    """
    choice = resolve_options(case, eps, beta, friction_limit, cap_friction, law, k, mu_c)
    return solve_choice(case, choice, units)


def load_case_for(command: str, case_name: str, law: str | None = None):
    """The case ``case_name`` for ``pim command``, which refuses its impact law (or ``law``)
    here, from the one table of :func:`pim.model.law.check_command_law`."""
    from pim.io.casefile import load_case
    from pim.model.law import check_command_law

    case = load_case(case_name)
    check_command_law(command, case, law)
    return case


#: Exit code of a command whose case has no impact (the vehicles separate at C).
NO_IMPACT_EXIT_CODE = 1
#: Exit code of a command whose answer is inadmissible (printed, reasons first), unless
#: --allow-inadmissible.
INADMISSIBLE_EXIT_CODE = 1

allow_inadmissible_option = click.option(
    "--allow-inadmissible", "allow_inadmissible", is_flag=True,
    help="Exit 0 even when the answer is inadmissible (the contact would pull, kinetic energy "
         "is gained, beta outside [0, 1] under Brach's law, C farther from a CG than the "
         "vehicle is long); the reasons are still printed first. Default: exit 1 after the "
         "answer.")


allow_inconsistent_option = click.option(
    "--allow-inconsistent", "allow_inconsistent", is_flag=True,
    help="Exit 0 even when the evidence contradicts itself (its chi-square's p below 0.001: "
         "the measurements, their sigmas or the model are wrong); the reason is still "
         "printed first. Default: exit 1 after the answer (--allow-inadmissible accepts it "
         "too).")


def say_contradiction(reason: str | None, allow: bool = False) -> None:
    """Before the answer: the evidence's contradiction ``reason`` (None: none) as an error on
    stderr, unless ``allow`` (the output's own warning says it then)."""
    if reason and not allow:
        click.echo(f"error: {reason}", err=True)


def finish_evidence(reason: str | None, allow: bool = False) -> None:
    """After the answer: exit :data:`INADMISSIBLE_EXIT_CODE` when the evidence contradicts
    itself (``reason`` not None), unless ``allow`` (--allow-inconsistent or
    --allow-inadmissible)."""
    if reason and not allow:
        click.echo("error: the evidence contradicts itself (the reason above); "
                   "--allow-inconsistent accepts it", err=True)
        raise click.exceptions.Exit(INADMISSIBLE_EXIT_CODE)


def say_findings(found: Findings, allow: bool = False, as_json: bool = False) -> None:
    """Print ``found`` on stderr before the answer, one line each: its errors ("error:",
    or "warning:" when ``allow``), then its warnings (left to the JSON when ``as_json``)."""
    for text in found.errors:
        click.echo(f"{'warning' if allow else 'error'}: {text}", err=True)
    for text in () if as_json else found.warnings:
        click.echo(f"warning: {text}", err=True)


def check_answer(case, result=None, units=None, friction_limit=None, allow=False,
                 as_json=False) -> Findings:
    """The errors and warnings about ``case`` and its answer ``result``
    (:func:`pim.model.plausibility.findings`), numbers in ``units`` (default: the case's),
    printed on stderr (:func:`say_findings`); end the command with :func:`finish_answer`."""
    from pim.io.units import quantity_text
    from pim.model.plausibility import findings

    found = findings(case, result, friction_limit, quantity_text(units or case.units))
    say_findings(found, allow, as_json)
    return found


def finish_answer(found: Findings, allow: bool = False) -> None:
    """After the answer: exit :data:`INADMISSIBLE_EXIT_CODE` when ``found`` holds errors,
    unless ``allow`` (--allow-inadmissible)."""
    if found.errors and not allow:
        click.echo(f"error: the answer is inadmissible ({len(found.errors)} reason"
                   f"{'s' if len(found.errors) > 1 else ''} above); --allow-inadmissible "
                   f"accepts it", err=True)
        raise click.exceptions.Exit(INADMISSIBLE_EXIT_CODE)


def findings_json(found: Findings) -> dict:
    """The JSON fields of ``found``: admissible, inadmissible (the errors), warnings and
    problems (both)."""
    return {"admissible": not found.errors, "inadmissible": found.errors,
            "warnings": found.warnings, "problems": found.all}


#: What click (8.2 and later) raises for `pim` without a command, after which it prints the
#: help as an error (8.1 printed it as --help does).
_NO_ARGS = getattr(click.exceptions, "NoArgsIsHelpError", ())


def main(argv=None) -> int:
    """Entry point of the ``pim`` console script; returns the exit code.

    SIGTERM is handled as SIGINT is: temporary files are removed and the exit code is 143
    (130 for Ctrl-C). A file or folder that cannot be written is one line and exit code 2.
    """
    try:
        code = cli.main(args=argv, prog_name="pim", standalone_mode=False)
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except _NO_ARGS as exc:             # `pim` alone: the help, as `pim --help` prints it
        click.echo(exc.format_message())
        return 0
    except click.UsageError as exc:     # one line, like every other input error
        hint = f" (see '{exc.ctx.command_path} --help')" if exc.ctx is not None else ""
        click.echo(f"error: {exc.format_message()}{hint}", err=True)
        return exc.exit_code
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except (click.exceptions.Abort, KeyboardInterrupt):
        click.echo("aborted", err=True)     # before a command ran (a run's: _interrupted)
        return 130
    except _one_line_errors() as exc:
        if not isinstance(exc, OSError):
            click.echo(f"error: {exc}", err=True)
            return 2
        where = f"{exc.filename}: " if exc.filename else ""
        click.echo(f"error: cannot write {where}{exc.strerror or exc}", err=True)
        return 2
    return code if isinstance(code, int) else 0     # any other exception: a bug, traceback


def _one_line_errors() -> tuple[type[BaseException], ...]:
    """The errors that are one line and exit code 2: bad input, an output folder that cannot
    be written, any other OSError (imported when one is raised: only a command that ran,
    and so loaded pim, can raise the first two)."""
    from pim.io.output import OutputError
    from pim.model.numbers import InputError

    return InputError, OutputError, OSError


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
