"""The finite-duration crush scene for a batch of scenes, on the compiled integrator.

:func:`simulate_batch` (``sim.simulate_compliant(..., engine="numba")``, the default) takes
a batched :class:`pim.Case` and per-scene contact inputs, any of them arrays broadcast
together as :func:`pim.solve` broadcasts, steps every scene with the compiled integrator of
:mod:`sim.compliant_kernel` (the functions of :mod:`sim.compliant_formula`, stepped as
pymunk steps them) and returns a :class:`CompliantBatch` of arrays. A scene that fails gets
a status code (:data:`STATUS_NAMES`) and NaN outputs instead of an exception; bad inputs
raise ValueError naming the field.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, replace

import numpy as np

import pim
from pim.model.geometry import kinetic_energy
from pim.model.numbers import InputError

from . import compliant_formula as f
from .batch import case_element
from .compliant_setup import (
    GEOMETRIES,
    CompliantResult,
    CompliantSettings,
    build_problem,
    case_rows,
    contact_step_limit,
    endless_contact,
    parameter_rows,
    physics_status,
    refuse_frozen,
    result_from_row,
    setup_arrays,
)
from .contact_law import (
    contact_duration_estimate,
    stiffness_for_duration,
    tangential_recovery_default,
)
from .contact_tyres import TYRE_MODES
from .failures import SimulationError

__all__ = ["CompliantBatch", "simulate_batch", "STATUS_NAMES", "STATUS_MESSAGES"]

#: Status of a scene by code: 0 "ok", then the :class:`sim.SimulationError` kinds.
STATUS_NAMES = f.STATUS_NAMES
#: What each failed status means.
STATUS_MESSAGES = {
    "no_contact": "no contact: the vehicles do not approach at C (u_n >= 0), or never "
                  "touched within settings.max_contact_time",
    "never_separated": "the contact still pushed after settings.max_contact_time (or "
                       "settings.max_fixed_steps steps), lasted longer, or its estimated "
                       "duration pi (1 + eps) / (2 sqrt(k K_nn)) already exceeded it ten "
                       "times (a stiffness far too low: refused before any step)",
    "tunnelled": "settings.dt resolves the estimated contact time in fewer than "
                 "settings.min_steps steps: reduce dt (or leave it None)",
    "energy_gained": "the kinetic energy at separation exceeds the start's by more than "
                     "sim.compliant_setup.ENERGY_TOLERANCE: the contact only loses energy",
}


@dataclass(frozen=True, eq=False)
class CompliantBatch:
    """Outcome of :func:`sim.simulate_compliant` on the compiled engine: arrays of the
    broadcast shape of the inputs (``shape``; () for one scene), NaN where ``status`` is not 0.

    Attributes
    ----------
    velocity1, velocity2 : ndarray (..., 2)
        CG velocities at separation [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        Yaw rates at separation [rad/s].
    contact_duration : ndarray
        Time from first contact to separation [s].
    contact_start : ndarray
        When the contact began [s] (0 for the point contact; the outline contact starts
        where the outlines first touch, moved back along the free paths).
    impulse : ndarray (..., 2)
        Contact impulse on vehicle 1 [N s].
    impact_point, impact_point_body1 : ndarray (..., 2)
        Impulse centroid [m], in the global frame and relative to CG 1 in vehicle 1's frame.
    impulse_normal, impulse_normal_body2 : ndarray (..., 2)
        Mean contact normal (weighted by |F| dt) [-], global and in vehicle 2's frame.
    peak_force : ndarray
        Largest |F| [N].
    peak_crush, permanent_crush : ndarray
        delta_max and delta_p [m].
    energy_before, energy_after : ndarray
        Kinetic energy at first contact and at separation [J].
    tyre_work : ndarray
        Work of the tyre forces during the contact [J] (<= 0).
    stick_fraction : ndarray
        Share of the contact time the friction spring stuck [-].
    slip_reversed : ndarray of bool
        The tangential slip reversed (:func:`sim.compliant_setup.reversal`).
    steps : ndarray of int
        Steps of the contact.
    status : ndarray of int8
        0 "ok", else the failure (:data:`STATUS_NAMES`, :data:`STATUS_MESSAGES`).
    crush_too_deep : ndarray of bool
        The peak crush exceeds half the shorter moving vehicle's length (the outlines
        would pass through each other): an inadmissible outcome, flagged.
    eps, stiffness, friction, tyre_friction, tangential_recovery, preload : ndarray
        The contact inputs of each scene (stiffness from ``contact_time`` when given)
        [-, N/m, -, -, -, N].
    locked : ndarray of bool
        Locked wheels (else free-rolling).
    k_nn : ndarray
        K_nn of the contact at t = 0 [1/kg].
    dt : ndarray
        The step of each scene [s].
    case : pim.Case
    geometry : str
    settings : CompliantSettings
    rows : ndarray (n, N_OUT)
        The kernel's output rows (:func:`sim.compliant_formula.write_outputs`), flat; the
        output attributes above are views of them (read on access, so a call that needs one
        field pays for no other).
    scenes : dict
        Flat per-scene inputs: the contact law's (:data:`sim.compliant_setup.LAW_INPUTS`,
        with ``stiffness`` from ``contact_time`` when given) and the masses, inertias,
        ``k_nn`` and ``energy_before`` of :func:`sim.compliant_setup.setup_arrays`.
    wall_time : float
        [s] of the whole batch.
    """

    rows: np.ndarray
    status: np.ndarray
    scenes: dict
    case: pim.Case
    geometry: str
    settings: CompliantSettings
    wall_time: float

    def _column(self, k: int, width: int = 1) -> np.ndarray:
        shape = self.status.shape
        if width == 1:
            return self.rows[:, k].reshape(shape)
        return self.rows[:, k:k + width].reshape(shape + (width,))

    def _scene(self, name: str) -> np.ndarray:
        return np.broadcast_to(self.scenes[name], self.rows.shape[:1]).reshape(
            self.status.shape)

    velocity1 = property(lambda self: self._column(f.O_V1, 2))
    velocity2 = property(lambda self: self._column(f.O_V2, 2))
    yaw_rate1 = property(lambda self: self._column(f.O_W1))
    yaw_rate2 = property(lambda self: self._column(f.O_W2))
    contact_duration = property(lambda self: self._column(f.O_DURATION))
    contact_start = property(lambda self: self._column(f.O_START))
    impulse = property(lambda self: self._column(f.O_IMPULSE, 2))
    impact_point = property(lambda self: self._column(f.O_POINT, 2))
    impact_point_body1 = property(lambda self: self._column(f.O_BODY_POINT, 2))
    impulse_normal = property(lambda self: self._column(f.O_NORMAL, 2))
    impulse_normal_body2 = property(lambda self: self._column(f.O_BODY_NORMAL, 2))
    peak_force = property(lambda self: self._column(f.O_PEAK_FORCE))
    peak_crush = property(lambda self: self._column(f.O_PEAK_CRUSH))
    permanent_crush = property(lambda self: self._column(f.O_PERMANENT))
    tyre_work = property(lambda self: self._column(f.O_TYRE_WORK))
    stick_fraction = property(lambda self: self._column(f.O_STICK))
    slip_reversed = property(lambda self: self._column(f.O_REVERSED) == 1.0)
    steps = property(lambda self: np.nan_to_num(self._column(f.O_STEPS)).astype(np.int64))
    eps = property(lambda self: self._scene("eps"))
    stiffness = property(lambda self: self._scene("stiffness"))
    friction = property(lambda self: self._scene("friction"))
    tyre_friction = property(lambda self: self._scene("tyre_friction"))
    tangential_recovery = property(lambda self: self._scene("tangential_recovery"))
    preload = property(lambda self: self._scene("preload"))
    locked = property(lambda self: self._scene("braking") == 1.0)
    k_nn = property(lambda self: self._scene("k_nn"))
    dt = property(lambda self: self._scene("dt"))
    energy_before = property(lambda self: self._scene("energy_before"))

    @property
    def energy_after(self) -> np.ndarray:
        """Kinetic energy at separation [J] (NaN where the scene failed)."""
        sc, rows = self.scenes, self.rows
        after = (kinetic_energy(sc["mass1"], sc["inertia1"], rows[:, f.O_V1:f.O_V1 + 2],
                                rows[:, f.O_W1])
                 + kinetic_energy(sc["mass2"], sc["inertia2"], rows[:, f.O_V2:f.O_V2 + 2],
                                  rows[:, f.O_W2]))
        return np.where(self.status.reshape(-1) == 0, after, np.nan).reshape(self.shape)

    @property
    def crush_too_deep(self) -> np.ndarray:
        """The peak crush exceeds half the shorter moving vehicle's length (flag)."""
        lengths = [v.length for v in (self.case.vehicle1, self.case.vehicle2)
                   if v.length is not None and not bool(np.all(v.fixed))]
        return self.peak_crush > (0.5 * min(lengths) if lengths else np.inf)

    @property
    def shape(self) -> tuple:
        """Broadcast shape of the scenes."""
        return self.status.shape

    @property
    def ok(self) -> np.ndarray:
        """True where the scene ran to separation (status 0)."""
        return self.status == 0

    @property
    def status_name(self) -> np.ndarray:
        """The status of each scene by name (:data:`STATUS_NAMES`)."""
        return np.asarray(STATUS_NAMES, dtype=object)[self.status]

    @property
    def energy_loss(self) -> np.ndarray:
        """Kinetic energy lost during the contact [J]."""
        return self.energy_before - self.energy_after

    def failures(self) -> dict:
        """Count of the scenes of each failed status, e.g. ``{"no_contact": 3}``."""
        codes, counts = np.unique(self.status[self.status != 0], return_counts=True)
        return {STATUS_NAMES[c]: int(k) for c, k in zip(codes, counts, strict=True)}

    def result(self, index=()) -> CompliantResult:
        """Scene ``index`` (a tuple into ``shape``, or a flat int) as a
        :class:`sim.CompliantResult` (no history or trajectory: those come from the pymunk
        engine).

        Raises
        ------
        SimulationError
            The scene's failure (its status), with :data:`STATUS_MESSAGES`.
        """
        flat = int(np.ravel_multi_index(index, self.shape)) if isinstance(index, tuple) \
            else int(index)
        code = int(self.status.reshape(-1)[flat])
        if code != 0:
            name = STATUS_NAMES[code]
            raise SimulationError(name, f"scene {flat}: {STATUS_MESSAGES[name]}", None)
        pick = {k: float(np.asarray(getattr(self, k)).reshape(-1)[flat])
                for k in ("eps", "stiffness", "friction", "tyre_friction",
                          "tangential_recovery", "preload")}
        settings = replace(self.settings, tyre_mode="locked" if bool(
            self.locked.reshape(-1)[flat]) else "rolling", preload=pick["preload"],
                           tangential_recovery=pick["tangential_recovery"], record=False,
                           duration=0.0)
        case = case_element(self.case, _case_index(self.case, self.shape, flat))
        problem = build_problem(case, pick["eps"], pick["stiffness"], pick["friction"],
                                self.geometry, pick["tyre_friction"], settings)
        return result_from_row(self.rows[flat], problem, integrator="numba")


