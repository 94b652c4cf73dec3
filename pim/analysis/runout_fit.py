"""Run-out inverse: from the evidence at rest back to the post-impact motion.

Unknowns: the post-impact CG speed ``V`` [m/s], its direction ``theta`` [rad] and the yaw
rate ``omega`` [rad/s] (polar, so the speed's bounds are a box). Data: the measured rest
position and heading, optionally points the CG passed through (e.g. the end of a tyre mark,
reduced to the CG). Residuals, each divided by its standard deviation:

- rest position: ``(x_rest(p) - x_meas) / sigma_pos`` (two components);
- rest heading: ``wrap(psi_rest(p) - psi_meas) / sigma_psi`` (wrapped to (-pi, pi]);
- each path point: distance from the point to the fitted CG path / ``sigma_pos``.

Solved by the project's one least-squares engine, the bounded Levenberg-Marquardt iteration
:func:`pim.analysis.least_squares_batch.least_squares_batch` with forward-difference
Jacobians (:func:`~pim.analysis.least_squares_batch.with_forward_differences`), over the
solve_ivp forward model :func:`pim.model.runout.runout` on the compiled right-hand side
(:class:`pim.model.runout_kernel.CompiledRhs`: :mod:`pim.model.runout_formula` compiled, a
few microseconds a call instead of 0.1-1 ms), from several starts refined together (the rest
heading fixes the rotation only modulo a full turn, so starts with -1, 0 and +1 extra turns
are tried and distinct minima reported). A rest state that no motion within the
bounds reaches is said plainly (``reachable = False``) with the closest reachable rest
state; a motion that does not stop within ``max_time`` is flagged (``stopped = False``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model.numbers import InputError, real_array, speed_text, unit_text
from ..model.pdof import wrap_angle
from ..model.runout import MAX_TIME, Runout, RunoutVehicle, runout
from .least_squares_batch import least_squares_batch, with_forward_differences

__all__ = ["RunoutFit", "RunoutFitSettings", "fit_runout", "path_distance"]


@dataclass(frozen=True)
class RunoutFit:
    """Post-impact motion fitted to the rest evidence (SI, global frame).

    Attributes
    ----------
    velocity : ndarray (2,) [m/s] post-impact CG velocity
    yaw_rate : float [rad/s] post-impact yaw rate
    speed, direction : float [m/s], [rad] the same velocity in polar form
    runout : Runout, the fitted forward run (trajectory to rest)
    rest_position, rest_heading : the fitted run's rest state [m], [rad]
    residual_names, residuals : the weighted residuals at the optimum
    cost : float, half the sum of squared weighted residuals
    covariance : ndarray (3, 3), of (speed, direction, yaw rate) from the Jacobian
    reachable : bool, False when no motion within the bounds reaches the rest evidence
    stopped : bool, False when the fitted motion has not stopped after ``max_time``
    on_bound : tuple of the parameters ("speed", "yaw_rate") on a bound
    minima : list of (cost, speed, direction, yaw_rate) distinct local minima, best first
    message : str, plain-language summary (empty when all is well)
    tyre_model : str, the run-out's tyre law: "coulomb" (:func:`pim.model.tyres.wheel_force`)
        or "brush" (the field tyre, :func:`pim.model.tyres.field_wheel_force`)
    """

    velocity: np.ndarray
    yaw_rate: float
    speed: float
    direction: float
    runout: Runout
    rest_position: np.ndarray
    rest_heading: float
    residual_names: tuple
    residuals: np.ndarray
    cost: float
    covariance: np.ndarray
    reachable: bool
    stopped: bool
    on_bound: tuple
    minima: list
    message: str
    tyre_model: str = "coulomb"


def path_distance(points, run: Runout, signed: bool = False) -> np.ndarray:
    """Distance [m] from each point (k, 2) to the CG path of ``run``.

    With ``signed``, positive for a point to the left of the direction of travel and
    negative to its right: the cross-track error, smooth through zero (an exact tyre-mark
    point), which is what a least-squares fit needs.

    The nearest point of the polyline of the integrator's steps is refined by Newton's method
    on ``f(t) = (x(t) - p) . v(t) = 0`` over solve_ivp's dense output, and the distance is
    that to the continuous path at the refined time (the polyline's chords cut inside a
    curved path by millimetres between solve_ivp's large steps).
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    path = run.states[:, :2]
    a, b = path[:-1], path[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=-1), 1e-300)
    rel = points[:, None, :] - a[None, :, :]
    s = np.clip((rel * ab).sum(axis=-1) / length2, 0.0, 1.0)
    nearest = a + s[..., None] * ab
    gap = np.hypot(*(points[:, None, :] - nearest).transpose(2, 0, 1))
    k = np.argmin(gap, axis=1)
    distance = gap[np.arange(len(points)), k]
    if run.interpolant is None or len(points) == 0:
        if signed:
            k_ = np.arange(len(points))
            cross = (ab[k, 0] * (points[:, 1] - nearest[k_, k, 1])
                     - ab[k, 1] * (points[:, 0] - nearest[k_, k, 0]))
            distance = np.where(cross < 0, -distance, distance)
        return distance
    t = run.time[k] + s[np.arange(len(points)), k] * (run.time[k + 1] - run.time[k])
    t_end = run.time[-1]
    h = 1e-6 * max(t_end, 1e-3)
    for _ in range(4):
        y = run.interpolant(t)
        ya = run.interpolant(np.minimum(t + h, t_end))
        yb = run.interpolant(np.maximum(t - h, 0.0))
        x, v = y[:2].T - points, y[3:5].T
        acc = ((ya[3:5] - yb[3:5]) / (np.minimum(t + h, t_end) - np.maximum(t - h, 0.0))).T
        f = (x * v).sum(axis=-1)
        df = (v * v).sum(axis=-1) + (x * acc).sum(axis=-1)
        t = np.clip(t - f / np.where(np.abs(df) > 1e-12, df, 1e-12), 0.0, t_end)
    y = run.interpolant(t)
    # the distance to the continuous path: the polyline's chords cut inside a curved path
    # by ~L^2 kappa / 8 (millimetres between solve_ivp's large steps), so its distance is
    # only the starting guess, never the answer
    gap = points - y[:2].T
    out = np.hypot(*gap.T)
    if signed:
        v = y[3:5].T
        out = np.where(v[:, 0] * gap[:, 1] - v[:, 1] * gap[:, 0] < 0, -out, out)
    return out


