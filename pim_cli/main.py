"""The ``pim`` command line.

pim's own commands are defined here; commands of the layers above it (``pim sim``,
``pim compare`` ...) are registered by their packages under the ``pim.commands`` entry-point
group and loaded only when used, so that ``pim/`` never imports ``sim/`` or
``comparisons/``. A :class:`pim.InputError` (bad input) or a click usage error becomes a
one-line message and exit code 2; any other exception is a bug and keeps its traceback.
"""

from __future__ import annotations

import json
import math
import os
import sys
from importlib.metadata import entry_points

import click

from pim.io.output import OutputError, note_signal, signal_received
from pim.model.case import BETA_RANGE_TEXT
from pim.model.numbers import InputError
from pim.model.plausibility import Findings, findings, warnings_of

__all__ = ["main", "cli", "FiniteFloat", "Beta", "SEED", "in_callback", "CALLBACK_PATHS",
           "case_argument", "eps_option", "beta_option", "units_option", "output_units",
           "json_option", "echo_json", "friction_limit_option", "cap_friction_option",
           "solve_with_options", "warnings_of", "NO_IMPACT_EXIT_CODE", "law_options",
           "load_case_for", "OPTION_NAMES", "resolve_options", "solve_choice",
           "allow_inadmissible_option", "INADMISSIBLE_EXIT_CODE",
           "check_answer", "say_findings", "finish_answer", "findings_json"]

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


@cli.command()
def cases():
    """List the bundled cases."""
    from pim.io.casefile import list_cases

    items = list_cases()
    width = max(len(name) for name, _ in items)
    for name, description in items:
        click.echo(f"{name:<{width}}  {description}")


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
    from pim.io.units import convert, display_units
    from pim.model.law import solve
    from pim.model.plausibility import no_impact_message

    result = solve(case, choice.restitution, choice.beta, law=choice.law,
                   mu_c=choice.contact_friction)
    scale, label = convert(1.0, "velocity", display_units(units, case=case))
    message = no_impact_message(result, label, float(scale))
    if message:
        click.echo(message, err=True)
        raise click.exceptions.Exit(NO_IMPACT_EXIT_CODE)
    return result


def solve_with_options(case, eps, beta, friction_limit=None, cap_friction=False, law=None,
                       k=None, mu_c=None, units=None):
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


@cli.command()
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
    from pim.plotting.tables import format_table, rows_to_json, summarize

    case = load_case_for("solve", case_name, law)
    units = output_units(case, units, speed_unit)
    choice = resolve_options(case, eps, beta, friction_limit, cap_friction, law, k, mu_c)
    result = solve_choice(case, choice, units)
    pre_impact = pre_impact_rows(case_pre_impact(case), units)     # marks, driver tables
    if result.q_singular.any():
        problems = result.problems()
        raise InputError(problems[0] if problems else "q is singular")
    found = check_answer(case, result, units, friction_limit, allow_inadmissible, as_json)
    rows = summarize(result, units)
    law = choice.law
    if as_json:
        echo_json({"case": case.name, "units": units.to_json(), "law": law, **findings_json(found),
                   "results": rows_to_json(rows), "pre_impact": pre_impact_json(pre_impact)})
    else:
        click.echo(format_table(rows, _title(case, result, law)))
        if pre_impact:
            click.echo("\nSpeeds before the impact (from the case's impact velocities):")
            for line in pre_impact_lines(pre_impact):
                click.echo(line)
    finish_answer(found, allow_inadmissible)


def _title(case, result, law: str) -> str:
    """The table's title: the law and the parameters it used."""
    if law == "kudlich-slibar":
        return (f"{case.name}: Kudlich-Slibar law, k = {float(result.eps):g}, mu_c = "
                f"{float(result.contact_friction):g} (equivalent PIM beta = "
                f"{float(result.beta):g})")
    title = f"{case.name}: epsilon = {float(result.eps):g}, beta = {float(result.beta):g}"
    if law == "brach-capped":
        title += " (friction-capped Brach, effective beta)"
    return title


@cli.command()
@case_argument
@click.option("--out", "out", type=click.Path(dir_okay=False), required=True,
              help="Image file to write (.png or .svg).")