def _case_index(case: pim.Case, shape: tuple, flat: int) -> int:
    """The flat index into ``case``'s own shape of scene ``flat`` of the broadcast ``shape``."""
    own = case.shape
    where = np.unravel_index(flat, shape) if shape else ()
    where = where[len(shape) - len(own):]
    where = tuple(0 if size == 1 else i for i, size in zip(where, own, strict=True))
    return int(np.ravel_multi_index(where, own)) if own else 0


def _per_scene(value, name: str, unit: str, low: float, high: float = np.inf,
               allow_low: bool = True) -> np.ndarray:
    """``value`` as a float array, every element finite and in range, or a ValueError that
    names ``name``, the range and the first bad value (and its index)."""
    if type(value) is float and (low <= value if allow_low else low < value) and value <= high \
            and value < np.inf:
        return np.float64(value)          # the common plain number, checked at once
    if isinstance(value, bool | np.bool_) or isinstance(value, str | bytes):
        raise InputError(f"{name} must be a number or an array of numbers [{unit}], "
                         f"got {value!r}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number or an array of numbers [{unit}], "
                         f"got {value!r}") from None
    if np.asarray(value).dtype.kind == "b":
        raise InputError(f"{name} must be numbers [{unit}], got booleans")
    good = np.isfinite(arr) & (arr >= low if allow_low else arr > low) & (arr <= high)
    if not good.all():
        bad = int(np.argmax(~good.reshape(-1)))
        where = (f" at index {tuple(int(i) for i in np.unravel_index(bad, arr.shape))}"
                 if arr.ndim else "")
        bound = f"{'>=' if allow_low else '>'} {low:g}" + (f" and <= {high:g}"
                                                          if np.isfinite(high) else "")
        raise InputError(f"{name} must be finite, {bound} [{unit}], got "
                         f"{float(arr.reshape(-1)[bad])!r}{where}")
    return arr


