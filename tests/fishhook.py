"""The NHTSA fishhook of a 2004 Chevrolet Malibu: PC-Crash's published run against the
project's planar run-out (field tyre, driver table), at 35, 40 and 45 mph.

Source data (tests/data/pccrash-fishhook-malibu-*.csv, first lines): PC-Crash exports of the
NHTSA fishhook steering (Forkenbrock et al., SAE 2003-01-1008; DOT HS 809 705: handwheel
ramp at about 720 deg/s to 6.5 times the 0.3 g angle, dwell, countersteer at the same rate,
hold, unwind) on a 2004 Chevrolet Malibu, published with the vehicle data in
github.com/joe-cormier/pycrash (projects/validation - single vehicle motion). PC-Crash is a
3D simulator (suspension, roll, its own tyre model): these are a commercial simulator's
published runs of the manoeuvre, not track measurements (none with a vehicle's complete data
could be found; docs/tyres.md says what was searched).

The run-out gets only the published inputs: the vehicle data as entered in PC-Crash, the
entrance speed, and the road-wheel angle samples as a ``[driver]`` steer table (the mean of
the published left and right angles: the project steers both front wheels alike). The tyre
is the brush model with PC-Crash's friction (0.76) and a cornering stiffness from PC-Crash's
"slip angle at maximum force" (10 deg) by one of the two mappings of docs/tyres.md:
``"saturation"`` (the brush saturates at the same angle: ``C = 3 mu N / tan(10 deg)``) or
``"slope"`` (the same initial slope as PC-Crash's linear tyre: ``C = mu N / 10 deg``).

``python -m tests.fishhook`` prints the comparison table (docs/tyres.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pim.model.driver import DriverInputs
from pim.model.runout import RunoutVehicle, TimedRhs, runout
from pim.model.tyres import STANDARD_GRAVITY, TyreData, static_loads

DATA = Path(__file__).resolve().parent / "data"
SPEEDS_MPH = (35, 40, 45)
MAPPINGS = ("saturation", "slope")
LB, INCH, FT, MPH = 0.45359237, 0.0254, 0.3048, 0.44704
SLUG_FT2 = 14.59390294 * FT * FT

#: 2004 Chevrolet Malibu as entered in PC-Crash (the source's notebook), SI.
MALIBU = {"mass": 3298 * LB, "yaw_inertia": 2040 * SLUG_FT2, "wheelbase": 106 * INCH,
          "track": 60 * INCH, "cg_to_front_axle": 38.1 * INCH, "friction": 0.76}
MALIBU_CG_HEIGHT = 21.5 * INCH
SLIP_AT_MAX_FORCE = np.radians(10.0)   # PC-Crash tyre: slip angle at maximum lateral force
STEER_START = 1.0                      # [s] the published steer leaves zero after this


@dataclass(frozen=True)
class Motion:
    """A fishhook's planar motion (SI, ground frame): CG path, heading, yaw rate, lateral
    acceleration (body frame), on the published 0.1 s samples."""

    time: np.ndarray
    x: np.ndarray
    y: np.ndarray
    yaw: np.ndarray
    yaw_rate: np.ndarray
    lateral_acceleration: np.ndarray


@dataclass(frozen=True)
class Published:
    """One published run: its motion, the road-wheel steer [rad] and roll [rad]."""

    speed_mph: float
    motion: Motion
    steer: np.ndarray
    roll: np.ndarray


def published_table(name: str) -> dict:
    """Columns of a tests/data CSV (``#`` source lines, one header line, numbers) by name."""
    lines = [line for line in (DATA / name).read_text().splitlines()
             if not line.startswith("#")]
    table = np.atleast_2d(np.loadtxt(lines[1:], delimiter=","))
    return {column: table[:, i] for i, column in enumerate(lines[0].split(","))}


def load(speed_mph: int) -> Published:
    """The published run at ``speed_mph`` (35, 40 or 45), converted to SI; the yaw rate is
    the published yaw angle's central difference (``numpy.gradient``)."""
    col = published_table(f"pccrash-fishhook-malibu-{speed_mph}mph.csv")
    time, yaw = col["time_s"], np.radians(col["yaw_deg"])
    motion = Motion(time, col["x_ft"] * FT, col["y_ft"] * FT, yaw, np.gradient(yaw, time),
                    col["lat_accel_g"] * STANDARD_GRAVITY)
    steer = np.radians(0.5 * (col["road_wheel_lf_deg"] + col["road_wheel_rf_deg"]))
    return Published(float(col["vx_mph"][0]), motion, steer, np.radians(col["roll_deg"]))


def malibu(driver: DriverInputs, mapping: str = "saturation") -> RunoutVehicle:
    """The Malibu on the field tyre (no braking, no rolling resistance: PC-Crash's run keeps
    its speed once straight), cornering stiffness per tyre by ``mapping``."""
    if mapping not in MAPPINGS:
        raise ValueError(f"mapping must be one of {MAPPINGS}, got {mapping!r}")
    loads = static_loads(MALIBU["mass"], MALIBU["wheelbase"], MALIBU["cg_to_front_axle"])
    mu = MALIBU["friction"]
    stiffness = (3 * mu * loads / np.tan(SLIP_AT_MAX_FORCE) if mapping == "saturation"
                 else mu * loads / SLIP_AT_MAX_FORCE)
    tyre = TyreData(cornering_stiffness=stiffness, cg_height=MALIBU_CG_HEIGHT,
                    rolling_resistance=0.0)
    return RunoutVehicle(**MALIBU, braking=(0.0, 0.0, 0.0, 0.0), tyre=tyre, driver=driver)


def simulate(run: Published, mapping: str = "saturation") -> Motion:
    """The project's run-out through the published steer table from the entrance speed."""
    driver = DriverInputs(run.motion.time, run.steer, np.zeros((run.steer.size, 4)))
    car = malibu(driver, mapping)
    time = run.motion.time
    result = runout(car, [0.0, 0.0], 0.0, [run.speed_mph * MPH, 0.0], 0.0,
                    max_time=float(time[-1]), dense_output=True, rtol=1e-7, atol=1e-9)
    states = result.interpolant(time)
    rate = TimedRhs(car)
    acceleration = np.array([rate(t, s)[3:5] for t, s in zip(time, states.T, strict=True)])
    psi = states[2]
    lateral = -np.sin(psi) * acceleration[:, 0] + np.cos(psi) * acceleration[:, 1]
    return Motion(time, states[0], states[1], psi, states[5], lateral)


@dataclass(frozen=True)
class Metrics:
    """The planar figures the source gives, each ``(published, model)`` (SI, rad)."""

    first_peak_yaw_rate: tuple      # [rad/s] largest yaw rate in the first steer's direction
    first_peak_time: tuple          # [s]
    second_peak_yaw_rate: tuple     # [rad/s] largest in the countersteer's direction
    second_peak_time: tuple         # [s]
    first_peak_lateral: tuple       # [m/s^2] largest a_y in the first steer's direction
    final_heading: tuple            # [rad]
    path_error_3s: float            # [m] largest CG distance model - published, t <= 3 s
    path_error_end: float           # [m] largest CG distance over the whole run
    peak_roll: float                # [rad] published; the planar model has none


def _peak(motion: Motion, name: str, window, sign: float) -> tuple:
    """Largest value of ``sign * motion.name`` in ``window``, and its time."""
    values = sign * getattr(motion, name)[window]
    i = int(np.argmax(values))
    return float(values[i]), float(motion.time[window][i])


def compare(run: Published, model: Motion) -> Metrics:
    """The metrics of ``model`` against ``run``. The first steer runs from the steer start
    to the countersteer's zero crossing, the second phase from there to the end of the
    hold (where the published steer starts to unwind); peaks are taken in each phase's
    steer direction (yaw rate and lateral acceleration of the first steer's sign, then of
    the countersteer's)."""
    time, steer = run.motion.time, run.steer
    first_extreme = int(np.argmax(np.abs(steer)))
    cross = first_extreme + int(np.argmax(np.sign(steer[first_extreme:])
                                          != np.sign(steer[first_extreme])))
    second_extreme = cross + int(np.argmax(np.abs(steer[cross:])))
    hold = second_extreme + int(np.argmax(np.abs(steer[second_extreme:])
                                          < np.abs(steer[second_extreme])))
    first = slice(int(np.searchsorted(time, STEER_START)), cross + 1)
    second = slice(cross, hold + 1)
    sign, pairs = float(np.sign(steer[first_extreme])), {}
    for name, field, window, s in (("first", "yaw_rate", first, sign),
                                   ("second", "yaw_rate", second, -sign),
                                   ("lateral", "lateral_acceleration", first, sign)):
        pub, mod = _peak(run.motion, field, window, s), _peak(model, field, window, s)
        pairs[name] = ((pub[0], mod[0]), (pub[1], mod[1]))
    gap = np.hypot(model.x - run.motion.x, model.y - run.motion.y)
    return Metrics(pairs["first"][0], pairs["first"][1], pairs["second"][0],
                   pairs["second"][1], pairs["lateral"][0],
                   (float(run.motion.yaw[-1]), float(model.yaw[-1])),
                   float(gap[time <= 3.0].max()), float(gap.max()),
                   float(np.abs(run.roll).max()))


def rows(speeds=SPEEDS_MPH, mappings=MAPPINGS):
    """``(speed_mph, mapping, Metrics)`` for each run."""
    for speed in speeds:
        run = load(speed)
        for mapping in mappings:
            yield speed, mapping, compare(run, simulate(run, mapping))


def main() -> None:  # pragma: no cover - prints the table of docs/tyres.md
    deg, g = np.degrees, STANDARD_GRAVITY
    print("| mph | C_y mapping | 1st yaw-rate peak deg/s (t s): PC-Crash / model | "
          "2nd peak deg/s (t s) | 1st peak a_y g | final heading deg | CG gap m, t<=3 s / "
          "whole | PC-Crash peak roll deg |")
    print("|---|---|---|---|---|---|---|---|")
    for speed, mapping, m in rows():
        print(f"| {speed} | {mapping} | {deg(m.first_peak_yaw_rate[0]):.1f} "
              f"({m.first_peak_time[0]:.1f}) / {deg(m.first_peak_yaw_rate[1]):.1f} "
              f"({m.first_peak_time[1]:.1f}) | {deg(m.second_peak_yaw_rate[0]):.1f} "
              f"({m.second_peak_time[0]:.1f}) / {deg(m.second_peak_yaw_rate[1]):.1f} "
              f"({m.second_peak_time[1]:.1f}) | {m.first_peak_lateral[0] / g:.2f} / "
              f"{m.first_peak_lateral[1] / g:.2f} | {deg(m.final_heading[0]):.1f} / "
              f"{deg(m.final_heading[1]):.1f} | {m.path_error_3s:.2f} / "
              f"{m.path_error_end:.1f} | {deg(m.peak_roll):.1f} |")


if __name__ == "__main__":  # pragma: no cover
    main()