#: Default standard deviation of a measured rest heading [rad] (2 deg).
HEADING_SIGMA = float(np.radians(2.0))
#: Default heading mismatch [rad] (1 deg) below which a rest state counts as reached.
HEADING_TOLERANCE = float(np.radians(1.0))


@dataclass(frozen=True)
class RunoutFitSettings:
    """How :func:`fit_runout` weighs the evidence, bounds the search and runs the model (SI).

    Attributes
    ----------
    position_sigma, heading_sigma : float
        Standard deviations of the measured positions [m] and heading [rad] (weights); one
        per sample, (n,), in :func:`pim.analysis.runout_fit_batch.fit_runout_many`.
    speed_bounds : (float, float)
        [m/s] bounds of the post-impact speed (0 <= low <= high).
    yaw_rate_bounds : (float, float)
        [rad/s] bounds of the post-impact yaw rate.
    max_time : float
        [s] a motion still moving after this is flagged.
    position_tolerance, heading_tolerance : float
        [m], [rad] the largest rest miss still counted as reaching the evidence.
    rtol, atol : float
        Tolerances of the forward model's solve_ivp (tight: the Jacobian is by finite
        differences).
    max_evaluations : int
        Forward runs allowed per start of the local search.
    """

    position_sigma: float = 0.1
    heading_sigma: float = HEADING_SIGMA
    speed_bounds: tuple = (0.0, 60.0)
    yaw_rate_bounds: tuple = (-15.0, 15.0)
    max_time: float = MAX_TIME
    position_tolerance: float = 0.05
    heading_tolerance: float = HEADING_TOLERANCE
    rtol: float = 1e-9
    atol: float = 1e-11
    max_evaluations: int = 60

    def __post_init__(self) -> None:
        for name, unit in (("position_sigma", "m"), ("heading_sigma", "rad")):
            value = np.asarray(getattr(self, name), dtype=float)   # (n,) in the batch fit
            if not (np.all(np.isfinite(value)) and np.all(value > 0)):
                raise InputError(f"evidence.{name} must be finite and > 0 [{unit}], "
                                 f"got {value!r}")
        lo_v, hi_v = (float(v) for v in _finite(self.speed_bounds, "unknown.speed bounds",
                                                "m/s", (2,)))
        if lo_v < 0 or hi_v < lo_v:
            raise InputError(f"unknown.speed bounds must satisfy 0 <= low <= high [m/s], "
                             f"got {self.speed_bounds!r}")
        lo_w, hi_w = (float(v) for v in _finite(self.yaw_rate_bounds,
                                                "unknown.yaw_rate bounds", "rad/s", (2,)))
        if hi_w < lo_w:
            raise InputError(f"unknown.yaw_rate bounds must satisfy low <= high [rad/s], "
                             f"got {self.yaw_rate_bounds!r}")
        object.__setattr__(self, "speed_bounds", (lo_v, hi_v))
        object.__setattr__(self, "yaw_rate_bounds", (lo_w, hi_w))


