"""Validation on published crash tests: the IIHS small-overlap barrier tests as PIM cases,
reproduction with the published coefficients, the radius of gyration they imply.

Barrier tests in Brach's form (Brach, Welsh & Brach, SAE 2014-01-0469): the car is vehicle 1
with theta1 = 0 (its heading is 180 deg, moving along -x, :mod:`pim.io.brach`), the impact
point C at the origin, the CG at ``cg_from_brach(0, phi, d1, 1)``, the impact plane's normal
at Gamma, vehicle 2 a fixed obstacle. The measured delta-V components are magnitudes along the
car's axes: with this geometry the car slows (-dVx along its heading), is pushed to its right
(-dVy along its left axis) and yaws counter-clockwise (+Omega); :func:`barrier_case` puts them
in ``case.measured`` with those signs, and :func:`reproduce_barrier` checks that the published
coefficients give the same signs.

The yaw inertia is not published (the authors scaled the manufacturer's value by the test
mass), so the radius of gyration k (I = m k^2) is an explicit input. A barrier impact depends
on the mass only through k (the obstacle has infinite mass), so the car's mass is a
placeholder (:data:`PLACEHOLDER_MASS`). :func:`fit_radius_of_gyration` finds, per test, the k
with which the published coefficients best reproduce the measured delta-V and yaw rate: a
one-parameter least-squares fit, residuals scaled by the reproduction tolerances (1 mph for
each delta-V component, 10 deg/s for the yaw rate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..io.brach import cg_from_brach
from ..model.case import Case, Impact, Measured, Vehicle
from ..model.geometry import outline_distance
from ..model.numbers import InputError
from ..model.solver import solve
from .fitting import fit

__all__ = ["PLACEHOLDER_MASS", "SPEED_TOLERANCE", "YAW_TOLERANCE", "K_BOUNDS", "barrier_case",
           "barrier_motion", "fit_radius_of_gyration", "BarrierReproduction",
           "reproduce_barrier", "BarrierRefit", "refit_barrier", "PHI_RANGE",
           "class_radius_of_gyration", "summary_errors", "CoefficientStats", "CRASH_CLASSES",
           "ricsac_case", "RicsacRefit", "refit_ricsac", "coefficient_stats",
           "ricsac_published_errors", "nhtsa_case", "nhtsa_motion"]

PLACEHOLDER_MASS = 1500.0             # kg; a barrier impact depends on k, not m
SPEED_TOLERANCE = 0.44704             # m/s = 1 mph: reproduction tolerance of a delta-V
YAW_TOLERANCE = np.radians(10.0)      # rad/s = 10 deg/s: reproduction tolerance of a yaw rate
K_BOUNDS = (0.6, 2.4)                 # m: search range of the radius of gyration


def _heading_axes():
    h = np.pi
    return h, np.array([np.cos(h), np.sin(h)]), np.array([-np.sin(h), np.cos(h)])


def barrier_case(test, radius_of_gyration, *, phi=None, d=None) -> Case:
    """A :class:`pim.Case` of one barrier test (module notes) [SI].

    Parameters
    ----------
    test : pim.io.datasets.BarrierTest
    radius_of_gyration : array_like
        k [m] (yaw inertia = m k^2); arrays give a batch of cases.
    phi, d : array_like, optional
        Brach's phi [rad] and d [m] of C from the CG instead of the published ones.
    """
    k = np.asarray(radius_of_gyration, dtype=float)
    if (~np.isfinite(k) | (k <= 0)).any():
        raise InputError("radius_of_gyration must be > 0 [m]")
    phi = test.phi if phi is None else np.asarray(phi, float)
    d = test.d if d is None else np.asarray(d, float)
    h, ahead, left = _heading_axes()
    cg = cg_from_brach(0.0, phi, d, 1)
    car = Vehicle(mass=PLACEHOLDER_MASS, yaw_inertia=PLACEHOLDER_MASS * k**2, cg=cg,
                  velocity=test.speed * ahead, heading=h)
    wall = Vehicle.obstacle(cg=(0.0, 0.0))
    dv = -test.delta_v_x * ahead - test.delta_v_y * left
    # standard deviations = the reproduction tolerances, so a fit's chi-square counts them
    measured = Measured(velocity1=test.speed * ahead + dv, yaw_rate1=test.yaw_rate,
                        velocity1_sigma=(SPEED_TOLERANCE, SPEED_TOLERANCE),
                        yaw_rate1_sigma=YAW_TOLERANCE)
    return Case(car, wall, Impact(point=(0.0, 0.0), normal_angle=test.normal_angle,
                                  restitution=test.restitution, beta=test.beta),
                measured=measured, name=test.test_id,
                description=f"IIHS {test.test_id} {test.model_year} {test.vehicle}, "
                            f"{test.barrier} (Brach et al. 2014)")


def barrier_motion(result):
    """(dVx, dVy, Omega) of a barrier solve in the table's sign convention [m/s, m/s, rad/s]:
    slowing along the heading, pushed along the car's right, yaw counter-clockwise."""
    _, ahead, left = _heading_axes()
    dv = result.delta_v1
    return -(dv @ ahead), -(dv @ left), np.asarray(result.yaw_rate1, dtype=float)