def _braking(tyre_mode) -> np.ndarray:
    """1.0 for "locked", 0.0 for "rolling", per scene (a string or an array of them)."""
    if type(tyre_mode) is str and tyre_mode in TYRE_MODES:
        return np.float64(tyre_mode == "locked")
    modes = np.asarray(tyre_mode, dtype=object)
    known = np.isin(modes, TYRE_MODES) if modes.size else np.array(True)
    if not np.all(known):
        bad = modes.reshape(-1)[int(np.argmax(~np.asarray(known).reshape(-1)))]
        raise InputError(f"tyre_mode must be one of {TYRE_MODES} (or an array of them), "
                         f"got {bad!r}")
    return (modes == "locked").astype(float)


def contact_inputs(eps, stiffness, friction, tyre_friction, settings: CompliantSettings, *,
                   tyre_mode=None, preload=None, tangential_recovery=None,
                   contact_time=None) -> dict:
    """The per-scene contact inputs checked (ValueError naming the field) as float arrays.

    ``None`` for tyre_mode, preload or tangential_recovery takes the settings' value;
    exactly one of ``stiffness`` and ``contact_time`` is given.
    """
    if (stiffness is None) == (contact_time is None):
        raise InputError("give either stiffness [N/m] or contact_time [s] (not both, not "
                         "neither)")
    out = {"eps": _per_scene(eps, "eps", "-", 0.0, 1.0),
           "friction": _per_scene(friction, "friction", "-", 0.0),
           "tyre_friction": _per_scene(tyre_friction, "tyre_friction", "-", 0.0),
           "preload": _per_scene(settings.preload if preload is None else preload, "preload",
                                 "N", 0.0),
           "braking": _braking(settings.tyre_mode if tyre_mode is None else tyre_mode)}
    if stiffness is not None:
        out["stiffness"] = _per_scene(stiffness, "stiffness", "N/m", 0.0, allow_low=False)
    else:
        out["contact_time"] = _per_scene(contact_time, "contact_time", "s", 0.0,
                                         allow_low=False)
    recovery = (settings.tangential_recovery if tangential_recovery is None
                else tangential_recovery)
    out["tangential_recovery"] = (tangential_recovery_default(out["eps"]) if recovery is None
                                  else _per_scene(recovery, "tangential_recovery", "-", 0.0,
                                                  1.0))
    return out