@dataclass(frozen=True)
class _Problem:
    """The run-out inverse of one vehicle: forward model and weighted residuals."""

    vehicle: RunoutVehicle
    position: np.ndarray
    heading: float
    rest_position: np.ndarray
    rest_heading: float
    points: np.ndarray
    settings: RunoutFitSettings
    rhs: object = None

    @property
    def names(self) -> tuple:
        return ("rest_x", "rest_y", "rest_heading") + tuple(
            f"path_point{i + 1}" for i in range(len(self.points)))

    def forward(self, p) -> Runout:
        speed, direction, omega = p
        s = self.settings
        return runout(self.vehicle, self.position, self.heading,
                      speed * np.array([np.cos(direction), np.sin(direction)]), omega,
                      max_time=s.max_time, rtol=s.rtol, atol=s.atol,
                      dense_output=len(self.points) > 0, rhs=self.rhs)

    def residuals_of(self, run: Runout) -> np.ndarray:
        s = self.settings
        r = np.concatenate([(run.rest_position - self.rest_position) / s.position_sigma,
                            [wrap_angle(run.rest_heading - self.rest_heading)
                             / s.heading_sigma]])
        if len(self.points):
            r = np.concatenate([r, path_distance(self.points, run, signed=True)
                                / s.position_sigma])
        return r

    def __call__(self, p) -> np.ndarray:
        return self.residuals_of(self.forward(p))


#: Forward-difference step of the single fit, in box-scaled unknowns (1e-6 of each bound's
#: width: 6e-5 m/s of speed in the default box, well above solve_ivp's noise at rtol 1e-9).
FD_STEP = 1e-6
#: The single fit's stopping tolerances (:func:`least_squares_batch`): relative decrease of
#: the cost, step in box-scaled unknowns.
FTOL, XTOL = 1e-12, 1e-10


def _box(problem: _Problem, direction0: float) -> tuple[np.ndarray, np.ndarray]:
    """The search box of (speed, direction, yaw rate): the settings' bounds (a fixed speed
    or yaw rate widened by round-off, the engine needs lower < upper) and 1.5 turns either
    side of the starting direction (a direction is a direction modulo a turn)."""
    (lo_v, hi_v), (lo_w, hi_w) = problem.settings.speed_bounds, problem.settings.yaw_rate_bounds
    lower = np.array([lo_v, direction0 - 3 * np.pi, lo_w])
    upper = np.array([hi_v, direction0 + 3 * np.pi, hi_w])
    upper = np.where(upper > lower, upper, lower + 1e-12 * np.maximum(np.abs(lower), 1.0))
    return lower, upper