def _scaled_residuals(test, result):
    dvx, dvy, om = barrier_motion(result)
    return np.stack([(dvx - test.delta_v_x) / SPEED_TOLERANCE,
                     (dvy - test.delta_v_y) / SPEED_TOLERANCE,
                     (om - test.yaw_rate) / YAW_TOLERANCE], axis=-1)


def fit_radius_of_gyration(test, bounds=K_BOUNDS, grid=121) -> float:
    """The k [m] with which the published coefficients best reproduce the measured motion.

    A grid over ``bounds`` (one batched solve), then a bounded scalar refinement of the sum
    of squared residuals scaled by 1 mph and 10 deg/s (module notes).
    """
    from scipy.optimize import minimize_scalar

    def cost(k):
        r = _scaled_residuals(test, solve(barrier_case(test, k), backend="numpy"))
        return (r**2).sum(-1)

    ks = np.linspace(*bounds, grid)
    i = int(np.argmin(cost(ks)))
    lo, hi = ks[max(i - 1, 0)], ks[min(i + 1, grid - 1)]
    best = minimize_scalar(lambda k: float(cost(k)), bounds=(lo, hi), method="bounded",
                           options={"xatol": 1e-5})
    return float(best.x)


@dataclass(frozen=True)
class BarrierReproduction:
    """One barrier test reproduced with the published coefficients [SI].

    Attributes
    ----------
    test : BarrierTest
        The published test (:mod:`pim.io.datasets`).
    radius_of_gyration : float
        Radius of gyration used [m].
    predicted, measured : tuple
        (dVx, dVy, Omega) [m/s, m/s, rad/s], PIM's and the test's.
    delta_v_error : float
        Length of the delta-V vector error [m/s].
    delta_v_magnitude_error : float
        Predicted |delta-V| minus the tabulated resultant dV [m/s].
    yaw_error : float
        Yaw-rate error [rad/s].
    within_tolerance : bool
        delta-V within 1 mph and yaw rate within 10 deg/s.
    """

    test: object
    radius_of_gyration: float
    predicted: tuple
    measured: tuple

    @property
    def delta_v_error(self) -> float:
        return float(np.hypot(self.predicted[0] - self.measured[0],
                              self.predicted[1] - self.measured[1]))

    @property
    def delta_v_magnitude_error(self) -> float:
        """Predicted |delta-V| minus the tabulated resultant dV [m/s]."""
        return float(np.hypot(*self.predicted[:2]) - self.test.delta_v)

    @property
    def yaw_error(self) -> float:
        return float(self.predicted[2] - self.measured[2])

    @property
    def within_tolerance(self) -> bool:
        """delta-V within 1 mph and yaw rate within 10 deg/s."""
        return self.delta_v_error <= SPEED_TOLERANCE and abs(self.yaw_error) <= YAW_TOLERANCE


