"""The table of ``pim``'s commands: each command's name, where it lives, its group, its summary.

``pim --help`` is printed from this table alone: no command module is imported to list the
commands (nor numpy, scipy, pymunk or pim itself), so it answers at once. A command's module
(``target``, "module:function") is imported when that command runs. Each summary is the
first sentence of the command's docstring, whole (``tests/pim_cli/test_commands.py`` checks
both), and the commands are listed by what a user wants to do (:data:`GROUPS`), in the order
of the work, not alphabetically. :data:`LOOK_ALIKES` says which of the commands that sound
alike to use (the help's epilog).

This table is the command line's, so it may name every package's commands: no package
registers anything with the command line, and none imports it.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["Command", "COMMANDS", "GROUPS", "LOOK_ALIKES", "by_name"]


class Command(NamedTuple):
    """One row of the table.

    Attributes
    ----------
    name : str
        What the user types after ``pim``.
    target : str
        ``"module:function"`` of its click command, imported when it runs.
    group : str
        Its heading in ``pim --help`` (one of :data:`GROUPS`).
    summary : str
        One whole sentence: the first sentence of its docstring.
    """

    name: str
    target: str
    group: str
    summary: str


RECONSTRUCT, MODEL, REGRESSION = "Reconstruct a crash", "Check the model", "Regression tests"
#: The headings of ``pim --help``, in their order.
GROUPS = (RECONSTRUCT, MODEL, REGRESSION)

#: Every command, in the order ``pim --help`` lists them within their group.
COMMANDS = (
    Command("cases", "pim_cli.solve:cases", RECONSTRUCT, "List the bundled cases."),
    Command("solve", "pim_cli.solve:solve", RECONSTRUCT,
            "Solve CASE under its impact law (default Brach's PIM) and print the post-impact "
            "results."),
    Command("fit", "pim_cli.fit:fit", RECONSTRUCT,
            "Fit the impact law's parameters (Brach's epsilon and beta, or k and mu_c) to "
            "CASE's measured post-impact motion."),
    Command("reconstruct", "pim_cli.reconstruct:reconstruct", RECONSTRUCT,
            "Reconstruct CASE's unknowns, such as the impact speeds, from its evidence."),
    Command("uncertainty", "pim_cli.uncertainty:uncertainty", RECONSTRUCT,
            "Propagate CASE's [uncertainty] table by Monte Carlo: the 5/50/95 % of each "
            "result and the inputs that drive its spread."),
    Command("sensitivity", "pim_cli.fit:sensitivity", RECONSTRUCT,
            "Rank CASE's uncertain inputs by how much they move the fitted (epsilon, beta) "
            "and delta-V."),
    Command("compare", "pim_cli.compare:compare", RECONSTRUCT,
            "Write CASE's reconstruction report to a folder: PIM's answer, its plots and "
            "animation, and a pymunk cross-check."),
    Command("event", "pim_cli.event:event", RECONSTRUCT,
            "Write CASE's whole event, from the approach to rest, to a folder: every impact, "
            "the run-out, its video and plan view."),
    Command("draw", "pim_cli.solve:draw", RECONSTRUCT,
            "Draw CASE's geometry and sign conventions to an image file."),
    Command("plot", "pim_cli.fit:plot", RECONSTRUCT,
            "Draw the design sheet's graphs for CASE into --out (PNG and SVG)."),
    Command("animate", "pim_cli.compare:animate", RECONSTRUCT,
            "Animate CASE's whole event, from the approach to rest: the pymunk event solid, "
            "the analytic event (pim event) as a ghost (MP4)."),
    Command("validate", "pim_cli.validate:validate", MODEL,
            "Validate PIM on the bundled published crash tests (DATASET: all by default)."),
    Command("validate-models", "pim_cli.models:validate_models", MODEL,
            "Compare PIM with the finite-duration scene tuned to the bundled crash tests, on "
            "tests held out of each fit, with a verdict."),
    Command("assumptions", "pim_cli.compare:assumptions", MODEL,
            "Test PIM's assumptions for CASE, one at a time, on a ladder of crush scenes."),
    Command("pulses", "pim_cli.models:pulses", MODEL,
            "Compare the contact law's force and delta-V pulses with NHTSA test 10146."),
    Command("sim", "pim_cli.sim:sim", MODEL,
            "Simulate CASE with pymunk and compare the result with the analytic answer "
            "(pim solve)."),
    Command("speed-error", "pim_cli.compare:speed_error", MODEL,
            "Sweep the simulator's dt, iterations, contact start and geometry for each CASE."),
    Command("hard-cases", "pim_cli.compare:hard_cases", MODEL,
            "Run every bundled hard case through PIM and the simulator."),
    Command("baseline", "pim_cli.regression:baseline", REGRESSION,
            "Record every output each CASE supports, with its tolerance, in a baseline file."),
    Command("check", "pim_cli.regression:check", REGRESSION,
            "Rerun a baseline's cases and list every quantity that moved beyond its "
            "tolerance."),
)

#: Which command to use: (the commands that sound alike, how to choose), the help's epilog.
LOOK_ALIKES = (
    ("solve, sim or compare?",
     "solve prints PIM's answer for CASE; sim runs the same impact in pymunk and prints both "
     "answers side by side; compare writes the whole report (answer, fit, plots, animation, "
     "the pymunk cross-check) into a folder."),
    ("fit or reconstruct?",
     "fit finds the impact law's coefficients from the post-impact motion you measured "
     "([measured]); reconstruct finds what you do not know ([unknown]: the impact speeds, "
     "the coefficients) from the evidence (rest positions, tyre marks, crush)."),
    ("uncertainty, sensitivity or reconstruct --samples?",
     "uncertainty spreads the case's [uncertainty] table through PIM's answer by Monte "
     "Carlo; sensitivity ranks the inputs that move the fitted (epsilon, beta) by their "
     "derivatives, without sampling; reconstruct --samples N gives the spread of what a "
     "reconstruction found."),
    ("validate, validate-models or check?",
     "validate holds PIM against published crash tests; validate-models compares PIM with a "
     "tuned finite-duration contact on tests held out of the fit; check reruns your own "
     "baseline to find what changed (a regression test, not a validation)."),
    ("draw or plot?",
     "draw makes one picture of the case's geometry and sign conventions; plot writes the "
     "design sheet's graphs (cost, impulse, energy against epsilon, the cost map) into a "
     "folder."),
)


def by_name(name: str) -> Command | None:
    """The row of command ``name``, or None."""
    return next((c for c in COMMANDS if c.name == name), None)
