"""The compiled, parallel batch integrator of the finite-duration crush scene.

numba compiles the functions of :mod:`sim.compliant_formula` themselves (one source: the
pymunk scene of :mod:`sim.compliant` calls the same functions for its forces), and steps
each scene as pymunk does: Chipmunk's position update (:func:`~sim.compliant_formula.drift`),
the loads at the new positions and the old velocities, Chipmunk's velocity update
(:func:`~sim.compliant_formula.kick`), the same step, the same half kick at the start, the
same separation test and post-impact velocities. The scenes of a batch run on all cores
(``prange``), each with its own step and its own end.

The kernel is compiled on first use (never on import of :mod:`sim`: this module is imported
only when the compiled engine runs) for one signature, and cached on disk under a key that
covers this file, the formula and the tyre law (:func:`pim.model.numba_cache.stamped_cache`),
so a later process loads it instead of compiling.
"""

from __future__ import annotations

from types import FunctionType, SimpleNamespace

import numpy as np
from numba import njit, prange, types

from pim.model import tyres
from pim.model.numba_cache import stamped_cache

from . import compliant_formula

__all__ = ["integrate", "compile_module", "kernels", "SIGNATURE", "SERIAL_BELOW"]


def compile_module(module, separate=()) -> SimpleNamespace:
    """numba versions of every function defined in ``module``, calling each other.

    Each function is copied with a namespace in which the module's functions, and the plain
    functions it imports (the tyre law), are their compiled versions: the Python source is
    the one the pymunk scene runs. They are inlined where they are called (numba's
    ``inline="always"``: 1.3-1.4 times faster steps than separate functions, measured on
    RICSAC 9), except those named in ``separate``, compiled as functions of their own
    (:data:`SEPARATE`: inlining everything doubled the compile time for no speed).
    """
    namespace = dict(vars(module))
    compiled = {}
    for name, obj in vars(module).items():
        if not isinstance(obj, FunctionType):
            continue
        if obj.__module__ == module.__name__:
            obj = FunctionType(obj.__code__, namespace, name, obj.__defaults__, obj.__closure__)
        inline = "never" if name in separate else "always"
        compiled[name] = njit(inline=inline, error_model="numpy")(obj)
    namespace.update(compiled)
    return SimpleNamespace(**compiled)


#: The formula's functions compiled as functions of their own (not inlined): the outline
#: contact's geometry and its parts, what runs once per scene, and the four tyres of one
#: vehicle (called twice per step). Inlining only the rest of the step halves the compile
#: time of a clean checkout (46 -> 22 s CPU) at the same speed per step of the point
#: contact (129 and 133 ns, measured on the benchmark's scenes, one thread).
SEPARATE = ("outline_geometry", "outline_start", "place_corners", "clip_polygon",
            "area_centroid", "_extent", "separating_axis", "outline_overlap", "place_outlines",
            "outlines_touch", "free_state", "write_outputs", "post_velocities",
            "separation_time", "slip_reversed", "_centroid", "_unit", "half_kick",
            "normal_stiffness", "vehicle_tyre_force")


_f = compile_module(compliant_formula, SEPARATE)
_drift, _kick, _half_kick, _angles = _f.drift, _f.kick, _f.half_kick, _f.angles
_advance_angles = _f.advance_angles
_outline_start, _outline_geometry = _f.outline_start, _f.outline_geometry
_free_state, _freeze_point = _f.free_state, _f.freeze_point
_point_geometry, _contact_loads, _total_loads = _f.point_geometry, _f.contact_loads, _f.total_loads
_permanent_crush, _separation_time = _f.permanent_crush, _f.separation_time
_post_velocities, _write_outputs = _f.post_velocities, _f.write_outputs
_F = compliant_formula
N_MEM, N_TAL, M_ON, M_STARTED, M_SEPARATED, M_DMAX = (
    _F.N_MEM, _F.N_TAL, _F.M_ON, _F.M_STARTED, _F.M_SEPARATED, _F.M_DMAX)
P_DT, P_START, P_MAX_STEPS, P_FIXED2 = _F.P_DT, _F.P_START, _F.P_MAX_STEPS, _F.P_FIXED2
P_EPS, P_PRELOAD, P_STIFFNESS, P_TYRE = _F.P_EPS, _F.P_PRELOAD, _F.P_STIFFNESS, _F.P_TYRE
STATUS_OK, STATUS_NO_CONTACT, STATUS_NEVER_SEPARATED, STATUS_TUNNELLED = (
    _F.STATUS_OK, _F.STATUS_NO_CONTACT, _F.STATUS_NEVER_SEPARATED, _F.STATUS_TUNNELLED)
P_OUTLINE, P_SPEED, T_LAST_SLIP_N, N_WORK = _F.P_OUTLINE, _F.P_SPEED, _F.T_LAST_SLIP_N, _F.N_WORK
P_FROZEN = _F.P_FROZEN

_cached = stamped_cache(compliant_formula, tyres)


@njit(error_model="numpy")
def _start(par, state0, st, wk):  # pragma: no cover - compiled
    """The state where the contact starts into ``st``: ``state0`` (point contact, which must
    approach at C) or moved back along the free paths to where the outlines first touch
    (its time into ``par[P_START]``). Returns a status code."""
    if par[P_OUTLINE] == 0.0:
        for j in range(12):
            st[j] = state0[j]
        if par[P_FROZEN] != 0.0:
            _freeze_point(par, st)
        if not _point_geometry(par, st, _angles(st), 0.0)[5] < 0.0:
            return STATUS_NO_CONTACT              # the vehicles do not approach at C
        return STATUS_OK
    start = _outline_start(par, state0, wk)
    if np.isnan(start):
        return STATUS_TUNNELLED                   # overlapping along all the free paths
    par[P_START] = start
    _free_state(state0, start, st)
    return STATUS_OK