def _law(inputs: dict, arrays: dict, shape: tuple, settings: CompliantSettings) -> dict:
    """The flat per-scene law of :func:`sim.compliant_setup.parameter_rows`, the step and
    the scenes refused before stepping (status)."""
    flat = {k: v if np.ndim(v) == 0 else np.broadcast_to(v, shape).reshape(-1)
            for k, v in inputs.items()}
    k_nn = arrays["k_nn"]
    if "contact_time" in flat:
        flat["stiffness"] = stiffness_for_duration(flat.pop("contact_time"), k_nn, flat["eps"])
    estimate = contact_duration_estimate(flat["stiffness"], k_nn, flat["eps"])
    dt = (np.full(k_nn.shape, settings.dt) if settings.dt is not None
          else estimate / settings.steps_per_contact)
    status = np.where(estimate / dt < settings.min_steps, f.STATUS_TUNNELLED,
                      f.STATUS_OK).astype(np.int8)
    status[endless_contact(estimate, settings) & (status == f.STATUS_OK)] = \
        f.STATUS_NEVER_SEPARATED
    kt = (np.full(k_nn.shape, settings.tangential_stiffness)
          if settings.tangential_stiffness is not None else flat["stiffness"])
    flat.update(tangential_stiffness=kt, dt=dt, start=0.0,
                max_steps=contact_step_limit(settings, dt), outline=0.0,
                frozen=0.0 if settings.geometry_change else 1.0)
    return flat, status


#: Scenes up to this many keep their case's setup for the next call (:func:`_setup`).
CACHE_SCENES = 65536


class _SameCase:
    """A case as a cache key, equal only to itself (a Case holds arrays: it has no value
    hash); the key holds the case, so its identity is not reused while it is kept."""

    __slots__ = ("case",)

    def __init__(self, case: pim.Case):
        self.case = case

    def __hash__(self) -> int:
        return id(self.case)

    def __eq__(self, other) -> bool:
        return isinstance(other, _SameCase) and other.case is self.case


def _setup(case: pim.Case, shape: tuple, gravity: float) -> dict:
    """:func:`sim.compliant_setup.setup_arrays` with its :func:`sim.compliant_setup.case_rows`
    (``"rows"``), kept for the last 4 (case, shape, gravity) of at most :data:`CACHE_SCENES`
    scenes (:func:`_kept_setup`): a fit that calls again and again with one case and new
    contact inputs sets the case up once."""
    if math.prod(shape) <= CACHE_SCENES:
        return _kept_setup(_SameCase(case), shape, gravity)
    return _fresh_setup(case, shape, gravity)


