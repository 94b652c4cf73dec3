"""Analytic PIM versus the pymunk simulation of the same case: values and errors."""

from __future__ import annotations

from dataclasses import dataclass

import pim
from pim.io.units import display_units

from .error_measure import ERROR_DEFINITION, TABLE_HEADER, compare_results, impact_error
from .kudlich_slibar import KudlichSlibarCheck, crosscheck_kudlich_slibar
from .limits import limitations
from .result import SimResult
from .run import simulate
from .scene import resolve_coefficients
from .settings import Settings

__all__ = ["CrossCheck", "crosscheck", "crosscheck_law"]


@dataclass(frozen=True, eq=False)
class CrossCheck:
    """The outcome of :func:`crosscheck`.

    Attributes
    ----------
    case_name : str
        The case's name.
    eps, beta : float
        Coefficient of restitution and fraction of mu0 of both answers [-].
    analytic : pim.Result
        PIM's answer.
    simulated : SimResult
        The simulation's answer.
    rows : list of QuantityError
        Every post-impact quantity of :data:`sim.error_measure.QUANTITIES`, analytic against
        simulated, with absolute and relative errors.
    error : float
        The project's one comparison error (:func:`sim.error_measure.impact_error`): the
        largest error in the velocity changes the impact makes (yaw rates times the radius
        of gyration), relative to the largest such change [-].
    limitations : list of str
        Why the engine cannot reproduce PIM here (empty when it can).
    """

    case_name: str
    eps: float
    beta: float
    rows: list
    error: float
    limitations: list
    analytic: pim.Result
    simulated: SimResult

    def format_table(self, units="si") -> str:
        """A plain-text table of the comparison and the run's diagnostics, in the ``units``
        system ("si" or "us"; relative errors are unit-free)."""
        s = self.simulated
        lines = [f"{self.case_name}: epsilon = {self.eps:g}, beta = {self.beta:g}  "
                 f"(pymunk: dt = {s.settings.dt:g} s, {s.iterations} iterations, contact = "
                 f"{s.settings.contact}, start = {s.settings.start})", TABLE_HEADER]
        lines += [r.line(units) for r in self.rows]
        lines.append(f"error {self.error:.3g} ({ERROR_DEFINITION})")
        lines.append(f"wall time {1e3 * s.wall_time:.3f} ms, {s.steps} steps, contact "
                     f"{s.contact_steps} step(s) = {s.contact_duration:.6g} s, "
                     f"{s.contact_points} contact point(s)")
        return "\n".join(lines)

    def to_json(self, units="si") -> dict:
        """Plain data for ``--json``, the quantities in the ``units`` system (named in
        ``units``; each row carries its unit; times in s)."""
        s = self.simulated

        return {
            "case": self.case_name, "units": display_units(units).to_json(), "eps": self.eps,
            "beta": self.beta,
            "rows": [r.to_json(units) for r in self.rows],
            "error": self.error, "error_definition": ERROR_DEFINITION,
            "limitations": list(self.limitations),
            "wall_time": s.wall_time, "steps": s.steps, "contact_steps": s.contact_steps,
            "contact_duration": s.contact_duration, "contact_points": s.contact_points,
            "iterations": s.iterations, "settings": s.settings.as_dict(),
        }


def crosscheck(case: pim.Case, eps=None, beta=None,
               settings: Settings | None = None) -> CrossCheck:
    """Solve ``case`` with :func:`pim.solve` and simulate it; compare the two.

    Raises :class:`sim.SimulationError` if the simulation fails, ValueError on bad input.
    """
    eps, beta = resolve_coefficients(case, eps, beta)
    analytic = pim.solve(case, eps, beta, law="brach")
    simulated = simulate(case, eps, beta, settings)
    rows = compare_results(case, analytic, simulated)
    error = float(impact_error(case, analytic, simulated.velocity1, simulated.velocity2,
                               simulated.yaw_rate1, simulated.yaw_rate2))
    return CrossCheck(case_name=case.name or "case", eps=eps, beta=beta, rows=rows,
                      error=error,
                      limitations=limitations(case, eps, beta), analytic=analytic,
                      simulated=simulated)


def crosscheck_law(case: pim.Case, eps=None, beta=None, settings: Settings | None = None, *,
                   names: dict | None = None) -> CrossCheck | KudlichSlibarCheck:
    """The cross-check of ``case`` under its own impact law (``case.impact.law``).

    Brach's law: :func:`crosscheck` at (eps, beta). Friction-capped Brach: the same at its
    effective beta (:func:`pim.solve` under the law gives it). Kudlich-Slibar: the two-phase
    run of :func:`sim.kudlich_slibar.crosscheck_kudlich_slibar` at the case's k and mu_c
    (docs/impact-laws.md), which takes no eps or beta.

    Raises :class:`pim.InputError` for eps or beta under Kudlich-Slibar (named as ``names``
    says, e.g. the command line's {"eps": "--eps", "beta": "--beta"}),
    :class:`sim.SimulationError` when the run fails.
    """
    law = case.impact.law or "brach"
    if law == "kudlich-slibar":
        if eps is not None or beta is not None:
            names = {"eps": "eps", "beta": "beta", **(names or {})}
            raise pim.InputError(f"{names['eps']} and {names['beta']} do not apply to law "
                                 "kudlich-slibar (set impact.restitution and "
                                 "impact.contact_friction in the case)")
        return crosscheck_kudlich_slibar(case, settings=settings)
    if law == "brach-capped":
        capped = pim.solve(case, eps, beta)
        eps, beta = float(capped.eps), float(capped.beta)
    return crosscheck(case, eps, beta, settings)
