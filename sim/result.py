"""What a simulation returns: post-impact state, the impulse, timing and the trajectory."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .settings import Settings

__all__ = ["Trajectory", "SimResult", "BatchResult"]


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Recorded motion of both bodies (SI, global frame), for animations and plots.

    Attributes
    ----------
    time : ndarray (N,)
        Time [s]; 0 is the instant PIM places the impact (bodies at the case's CGs).
    position1, position2 : ndarray (N, 2)
        CG positions [m].
    angle1, angle2 : ndarray (N,)
        Headings [rad] from +x (the case's heading at t = 0, advanced by the yaw rate).
    velocity1, velocity2 : ndarray (N, 2)
        CG velocities [m/s].
    yaw_rate1, yaw_rate2 : ndarray (N,)
        Yaw rates [rad/s].
    impact_index : int
        Index of the state at the end of the first step in which the engine applied the
        contact impulse; ``impact_time = time[impact_index]``.
    outline1, outline2 : ndarray (4, 2) or None
        Corners of the length x width rectangles in the body frame [m] (x along the
        heading), None where the case gives no dimensions; vehicle 2 of a barrier case
        without dimensions has none.
    fixed2 : bool
        Vehicle 2 is a fixed obstacle.
    """

    time: np.ndarray
    position1: np.ndarray
    angle1: np.ndarray
    position2: np.ndarray
    angle2: np.ndarray
    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: np.ndarray
    yaw_rate2: np.ndarray
    impact_index: int
    outline1: np.ndarray | None = None
    outline2: np.ndarray | None = None
    fixed2: bool = False

    @property
    def impact_time(self) -> float:
        """Time [s] of the recorded impact state."""
        return float(self.time[self.impact_index])

    def __len__(self) -> int:
        return len(self.time)


@dataclass(frozen=True, eq=False)
class SimResult:
    """The outcome of :func:`sim.simulate`: the engine's post-impact state and diagnostics.

    Attributes
    ----------
    velocity1, velocity2 : ndarray (2,)
        CG velocities at separation [m/s].
    yaw_rate1, yaw_rate2 : float
        Yaw rates at separation [rad/s].
    impulse : ndarray (2,)
        Contact impulse the engine applied to vehicle 1 [N s], summed over the contact steps
        (vehicle 2 received its negative).
    contact_duration : float
        Time the contact was processed [s] (steps with contact x dt).
    contact_steps : int
        Steps in which the engine processed the contact.
    contact_points : int
        Most contact points seen in one step.
    steps : int
        Steps simulated in all.
    wall_time : float
        Wall-clock time to build and run the scene [s].
    energy_before, energy_after : float
        Kinetic energy before the impact and at separation [J].
    eps, beta : float
        Restitution and friction fraction simulated.
    friction : float
        Coulomb coefficient given to the engine's contact [-] (|mu| for beta < 1, a
        sticking value for beta = 1).
    iterations : int
        Solver sweeps per step used (automatic unless ``settings.iterations`` is set).
    contraction_rate : float
        Predicted error factor per sweep of PIM's contact (:mod:`sim.convergence`).
    settings : Settings
        The settings used.
    trajectory : Trajectory
        Recorded motion.
    final_velocity1, final_velocity2, final_yaw_rate1, final_yaw_rate2 :
        State at the end of the run (differs from the separation state only with
        ``duration > 0``).
    """

    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: float
    yaw_rate2: float
    impulse: np.ndarray
    contact_duration: float
    contact_steps: int
    contact_points: int
    steps: int
    wall_time: float
    energy_before: float
    energy_after: float
    eps: float
    beta: float
    friction: float
    iterations: int
    contraction_rate: float
    settings: Settings
    trajectory: Trajectory
    final_velocity1: np.ndarray
    final_velocity2: np.ndarray
    final_yaw_rate1: float
    final_yaw_rate2: float

    @property
    def energy_loss(self) -> float:
        """Kinetic energy lost in the impact [J]."""
        return self.energy_before - self.energy_after


@dataclass(frozen=True, eq=False)
class BatchResult:
    """The outcome of :func:`sim.simulate_many` (one row per scene; NaN where it failed).

    Attributes
    ----------
    velocity1, velocity2 : ndarray (N, 2)
        CG velocities at separation [m/s].
    yaw_rate1, yaw_rate2 : ndarray (N,)
        Yaw rates at separation [rad/s].
    impulse : ndarray (N, 2)
        Impulse on vehicle 1 [N s].
    contact_duration : ndarray (N,)
        Contact time [s].
    steps : ndarray (N,) of int
        Steps simulated.
    wall_time : ndarray (N,)
        Wall time per scene [s].
    failure : ndarray (N,) of object
        None where the run succeeded, else the :class:`sim.SimulationError` kind.
    message : ndarray (N,) of object
        None or the failure message.
    settings : Settings
        The settings every scene ran with.
    results : tuple
        Each scene's :class:`sim.SimResult` (with its trajectory when ``record``) or
        :class:`sim.SimulationError`, in order.
    """

    velocity1: np.ndarray
    velocity2: np.ndarray
    yaw_rate1: np.ndarray
    yaw_rate2: np.ndarray
    impulse: np.ndarray
    contact_duration: np.ndarray
    steps: np.ndarray
    wall_time: np.ndarray
    failure: np.ndarray
    message: np.ndarray
    settings: Settings
    results: tuple = ()

    @property
    def ok(self) -> np.ndarray:
        """True where the scene simulated without failure."""
        return np.array([f is None for f in self.failure], dtype=bool)

    def __len__(self) -> int:
        return len(self.failure)
