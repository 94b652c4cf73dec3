"""The Kudlich-Slibar impact (PC-Crash, Virtual CRASH) in the rigid pymunk scene.

Chipmunk's contact is Newton restitution plus a Coulomb clamp whose sticking target is no
tangential slip, so one contact cannot return the law's sticking answer U = -k u (it has no
tangential restitution). The law's two phases can be played as physical inputs, though:

1. **Compression**: the rigid scene of :mod:`sim.scene` with restitution 0 and the contact
   friction mu_c as the Coulomb coefficient of the contact. The engine's impulse P_c then
   stops the relative motion at C in both directions, or slides at |Pt| = mu_c Pn when
   sticking would need more: exactly the law's compression impulse.
2. **Restitution**: k times the impulse the engine applied (read from the engine, not from
   the model), applied at C to vehicle 1 and its opposite to vehicle 2.

Only the case, k and mu_c enter; :func:`pim.model.impact_laws.solve_kudlich_slibar` is not
consulted. The solver's sweep count comes from the contact's convergence rate for both
sticking and sliding at mu_c (:mod:`sim.convergence`); where sliding at mu_c would diverge
(|mu_c K_nt| >= K_nn) the engine cannot reproduce a sliding contact, as for Brach's law.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

import pim
from pim.io.units import display_units
from pim.model.geometry import kinetic_energy
from pim.model.impact_laws import (
    check_contact_friction,
    check_restitution,
    solve_kudlich_slibar,
)
from pim.model.numbers import InputError

from .convergence import auto_iterations, contraction_rate
from .error_measure import ERROR_DEFINITION, TABLE_HEADER, compare_results, impact_error
from .result import Trajectory
from .run import body_state, continue_after_impact, run_scene, trajectory_of
from .scene import build_scene
from .settings import Settings

__all__ = ["KudlichSlibarRun", "KudlichSlibarCheck", "simulate_kudlich_slibar",
           "crosscheck_kudlich_slibar", "engine_friction", "ALWAYS_STICK"]

#: The Coulomb coefficient the engine gets for an infinite mu_c (a contact that always
#: sticks): larger than any sticking impulse ratio needs.
ALWAYS_STICK = 1e6


def engine_friction(mu_c: float) -> float:
    """``mu_c`` as the engine takes it: finite, :data:`ALWAYS_STICK` for an infinite one."""
    return mu_c if np.isfinite(mu_c) else ALWAYS_STICK


@dataclass(frozen=True)
class KudlichSlibarRun:
    """Post-impact state of the two-phase pymunk run (SI, global frame).

    Attributes
    ----------
    velocity1, velocity2 : ndarray (2,)
        CG velocities after the restitution impulse [m/s].
    yaw_rate1, yaw_rate2 : float
        Yaw rates after it [rad/s].
    compression_impulse : ndarray (2,)
        The engine's impulse on vehicle 1 in the compression step [N s].
    impulse : ndarray (2,)
        Total impulse on vehicle 1, (1 + k) times the compression impulse [N s].
    iterations : int
        Solver sweeps used in the compression step.
    energy_before, energy_after : float
        Kinetic energy before and after the impact [J].
    wall_time : float
        Building and running the scene [s].
    trajectory : Trajectory
        Recorded motion: the start, the state after both phases at t = 0 (the impact
        configuration), then ``settings.duration`` of free motion when recording.
    settings : Settings
        The settings used.
    """

    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: float
    yaw_rate2: float
    compression_impulse: np.ndarray
    impulse: np.ndarray
    iterations: int
    energy_before: float = 0.0
    energy_after: float = 0.0
    wall_time: float = 0.0
    trajectory: Trajectory | None = None
    settings: Settings | None = None


def _compression_scene(case: pim.Case, mu_c: float, settings: Settings):
    """The rigid scene at restitution 0 with Coulomb coefficient mu_c at the contact."""
    scene = build_scene(case, 0.0, 1.0, settings)
    circle = scene.contact_shapes[0]
    circle.friction = mu_c                  # the other shape's friction is 1
    scene.friction = mu_c
    if settings.iterations is None:
        k_nn, k_nt, k_tt = scene.k
        # the engine decides between sticking and sliding: enough sweeps for either, except
        # a sliding rate >= 1, which no sweep count cures (the run's check reports it)
        rates = [contraction_rate(k_nn, k_nt, k_tt, mu_c, sticking) for sticking in (True, False)]
        scene.contraction_rate = max(r for r in rates if r < 1.0) if min(rates) < 1.0 else rates[1]
        scene.iterations = max(auto_iterations(r) for r in rates)
        scene.space.iterations = scene.iterations
    return scene


def simulate_kudlich_slibar(case: pim.Case, k: float, mu_c: float,
                            settings: Settings | None = None) -> KudlichSlibarRun:
    """Play the Kudlich-Slibar impact in pymunk: compression by the engine, then restitution.

    Parameters
    ----------
    case : pim.Case
        A single case (scalar fields).
    k : float
        Restitution k [-] in [0, 1].
    mu_c : float
        Contact friction mu_c [-] >= 0 (finite: the engine's Coulomb coefficient).
    settings : Settings, optional
        Numerics; ``contact`` must be "point" and ``start`` "exact" (the law's impulse acts
        at C at the impact configuration). ``duration``, ``record`` and ``tyre_friction``
        continue the run after separation as :func:`sim.simulate` does (for animations).
        Default ``Settings()``.

    Returns
    -------
    KudlichSlibarRun

    Raises
    ------
    ValueError
        k outside [0, 1], mu_c < 0 or infinite, or settings other than point/exact.
    sim.SimulationError
        The compression step failed (no contact, not converged, energy gained).
    """
    k = float(check_restitution(k))
    mu_c = float(check_contact_friction(mu_c))
    if not np.isfinite(mu_c):
        raise InputError("contact_friction mu_c must be finite for the simulator (use a large "
                         "value for a sticking contact)")
    settings = settings or Settings()
    if settings.contact != "point" or settings.start != "exact":
        raise InputError("the two-phase Kudlich-Slibar run needs contact='point' and "
                         "start='exact' (the impulse acts at C)")
    started = time.perf_counter()
    scene = _compression_scene(case, mu_c, replace(settings, duration=0.0))
    out = run_scene(scene, replace(settings, duration=0.0))
    compression = np.asarray(out["impulse"], float)
    c = (float(scene.point[0]), float(scene.point[1]))
    restitution = k * compression
    scene.body1.apply_impulse_at_world_point(tuple(restitution), c)
    if not scene.fixed2:
        scene.body2.apply_impulse_at_world_point(tuple(-restitution), c)
    b1, b2 = scene.body1, scene.body2
    v1, v2 = np.array(b1.velocity), np.array(b2.velocity)
    w1, w2 = float(b1.angular_velocity), float(b2.angular_velocity)
    trajectory = _continue(scene, settings, out)
    wall = time.perf_counter() - started
    after = float(kinetic_energy(case.vehicle1.mass, case.vehicle1.yaw_inertia, v1, w1)
                  + kinetic_energy(case.vehicle2.mass, case.vehicle2.yaw_inertia, v2, w2))
    return KudlichSlibarRun(
        velocity1=v1, velocity2=v2, yaw_rate1=w1, yaw_rate2=w2,
        compression_impulse=compression, impulse=(1.0 + k) * compression,
        iterations=int(scene.iterations), energy_before=float(scene.energy_before),
        energy_after=after, wall_time=wall, trajectory=trajectory, settings=settings)


def _continue(scene, settings: Settings, out: dict) -> Trajectory:
    """The recorded trajectory: the compression run's rows before the impact, the state
    after both phases at the impact instant, then the free motion after separation."""
    tr = out["trajectory"]
    idx = tr.impact_index
    rows = np.column_stack([tr.time, tr.position1, tr.angle1, tr.position2, tr.angle2,
                            tr.velocity1, tr.yaw_rate1, tr.velocity2, tr.yaw_rate2])
    states = [tuple(r) for r in rows[:idx]] + [body_state(float(tr.time[idx]), scene)]
    continue_after_impact(scene, settings, int(out["steps"]), states)
    return trajectory_of(scene, states, idx)


@dataclass(frozen=True, eq=False)
class KudlichSlibarCheck:
    """:func:`pim.model.impact_laws.solve_kudlich_slibar` against the two-phase pymunk run.

    Attributes
    ----------
    case_name : str
        Name of the case compared.
    k : float
        Kudlich-Slibar restitution factor k [-].
    mu_c : float
        Coefficient of friction mu_c of the contact [-].
    rows : list
        Per-quantity comparison rows of :func:`sim.error_measure.compare_results` (SI).
    error : float
        :func:`sim.error_measure.impact_error` of the analytic result against the run [-].
    analytic : pim.Result
        :func:`pim.model.impact_laws.solve_kudlich_slibar`'s result.
    run : KudlichSlibarRun
        The two-phase pymunk run.
    """

    case_name: str
    k: float
    mu_c: float
    rows: list
    error: float
    analytic: pim.Result
    run: KudlichSlibarRun

    def format_table(self, units="si") -> str:
        """A plain-text table of the comparison, in the ``units`` system."""
        lines = [f"{self.case_name}: Kudlich-Slibar law, k = {self.k:g}, mu_c = {self.mu_c:g}  "
                 f"(pymunk: compression at restitution 0 and friction mu_c, "
                 f"{self.run.iterations} iterations; restitution k x its impulse)", TABLE_HEADER]
        lines += [r.line(units) for r in self.rows]
        lines.append(f"error {self.error:.3g} ({ERROR_DEFINITION})")
        lines.append(f"wall time {1e3 * self.run.wall_time:.3f} ms")
        return "\n".join(lines)

    def to_json(self, units="si") -> dict:
        """Plain data for ``--json``, the quantities in the ``units`` system (named in
        ``units``; each row carries its unit; times in s)."""
        return {"case": self.case_name, "units": display_units(units).to_json(),
                "law": "kudlich-slibar", "k": self.k,
                "mu_c": self.mu_c, "error": self.error, "error_definition": ERROR_DEFINITION,
                "rows": [r.to_json(units) for r in self.rows],
                "iterations": self.run.iterations, "wall_time": self.run.wall_time}


def crosscheck_kudlich_slibar(case: pim.Case, k=None, mu_c=None,
                              settings: Settings | None = None) -> KudlichSlibarCheck:
    """Solve ``case`` under the Kudlich-Slibar law and play it in pymunk; compare.

    k and mu_c default to the case's ``impact.restitution`` and ``impact.contact_friction``.
    Raises :class:`sim.SimulationError` if the run fails, ValueError on bad input.
    """
    analytic = solve_kudlich_slibar(case, k, mu_c)
    k, mu_c = float(analytic.eps), float(analytic.contact_friction)
    run = simulate_kudlich_slibar(case, k, mu_c, settings)
    rows = compare_results(case, analytic, run)
    error = float(impact_error(case, analytic, run.velocity1, run.velocity2, run.yaw_rate1,
                               run.yaw_rate2))
    return KudlichSlibarCheck(case.name or "case", k, mu_c, rows, error, analytic, run)