def _local_minima(problem: _Problem) -> list:
    """Local fits from the energy estimate along the displacement, with the rotation taken
    with -1, 0 and +1 extra turns, refined together by the one engine: (cost, speed,
    direction, yaw rate, jacobian), cost half the sum of squared residuals, best first."""
    (lo_v, hi_v), (lo_w, hi_w) = problem.settings.speed_bounds, problem.settings.yaw_rate_bounds
    displacement = problem.rest_position - problem.position
    braking = float(np.mean(np.asarray(problem.vehicle.braking, dtype=float)))
    decel = max(float(problem.vehicle.friction) * max(braking, 0.2)
                * problem.vehicle.gravity, 1e-3)
    speed0 = float(np.clip(np.sqrt(2 * decel * np.hypot(*displacement)), lo_v, hi_v))
    direction0 = float(np.arctan2(displacement[1], displacement[0]))
    t_stop = max(speed0 / decel, 0.3)
    turn = float(wrap_angle(problem.rest_heading - problem.heading))
    starts = np.array([[speed0, direction0, np.clip(2 * (turn + 2 * np.pi * k) / t_stop,
                                                    lo_w, hi_w)] for k in (0, -1, 1)])
    lower, upper = _box(problem, direction0)

    def residuals(x, index):               # (p, q, 3) points -> (p, q, k) residuals
        return np.array([[problem(point) for point in points] for points in x])

    out = least_squares_batch(with_forward_differences(residuals, lower, upper, FD_STEP),
                              starts, lower, upper, max_iter=problem.settings.max_evaluations,
                              ftol=FTOL, xtol=XTOL)
    minima = [(0.5 * float(cost), float(x[0]), float(wrap_angle(x[1])), float(x[2]), jac)
              for cost, x, jac in zip(out.cost, out.x, out.jacobian, strict=True)]
    minima.sort(key=lambda m: m[0])
    return minima


def _distinct_minima(minima: list) -> tuple[list, list]:
    """Distinct minima, the chosen one first, and the others that fit equally well.

    The rest heading fixes the rotation only modulo a turn: among equally good minima the
    least rotation is taken."""
    distinct = []
    for m in minima:
        if all(abs(m[1] - d[1]) + abs(m[3] - d[3]) > 1e-4 for d in distinct):
            distinct.append(m)
    tie = distinct[0][0] + 1e-6 * (1 + distinct[0][0])
    distinct.sort(key=lambda m: (m[0] > tie, abs(m[3]) if m[0] <= tie else m[0]))
    return distinct, [m for m in distinct[1:] if m[0] <= tie]


def _point(xy) -> str:
    """A point [m] as a message prints it, in the user's length unit: "12.35 m, -3.2 m"."""
    return f"{unit_text(xy[0], 'length', '.5g')}, {unit_text(xy[1], 'length', '.5g')}"


def _messages(problem: _Problem, run: Runout, reachable: bool, miss: float,
              heading_miss: float, distinct: list, equally_good: list) -> str:
    """Plain-language warnings: unreachable rest, no stop, several equally good motions."""
    s = problem.settings
    (lo_v, hi_v), (lo_w, hi_w) = s.speed_bounds, s.yaw_rate_bounds
    rest, rest_heading = problem.rest_position, problem.rest_heading
    messages = []
    if not reachable:
        messages.append(
            f"the rest state ({_point(rest)}, heading {np.degrees(rest_heading):.2f} deg) is "
            f"not reached by any post-impact motion with speed from {speed_text(lo_v, '.4g')} "
            f"to {speed_text(hi_v, '.4g')} and yaw rate from "
            f"{unit_text(lo_w, 'angular_velocity', '.4g')} to "
            f"{unit_text(hi_w, 'angular_velocity', '.4g')}; the closest reachable rest is "
            f"({_point(run.rest_position)}, heading "
            f"{np.degrees(wrap_angle(run.rest_heading)):.2f} deg), "
            f"missing by {unit_text(miss, 'length', '.4g')} and "
            f"{np.degrees(heading_miss):.2f} deg")
    if not run.stopped:
        messages.append(f"the fitted motion has not stopped after {s.max_time:g} s of "
                        f"simulated time (free-rolling wheels?)")
    if equally_good:
        messages.append(f"{len(equally_good) + 1} distinct motions fit the evidence equally "
                        f"well (yaw rates "
                        + ", ".join(unit_text(m[3], "angular_velocity", ".4g")
                                    for m in distinct[:len(equally_good) + 1])
                        + "); the least rotation is reported, a path point (tyre mark) "
                        "decides")
    return "; ".join(messages)


