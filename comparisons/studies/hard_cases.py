"""``pim hard-cases``: every bundled hard case through PIM and the simulator.

For each case file ``pim/io/cases/hard-*.toml`` (grazing impact, epsilon = 0, epsilon = 1
frictionless, beta = 0, car against a truck 1:50, barrier, pole, both vehicles spinning,
C within 1 cm of a CG, Gamma = 37 deg, 100 m/s closing speed, near-singular q) at the
case's own (epsilon, beta):

* PIM's answer (velocity changes, yaw rates, impulse, energy loss) and its flags;
* the simulator at its default settings: the error against PIM
  (:func:`sim.error_measure.impact_error`), the sweeps used, the wall time, or the failure;
* what the simulator needs to reach 1e-6, from the full speed-error sweep
  (:func:`comparisons.studies.speed_error.sweep`): with the exact contact start, the fewest solver
  iterations (and the largest dt with them); with the detected start, the largest dt, or
  the best error it reaches and why it cannot; with the outline contact, the best error;
  and the failures (tunnelling, non-convergence ...) with the dt at which they appear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import pim
import sim
from comparisons.report.tables import Table, fmt_error
from comparisons.studies.speed_error import TARGET, SpeedErrorStudy, sweep
from pim.io.units import convert
from sim.error_measure import impact_error

__all__ = ["HardCase", "HardCaseStudy", "run_hard_case", "run_hard_cases", "hard_case_names",
           "TARGET"]


def _f(x) -> float:
    return float(np.asarray(x, float).reshape(()))


def hard_case_names() -> list[str]:
    """Names of the bundled hard cases, sorted."""
    return sorted(name for name, _ in pim.list_cases() if name.startswith("hard-"))


@dataclass(frozen=True, eq=False)
class HardCase:
    """One hard case: PIM's answer, the default simulation, and the sweep.

    Attributes
    ----------
    name, description : str
    eps, beta : float
    result : pim.Result
    problems : list of str
        PIM's own flags (``result.problems()``).
    limitations : list of str
        :func:`sim.limitations`: why the engine cannot reproduce PIM here (empty if it can).
    error : float
        Default-settings simulation error [-] (NaN if it failed).
    iterations : int
        Sweeps the default settings used (0 if failed).
    wall_time : float
        Default-settings wall time [s].
    failure : str or None
        Failure kind of the default run.
    study : SpeedErrorStudy
        The full sweep.
    """

    name: str
    description: str
    eps: float
    beta: float
    result: pim.Result
    problems: list
    limitations: list
    error: float
    iterations: int
    wall_time: float
    failure: str | None
    study: SpeedErrorStudy

    # ---- what the simulator needs -----------------------------------------------------
    @property
    def exact_needs(self):
        """Exact start, point contact: the run reaching 1e-6 with the fewest iterations."""
        return self.study.cheapest_reaching(TARGET, start="exact", contact="point")

    @property
    def detected_needs(self):
        """Detected start, point contact: the largest dt reaching 1e-6 (None if none)."""
        return self.study.cheapest_reaching(TARGET, start="detected", contact="point")

    def failures(self, **where) -> dict:
        """Failure kind -> largest dt at which it occurred, among matching runs."""
        out: dict = {}
        for p in self.study.points:
            if not p.ok and all(getattr(p, k) == v for k, v in where.items()):
                out[p.failure] = max(out.get(p.failure, 0.0), p.dt)
        return out

    def _min_iterations(self) -> int | None:
        """Fewest fixed iterations that reach 1e-6 at every dt of the sweep (exact start)."""
        pts = [p for p in self.study.points if p.start == "exact" and p.contact == "point"
               and p.iterations is not None]
        for its in sorted({p.iterations for p in pts}):
            row = [p for p in pts if p.iterations == its]
            if row and all(p.ok and p.error <= TARGET for p in row):
                return its
        return None

    def needs_text(self) -> str:
        """Plain-language answer: what it takes to reach 1e-6, and where it cannot."""
        parts = []
        its = self._min_iterations()
        if its is not None:
            parts.append(f"exact start: any dt in the sweep (1e-2 ... 1e-5 s) with >= {its} "
                         f"iterations")
        else:
            best = self.study.best(start="exact", contact="point")
            why = "; ".join(self.limitations) or ", ".join(
                f"{k}" for k in self.failures(start="exact", contact="point"))
            parts.append("exact start: cannot" + (f" (best {best.error:.1e})" if best else "")
                         + (f" -- {why}" if why else ""))
        det = self.detected_needs
        if det is not None:
            parts.append(f"detected start: dt <= {det.dt:g} s")
        else:
            best = self.study.best(start="detected", contact="point")
            text = "detected start: cannot"
            if best is not None:
                text += (f" (best {best.error:.1e} at dt = {best.dt:g} s; the lever arms are "
                         f"off by the distance moved in part of a step, error ~ dt)")
            parts.append(text)
        fails = self.failures(start="detected", contact="point")
        if "no_contact" in fails:
            parts.append(f"tunnelling (no contact found) at dt >= "
                         f"{min(p.dt for p in self.study.points if p.failure == 'no_contact'):g} s")
        return "; ".join(parts)

    def outline_text(self) -> str:
        best = self.study.best(contact="outline")
        fails = self.failures(contact="outline")
        if best is None:
            return "fails: " + ", ".join(fails) if fails else "not run"
        text = f"best {best.error:.1e}"
        if best.error > TARGET:
            text += " (a contact patch, not PIM's single point)"
        return text


@dataclass(frozen=True, eq=False)
class HardCaseStudy:
    """All hard cases.

    Attributes
    ----------
    cases : tuple of HardCase
        One entry per hard case, in the order run (looked up by name with ``study[name]``).
    """

    cases: tuple[HardCase, ...]

    def __getitem__(self, name: str) -> HardCase:
        for c in self.cases:
            if c.name == name:
                return c
        raise KeyError(name)

    def results_table(self, units: str = "si") -> Table:
        """PIM's answer and the default simulation's error, per case, in ``units``."""
        fv, uv = convert(1.0, "velocity", units)
        fw, uw = convert(1.0, "angular_velocity", units)
        fp, up = convert(1.0, "impulse", units)
        fv, fw, fp = float(fv), float(fw), float(fp)
        rows = []
        for c in self.cases:
            r = c.result
            rows.append((c.name, c.eps, c.beta, _f(r.delta_v1_magnitude) * fv,
                         _f(r.delta_v2_magnitude) * fv, _f(r.yaw_rate1) * fw,
                         _f(r.yaw_rate2) * fw, _f(r.impulse_n) * fp, _f(r.impulse_t) * fp,
                         _f(r.energy_loss_percent),
                         "; ".join(c.problems) or "",
                         c.error, c.iterations or None,
                         c.wall_time * 1e3 if c.failure is None else math.nan,
                         c.failure or ""))
        return Table("hard-cases", "Hard cases: PIM's answer and the pymunk simulation "
                     "(default settings) against it",
                     ("case", "eps", "beta", f"|dV1| [{uv}]", f"|dV2| [{uv}]", f"W1 [{uw}]",
                      f"W2 [{uw}]", f"Pn [{up}]", f"Pt [{up}]", "energy lost [%]", "PIM flags",
                      "sim error [-]", "sweeps", "sim time [ms]", "sim failure"),
                     tuple(rows), formats={"sim error [-]": fmt_error})

    def needs_table(self) -> Table:
        """What the simulator needs to reach 1e-6, per case."""
        rows = []
        for c in self.cases:
            best_exact = c.study.best(start="exact", contact="point")
            best_det = c.study.best(start="detected", contact="point")
            rows.append((c.name, c._min_iterations(),
                         best_exact.error if best_exact else math.nan,
                         c.detected_needs.dt if c.detected_needs else None,
                         best_det.error if best_det else math.nan,
                         best_det.dt if best_det else None,
                         c.outline_text(), c.needs_text(),
                         "; ".join(c.limitations)))
        return Table("hard-cases-needs", f"What the simulator needs to reach {TARGET:g} "
                     "(point contact unless stated)",
                     ("case", "exact start: iterations", "exact start: best error",
                      "detected start: largest dt [s]", "detected start: best error",
                      "at dt [s]", "outline contact", "needs", "engine limitation"),
                     tuple(rows), formats={"exact start: best error": fmt_error,
                                           "detected start: best error": fmt_error})

    def to_json(self) -> list:
        out = []
        for c in self.cases:
            out.append({"case": c.name, "eps": c.eps, "beta": c.beta, "error": c.error,
                        "iterations": c.iterations, "failure": c.failure,
                        "problems": c.problems, "limitations": c.limitations,
                        "exact_iterations": c._min_iterations(),
                        "detected_dt": c.detected_needs.dt if c.detected_needs else None,
                        "needs": c.needs_text(), "outline": c.outline_text()})
        return out


def run_hard_case(name: str, repeats: int = 1, progress: bool | None = False) -> HardCase:
    """PIM, the default simulation and the full sweep for one bundled case."""

    case = pim.load_case(name)
    eps, beta = sim.scene.resolve_coefficients(case, None, None)
    result = pim.solve(case, eps, beta)
    failure, error, its, wall = None, math.nan, 0, math.nan
    try:
        s = sim.simulate(case, eps, beta)
        error = float(impact_error(case, result, s.velocity1, s.velocity2, s.yaw_rate1,
                                   s.yaw_rate2))
        its, wall = s.iterations, s.wall_time
    except sim.SimulationError as exc:
        failure = exc.kind
    study = sweep(case, eps, beta, repeats=repeats, progress=progress)
    return HardCase(name=case.name or name, description=case.description or "", eps=eps,
                    beta=beta, result=result, problems=result.problems(),
                    limitations=sim.limitations(case, eps, beta), error=error,
                    iterations=its, wall_time=wall, failure=failure, study=study)


def run_hard_cases(names=None, repeats: int = 1, progress: bool | None = None) -> HardCaseStudy:
    """:func:`run_hard_case` for every bundled hard case (or ``names``)."""
    from tqdm import tqdm

    names = hard_case_names() if names is None else list(names)
    cases = [run_hard_case(n, repeats) for n in tqdm(
        names, desc="hard cases", unit="case", disable=None if progress is None
        else not progress)]
    return HardCaseStudy(tuple(cases))