def _fresh_setup(case: pim.Case, shape: tuple, gravity: float) -> dict:
    arrays = setup_arrays(case, shape, gravity)
    arrays["rows"] = case_rows(arrays)
    return arrays


@functools.lru_cache(maxsize=4)
def _kept_setup(key: _SameCase, shape: tuple, gravity: float) -> dict:
    """:func:`_fresh_setup` of ``key.case``, read-only, for the last 4 keys (a Case is
    immutable (frozen), so the arrays stay valid)."""
    arrays = _fresh_setup(key.case, shape, gravity)
    for value in arrays.values():
        value.flags.writeable = False
    return arrays


def _check_geometry(case: pim.Case, geometry: str) -> None:
    """A known contact geometry, and outlines for the outline contact (ValueError)."""
    if geometry not in GEOMETRIES:
        raise InputError(f"geometry must be one of {GEOMETRIES}, got {geometry!r}")
    if geometry == "outline":
        v1, v2 = case.vehicle1, case.vehicle2
        if v1.length is None or v1.width is None:
            raise InputError("geometry='outline' needs vehicle1.length and vehicle1.width")
        if (v2.length is None or v2.width is None) and not np.all(v2.fixed):
            raise InputError("geometry='outline' needs vehicle2.length and vehicle2.width")


_DEFAULT_SETTINGS = CompliantSettings()


def _integrate():
    """:func:`sim.compliant_kernel.integrate`, imported on first use (numba: the kernel is
    compiled, or loaded from numba's cache, then; never on ``import sim``)."""
    from .compliant_kernel import integrate
    return integrate


def simulate_batch(case: pim.Case, eps, stiffness=None, friction=0.0, geometry="point",
                   tyre_friction=0.0, settings: CompliantSettings | None = None, *,
                   tyre_mode=None, preload=None, tangential_recovery=None,
                   contact_time=None) -> CompliantBatch:
    """:func:`sim.simulate_compliant` on the compiled engine (its parameters); a
    :class:`CompliantBatch` at the broadcast shape of every input."""
    wall = time.perf_counter()
    settings = _DEFAULT_SETTINGS if settings is None else settings
    if not isinstance(settings, CompliantSettings):
        raise InputError(f"settings must be a sim.CompliantSettings, got "
                         f"{type(settings).__name__}")
    if not isinstance(case, pim.Case):
        raise InputError(f"case must be a pim.Case, got {type(case).__name__}")
    _check_geometry(case, geometry)
    if geometry != "point":
        refuse_frozen(settings, "the outline contact")
    inputs = contact_inputs(eps, stiffness, friction, tyre_friction, settings,
                            tyre_mode=tyre_mode, preload=preload,
                            tangential_recovery=tangential_recovery, contact_time=contact_time)
    try:
        shape = np.broadcast_shapes(case.shape, *(np.shape(v) for v in inputs.values()))
    except ValueError:
        shapes = {k: np.shape(v) for k, v in inputs.items() if np.shape(v)}
        raise InputError(f"the inputs do not broadcast together: case {case.shape}, "
                         f"{shapes}") from None
    arrays = _setup(case, shape, settings.gravity)
    law, status = _law(inputs, arrays, shape, settings)
    law["outline"] = 1.0 if geometry == "outline" else 0.0
    rows = _integrate()(parameter_rows(arrays, law, arrays["rows"]), arrays["state0"], status)
    scenes = dict(law)
    scenes.update({k: arrays[k] for k in ("mass1", "inertia1", "mass2", "inertia2", "k_nn",
                                          "energy_before")})
    batch = CompliantBatch(rows=rows, status=status.reshape(shape), scenes=scenes, case=case,
                           geometry=geometry, settings=settings,
                           wall_time=time.perf_counter() - wall)
    return _keep_physics(batch)


def _keep_physics(batch: CompliantBatch) -> CompliantBatch:
    """``batch`` with every stepped scene that gained energy or whose contact outlasted
    ``settings.max_contact_time`` refused (:func:`sim.compliant_setup.physics_status`): its
    status set, its outputs NaN. Never an ok result that breaks physics."""
    ran = batch.status.reshape(-1) == f.STATUS_OK
    if not ran.any():
        return batch
    with np.errstate(invalid="ignore", over="ignore"):
        after = np.where(batch.ok, batch.energy_after, 0.0)
        found = physics_status(batch.energy_before, after, batch.contact_duration,
                               batch.settings).reshape(-1)
    bad = ran & (found != f.STATUS_OK)
    if bad.any():
        batch.status.reshape(-1)[bad] = found[bad]
        batch.rows[bad] = np.nan
    return batch