def fit_runout(vehicle: RunoutVehicle, position, heading, rest_position, rest_heading, *,
               path_points=None, settings: RunoutFitSettings | None = None,
               **options) -> RunoutFit:
    """Fit the post-impact velocity and yaw rate that carry the vehicle to its rest state.

    Parameters
    ----------
    vehicle : RunoutVehicle
        Scalar fields.
    position : array_like (2,) [m]; heading : float [rad]
        The vehicle's CG and heading at separation (end of the impact).
    rest_position : array_like (2,) [m]; rest_heading : float [rad]
        Measured rest state of the CG.
    path_points : array_like (k, 2) [m], optional
        Points the CG passed through between separation and rest.
    settings : RunoutFitSettings, optional
        Sigmas, bounds, tolerances and budget (defaults: :class:`RunoutFitSettings()`).
    **options
        Any field of :class:`RunoutFitSettings` by name (``position_sigma=0.2``,
        ``speed_bounds=(0, 30)`` ...), overriding ``settings``.

    Returns
    -------
    RunoutFit

    Raises
    ------
    ValueError
        Non-finite evidence, bad bounds or sigmas, naming the field.
    """
    from ..model.runout_kernel import CompiledRhs  # compiled run-out: numba on first use

    settings = replace(settings or RunoutFitSettings(), **options)
    points = (np.zeros((0, 2)) if path_points is None
              else _finite(path_points, "evidence.path_points", "m", None).reshape(-1, 2))
    problem = _Problem(
        vehicle, _finite(position, "evidence.position", "m", (2,)),
        float(_finite(heading, "evidence.heading", "rad", ())),
        _finite(rest_position, "evidence.rest_position", "m", (2,)),
        float(_finite(rest_heading, "evidence.rest_heading", "rad", ())), points, settings,
        CompiledRhs(vehicle))
    distinct, equally_good = _distinct_minima(_local_minima(problem))
    _, speed, direction, omega, jac = distinct[0]
    run = problem.forward((speed, direction, omega))
    res = problem.residuals_of(run)
    try:
        covariance = np.linalg.pinv(jac.T @ jac)
    except np.linalg.LinAlgError:
        covariance = np.full((3, 3), np.inf)
    (lo_v, hi_v), (lo_w, hi_w) = settings.speed_bounds, settings.yaw_rate_bounds
    on_bound = tuple(name for name, value, lo, hi in
                     (("speed", speed, lo_v, hi_v), ("yaw_rate", omega, lo_w, hi_w))
                     if np.isclose(value, lo, atol=1e-6) or np.isclose(value, hi, atol=1e-6))
    miss = float(np.hypot(*(run.rest_position - problem.rest_position)))
    heading_miss = float(abs(wrap_angle(run.rest_heading - problem.rest_heading)))
    reachable = (miss <= settings.position_tolerance
                 and heading_miss <= settings.heading_tolerance)
    velocity = speed * np.array([np.cos(direction), np.sin(direction)])
    return RunoutFit(velocity=velocity, yaw_rate=omega, speed=speed, direction=direction,
                     runout=run, rest_position=run.rest_position,
                     rest_heading=run.rest_heading, residual_names=problem.names,
                     residuals=res, cost=float(0.5 * res @ res), covariance=covariance,
                     reachable=bool(reachable), stopped=bool(run.stopped), on_bound=on_bound,
                     minima=[m[:4] for m in distinct],
                     message=_messages(problem, run, reachable, miss, heading_miss, distinct,
                                       equally_good),
                     tyre_model=vehicle.tyre_model)


def _finite(value, name, unit, shape):
    arr = real_array(value, name, unit)
    if shape is not None and arr.shape != shape:
        raise InputError(f"{name} must have shape {shape} [{unit}], got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite [{unit}], got {value!r}")
    return arr