def reproduce_barrier(tests, radius_of_gyration=None) -> list[BarrierReproduction]:
    """Each test's motion with the published (e, mu, d1, phi, Gamma).

    ``radius_of_gyration``: None (fitted per test, :func:`fit_radius_of_gyration`), a number
    [m] for every test, or a dict test_id -> k [m].
    """
    out = []
    for t in tests:
        if radius_of_gyration is None:
            k = fit_radius_of_gyration(t)
        elif isinstance(radius_of_gyration, dict):
            k = radius_of_gyration[t.test_id]
        else:
            k = float(radius_of_gyration)
        pred = barrier_motion(solve(barrier_case(t, k), backend="numpy"))
        out.append(BarrierReproduction(t, k, tuple(float(x) for x in pred),
                                       (t.delta_v_x, t.delta_v_y, t.yaw_rate)))
    return out


@dataclass(frozen=True)
class BarrierRefit(BarrierReproduction):
    """A barrier test refitted with :func:`pim.fit`: the fitted coefficients and their motion.

    Attributes
    ----------
    test : BarrierTest
        The published test (:mod:`pim.io.datasets`).
    radius_of_gyration : float
        Radius of gyration used [m].
    predicted, measured : tuple
        (dVx, dVy, Omega) [m/s, m/s, rad/s], PIM's with the refitted coefficients and the
        test's.
    restitution : float
        Fitted restitution epsilon [-].
    beta : float
        Fitted impulse ratio beta [-].
    phi : float
        Brach's phi of vehicle 1 [rad], as fitted (the published one when it was held
        fixed).
    on_bound : tuple of str
        The fitted parameters that sit on a bound (short names, e.g. "eps").
    delta_v_error, delta_v_magnitude_error, yaw_error, within_tolerance
        As :class:`BarrierReproduction` (properties).
    """

    restitution: float
    beta: float
    phi: float
    on_bound: tuple


#: Half-width [rad] of the search range of phi about the published value in the refit.
PHI_RANGE = float(np.radians(30.0))


def refit_barrier(tests, radius_of_gyration, *, free_phi: bool = False,
                  phi_range: float = PHI_RANGE) -> list[BarrierRefit]:
    """Refit each test with :func:`pim.fit` against its measured dVx, dVy and yaw rate.

    ``free_phi=False``: (epsilon, beta) at the published geometry. ``free_phi=True``: the
    published method of Brach et al. (SAE 2014-01-0469): epsilon, beta and the impact point's
    angle phi (Brach's phi of vehicle 1, the free key ``vehicle1.phi``) at the published
    arm length d1, phi within the published value +- ``phi_range`` [rad]; C then moves along
    the circle of radius d1 about the CG (the crush edge as the authors parametrise it).
    epsilon and beta stay in [0, 1] (the paper's mu <= mu0). ``radius_of_gyration``: a
    number [m] or a dict test_id -> k [m].
    """
    out = []
    for t in tests:
        k = (radius_of_gyration[t.test_id] if isinstance(radius_of_gyration, dict)
             else float(radius_of_gyration))
        case = barrier_case(t, k)
        free = {"vehicle1.phi": (t.phi - phi_range, t.phi + phi_range)} if free_phi else None
        r = fit(case, include_yaw=True, free=free)
        phi = r.values.get("vehicle1.phi", t.phi)
        pred = barrier_motion(solve(barrier_case(t, k, phi=phi), eps=r.eps, beta=r.beta,
                                    backend="numpy"))
        out.append(BarrierRefit(t, k, tuple(float(x) for x in pred),
                                (t.delta_v_x, t.delta_v_y, t.yaw_rate), float(r.eps),
                                float(r.beta), float(phi), tuple(r.on_bound)))
    return out


