"""What ``pim compare`` found for one case, as one typed object.

:func:`comparisons.report.compare.gather_report` fills a :class:`ReportData` (results, tables,
figures, the animation, the studies, timings);
:func:`comparisons.report.compare_document.compare_document` turns it into the report's
:class:`~comparisons.report.document.Document`, which the one pipeline renders (Markdown,
HTML, CSV).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pim
from comparisons.report.tables import Table

__all__ = ["ReportData", "monte_carlo_note"]


def monte_carlo_note(case) -> str:
    """How the report's 5-95 % intervals were drawn (one sentence, Markdown): the case's
    ``[uncertainty]`` table, and the scatter of each input the program estimated."""
    drawn = [e for e in case.estimates if e.name in case.uncertainty.inputs]
    stated = set(case.uncertainty.inputs) - {e.name for e in drawn}
    parts = (["the case's `[uncertainty]` table"] if stated else []) + [
        f"the scatter of the estimated `{e.name}` (normal, ±{100 * e.relative_sd:.1f} % "
        f"1 sd; the case file gives it no distribution)" for e in drawn]
    return (f"5-95 % intervals: Monte Carlo (`pim uncertainty`) of {' and '.join(parts)}, "
            f"at the coefficients above unless the table varies them.")


@dataclass
class ReportData:
    """Everything a report of one case shows.

    Attributes
    ----------
    case : pim.Case
        The case.
    case_path : str
        The case as the user gave it (a bundled name or a file path): the commands the
        report suggests use it, so that they run as printed.
    units : pim.io.units.DisplayUnits or {"si", "us"}
        Units of every number shown.
    eps, beta : float
        The coefficients used [-].
    sources : dict
        Where each coefficient comes from ({"eps": ..., "beta": ...}, in words).
    result : pim.Result
        PIM's answer at (eps, beta).
    tables : dict of str to Table
        The report's tables by name (results, inputs, fit, crosscheck, speed_error_pareto,
        speed_error, assumptions), in the order they are written.
    fit : pim.analysis.fitting.FitResult or None
        The least-squares fit, when one was made.
    warnings : list of str
        Plausibility warnings (:func:`pim.model.plausibility.findings`).
    spread : pim.analysis.montecarlo.UncertaintyResult or None
        The Monte Carlo of the case's ``[uncertainty]`` table (the 5-95 % intervals).
    misfit : pim.analysis.misfit.Misfit or None
        Each measured quantity against the answer.
    errors : list of str
        Why the answer is inadmissible or the scene impossible (the findings' errors), said
        before the results.
    simulated : sim.SimResult or None
        The pymunk cross-check (None when it failed: ``sim_error``).
    sim_error : sim.SimulationError or None
        Why the cross-check failed.
    limits : list of str
        Where the simulator cannot reproduce PIM for this case.
    error : float
        Largest relative error of the impact's velocity changes, pymunk against PIM.
    plot_files : list of str
        The design sheet's figures, relative to the report folder.
    animation : comparisons.animation.render.AnimationInfo or None
        The animation written (paths relative to the report folder), if any.
    animation_error : sim.SimulationError or None
        Why no animation could be simulated.
    animation_requested : bool
        False with ``--no-animation``.
    plan : str or None
        The plan view of the whole event (``plan.png``), if drawn.
    event_check : sim.EventCheck or None
        The analytic event against the pymunk event at each impact and at rest
        (:func:`sim.event_crosscheck`), when both were computed.
    study : comparisons.studies.speed_error.SpeedErrorStudy or None
        The coarse speed-against-error sweep.
    assumptions : comparisons.studies.assumptions.AssumptionStudy or None
        PIM's assumptions at typical values.
    files : list of str
        The figures and videos written (the report's own files come from its document),
        relative to the report folder.
    seconds : dict of str to float
        Wall and CPU time per step [s].
    """

    case: pim.Case
    case_path: str
    units: object       # pim.io.units.DisplayUnits (or "si"/"us")
    eps: float
    beta: float
    sources: dict
    result: pim.Result
    tables: dict = field(default_factory=dict)
    fit: object = None
    warnings: list = field(default_factory=list)
    spread: object = None
    misfit: object = None
    errors: list = field(default_factory=list)
    simulated: object = None
    sim_error: object = None
    limits: list = field(default_factory=list)
    error: float = float("nan")
    plot_files: list = field(default_factory=list)
    animation: object = None
    animation_error: object = None
    animation_requested: bool = True
    plan: str | None = None
    event_check: object = None
    study: object = None
    assumptions: object = None
    files: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)

    def add_table(self, table: Table) -> None:
        """Add ``table`` (its name is its key and its CSV's stem)."""
        self.tables[table.name] = table
