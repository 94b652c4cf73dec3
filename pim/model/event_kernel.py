"""Compiled run-out of both vehicles with the outlines watched: the event after its first impact.

Each sample's two vehicles are stepped together by the run-out's fixed-step classical RK4 on
the run-out's right-hand side (:mod:`pim.model.runout_formula`, compiled through
:data:`pim.model.runout_kernel.rk4_stages`: the same tyres, the same equations, either tyre
law); a stopped vehicle is held (and woken by an impact), a fixed obstacle never moves.
After every step the outlines are watched (:mod:`pim.model.event_formula`):

- **no contact test while the vehicles are far apart**: only when the circles about the CGs
  that hold the outlines overlap is the separating-axis test run;
- **no tunnelling**: while they overlap, the step is at most :data:`TUNNEL_FRACTION` of the
  smallest outline dimension over a bound of the closing speed of any two outline points
  (``|v_1 - v_2| + |omega_1| R_1 + |omega_2| R_2``), so no corner crosses a quarter of a
  vehicle's width in one step;
- **a new contact** is an overlap depth more than ``tolerance`` above its least value since
  the last impact; the step is then bisected down to 1 microsecond to the time the depth
  first passes that level, so no sample penetrates by much more than ``tolerance``; if C
  closes there, the secondary impact (:func:`pim.model.event_formula.further_impact`, under
  the law and coefficients of :data:`COEFFICIENT_COLUMNS`, at C and Gamma of the contact
  unless they are given) is solved in the kernel (``solve``; a recorded sample gets a row
  just before and one just after it, at the same time) or the run stops and returns the
  contact for the caller to solve.

Samples run in parallel (``prange``), each to rest (every vehicle's ``|v| + |omega| r_max``
below ``stop_speed``), to ``max_time`` or to a contact. Sample 0's every step can be
recorded (the single event's timeline).

numba is imported only when this module is; the kernel is cached on disk under a key that
covers this file and the formulas it compiles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import carray, get_num_threads, njit, prange, set_num_threads
from numba.core import types
from numba.extending import intrinsic

from . import event_formula, evidence_terms, formula, runout_formula, runout_kernel, tyres
from .numba_cache import compile_module, stamped_cache
from .numbers import InputError
from .runout import RhsData
from .event_formula import (
    BISECTION_STEP,
    CONTACT_TOLERANCE,
    EVENT_STEP,
    MAX_IMPACTS,
    TUNNEL_FRACTION,
)
from .runout_kernel import one_signature, rk4_stages

__all__ = ["EventScene", "EventRun", "KernelScene", "kernel_scene", "run_event", "sliding_rows", "STATUS", "IMPACT_COLUMNS",
           "RECORD_COLUMNS", "COEFFICIENT_COLUMNS"]

#: Fewer samples than this run on one thread (a single event: waking the pool costs more).
SERIAL_BELOW = 8
#: What ended each sample's run (the kernel's status codes, in order).
STATUS = ("rest", "time", "contact", "impacts", "energy", "record")
#: Columns of an in-kernel impact's record: its time, C and n, the impulse on vehicle 1, the
#: contact's depth, both vehicles' velocities and yaw rates after, the energy lost, their
#: velocities and yaw rates before, their headings, and the law's ratio
#: (:func:`pim.model.event_formula.further_impact`: the effective beta of Brach's laws, mu
#: of Kudlich-Slibar's).
IMPACT_COLUMNS = ("time", "cx", "cy", "nx", "ny", "px", "py", "depth", "vx1", "vy1", "w1",
                  "vx2", "vy2", "w2", "energy_loss", "vx1_before", "vy1_before", "w1_before",
                  "vx2_before", "vy2_before", "w2_before", "psi1", "psi2", "ratio")
#: Columns of each further impact's law: restitution (eps, or k) [-], fraction of mu0 [-],
#: the cap or contact friction [-] (inf: none), the law's code
#: (:data:`pim.model.impact_laws.LAW_CODES`), and C [m] and Gamma [rad] where the case
#: gives them (NaN: the outlines' contact).
COEFFICIENT_COLUMNS = ("restitution", "beta", "cap", "law", "cx", "cy", "gamma")
#: Columns of a recorded step: time and both vehicles' (x, y, psi, v_x, v_y, omega).
RECORD_COLUMNS = ("time",) + tuple(f"{q}{i}" for i in (1, 2)
                                   for q in ("x", "y", "psi", "vx", "vy", "omega"))

_PIM = compile_module(formula)
_GEO = compile_module(event_formula, {
    "contact": _PIM.contact, "post_impact": _PIM.post_impact,
    "impulse_work": njit(inline="always", error_model="numpy")(evidence_terms.impulse_work)})
_box, _contact_geometry, _separating_axis = (_GEO.box, _GEO.contact_geometry,
                                             _GEO.separating_axis)
_further_impact, _energy_loss = _GEO.further_impact, _GEO.energy_loss
_slip_speed = _GEO.slip_speed
_cached = stamped_cache(event_formula, formula, runout_formula, tyres, runout_kernel,
                        evidence_terms)


@intrinsic
def _data_pointer(typingctx, array):  # pragma: no cover - compiled
    """The pointer to a C-contiguous array's first element (for :func:`numba.carray`). Any
    other layout does not compile (no signature: a typing error), since :func:`numba.carray`
    over a strided array's data would read other numbers."""
    if not isinstance(array, types.Array) or array.layout != "C":
        return None

    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data

    return types.CPointer(array.dtype)(array), codegen