#: Length of a car from its radius of gyration, L = sqrt(12) k (a uniform slender body;
#: RICSAC 9's 13.0 ft and 17.5 ft cars have sqrt(12) k = 12.9 ft and 17.7 ft).
LENGTH_PER_K = float(np.sqrt(12.0))
#: Width over length of the outline (RICSAC 9's cars: 0.41 and 0.37).
WIDTH_PER_LENGTH = 0.39
#: Search range [m] of C along the contact plane in the RICSAC refit.
ALONG_RANGE = 1.0


def ricsac_case(test) -> Case:
    """A :class:`pim.Case` of one RICSAC test with measured pre- and post-impact motion [SI].

    The sources give Brach's theta and phi but not the CG-to-impact distances d, so C is put
    on a documented crush edge: the undeformed rectangular outline of each car (length
    ``sqrt(12) k``, width ``0.39 L``, CG at mid-length; k = sqrt(I/m) from the source's
    inertias), where the ray from the CG at Brach's phi leaves it
    (:func:`pim.model.geometry.outline_distance`); C at the origin, each CG at d_i back along
    its ray (:func:`pim.io.brach.cg_from_brach`); the headings from theta (vehicle 1's is
    theta1 + 180 deg, Brach's convention); pre-impact yaw rates 0; the normal at the
    published Gamma. ``measured`` holds the post-impact velocities and yaw rates.
    """
    if not test.has_motion or test.normal_angle is None:
        raise InputError(f"RICSAC {test.number}: no measured pre/post motion or geometry")
    vehicles = []
    for i, (m, inertia, theta, phi, v) in enumerate(
            ((test.mass1, test.yaw_inertia1, test.theta1, test.phi1, test.velocity1_pre),
             (test.mass2, test.yaw_inertia2, test.theta2, test.phi2, test.velocity2_pre)),
            start=1):
        length = LENGTH_PER_K * float(np.sqrt(inertia / m))
        width = WIDTH_PER_LENGTH * length
        d = float(outline_distance(phi, length, width))
        heading = theta + np.pi if i == 1 else theta
        vehicles.append(Vehicle(mass=m, yaw_inertia=inertia, cg=cg_from_brach(theta, phi, d, i),
                                velocity=v, heading=heading, length=length, width=width))
    measured = Measured(velocity1=test.velocity1_post, velocity2=test.velocity2_post,
                        yaw_rate1=test.yaw_rate1_post, yaw_rate2=test.yaw_rate2_post)
    return Case(*vehicles, Impact(point=(0.0, 0.0), normal_angle=test.normal_angle),
                measured=measured, name=f"ricsac{test.number}",
                description=f"RICSAC {test.number} (crush-edge geometry, see ricsac_case)")


def nhtsa_case(test) -> Case:
    """A :class:`pim.Case` of one NHTSA car-to-car test of Rose et al. [SI].

    C at the origin, each CG at ``d`` back along the ray at ``heading + phi``
    (:class:`pim.io.datasets.NhtsaCarToCarTest`), velocities along the headings, no pre-impact
    yaw, the normal at the tabulated angle. The tabulated outcome (delta-V and yaw-rate change
    magnitudes, the authors' PIM output) is not a post-impact velocity, so ``measured`` is
    None: :func:`nhtsa_motion` gives the same quantities from a result.
    """
    vehicles = []
    for i in (1, 2):
        h, phi, d = (getattr(test, f"{k}{i}") for k in ("heading", "phi", "d"))
        arm = np.array([np.cos(h + phi), np.sin(h + phi)])
        vehicles.append(Vehicle(mass=getattr(test, f"mass{i}"),
                                yaw_inertia=getattr(test, f"yaw_inertia{i}"), cg=-d * arm,
                                velocity=getattr(test, f"speed{i}") * np.array([np.cos(h),
                                                                               np.sin(h)]),
                                heading=h))
    return Case(*vehicles, Impact(point=(0.0, 0.0), normal_angle=test.normal_angle,
                                  restitution=test.restitution, beta=test.beta),
                name=f"nhtsa{test.test}",
                description=f"NHTSA {test.test}, {test.vehicle1} and {test.vehicle2} "
                            f"(Rose et al. 2006)")


