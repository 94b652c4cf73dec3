"""The NHTSA crash test 10146 force-crush history, and the contact parameters it gives.

NHTSA test 10146: 2018 Toyota Camry LE, NCAP full frontal into a load-cell barrier at
57.09 km/h, test mass 1719 kg (NHTSA public-domain data; the ASCII channels as collected in
github.com/joe-cormier/pycrash, projects/pycrash demo/data/input/v10146ascii). The CSV in
``sim/data`` was derived from them (its first line says how): barrier force = minus the sum
of the load-cell Fx channels, crush and velocity from the rear-seat crossmember
accelerations. :func:`nhtsa10146` loads it, :func:`contact_parameters` derives the linear
crush stiffness (least squares through the origin on the loading part), the peak force and
crush, the restitution (rebound speed / impact speed) and the contact duration (force above
5 % of its peak). docs/contact-model.md cites it.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources

import numpy as np

__all__ = ["CrashTest", "ContactParameters", "nhtsa10146", "contact_parameters"]

#: Test mass [kg] of NHTSA test 10146 (from the data file's source line).
NHTSA10146_MASS = 1719.0


@dataclass(frozen=True, eq=False)
class CrashTest:
    """A barrier test's history (SI): time [s], crush [m], velocity [m/s], force [N].

    Attributes
    ----------
    time : ndarray (n,)
        Time since the impact (the record's zero) [s].
    crush : ndarray (n,)
        Dynamic crush [m].
    velocity : ndarray (n,)
        Vehicle velocity towards the barrier [m/s] (negative after rebound).
    force : ndarray (n,)
        Barrier force [N].
    mass : float
        Test mass [kg].
    source : str
        Where the data come from (the data file's first line).
    """

    time: np.ndarray
    crush: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    mass: float
    source: str


@dataclass(frozen=True)
class ContactParameters:
    """What a barrier test says about the contact law.

    Attributes
    ----------
    stiffness : float
        Linear loading stiffness k [N/m] (least squares F = k delta up to peak crush).
    peak_force : float
        [N] (2.5 ms samples).
    peak_crush : float
        Maximum dynamic crush [m].
    restitution : float
        Rebound speed over impact speed [-] at the end of the record.
    contact_start, contact_end : float
        First and last time the force exceeds 5 % of its peak [s].
    """

    stiffness: float
    peak_force: float
    peak_crush: float
    restitution: float
    contact_start: float
    contact_end: float


def nhtsa10146() -> CrashTest:
    """Load the bundled NHTSA 10146 force-crush history."""
    text = resources.files("sim").joinpath("data/nhtsa10146_camry_lcb_force_crush.csv") \
        .read_text(encoding="utf-8")
    lines = text.splitlines()
    source = lines[0].lstrip("# ")
    data = np.loadtxt(lines[2:], delimiter=",")
    return CrashTest(time=data[:, 0] / 1e3, crush=data[:, 1], velocity=data[:, 2],
                     force=data[:, 3] * 1e3, mass=NHTSA10146_MASS, source=source)


def contact_parameters(test: CrashTest) -> ContactParameters:
    """The contact law's parameters from a barrier test (module notes)."""
    peak = int(np.argmax(test.crush))
    x, f = test.crush[:peak + 1], test.force[:peak + 1]
    stiffness = float(x @ f / (x @ x))
    above = np.flatnonzero(test.force > 0.05 * test.force.max())
    return ContactParameters(
        stiffness=stiffness, peak_force=float(test.force.max()),
        peak_crush=float(test.crush.max()),
        restitution=float(-test.velocity[-1] / test.velocity[0]),
        contact_start=float(test.time[above[0]]), contact_end=float(test.time[above[-1]]))
