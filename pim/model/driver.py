"""Driver inputs over time: road-wheel steer angle and per-wheel braking as piecewise-linear
tables of time.

Time ``t`` is counted from the impact (separation): the run-out reads the tables at
``t >= 0``; entries at negative times describe the approach (a vehicle braking into the
impact, :func:`pim.model.runout.pre_impact_motion`). Between entries the inputs are
interpolated linearly, beyond the table they hold the first or last entry (``numpy.interp``,
the same in the compiled run-out). The steer angle is the road-wheel angle of both front
wheels (counter-clockwise, from the vehicle's heading; no Ackermann split, rear wheels
straight); the braking fractions are those of :mod:`pim.model.tyres` (0 free-rolling,
1 locked).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .numbers import InputError, real_array

__all__ = ["DriverInputs", "wheel_tables"]


@dataclass(frozen=True)
class DriverInputs:
    """Piecewise-linear driver inputs (SI).

    Attributes
    ----------
    time : (k,) [s], strictly increasing, relative to the impact
    steer : (k,) [rad] road-wheel steer angle of the front wheels
    brake : (k, 4) [-] braking fraction of each wheel in [0, 1] (front-left, front-right,
        rear-left, rear-right)
    """

    time: object
    steer: object
    brake: object

    def __post_init__(self):
        time = real_array(self.time, "driver.time", "s")
        if time.ndim != 1 or time.size < 1 or not np.all(np.isfinite(time)) or np.any(
                np.diff(time) <= 0):
            raise InputError(f"driver.time must be a strictly increasing list of finite "
                             f"times [s], got {self.time!r}")
        steer = real_array(self.steer, "driver.steer", "rad")
        if steer.shape != time.shape or not np.all(np.isfinite(steer)):
            raise InputError(f"driver.steer must hold one finite angle per time "
                             f"({time.size}) [rad], got {self.steer!r}")
        brake = real_array(self.brake, "driver.brake", "-")
        if brake.shape != time.shape + (4,) or not np.all((brake >= 0) & (brake <= 1)):
            raise InputError(f"driver.brake must hold four fractions in [0, 1] per time "
                             f"({time.size} x 4), got {self.brake!r}")
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "steer", steer)
        object.__setattr__(self, "brake", brake)

    @property
    def brake_start(self) -> float:
        """Time [s] at which the braking starts rising from zero (where the brake build-up
        starts); ``-inf`` when the table brakes from its first entry (no build-up) or never."""
        on = np.flatnonzero(np.any(self.brake > 0, axis=-1))
        if on.size == 0 or on[0] == 0:
            return -np.inf
        return float(self.time[on[0] - 1])


def wheel_tables(driver: DriverInputs | None, braking, steer):
    """Per-wheel tables ``(time (k,), steer (k, 4), brake (k, 4), brake_start)`` for the
    run-out: from the driver's tables, or the constant ``braking`` and ``steer`` (four
    values each) when ``driver`` is None."""
    if driver is None:
        brake = np.broadcast_to(np.asarray(braking, dtype=float), (4,))[None, :]
        angles = np.broadcast_to(np.asarray(steer, dtype=float), (4,))[None, :]
        return np.zeros(1), np.array(angles), np.array(brake), 0.0
    angles = np.zeros((driver.time.size, 4))
    angles[:, 0] = angles[:, 1] = driver.steer
    return driver.time, angles, driver.brake.copy(), driver.brake_start