def nhtsa_motion(case, velocity1, yaw_rate1, velocity2, yaw_rate2) -> np.ndarray:
    """(|dV1|, |dw1|, |dV2|, |dw2|) [m/s, rad/s, m/s, rad/s], the quantities the NHTSA
    car-to-car table gives, from post-impact velocities [m/s] and yaw rates [rad/s]
    (arrays broadcast; the last axis of the output holds the four)."""
    out = []
    for v, w, veh in ((velocity1, yaw_rate1, case.vehicle1), (velocity2, yaw_rate2,
                                                              case.vehicle2)):
        dv = np.asarray(v, float) - np.asarray(veh.velocity, float)
        out += [np.hypot(dv[..., 0], dv[..., 1]),
                np.abs(np.asarray(w, float) - np.asarray(veh.yaw_rate, float))]
    return np.stack(np.broadcast_arrays(*out), axis=-1)


@dataclass(frozen=True)
class RicsacRefit:
    """One RICSAC test refitted: (eps, beta) and C along the contact plane [SI].

    Attributes
    ----------
    test : RicsacTest
        The published test (:mod:`pim.io.datasets`).
    restitution : float
        Fitted restitution epsilon [-] (NaN when the fit failed).
    beta : float
        Fitted impulse ratio beta [-] (NaN when the fit failed).
    along : float
        Fitted position of C along the contact plane, ``impact.point_along`` [m] (NaN when
        the fit failed).
    residuals : dict of str to float
        Measured term ("velocity1_x", ..., "yaw_rate2") -> model minus measured [m/s or
        rad/s] (empty when the fit failed).
    on_bound : tuple of str
        The fitted parameters that sit on a bound (short names, e.g. "eps").
    message : str
        Why the test could not be fitted ("" when it was).
    velocity_error : float
        Largest post-impact velocity error (vector length) of the two cars [m/s] (property).
    yaw_error : float
        Largest post-impact yaw-rate error [rad/s] (property).
    within_tolerance : bool
        Both cars within 1 mph and 10 deg/s (property).
    """

    test: object
    restitution: float
    beta: float
    along: float
    residuals: dict
    on_bound: tuple
    message: str = ""

    @property
    def velocity_error(self) -> float:
        """Largest post-impact velocity error (vector length) of the two cars [m/s]."""
        r = self.residuals
        return float(max(np.hypot(r["velocity1_x"], r["velocity1_y"]),
                         np.hypot(r["velocity2_x"], r["velocity2_y"])))

    @property
    def yaw_error(self) -> float:
        """Largest post-impact yaw-rate error [rad/s]."""
        return float(max(abs(self.residuals["yaw_rate1"]), abs(self.residuals["yaw_rate2"])))

    @property
    def within_tolerance(self) -> bool:
        """Both cars within 1 mph and 10 deg/s."""
        return self.velocity_error <= SPEED_TOLERANCE and self.yaw_error <= YAW_TOLERANCE


def refit_ricsac(tests, along_range: float = ALONG_RANGE) -> list[RicsacRefit]:
    """Fit epsilon, beta (in [0, 1]) and C's position along the contact plane
    (``impact.point_along`` within +- ``along_range`` [m]) of each test with motion, against
    the measured post-impact velocities and yaw rates (yaw weighted by k, as
    :mod:`pim.analysis.residuals`)."""
    out = []
    for t in tests:
        if not t.has_motion or t.normal_angle is None:
            continue
        case = ricsac_case(t)
        try:
            r = fit(case, include_yaw=True,
                    free={"impact.point_along": (-along_range, along_range)})
        except ValueError as exc:
            out.append(RicsacRefit(t, np.nan, np.nan, np.nan, {}, (), str(exc)))
            continue
        res = solve(r.case, r.eps, r.beta)
        m = case.measured
        residuals = {"velocity1_x": float(res.velocity1[0] - m.velocity1[0]),
                     "velocity1_y": float(res.velocity1[1] - m.velocity1[1]),
                     "velocity2_x": float(res.velocity2[0] - m.velocity2[0]),
                     "velocity2_y": float(res.velocity2[1] - m.velocity2[1]),
                     "yaw_rate1": float(res.yaw_rate1 - m.yaw_rate1),
                     "yaw_rate2": float(res.yaw_rate2 - m.yaw_rate2)}
        out.append(RicsacRefit(t, float(r.eps), float(r.beta),
                               float(r.values["impact.point_along"]), residuals,
                               tuple(r.on_bound)))
    return out