@njit(error_model="numpy")
def _scene(par, state0, out):  # pragma: no cover - compiled
    """Step one scene from ``state0`` (12) to separation; its outputs into ``out``.
    Returns the status code."""
    st = np.empty(12)
    wk = np.zeros(N_WORK)
    status = _start(par, state0, st, wk)
    if status != STATUS_OK:
        return status
    mem = np.zeros(N_MEM)
    mem[M_ON] = 1.0
    tal = np.zeros(N_TAL)
    lo = np.zeros(6)
    dt = par[P_DT]
    outline = par[P_OUTLINE] != 0.0
    if par[P_TYRE] > 0.0:
        v = _half_kick(par, st, lo)
        st[3], st[4], st[5] = v[0], v[1], v[2]
        if par[P_FIXED2] == 0.0:
            st[9], st[10], st[11] = v[3], v[4], v[5]
    max_steps = int(par[P_MAX_STEPS])
    steps = 0
    trig = _angles(st)
    while True:
        _drift(par, st, dt)
        fx = fy = m1 = m2 = 0.0
        trig = _advance_angles(par, trig, st, dt)
        if mem[M_ON] != 0.0:
            if outline:
                px, py, nx, ny, delta, slip_n, slip_t, overlap, flipped = _outline_geometry(
                    par, mem, st, trig, wk)
                if flipped:
                    return STATUS_TUNNELLED           # the outlines passed through
            else:
                px, py, nx, ny, delta, slip_n, slip_t = _point_geometry(par, st, trig, dt)
                overlap = True
            res = _contact_loads(par, mem, tal, st, trig, dt, px, py, nx, ny, delta, slip_n,
                                 slip_t, overlap)
            fx, fy, m1, m2 = res[1], res[2], res[3], res[4]
        _total_loads(par, st, trig, lo, tal, dt, fx, fy, m1, m2)
        _kick(par, st, lo, dt)
        steps += 1
        if mem[M_SEPARATED] != 0.0:
            break
        if steps >= max_steps:
            return STATUS_NEVER_SEPARATED if mem[M_STARTED] != 0.0 else STATUS_NO_CONTACT
    if outline and tal[T_LAST_SLIP_N] < -1e-3 * par[P_SPEED]:
        return STATUS_TUNNELLED                       # the overlap ended while approaching
    start = par[P_START]
    delta_p = _permanent_crush(mem[M_DMAX], par[P_EPS], par[P_PRELOAD], par[P_STIFFNESS])
    t_end = _separation_time(mem, start, steps, dt, delta_p)
    post = _post_velocities(par, st, lo, start + steps * dt, t_end)
    _write_outputs(par, mem, tal, out, steps, t_end, post)
    return STATUS_OK


@_cached
@njit(parallel=True, error_model="numpy")
def _integrate(par, state0, out, status):  # pragma: no cover - compiled
    """Every scene whose ``status`` is 0 (the others are refused already), in parallel."""
    for i in prange(par.shape[0]):
        if status[i] == STATUS_OK:
            status[i] = _scene(par[i], state0[i], out[i])


@_cached
@njit(error_model="numpy")
def _integrate_serial(par, state0, out, status):  # pragma: no cover - compiled
    """:func:`_integrate` on one thread (small batches: no thread launch)."""
    for i in range(par.shape[0]):
        if status[i] == STATUS_OK:
            status[i] = _scene(par[i], state0[i], out[i])


_C2 = types.Array(types.float64, 2, "C")
#: The one signature the kernels are compiled for: par (n, N_PAR), state0 (n, 12, read-only),
#: out (n, N_OUT), all C-contiguous float64, and status (n,) int8.
SIGNATURE = (_C2, types.Array(types.float64, 2, "C", readonly=True), _C2,
             types.Array(types.int8, 1, "C"))
#: Batches up to this size run on one thread.
SERIAL_BELOW = 32


def _ready(dispatcher):
    """``dispatcher`` compiled for :data:`SIGNATURE` only (from numba's cache when it holds
    it), on first use; later calls never compile again (the signature is then among its
    overloads)."""
    if SIGNATURE not in dispatcher.overloads:
        dispatcher.compile(SIGNATURE)
        dispatcher.disable_compile()
    return dispatcher


def kernels() -> dict:
    """The two compiled kernels by name ("serial", "parallel"), e.g. to count what numba
    compiled for them (one signature each)."""
    return {"serial": _integrate_serial, "parallel": _integrate}


def integrate(par: np.ndarray, state0: np.ndarray, status: np.ndarray) -> np.ndarray:
    """Step every scene (rows of ``par`` and ``state0``) whose ``status`` is 0.

    Parameters
    ----------
    par : ndarray (n, N_PAR)
        :func:`sim.compliant_setup.parameter_rows`.
    state0 : ndarray (n, 12)
        The state at the start of the contact [SI].
    status : ndarray (n,) int8
        0 for the scenes to run; the kernel writes each one's status code
        (:data:`sim.compliant_formula.STATUS_NAMES`).

    Returns
    -------
    ndarray (n, N_OUT)
        :func:`sim.compliant_formula.write_outputs` rows (NaN where the status is not 0).
    """
    out = np.full((par.shape[0], compliant_formula.N_OUT), np.nan)
    kernel = _integrate_serial if par.shape[0] < SERIAL_BELOW else _integrate
    state0 = np.ascontiguousarray(state0, dtype=float).view()
    state0.flags.writeable = False
    _ready(kernel)(np.ascontiguousarray(par, dtype=float), state0, out, status)
    return out
