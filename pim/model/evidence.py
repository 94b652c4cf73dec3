"""Evidence after the impact (rest positions and headings, tyre marks, wheel states, road
friction, wheelbase and track) and the unknowns a reconstruction solves for.

Built by :mod:`pim.io.evidence_table` from a case file's ``[evidence]`` and ``[unknown]``
tables; used by :mod:`pim.analysis.reconstruction`. SI units, global frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .crush import CrushProfile, compared_energy
from .driver import DriverInputs
from .numbers import InputError
from .pre_impact import PreImpactMarks
from .runout import RunoutVehicle
from .tyres import TyreData

__all__ = ["VehicleEvidence", "Evidence", "UNKNOWN_KINDS"]

#: Dotted keys an ``[unknown]`` table may name, with the physical kind of their bounds
#: (the keys of /work/notes/fit-api.md's ``free``).
UNKNOWN_KINDS = {
    **{f"vehicle{i}.{key}": kind for i in (1, 2) for key, kind in (
        ("speed", "velocity"), ("velocity_x", "velocity"), ("velocity_y", "velocity"),
        ("yaw_rate", "angular_velocity"), ("phi", "angle"), ("d", "length"),
        ("radius_of_gyration", "length"), ("yaw_inertia", "inertia"))},
    "impact.restitution": "dimensionless", "impact.beta": "dimensionless",
    "impact.normal_angle": "angle", "impact.point_x": "length", "impact.point_y": "length",
    "impact.point_along": "length", "impact.k": "dimensionless", "impact.mu_c": "dimensionless",
}


@dataclass(frozen=True)
class VehicleEvidence:
    """One vehicle's evidence after the impact.

    Attributes
    ----------
    rest_position : ndarray (2,) [m] measured CG at rest
    rest_heading : float [rad] measured heading at rest
    wheelbase, track : float [m] (see :mod:`pim.model.tyres`)
    cg_to_front_axle : float [m] CG forward to the front AXLE, in [0, wheelbase]
        (``[evidence.vehicleN] cg_to_front_axle``); not :attr:`pim.Vehicle.cg_to_front`,
        the CG to the front of the outline (bumper)
    friction : float [-] tyre-road friction coefficient (> 0)
    braking : tuple of four fractions in [0, 1] (0 free-rolling, 1 locked)
    steer : tuple of four angles [rad]
    position_sigma : float [m] standard deviation of the measured positions
    heading_sigma : float [rad] standard deviation of the measured heading
    path_points : ndarray (k, 2) [m] points the CG passed through (e.g. tyre-mark ends)
    where : str, the case-file table named in error messages (e.g. ``evidence.vehicle1``)
    tyre : TyreData or None, the field tyre ([tyres.vehicleN]), or None for the Coulomb tyre
    driver : DriverInputs or None, inputs over time ([driver.vehicleN])
    pre_impact : PreImpactMarks or None, tyre marks before the impact
        ([evidence.vehicleN.pre_impact], :mod:`pim.model.pre_impact`)
    """

    rest_position: np.ndarray
    rest_heading: float
    wheelbase: float
    track: float
    cg_to_front_axle: float
    friction: float
    braking: tuple = (1.0, 1.0, 1.0, 1.0)
    steer: tuple = (0.0, 0.0, 0.0, 0.0)
    position_sigma: float = 0.1
    heading_sigma: float = float(np.radians(2.0))
    path_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    where: str = "evidence"
    tyre: TyreData | None = None
    driver: DriverInputs | None = None
    pre_impact: PreImpactMarks | None = None

    def __post_init__(self):
        w = self.where
        if not (np.isfinite(self.friction) and self.friction > 0):
            raise InputError(f"{w}.friction must be a finite number > 0, got {self.friction!r}")
        for name in ("wheelbase", "track", "position_sigma", "heading_sigma"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise InputError(f"{w}.{name} must be finite and > 0, got {value!r}")
        if not 0 <= self.cg_to_front_axle <= self.wheelbase:
            raise InputError(f"{w}.cg_to_front_axle must be in [0, wheelbase = "
                             f"{self.wheelbase:g} m], got {self.cg_to_front_axle!r}")
        if len(self.braking) != 4 or not all(0 <= b <= 1 for b in self.braking):
            raise InputError(f"{w}.braking must be four fractions in [0, 1] (front-left, "
                             f"front-right, rear-left, rear-right), got {self.braking!r}")
        for name in ("rest_position", "path_points"):
            if not np.all(np.isfinite(getattr(self, name))):
                raise InputError(f"{w}.{name} must be finite")

    @property
    def cg_to_front(self) -> float:
        """The old name of :attr:`cg_to_front_axle` [m] (CG to the front AXLE), kept for
        code written before the rename."""
        return self.cg_to_front_axle

    def runout_vehicle(self, mass, yaw_inertia) -> RunoutVehicle:
        """The :class:`RunoutVehicle` of this evidence with the given mass and inertia."""
        return RunoutVehicle(mass, yaw_inertia, self.wheelbase, self.track,
                             self.cg_to_front_axle, self.friction, braking=self.braking,
                             steer=self.steer, tyre=self.tyre, driver=self.driver)


@dataclass(frozen=True)
class Evidence:
    """The evidence of the two vehicles (any part may be missing).

    Attributes
    ----------
    vehicle1, vehicle2 : VehicleEvidence or None
        Run-out evidence (rest positions ...): None for a vehicle without a run-out.
    crush1, crush2 : CrushProfile or None
        Measured crush profiles with their stiffness (:mod:`pim.model.crush`).
    crush_partition : str
        Which PIM energy the crush energies are compared with
        (:func:`pim.model.crush.compared_energy`): "total" or "normal".
    marks1, marks2 : PreImpactMarks or None
        Tyre marks before the impact of a vehicle without run-out evidence (the skid
        formula needs none of it: the speed at the impact comes from any other evidence);
        a vehicle with run-out evidence keeps its marks in :attr:`VehicleEvidence.pre_impact`.
    """

    vehicle1: VehicleEvidence | None = None
    vehicle2: VehicleEvidence | None = None
    crush1: CrushProfile | None = None
    crush2: CrushProfile | None = None
    crush_partition: str = "total"
    marks1: PreImpactMarks | None = None
    marks2: PreImpactMarks | None = None

    def __post_init__(self):
        compared_energy(self.crush_partition)      # a clear error for an unknown one

    @property
    def has_runout(self) -> bool:
        """Whether any vehicle has run-out evidence (rest position ...)."""
        return self.vehicle1 is not None or self.vehicle2 is not None

    @property
    def crush(self) -> dict:
        """Vehicle number -> its CrushProfile (only the vehicles with one)."""
        return {i: p for i, p in ((1, self.crush1), (2, self.crush2)) if p is not None}

    def pre_impact(self, i: int) -> PreImpactMarks | None:
        """Vehicle ``i``'s tyre marks before the impact (with its run-out evidence or
        without), or None."""
        ev = getattr(self, f"vehicle{i}")
        return ev.pre_impact if ev is not None else getattr(self, f"marks{i}")