@njit(inline="always")
def _borrowed(a):  # pragma: no cover - compiled
    """``a`` (C-contiguous) as an array that owns no reference (:func:`numba.carray` over
    its data: the same memory, shape and values)."""
    return carray(_data_pointer(a), a.shape)


@njit(inline="always")
def _borrowed_vehicle(veh):  # pragma: no cover - compiled
    """A run-out vehicle tuple (:mod:`pim.model.runout_formula`) with its arrays (C-contiguous,
    :func:`one_signature`'s) :func:`_borrowed`: the same numbers. numba counts references
    to every array a function binds, and the right-hand side, inlined, binds the vehicle's
    arrays several times per wheel: a call per binding and the floating-point registers
    spilled around it, tens of times per evaluation. With arrays known to own nothing LLVM
    drops that counting from the step (``python benchmarks/bench_event.py``: the kernel
    about twice as fast); the step only reads them while its caller holds the originals."""
    return (veh[0], veh[1], _borrowed(veh[2]), _borrowed(veh[3]), _borrowed(veh[4]), veh[5],
            veh[6], _borrowed(veh[7]), _borrowed(veh[8]), _borrowed(veh[9]),
            _borrowed(veh[10]))


@njit(error_model="numpy")
def _step(st, moving, t, h, veh1, veh2, new, ks):  # pragma: no cover - compiled
    """Both vehicles' states ``st`` (2, 6) advanced by one RK4 step of ``h`` [s] into
    ``new`` (the held ones copied; ``ks`` (4, 6) the stages' work space). One function (not
    inlined), called by the step and the bisection, so numba compiles the right-hand side
    once."""
    for v in range(2):
        for j in range(6):
            new[v, j] = st[v, j]
        if not moving[v]:
            continue
        veh = veh1 if v == 0 else veh2
        rk4_stages(t, h, (st[v, 2], st[v, 3], st[v, 4], st[v, 5]),
                   _borrowed_vehicle(veh), ks)
        w = h / 6.0
        for j in range(6):
            new[v, j] = st[v, j] + w * (ks[0, j] + 2.0 * ks[1, j] + 2.0 * ks[2, j] + ks[3, j])


