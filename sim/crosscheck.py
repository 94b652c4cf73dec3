"""Analytic PIM versus the pymunk simulation of the same case: values and errors."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import pim

from .limits import limitations
from .result import SimResult
from .run import simulate
from .scene import resolve_coefficients
from .settings import Settings

__all__ = ["CrossCheck", "CheckRow", "crosscheck"]


@dataclass(frozen=True)
class CheckRow:
    """One compared quantity: analytic and simulated values, errors (SI units)."""

    key: str
    label: str
    unit: str
    analytic: float
    simulated: float

    @property
    def abs_error(self) -> float:
        """|simulated - analytic| [unit]."""
        return abs(self.simulated - self.analytic)

    @property
    def rel_error(self) -> float:
        """|simulated - analytic| / |analytic| [-] (NaN where the analytic value is 0)."""
        return self.abs_error / abs(self.analytic) if self.analytic != 0 else float("nan")


@dataclass(frozen=True, eq=False)
class CrossCheck:
    """The outcome of :func:`crosscheck`.

    Attributes
    ----------
    rows : list of CheckRow
        Post-impact velocities, yaw rates, impulse and energy, analytic vs simulated.
    max_rel_error : float
        Largest error of the velocities and yaw rates, each relative to the largest
        magnitude of its kind (speed components; yaw rates) [-].
    limitations : list of str
        Why the engine cannot reproduce PIM here (empty when it can).
    """

    case_name: str
    eps: float
    beta: float
    rows: list
    max_rel_error: float
    limitations: list
    analytic: pim.Result
    simulated: SimResult

    def format_table(self, units: str = "si") -> str:
        """A plain-text table of the comparison and the run's diagnostics, in the ``units``
        system ("si" or "us"; relative errors are unit-free)."""
        from pim.io.units import convert

        kinds = {"m/s": "velocity", "rad/s": "angular_velocity", "N s": "impulse",
                 "J": "energy"}
        s = self.simulated
        lines = [f"{self.case_name}: epsilon = {self.eps:g}, beta = {self.beta:g}  "
                 f"(pymunk: dt = {s.settings.dt:g} s, {s.iterations} iterations, contact = "
                 f"{s.settings.contact}, start = {s.settings.start})",
                 f"{'quantity':<26}{'unit':<7}{'analytic':>15}{'simulated':>15}"
                 f"{'abs error':>12}{'rel error':>12}"]
        for r in self.rows:
            (a, b, e), unit = convert(np.array([r.analytic, r.simulated, r.abs_error]),
                                      kinds[r.unit], units)
            rel = "-" if r.rel_error != r.rel_error else f"{r.rel_error:.3g}"
            lines.append(f"{r.label:<26}{unit:<7}{a:>15.8g}{b:>15.8g}{e:>12.3g}{rel:>12}")
        lines.append(f"max relative error (velocities, yaw rates): {self.max_rel_error:.3g}")
        lines.append(f"wall time {1e3 * s.wall_time:.3f} ms, {s.steps} steps, contact "
                     f"{s.contact_steps} step(s) = {s.contact_duration:.6g} s, "
                     f"{s.contact_points} contact point(s)")
        return "\n".join(lines)

    def to_json(self) -> dict:
        """Plain data for ``--json``."""
        s = self.simulated
        return {
            "case": self.case_name, "eps": self.eps, "beta": self.beta,
            "rows": [{"key": r.key, "label": r.label, "unit": r.unit, "analytic": r.analytic,
                      "simulated": r.simulated, "abs_error": r.abs_error,
                      "rel_error": r.rel_error} for r in self.rows],
            "max_rel_error": self.max_rel_error, "limitations": list(self.limitations),
            "wall_time": s.wall_time, "steps": s.steps, "contact_steps": s.contact_steps,
            "contact_duration": s.contact_duration, "contact_points": s.contact_points,
            "iterations": s.iterations, "settings": s.settings.as_dict(),
        }


def _f(x) -> float:
    return float(np.asarray(x).reshape(()))


def crosscheck(case: pim.Case, eps=None, beta=None,
               settings: Settings | None = None) -> CrossCheck:
    """Solve ``case`` with :func:`pim.solve` and simulate it; compare the two.

    Raises :class:`sim.SimulationError` if the simulation fails, ValueError on bad input.
    """
    eps, beta = resolve_coefficients(case, eps, beta)
    analytic = pim.solve(case, eps, beta)
    simulated = simulate(case, eps, beta, settings)
    a, s = analytic, simulated
    rows = [
        CheckRow("velocity1_x", "vehicle 1 velocity x", "m/s",
                 _f(a.velocity1[..., 0]), s.velocity1[0]),
        CheckRow("velocity1_y", "vehicle 1 velocity y", "m/s",
                 _f(a.velocity1[..., 1]), s.velocity1[1]),
        CheckRow("velocity2_x", "vehicle 2 velocity x", "m/s",
                 _f(a.velocity2[..., 0]), s.velocity2[0]),
        CheckRow("velocity2_y", "vehicle 2 velocity y", "m/s",
                 _f(a.velocity2[..., 1]), s.velocity2[1]),
        CheckRow("yaw_rate1", "vehicle 1 yaw rate", "rad/s", _f(a.yaw_rate1), s.yaw_rate1),
        CheckRow("yaw_rate2", "vehicle 2 yaw rate", "rad/s", _f(a.yaw_rate2), s.yaw_rate2),
        CheckRow("impulse_x", "impulse on vehicle 1 x", "N s", _f(a.impulse[..., 0]), s.impulse[0]),
        CheckRow("impulse_y", "impulse on vehicle 1 y", "N s", _f(a.impulse[..., 1]), s.impulse[1]),
        CheckRow("energy_after", "kinetic energy after", "J", _f(a.kinetic_energy_after),
                 s.energy_after),
    ]
    speed = max(abs(r.analytic) for r in rows[:4])
    spin = max(abs(r.analytic) for r in rows[4:6])
    errors = [r.abs_error / speed for r in rows[:4] if speed > 0]
    errors += [r.abs_error / spin for r in rows[4:6] if spin > 0]
    return CrossCheck(case_name=case.name or "case", eps=eps, beta=beta, rows=rows,
                      max_rel_error=max(errors) if errors else 0.0,
                      limitations=limitations(case, eps, beta), analytic=analytic,
                      simulated=simulated)