def class_radius_of_gyration(rows) -> dict:
    """Median fitted k [m] per vehicle type over :class:`BarrierReproduction` rows."""
    by = {}
    for r in rows:
        by.setdefault(r.test.vehicle_type, []).append(r.radius_of_gyration)
    return {cls: float(np.median(ks)) for cls, ks in by.items()}


def summary_errors(values) -> dict:
    """Median, 90th percentile and maximum of the absolute values of ``values``."""
    a = np.abs(np.asarray(values, dtype=float))
    return {"median": float(np.median(a)), "p90": float(np.percentile(a, 90)),
            "max": float(a.max()), "n": int(a.size)}


@dataclass(frozen=True)
class CoefficientStats:
    """Distribution of one coefficient over the tests of one crash class.

    Attributes
    ----------
    crash_class : str
        A key of :data:`CRASH_CLASSES` ("barrier non-sideswipe", "barrier sideswipe",
        "car-to-car").
    coefficient : str
        "epsilon" (restitution) or "beta" (mu/mu0).
    values : tuple of float
        The published coefficient of each test of the class [-].
    n : int
        Number of tests (property).
    median, mean : float
        Of ``values`` [-] (properties).
    sd : float
        Sample standard deviation (n - 1) [-] (property).
    """

    crash_class: str
    coefficient: str
    values: tuple

    @property
    def n(self) -> int:
        return len(self.values)

    @property
    def median(self) -> float:
        return float(np.median(self.values))

    @property
    def mean(self) -> float:
        return float(np.mean(self.values))

    @property
    def sd(self) -> float:
        """Sample standard deviation (n - 1)."""
        return float(np.std(self.values, ddof=1))

    def percentile(self, q) -> float:
        return float(np.percentile(self.values, q))


#: Crash class -> (dataset, selector) of the tests it holds; one value per impact.
CRASH_CLASSES = {
    "barrier non-sideswipe": ("iihs-barrier", lambda t: t.group == "NS"),
    "barrier sideswipe": ("iihs-barrier", lambda t: t.group == "SS"),
    "car-to-car": ("iihs-car-to-car", lambda t: t.test_id.endswith("a")),
}


def coefficient_stats(records_by_dataset: dict) -> list[CoefficientStats]:
    """epsilon and beta (mu/mu0) statistics per :data:`CRASH_CLASSES` entry.

    ``records_by_dataset``: dataset name -> its records (:mod:`pim.io.datasets`).
    """
    out = []
    for cls, (dataset, keep) in CRASH_CLASSES.items():
        records = [r for r in records_by_dataset.get(dataset, ()) if keep(r)]
        if not records:
            continue
        for coefficient, attr in (("epsilon", "restitution"), ("beta", "beta")):
            out.append(CoefficientStats(cls, coefficient,
                                        tuple(getattr(r, attr) for r in records)))
    return out


def ricsac_published_errors(tests) -> dict:
    """Each published RICSAC delta-V analysis against the delta-V magnitudes of the measured
    pre/post velocities: analysis name -> list of (test number, vehicle, error [m/s])."""
    out = {}
    for t in tests:
        if not t.has_motion:
            continue
        measured = (float(np.hypot(*np.subtract(t.velocity1_post, t.velocity1_pre))),
                    float(np.hypot(*np.subtract(t.velocity2_post, t.velocity2_pre))))
        for name, values in t.published_delta_v.items():
            for i, (pub, meas) in enumerate(zip(values, measured, strict=True), start=1):
                if pub is not None:
                    out.setdefault(name, []).append((t.number, i, pub - meas))
    return out