@eps_option
@beta_option
@units_option
@allow_inadmissible_option
def draw(case_name, out, eps, beta, units, speed_unit, allow_inadmissible):
    """Draw CASE's geometry and sign conventions (outlines, C, n, t, Gamma, arms, velocities,
    and the impulse when epsilon is known) to an image file; no label covers another. What
    is implausible about the scene is said first; exit code 1 after drawing an impossible
    scene or an inadmissible impulse (--allow-inadmissible: exit 0)."""
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


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every atomic writer removes its temporary file."""


#: Code run from C with its exceptions printed and dropped ("Exception ignored from callback
#: for ffi.gc"): pymunk's collision callbacks and object destructors, at-fork hooks,
#: finalizers. A signal handled there is raised at the first moment outside it.
CALLBACK_PATHS = (f"{os.sep}pymunk{os.sep}", f"{os.sep}cffi{os.sep}")
CALLBACK_NAMES = frozenset({"__del__", "_releaseLock", "_acquireLock",
                            "_after_at_fork_child_reinit_locks", "_after_fork"})


def in_callback(frame) -> bool:
    """Whether ``frame`` (the one a signal handler interrupted) runs inside code whose
    exceptions are dropped (:data:`CALLBACK_PATHS`, :data:`CALLBACK_NAMES`)."""
    while frame is not None:
        code = frame.f_code
        if code.co_name in CALLBACK_NAMES or any(p in code.co_filename
                                                 for p in CALLBACK_PATHS):
            return True
        frame = frame.f_back
    return False


def _interrupt(signum, frame, error) -> None:
    """Record the signal and raise ``error``: here, or, when ``frame`` is inside a callback
    that would drop the exception (and let the run go on to its end), at the first event
    of the main thread outside it (a profile hook, removed as it raises)."""
    note_signal(signum)
    if not in_callback(frame):
        raise error()

    def outside(event_frame, event, arg):
        if not in_callback(event_frame):
            sys.setprofile(None)
            raise error()
    sys.setprofile(outside)


def _on_sigterm(signum, frame):
    _interrupt(signum, frame, Terminated)


def _on_sigint(signum, frame):
    _interrupt(signum, frame, KeyboardInterrupt)


def _interrupted_code() -> int | None:
    """130/143 (with one line on stderr) when SIGINT/SIGTERM arrived during the run.

    An error that follows a signal is reported as the interrupt (ffmpeg or a worker in the
    same process group may fail first, with a broken pipe); so is a run whose interrupt was
    swallowed on its way (its output folder was not swapped in).
    """
    import signal

    signum = signal_received()
    if signum is None:
        return None
    terminated = signum == signal.SIGTERM
    click.echo("terminated" if terminated else "aborted", err=True)
    return 143 if terminated else 130


def main(argv=None) -> int:
    """Entry point of the ``pim`` console script; returns the exit code.

    SIGTERM is handled as SIGINT is: temporary files are removed and the exit code is 143
    (130 for Ctrl-C). A file or folder that cannot be written is one line and exit code 2.
    """
    import signal
    import threading

    previous = {}
    note_signal(None)
    if threading.current_thread() is threading.main_thread():
        previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, _on_sigterm),
                    signal.SIGINT: signal.signal(signal.SIGINT, _on_sigint)}
    try:
        try:
            return _main(argv)
        except KeyboardInterrupt:       # a signal after _main knew its code: still one line
            return _interrupted_code() or 130
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _main(argv) -> int:
    try:
        code = cli.main(args=argv, prog_name="pim", standalone_mode=False)
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.UsageError as exc:     # one line, like every other input error
        hint = f" (see '{exc.ctx.command_path} --help')" if exc.ctx is not None else ""
        click.echo(f"error: {exc.format_message()}{hint}", err=True)
        return exc.exit_code
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except (click.exceptions.Abort, KeyboardInterrupt) as exc:
        code = _interrupted_code()
        if code is not None:
            return code
        terminated = isinstance(exc, Terminated) or isinstance(exc.__context__, Terminated)
        click.echo("terminated" if terminated else "aborted", err=True)
        return 143 if terminated else 130
    except (InputError, OutputError, OSError) as exc:
        code = _interrupted_code()
        if code is not None:
            return code
        if not isinstance(exc, OSError):
            click.echo(f"error: {exc}", err=True)
            return 2
        where = f"{exc.filename}: " if exc.filename else ""
        click.echo(f"error: cannot write {where}{exc.strerror or exc}", err=True)
        return 2
    except Exception:
        code = _interrupted_code()      # e.g. ffmpeg's broken pipe after Ctrl-C
        if code is not None:
            return code
        raise                           # anything else is a bug in pim: its traceback
    return _interrupted_code() or (code if isinstance(code, int) else 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


def run() -> None:
    """Console-script wrapper: exit with :func:`main`'s code."""
    sys.exit(main())