@njit(error_model="numpy")
def _contact(st, geo):  # pragma: no cover - compiled
    b1 = _box(st[0, 0], st[0, 1], st[0, 2], geo[0, 0], geo[0, 1], geo[0, 2])
    b2 = _box(st[1, 0], st[1, 1], st[1, 2], geo[1, 0], geo[1, 1], geo[1, 2])
    s1 = (st[0, 0], st[0, 1], st[0, 2], st[0, 3], st[0, 4], st[0, 5])
    s2 = (st[1, 0], st[1, 1], st[1, 2], st[1, 3], st[1, 4], st[1, 5])
    return _contact_geometry(b1, b2, s1, s2)


@njit(error_model="numpy")
def _depth(st, geo):  # pragma: no cover - compiled
    """The outlines' overlap depth [m] at the states ``st`` (:func:`_contact`'s first)."""
    b1 = _box(st[0, 0], st[0, 1], st[0, 2], geo[0, 0], geo[0, 1], geo[0, 2])
    b2 = _box(st[1, 0], st[1, 1], st[1, 2], geo[1, 0], geo[1, 1], geo[1, 2])
    return _separating_axis(b1, b2)[0]


@njit(error_model="numpy")
def _bisect(st, moving, t, h, veh1, veh2, new, geo, level, ks):  # pragma: no cover
    """The shortest step in (0, h] [s] (to :data:`BISECTION_STEP`) after which the overlap
    depth exceeds ``level`` [m]; ``new`` holds the state after it."""
    lo, hi = 0.0, h
    while hi - lo > BISECTION_STEP:
        mid = 0.5 * (lo + hi)
        _step(st, moving, t, mid, veh1, veh2, new, ks)
        if _depth(new, geo) > level:
            hi = mid
        else:
            lo = mid
    _step(st, moving, t, hi, veh1, veh2, new, ks)
    return hi


@njit(inline="always", error_model="numpy")
def _energy(st, inv):  # pragma: no cover - compiled
    e = 0.0
    for v in range(2):
        if inv[2 * v] > 0.0:
            e += 0.5 * ((st[v, 3] ** 2 + st[v, 4] ** 2) / inv[2 * v]
                        + st[v, 5] ** 2 / inv[2 * v + 1])
    return e


@njit(inline="always", error_model="numpy")
def _time_step(st, dt, rad, small):  # pragma: no cover - compiled
    """The step [s]: ``dt``, or less while the bounding circles overlap (no tunnelling);
    and whether they overlap."""
    gap = np.hypot(st[0, 0] - st[1, 0], st[0, 1] - st[1, 1])
    near = gap < rad[0] + rad[1]
    h = dt
    if near:
        closing = (np.hypot(st[0, 3] - st[1, 3], st[0, 4] - st[1, 4])
                   + abs(st[0, 5]) * rad[0] + abs(st[1, 5]) * rad[1])
        if closing * h > TUNNEL_FRACTION * small:
            h = TUNNEL_FRACTION * small / closing
    return h, near


