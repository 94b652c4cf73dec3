"""Run-out inverse for many evidence sets at once (the reconstruction Monte Carlo's step 1).

The least-squares problem of :func:`pim.analysis.runout_fit.fit_runout` (unknowns: the
post-impact speed, its direction and the yaw rate; residuals: the rest position and wrapped
rest heading, and the distance of each path point to the CG path, each over its standard
deviation), solved for n samples together: a bounded Levenberg-Marquardt vectorised over the
samples (:func:`pim.analysis.least_squares_batch.least_squares_batch`, the project's one
least-squares engine, as for the single fit) on the compiled, parallel fixed-step run-out
(:func:`pim.model.runout_kernel.integrate_many`), with forward finite-difference Jacobians
(:func:`~pim.analysis.least_squares_batch.with_forward_differences`: the base points and
their three shifted copies in one batched integration, steps of 1e-3 of the unknowns'
scales: well above the fixed step's stopping jitter of ~4e-5 m in the rest position).
Each sample starts from ``start`` (the nominal single fit: the Monte Carlo's samples are
perturbations of it, and it fixes the number of turns of the rest heading).

Path points are measured to the polyline of the integrator's steps (4 ms apart), not to
solve_ivp's dense output as in the single fit; the difference is below a millimetre on the
bundled cases (tested).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model.numbers import InputError
from ..model.pdof import wrap_angle
from ..model.runout import RunoutVehicle
from ..model.runout_kernel import RUNOUT_STEP, integrate_many
from .least_squares_batch import least_squares_batch, with_forward_differences
from .runout_fit import RunoutFitSettings

__all__ = ["RunoutFitBatch", "fit_runout_many"]

#: Forward-difference steps of (speed [m/s], direction [rad], yaw rate [rad/s]).
FD_STEP = np.array([1e-3, 1e-4, 5e-4])


@dataclass(frozen=True)
class RunoutFitBatch:
    """Post-impact motions fitted to n evidence sets (SI, global frame), per sample.

    Attributes
    ----------
    velocity : ndarray (n, 2) [m/s]; yaw_rate : (n,) [rad/s]
    speed, direction : (n,) [m/s], [rad]
    rest_position : (n, 2) [m]; rest_heading : (n,) [rad] of the fitted motions
    cost : (n,) sum of squared weighted residuals
    reachable : (n,) bool, the fitted motion comes to rest within the tolerances
    stopped : (n,) bool, it stops within ``max_time``
    converged : (n,) bool
    iterations : (n,) int
    tyre_model : str, the run-out's tyre law ("coulomb" or "brush")
    """

    velocity: np.ndarray
    yaw_rate: np.ndarray
    speed: np.ndarray
    direction: np.ndarray
    rest_position: np.ndarray
    rest_heading: np.ndarray
    cost: np.ndarray
    reachable: np.ndarray
    stopped: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    tyre_model: str = "coulomb"


def _per_sample(value, shape, name, unit):
    arr = np.asarray(value, dtype=float)
    try:
        arr = np.broadcast_to(arr, shape)
    except ValueError:
        raise InputError(f"{name} must broadcast to shape {shape} [{unit}], got "
                         f"{arr.shape}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite [{unit}]")
    return arr


@dataclass(frozen=True, eq=False)
class _Samples:
    """The n run-out inverses of :func:`fit_runout_many`: per-sample inputs (checked), the
    batched forward run and the weighted residuals (:meth:`residuals`, the engine's
    residual function for :func:`with_forward_differences`)."""

    vehicle: RunoutVehicle
    fields: dict
    position: np.ndarray
    heading: np.ndarray
    rest_position: np.ndarray
    rest_heading: np.ndarray
    sig_p: np.ndarray
    sig_h: np.ndarray
    points: np.ndarray
    dt: float
    max_time: float

    @classmethod
    def checked(cls, vehicle, separation, rest, *, path_points, settings: RunoutFitSettings,
                dt) -> _Samples:
        """``separation``: (position (n, 2), heading (n,)); ``rest``: (rest position (n, 2),
        rest heading (n,)); each checked and broadcast to the n samples."""
        rest_position = np.atleast_2d(np.asarray(rest[0], dtype=float))
        n = rest_position.shape[0]
        sig_p = _per_sample(settings.position_sigma, (n,), "evidence.position_sigma", "m")
        sig_h = _per_sample(settings.heading_sigma, (n,), "evidence.heading_sigma", "rad")
        if np.any(sig_p <= 0) or np.any(sig_h <= 0):
            raise InputError("evidence.position_sigma and heading_sigma must be > 0")
        if path_points is None or np.size(path_points) == 0:
            points = np.zeros((n, 0, 2))
        else:
            pts = np.asarray(path_points, dtype=float)
            pts = pts if pts.ndim == 3 else pts.reshape(-1, 2)
            points = _per_sample(pts, (n, pts.shape[-2], 2), "evidence.path_points", "m")
        fields = {name: _per_sample(getattr(vehicle, name), shape, f"runout.{name}", unit)
                  for name, shape, unit in (
                      ("mass", (n,), "kg"), ("yaw_inertia", (n,), "kg m^2"),
                      ("wheelbase", (n,), "m"), ("track", (n,), "m"),
                      ("cg_to_front_axle", (n,), "m"), ("friction", (n,), "-"),
                      ("braking", (n, 4), "-"), ("steer", (n, 4), "rad"))}
        return cls(vehicle=vehicle, fields=fields,
                   position=_per_sample(separation[0], (n, 2), "evidence.position", "m"),
                   heading=_per_sample(separation[1], (n,), "evidence.heading", "rad"),
                   rest_position=_per_sample(rest_position, (n, 2), "evidence.rest_position",
                                             "m"),
                   rest_heading=_per_sample(rest[1], (n,), "evidence.rest_heading", "rad"),
                   sig_p=sig_p, sig_h=sig_h, points=points, dt=dt,
                   max_time=settings.max_time)

    def run(self, x, idx):
        sub = replace(self.vehicle, **{k: v[idx] for k, v in self.fields.items()})
        velocity = x[:, :1] * np.stack([np.cos(x[:, 1]), np.sin(x[:, 1])], axis=-1)
        return integrate_many(sub, self.position[idx], self.heading[idx], velocity, x[:, 2],
                              path_points=self.points[idx], dt=self.dt,
                              max_time=self.max_time)

    def residuals_of(self, final, distance, idx):
        return np.concatenate([(final[:, :2] - self.rest_position[idx]) / self.sig_p[idx, None],
                               (wrap_angle(final[:, 2] - self.rest_heading[idx])
                                / self.sig_h[idx])[:, None],
                               distance / self.sig_p[idx, None]], axis=-1)

    def residuals(self, x, idx):
        """Residuals (p, q, k) at the points ``x`` (p, q, 3) of the samples ``idx`` (p,):
        one batched integration of all p q points."""
        p, q = x.shape[:2]
        every = np.repeat(idx, q)
        final, _, _, distance = self.run(x.reshape(p * q, 3), every)
        return self.residuals_of(final, distance, every).reshape(p, q, -1)


def fit_runout_many(vehicle: RunoutVehicle, position, heading, rest_position, rest_heading,
                    *, start, path_points=None, settings: RunoutFitSettings | None = None,
                    dt=RUNOUT_STEP, max_iter: int = 40, chord_steps: int = 2,
                    **options) -> RunoutFitBatch:
    """Fit n samples' post-impact motions to their rest evidence at once (module notes).

    Parameters
    ----------
    vehicle : RunoutVehicle
        Fields scalar or per sample ((n,), braking/steer (n, 4)).
    position : (n, 2) [m]; heading : (n,) [rad]
        Separation states (the impact positions and headings).
    rest_position : (n, 2) [m]; rest_heading : (n,) [rad]
        Measured rest states.
    start : (speed, direction, yaw_rate)
        Starting point [m/s, rad, rad/s], scalars or (n,).
    path_points : (k, 2) or (n, k, 2) [m], optional
    settings : RunoutFitSettings, optional
        The single fit's settings (:func:`pim.analysis.runout_fit.fit_runout`): the sigmas
        (weights; a float or one per sample (n,)), the speed and yaw-rate bounds (here
        low < high), ``max_time`` and the rest tolerances (``rtol``, ``atol`` and
        ``max_evaluations`` are the single fit's own). Default :class:`RunoutFitSettings()`.
    dt : float
        [s] fixed step of the integration.
    max_iter : int
        Levenberg-Marquardt iterations per sample.
    chord_steps : int
        Gauss-Newton steps with the first sample's Jacobian before the iteration.
    **options
        Any field of :class:`RunoutFitSettings` by name (``position_sigma=0.2``,
        ``speed_bounds=(0, 30)`` ...), overriding ``settings``.

    Returns
    -------
    RunoutFitBatch
    """
    settings = replace(settings or RunoutFitSettings(), **options)
    (lo_v, hi_v), (lo_w, hi_w) = settings.speed_bounds, settings.yaw_rate_bounds
    if not (lo_v < hi_v and lo_w < hi_w):
        raise InputError(f"speed bounds must satisfy 0 <= low < high and yaw-rate bounds "
                         f"low < high, got {settings.speed_bounds!r}, "
                         f"{settings.yaw_rate_bounds!r}")
    fun = _Samples.checked(vehicle, (position, heading), (rest_position, rest_heading),
                           path_points=path_points, settings=settings, dt=dt)
    n = fun.rest_position.shape[0]
    x0 = np.stack([_per_sample(v, (n,), "start", "SI") for v in start], axis=-1)
    lower = np.stack([np.full(n, lo_v), x0[:, 1] - np.pi, np.full(n, lo_w)], axis=-1)
    upper = np.stack([np.full(n, hi_v), x0[:, 1] + np.pi, np.full(n, hi_w)], axis=-1)
    x = np.clip(x0, lower, upper)
    jacobian = with_forward_differences(fun.residuals, lower, upper,
                                        FD_STEP / (upper[0] - lower[0]))

    # chord steps: Gauss-Newton with one Jacobian (the first sample's at the start) for all
    # samples, one batched integration each; the samples are perturbations of one problem,
    # so this brings them near their minima before the full iteration
    _, jac0 = jacobian(x[:1], np.arange(1))
    pinv0 = np.linalg.pinv(jac0[0])
    all_idx = np.arange(n)
    for _ in range(chord_steps):
        r = fun.residuals(x[:, None, :], all_idx)[:, 0]
        x = np.clip(x - r @ pinv0.T, lower, upper)
    out = least_squares_batch(jacobian, x, lower, upper, max_iter=max_iter, xtol=1e-7,
                              ftol=1e-10)
    final, _, stopped, _ = fun.run(out.x, all_idx)
    miss = np.hypot(*(final[:, :2] - fun.rest_position).T)
    heading_miss = np.abs(wrap_angle(final[:, 2] - fun.rest_heading))
    speed, direction, omega = out.x[:, 0], wrap_angle(out.x[:, 1]), out.x[:, 2]
    return RunoutFitBatch(
        velocity=speed[:, None] * np.stack([np.cos(direction), np.sin(direction)], axis=-1),
        yaw_rate=omega, speed=speed, direction=direction, rest_position=final[:, :2],
        rest_heading=final[:, 2], cost=out.cost,
        reachable=((miss <= settings.position_tolerance)
                   & (heading_miss <= settings.heading_tolerance)),
        stopped=stopped, converged=out.converged, iterations=out.iterations,
        tyre_model=vehicle.tyre_model)
