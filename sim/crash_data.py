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

The stiffness it gives is a property of the contact it was measured on: a full-width
frontal impact into a rigid barrier, the whole front engaged. :func:`contact_type` names a
case's contact (:data:`CONTACT_TYPES`) and :func:`default_stiffness` gives the measured
default of a contact type with its source, or refuses one for a contact no test measured
(an oblique, offset or small-overlap barrier contact engages part of the front; between
two vehicles the two fronts crush in series): give the stiffness, or the contact time
(:func:`sim.contact_law.stiffness_for_duration`), for those.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources

import numpy as np

import pim
from pim.model.numbers import InputError

from .compliant_setup import DEFAULT_STIFFNESS

__all__ = ["CrashTest", "ContactParameters", "StiffnessDefault", "nhtsa10146",
           "contact_parameters", "CONTACT_TYPES", "STIFFNESS_DEFAULTS", "contact_type",
           "default_stiffness", "HEAD_ON_TOLERANCE", "FULL_WIDTH_OFFSET"]

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
    name : str
        The test's short name ("NHTSA 10146").
    """

    time: np.ndarray
    crush: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    mass: float
    source: str
    name: str = "NHTSA 10146"


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


#: The contact types :func:`contact_type` tells apart.
CONTACT_TYPES = ("full-width frontal barrier", "offset frontal barrier", "oblique barrier",
                 "vehicle-to-vehicle")
#: Largest angle [deg] between the car's heading and the contact normal of a head-on
#: (frontal) barrier contact.
HEAD_ON_TOLERANCE = 10.0
#: Largest offset of C from the car's centreline, as a share of its width, of a full-width
#: contact [-] (an NCAP full frontal test engages the whole front; IIHS's small overlap is
#: 25 % of the width, a moderate overlap 40 %).
FULL_WIDTH_OFFSET = 0.1


@dataclass(frozen=True)
class StiffnessDefault:
    """A contact type's default linear stiffness and the test it comes from.

    Attributes
    ----------
    contact : str
        A key of :data:`CONTACT_TYPES`.
    stiffness : float
        Linear loading stiffness k [N/m].
    test : str
        The test it was measured on (:attr:`CrashTest.name`).
    source : str
        The test and how k was derived from it.
    """

    contact: str
    stiffness: float
    test: str
    source: str


#: Contact type -> its measured default; the types not listed have none.
STIFFNESS_DEFAULTS = {
    "full-width frontal barrier": StiffnessDefault(
        "full-width frontal barrier", DEFAULT_STIFFNESS, "NHTSA 10146",
        "NHTSA test 10146 (2018 Toyota Camry LE, NCAP full frontal into a load-cell barrier "
        "at 57.09 km/h): least squares F = k delta on the loading part gives 751 kN/m "
        "(sim.crash_data.contact_parameters), rounded to 7.5e5 N/m"),
}


def _width(vehicle) -> float:
    """The vehicle's width [m], or without an outline the four-tyre model's estimate
    (length k / 0.3, width 0.4 times it: sim.contact_tyres)."""
    if vehicle.width is not None:
        return float(vehicle.width)
    k = math.sqrt(float(vehicle.yaw_inertia) / float(vehicle.mass))
    return 0.4 * k / 0.3


def contact_type(case: pim.Case) -> str:
    """The contact of a single ``case``, one of :data:`CONTACT_TYPES`.

    A barrier contact (vehicle 2 fixed) is frontal when the car's heading lies within
    :data:`HEAD_ON_TOLERANCE` of the contact normal's line, full-width when C is within
    :data:`FULL_WIDTH_OFFSET` of the car's width from its centreline; any contact between
    two moving vehicles is "vehicle-to-vehicle".
    """
    if not bool(case.vehicle2.fixed):
        return "vehicle-to-vehicle"
    car = case.vehicle1
    heading = float(car.heading)
    ahead = np.array([math.cos(heading), math.sin(heading)])
    gamma = float(case.impact.normal_angle)
    if abs(ahead @ np.array([math.cos(gamma), math.sin(gamma)])) < math.cos(
            math.radians(HEAD_ON_TOLERANCE)):
        return "oblique barrier"
    arm = np.asarray(case.impact.point, float).reshape(2) - np.asarray(car.cg, float).reshape(2)
    offset = abs(ahead[0] * arm[1] - ahead[1] * arm[0])
    if offset > FULL_WIDTH_OFFSET * _width(car):
        return "offset frontal barrier"
    return "full-width frontal barrier"


def default_stiffness(contact: str) -> StiffnessDefault:
    """The measured default stiffness of a contact type (:data:`STIFFNESS_DEFAULTS`).

    Raises
    ------
    InputError
        ``contact`` is not one of :data:`CONTACT_TYPES`, or no test measured its
        stiffness (the message says which default exists and what to give instead).
    """
    if contact not in CONTACT_TYPES:
        raise InputError(f"contact type must be one of {', '.join(CONTACT_TYPES)}, got "
                         f"{contact!r}")
    if contact in STIFFNESS_DEFAULTS:
        return STIFFNESS_DEFAULTS[contact]
    measured = "; ".join(f"{d.stiffness:.3g} N/m for the {d.contact} contact ({d.source})"
                         for d in STIFFNESS_DEFAULTS.values())
    why = ("the two fronts crush in series" if contact == "vehicle-to-vehicle" else
           "it engages only part of the front")
    raise InputError(f"stiffness: no measured default for the contact type '{contact}' "
                     f"({why}); the only default is {measured}. Give the stiffness [N/m] or "
                     f"the contact time [s]")