@njit(error_model="numpy")
def _impact(st, c, inv, coef, rec):  # pragma: no cover - compiled
    """Solve the impact at contact ``c`` (depth, cx, cy, nx, ny) on the states ``st`` in
    place under the law ``coef`` (:data:`COEFFICIENT_COLUMNS`), its record into ``rec``
    (:data:`IMPACT_COLUMNS` from "cx"). 0: C does not close under the law's tolerance (no
    impulse, nothing changed); 1: solved; 2: solved, and it gains energy."""
    cx, cy, nx, ny = c[1], c[2], c[3], c[4]
    if not np.isnan(coef[4]):
        cx, cy = coef[4], coef[5]
    if not np.isnan(coef[6]):
        nx, ny = np.cos(coef[6]), np.sin(coef[6])
    s1 = (st[0, 0], st[0, 1], st[0, 2], st[0, 3], st[0, 4], st[0, 5])
    s2 = (st[1, 0], st[1, 1], st[1, 2], st[1, 3], st[1, 4], st[1, 5])
    before = _energy(st, inv)
    out = _further_impact(cx, cy, nx, ny, s1, s2, (inv[0], inv[1], inv[2], inv[3]),
                          (coef[0], coef[1], coef[2], coef[3]), (1e-12, 1e-12))
    if out[0] == 0.0 and out[1] == 0.0:
        return 0
    rec[0], rec[1], rec[2], rec[3] = cx, cy, nx, ny
    rec[4], rec[5], rec[6] = out[0], out[1], c[0]
    for j in range(6):
        rec[14 + j] = st[j // 3, 3 + j % 3]
    rec[20], rec[21], rec[22] = st[0, 2], st[1, 2], out[8]
    st[0, 3], st[0, 4], st[0, 5] = out[2], out[3], out[4]
    st[1, 3], st[1, 4], st[1, 5] = out[5], out[6], out[7]
    for j in range(6):
        rec[7 + j] = st[j // 3, 3 + j % 3]
    rec[13] = _energy_loss(cx, cy, s1, s2, out)
    return 2 if rec[13] < -1e-9 * (1.0 + before) else 1


@_cached
@njit(parallel=True, cache=True, error_model="numpy")
def _run(y0, t0, allowed0, data1, data2, geo, rad, reach, inv, coef, settings, out, tail,
         impacts, record):  # pragma: no cover - compiled
    n = y0.shape[0]
    dt, max_time, stop_speed, tol, solve = (settings[0], settings[1], settings[2],
                                            settings[3], settings[4] > 0.0)
    for i in prange(n):
        veh1 = (data1[0][i], data1[1][i], data1[2][i], data1[3][i], data1[4][i], data1[5][i],
                data1[6], data1[7], data1[8][i], data1[9][i], data1[10][i])
        veh2 = (data2[0][i], data2[1][i], data2[2][i], data2[3][i], data2[4][i], data2[5][i],
                data2[6], data2[7], data2[8][i], data2[9][i], data2[10][i])
        _sample(i, y0[i].copy(), t0[i], allowed0[i], veh1, veh2, geo[i], rad[i], reach[i],
                inv[i], coef[i], (dt, max_time, stop_speed, tol, solve), out, tail, impacts,
                record)


@njit(error_model="numpy")
def _sample(i, st, t, allowed, veh1, veh2, geo, rad, reach, inv, coef, settings, out, tail,
            impacts, record):  # pragma: no cover - compiled
    dt, max_time, stop_speed, tol, solve = settings
    new, ks = np.empty((2, 6)), np.empty((4, 6))
    moving = np.zeros(2, dtype=np.bool_)
    for v in range(2):
        moving[v] = inv[2 * v] > 0.0 and (np.hypot(st[v, 3], st[v, 4]) + abs(st[v, 5])
                                          * reach[v] >= stop_speed)
    small = min(geo[0, 1], geo[0, 2], geo[1, 1], geo[1, 2])
    if np.isnan(allowed):     # the outlines' overlap at the start is no contact
        allowed = max(_depth(st, geo), 0.0)
    status, count, rows = 1, 0, 0
    c = np.zeros(5)
    keep = record.shape[0] > 0 and i == 0
    if keep:
        rows = _write(record, rows, t, st)
    while t < max_time:
        if not moving[0] and not moving[1]:
            status = 0
            break
        h, near = _time_step(st, dt, rad, small)
        h = min(h, max_time - t)
        _step(st, moving, t, h, veh1, veh2, new, ks)
        hit = False
        if near or np.hypot(new[0, 0] - new[1, 0], new[0, 1] - new[1, 1]) < rad[0] + rad[1]:
            depth = _depth(new, geo)
            if depth > allowed + tol:
                h = _bisect(st, moving, t, h, veh1, veh2, new, geo, allowed + tol, ks)
                cg = _contact(new, geo)
                for j in range(5):
                    c[j] = cg[j]
                closing = cg[5] > 0
                hit = closing
                if closing and solve:
                    if count == impacts.shape[1]:
                        status = 3
                    elif keep and rows == record.shape[0]:
                        status = 5
                        break
                    else:
                        if keep:        # the row just before the impact
                            rows = _write(record, rows, t + h, new)
                        kind = _impact(new, c, inv, coef[count], impacts[i, count, 1:])
                        if kind > 0:
                            impacts[i, count, 0] = t + h
                            status = 4 if kind == 2 else status
                            count += 1
                            for v in range(2):
                                moving[v] = inv[2 * v] > 0.0
                        else:
                            hit = False
                            rows -= 1 if keep else 0
                allowed = max(c[0], 0.0)
            else:
                allowed = min(allowed, max(depth, 0.0))
        else:
            allowed = 0.0
        for v in range(2):
            for j in range(6):
                st[v, j] = new[v, j]
        t += h
        if keep:
            if rows == record.shape[0]:
                status = 5
                break
            rows = _write(record, rows, t, st)
        if status >= 3 or (hit and not solve):
            status = 2 if status < 3 else status
            break
        for v in range(2):
            if moving[v] and np.hypot(st[v, 3], st[v, 4]) + abs(st[v, 5]) * reach[v] < stop_speed:
                moving[v] = False
    for v in range(2):
        for j in range(6):
            out[i, v, j] = st[v, j]
    tail[i, 0], tail[i, 1], tail[i, 2], tail[i, 3] = t, status, count, allowed
    tail[i, 4], tail[i, 5] = moving[0], moving[1]
    tail[i, 6:11] = c
    if i == 0:
        tail[i, 11] = rows


@_cached
@njit(cache=True, error_model="numpy")
def _sliding(states, vehicles, first, pos, braking, steer, threshold,
             out):  # pragma: no cover - compiled
    """``out[v, i, w]``: wheel w of vehicle ``v = vehicles[k]`` slides at ``states[v, i]``
    (x, y, psi, v_x, v_y, omega), ``i >= first``: its
    :func:`pim.model.event_formula.slip_speed` above ``threshold``, with the wheels at
    ``pos[k]`` (4, 2) [m], ``braking[k]`` (4,) [-] and ``steer[k]`` (4,) [rad]."""
    for k in range(vehicles.shape[0]):
        v = vehicles[k]
        for i in range(first, states.shape[1]):
            psi = states[v, i, 2]
            c, s = np.cos(psi), np.sin(psi)
            for w in range(4):
                cw, sw = c, s
                if steer[k, w] != 0.0:
                    cw, sw = np.cos(psi + steer[k, w]), np.sin(psi + steer[k, w])
                out[v, i, w] = _slip_speed(c, s, states[v, i, 3], states[v, i, 4],
                                           states[v, i, 5], pos[k, w, 0], pos[k, w, 1], cw,
                                           sw, braking[k, w]) > threshold


def sliding_rows(states, pos, braking, steer, threshold, *, vehicles=None,
                 first: int = 0) -> np.ndarray:
    """Which wheels slide (V, N, 4) along V vehicles' states (V, N, 6) (compiled; see
    :func:`pim.analysis.event.sliding_flags`): of the vehicles ``vehicles`` (indices on the
    first axis, default all; ``pos`` (K, 4, 2), ``braking`` and ``steer`` (K, 4) theirs in
    that order) from sample ``first`` on, False elsewhere (the states are read in place,
    not copied, when they are C-contiguous floats)."""
    states = np.ascontiguousarray(states, dtype=float)
    out = np.zeros(states.shape[:2] + (4,), dtype=np.bool_)
    index = np.arange(states.shape[0]) if vehicles is None else np.asarray(vehicles,
                                                                           dtype=np.int64)
    _sliding(states, index, int(first), *one_signature(
        np.asarray(pos, float), np.asarray(braking, float), np.asarray(steer, float)),
             float(threshold), out)
    return out


@njit(inline="always", error_model="numpy")
def _write(record, rows, t, st):  # pragma: no cover - compiled
    record[rows, 0] = t
    for v in range(2):
        for j in range(6):
            record[rows, 1 + 6 * v + j] = st[v, j]
    return rows + 1


@dataclass(frozen=True)
class EventScene:
    """What the event kernel needs of n samples' two vehicles (SI).

    Attributes
    ----------
    data1, data2 : RhsData
        Each vehicle's run-out data for n samples (:meth:`pim.model.runout.RhsData.of`;
        ``friction`` 0 for free motion); ``data2`` None for a fixed obstacle.
    outlines : ndarray (n, 2, 3)
        Each vehicle's outline: CG to its front, length, width [m].
    inverse : ndarray (n, 4)
        1/m1, 1/I1, 1/m2, 1/I2 [1/kg, 1/(kg m^2)] (0 for a fixed obstacle).
    coefficients : ndarray (n, MAX_IMPACTS, len(COEFFICIENT_COLUMNS))
        Each further impact's law, coefficients and given C and Gamma
        (:data:`COEFFICIENT_COLUMNS`), for the in-kernel impacts.
    """

    data1: RhsData
    data2: RhsData | None
    outlines: np.ndarray
    inverse: np.ndarray
    coefficients: np.ndarray


@dataclass(frozen=True)
class EventRun:
    """The kernel's answer for n samples (SI; see :func:`run_event`).

    Attributes
    ----------
    final : ndarray (n, 2, 6)
        Each vehicle's last state (x, y, psi, v_x, v_y, omega).
    time : ndarray (n,)
        Time of the last state [s].
    status : ndarray of str (n,)
        What ended the run (:data:`STATUS`).
    count : ndarray of int (n,)
        Impacts solved in the kernel.
    allowed : ndarray (n,)
        The least overlap depth since the last impact [m] (to continue a run).
    moving : ndarray of bool (n, 2)
        Which vehicles still move.
    contact : ndarray (n, 5)
        The last contact found: depth [m], C [m], normal (2,) [-].
    impacts : ndarray (n, MAX_IMPACTS, len(IMPACT_COLUMNS))
        The in-kernel impacts (:data:`IMPACT_COLUMNS`), the first ``count`` rows valid.
    record : ndarray (m, 13) or None
        Sample 0's every step (:data:`RECORD_COLUMNS`).
    """

    final: np.ndarray
    time: np.ndarray
    status: np.ndarray
    count: np.ndarray
    allowed: np.ndarray
    moving: np.ndarray
    contact: np.ndarray
    impacts: np.ndarray
    record: np.ndarray | None


def _columns(data: RhsData) -> tuple:
    return (data.mass, data.yaw_inertia, data.wheel_x, data.wheel_y, data.load,
            data.friction, float(data.regularisation), data.times, data.steer, data.brake,
            data.tyre)


@dataclass(frozen=True)
class KernelScene:
    """An :class:`EventScene` of n samples in the kernel's own layout (:func:`kernel_scene`):
    built once, run from any start (:func:`run_event`).

    Attributes
    ----------
    n : int
        Samples.
    vehicles : tuple
        Each vehicle's run-out data columns (:class:`pim.model.runout.RhsData`'s).
    arrays : tuple
        Outlines (n, 2, 3), bounding radii (n, 2), tyre reach (n, 2), inverse masses and
        inertias (n, 4) and the further impacts' laws (n, MAX_IMPACTS, 7).
    """

    n: int
    vehicles: tuple
    arrays: tuple


def kernel_scene(scene: EventScene, n: int) -> KernelScene:
    """``scene``'s arrays for n samples as the kernel takes them (broadcast, C-contiguous)."""
    data2 = scene.data2 if scene.data2 is not None else scene.data1
    outlines = _shaped(scene.outlines, (n, 2, 3))
    rad = event_formula.bound_radius(outlines[..., 0], outlines[..., 1], outlines[..., 2])
    reach = np.empty((n, 2))
    reach[:, 0], reach[:, 1] = scene.data1.reach, data2.reach
    inv = _shaped(scene.inverse, (n, 4))
    coefficients = _shaped(scene.coefficients, (n, MAX_IMPACTS, len(COEFFICIENT_COLUMNS)))
    return KernelScene(n, (one_signature(*_columns(scene.data1)),
                           one_signature(*_columns(data2))),
                       one_signature(outlines, rad, reach, inv, coefficients))


def _shaped(value, shape: tuple) -> np.ndarray:
    """``value`` as floats broadcast to ``shape`` in a writable array (no read-only view
    for :func:`one_signature` to copy): itself when it has that shape already (a copy of
    a read-only one)."""
    a = np.asarray(value, float)
    if a.shape == shape:
        return a if a.flags.writeable else a.copy()
    out = np.empty(shape)       # (writable: no copy by one_signature)
    out[...] = a
    return out


def run_event(scene, start, *, start_time=0.0, allowed=None, solve=True, record=0,
              step=EVENT_STEP, max_time=60.0, stop_speed=0.05,
              tolerance=CONTACT_TOLERANCE) -> EventRun:
    """Run n samples' two vehicles from ``start`` until rest, ``max_time`` or a contact.

    Parameters
    ----------
    scene : EventScene or KernelScene
        The vehicles (a :class:`KernelScene` of the same n: no arrays rebuilt).
    start : array_like (n, 2, 6)
        Each vehicle's state (x, y, psi, v_x, v_y, omega) at ``start_time`` [SI].
    start_time : float or (n,) [s]
    allowed : (n,), optional
        The overlap depth [m] that counts as no new contact (default: the depth at the
        start, e.g. the outlines' overlap at PIM's impact configuration).
    solve : bool
        Solve each further impact in the kernel (the Monte Carlo, the single event); False:
        stop at the first closing contact (status "contact") for the caller to solve.
    record : int
        Rows of sample 0's recording (0: none).
    step, max_time, stop_speed, tolerance
        [s], [s], [m/s], [m]: the fixed step, the time limit, the rest threshold of
        ``|v| + |omega| r_max``, the contact tolerance (module notes).
    """
    start = np.ascontiguousarray(np.asarray(start, dtype=float).reshape(-1, 2, 6))
    n = start.shape[0]
    if not np.isfinite(start).all():
        raise InputError("event: the start states must be finite")
    if not isinstance(scene, KernelScene):
        scene = kernel_scene(scene, n)
    if allowed is None:       # NaN: the kernel takes the depth at the start
        allowed = np.full(n, np.nan)
    out, tail = np.empty((n, 2, 6)), np.zeros((n, 12))
    impacts = np.zeros((n, MAX_IMPACTS, len(IMPACT_COLUMNS)))
    rec = np.empty((int(record), 13))
    settings = np.array([step, max_time, stop_speed, tolerance, 1.0 if solve else 0.0])
    threads = get_num_threads()
    serial = n < SERIAL_BELOW and threads > 1    # a single event: waking the thread pool
    if serial:                                    # costs more than it is
        set_num_threads(1)
    try:
        _run(*one_signature(start, _shaped(start_time, (n,)), np.asarray(allowed, float)),
             *scene.vehicles, *scene.arrays, settings, out, tail, impacts, rec)
    finally:
        if serial:
            set_num_threads(threads)
    return EventRun(final=out, time=tail[:, 0], status=_STATUS[tail[:, 1].astype(int)],
                    count=tail[:, 2].astype(int), allowed=tail[:, 3],
                    moving=tail[:, 4:6] > 0, contact=tail[:, 6:11], impacts=impacts,
                    record=rec[:int(tail[0, 11])] if record else None)


#: :data:`STATUS` as a read-only array (the kernel's codes to their names).
_STATUS = np.array(STATUS)
_STATUS.setflags(write=False)
