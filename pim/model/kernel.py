"""Fused, parallel compiled kernel of :func:`pim.solve` for large batches of cases.

Closed-form PIM costs a few dozen flops per case, so a batch of millions of cases is limited
by memory traffic: reading 19 inputs and writing the core outputs. The numpy reference path
in :mod:`pim.model.solver` makes one pass over memory per arithmetic operation (about a hundred
temporaries of N doubles); this module makes one: each case is read once, solved in registers
and written once, on all cores (numba ``prange``).

The arithmetic is :mod:`pim.model.formula` itself, compiled by numba (no fast-math, no fused
multiply-add contraction). By default the kernel takes sine and cosine of Gamma from its own
branch-free fdlibm polynomials (:func:`_sincos`, within 1 ulp of the C library's), which lets
LLVM vectorise the loop (:func:`_solve_kernel_simd`, near the memory-copy bound; the figures
are printed by ``benchmarks/bench_solve.py`` and kept in docs/performance.md). The results
then agree with the numpy path within :data:`ULP_BOUND` ulp of each output's scale times the
condition number of q (``tests/pim/model/test_kernel.py``, hypothesis over the inputs), the approach
and singular-q flags included. With ``fast_trig=False`` the kernel calls the C library's
sine and cosine, as numpy does, and gives bitwise the numpy path's values, at about 0.35 of
the copy bound (the calls keep the loop scalar). The tolerances are arguments of the
compiled functions, not constants baked into numba's cache, and the cache key covers
pim/model/formula.py as well as this file (:func:`_cached`), so an edit of the formula
recompiles the kernels instead of leaving a stale one. numba is imported only when this
module is, which :func:`pim.solve` does only when it takes the fast path.

Outputs: the kernel writes only the core outputs (post-impact velocities, yaw rates, impulse,
mu0 and the two flags), at the full broadcast shape of the inputs, so a batch costs 19 doubles
read and 9 doubles and 2 bytes written per case. The auxiliary fields of :class:`pim.Result`
(arms, approach velocity, K, n-t and critical impulse components, normal, tangent) are written
by a second pass of the same kernel when one of them is first read (the ``fill`` function of
the :class:`pim.Result` that :func:`solve_case` returns).
The unit normal and tangent share one buffer ``(-sin G, cos G, sin G)`` of shape (..., 3):
``normal`` is its view ``[..., 1:]`` and ``tangent`` its view ``[..., :2]`` (read-only).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange, types

from . import formula
from .numba_cache import files_stamp, stamped_cache
from .numbers import InputError
from .quantities import FIELDS, VECTOR_FIELDS
from .result import Result

__all__ = ["solve_case", "solve_arrays", "stream_copy", "scalar_kernel", "INPUTS", "CORE_VECTORS",
           "CORE_SCALARS", "AUX", "SCALAR_SIGNATURE"]

#: Input names, in the order the compiled functions take them (vectors have a trailing 2):
#: the case's fields of :data:`pim.model.quantities.FIELDS` but the headings.
INPUTS = tuple(name for name in FIELDS if not name.endswith(".heading"))

#: Core outputs written on every call: vectors (N, 2) and scalars (N,), in kernel order.
CORE_VECTORS = ("velocity1", "velocity2", "impulse")
CORE_SCALARS = ("yaw_rate1", "yaw_rate2", "mu0")
#: Auxiliary outputs, written by a second pass when one of them is first read.
AUX_VECTORS = ("arm1", "arm2", "approach_velocity")
AUX_SCALARS = ("impulse_n", "impulse_t", "critical_impulse_n", "critical_impulse_t",
               "approach_n", "approach_t", "k_nn", "k_nt", "k_tt")
AUX = AUX_VECTORS + AUX_SCALARS + ("normal", "tangent")


# ---- numba's cache, keyed on this file and on the formula -------------------------------------
#: SHA-256 of pim/model/formula.py: part of the numba cache key of every kernel here.
FORMULA_STAMP = files_stamp(formula)
#: Decorator caching a kernel under a key that covers kernel.py and the formula.
_cached = stamped_cache(formula)


#: Angles |Gamma| [rad] up to this take the kernel's own sine and cosine; beyond it the
#: batch is redone with the C library's (the Cody-Waite reduction below is exact up to here).
TRIG_LIMIT = 1.0e5
#: Cases per block of the parallel loop (the inner loop over a block is vectorised).
BLOCK = 8192
#: The fast (default) kernel agrees with the numpy path within this many ulp of each output's
#: scale (the largest magnitude among the quantities it is formed from) times the condition
#: number of q, (|K_nn Pn0| + |beta K_nt Pt0|) / |K_nn Pn0 + beta K_nt Pt0| (measured: a few
#: hundred at most over 10^6 random scenes; tests/pim/model/test_kernel.py).
ULP_BOUND = 1024

# fdlibm's minimax coefficients of sin and cos on [-pi/4, pi/4] and its split of pi/2.
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11
_INVPIO2 = 6.36619772367581382433e-01
_PIO2_1 = 1.57079632673412561417e+00
_PIO2_2, _PIO2_2T = 6.07710050630396597660e-11, 2.02226624879595063154e-21


@njit(inline="always", error_model="numpy")
def _sincos(x):  # pragma: no cover - compiled
    """sin x and cos x to within 1 ulp of the C library's for |x| <= TRIG_LIMIT, branch-free.

    x = k pi/2 + y with k = rint(2x/pi), y reduced in three parts (Cody-Waite, fdlibm's
    constants) and carried as a head y and tail yy; fdlibm's kernels on [-pi/4, pi/4]; the
    quadrant k mod 4 swaps and negates them. No branches and no library call: about twice as
    fast as the C library's sin and cos together (LLVM still keeps the loop scalar).
    """
    k = np.rint(x * _INVPIO2)
    r = x - k * _PIO2_1
    w = k * _PIO2_2
    t = r
    r = t - w
    w = k * _PIO2_2T - ((t - r) - w)
    y = r - w
    yy = (r - y) - w
    z = y * y
    v = z * y
    rs = _S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))
    s = y - ((z * (0.5 * yy - v * rs) - yy) - v * _S1)
    rc = z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    hz = 0.5 * z
    w2 = 1.0 - hz
    c = w2 + (((1.0 - w2) - hz) + (z * rc - y * yy))
    q = k - 4.0 * np.floor(k * 0.25)  # quadrant k mod 4 in doubles: exact, and vectorisable
    swap = (q == 1.0) | (q == 3.0)
    a = c if swap else s
    b = s if swap else c
    sin_x = -a if q >= 2.0 else a
    cos_x = -b if (q == 1.0) | (q == 2.0) else b
    return sin_x, cos_x


_contact = njit(inline="always", error_model="numpy")(formula.contact)
_post_impact = njit(inline="always", error_model="numpy")(formula.post_impact)


@njit(inline="always", error_model="numpy")
def _impact(cs, sn, a1, b1, r1x, r1y, v1x, v1y, om1, a2, b2, r2x, r2y, v2x, v2y, om2, e, b,
            approach_tol, singular_tol):  # pragma: no cover - compiled
    """The formula with its two selections (no impulse without approach, NaN where q is
    singular), for one case: the contact quantities, then the post-impact ones."""
    ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, drive, denom, appr, sing = _contact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, om1, a2, b2, r2x, r2y, v2x, v2y, om2, e, b,
        approach_tol, singular_tol)
    scale = drive / denom if appr else 0.0
    scale = np.nan if sing else scale
    p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2 = _post_impact(
        scale, pn0, pt0, b, cs, sn, a1, b1, r1x, r1y, v1x, v1y, om1, a2, b2, r2x, r2y, v2x,
        v2y, om2)
    return (ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, appr, sing,
            p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2)


@njit(inline="always", error_model="numpy")
def _case(i, cs, sn, m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, eps, beta, approach_tol,
          singular_tol, full, cvec, csc, approaching, singular, avec, asc,
          trig):  # pragma: no cover - compiled
    """Solve case i given cos and sin of its Gamma: :mod:`pim.model.formula`, compiled."""
    e = eps[i]
    b = beta[i]
    a1 = 1.0 / m1[i]
    b1 = 1.0 / i1[i]
    a2 = 1.0 / m2[i]
    b2 = 1.0 / i2[i]
    r1x = pt[i, 0] - cg1[i, 0]
    r1y = pt[i, 1] - cg1[i, 1]
    r2x = pt[i, 0] - cg2[i, 0]
    r2y = pt[i, 1] - cg2[i, 1]
    v1x = v1[i, 0]
    v1y = v1[i, 1]
    v2x = v2[i, 0]
    v2y = v2[i, 1]
    om1 = w1[i]
    om2 = w2[i]
    (ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, appr, sing,
     p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2) = _impact(
        cs, sn, a1, b1, r1x, r1y, v1x, v1y, om1, a2, b2, r2x, r2y, v2x, v2y, om2, e, b,
        approach_tol, singular_tol)
    cvec[0, i, 0] = vx1
    cvec[0, i, 1] = vy1
    cvec[1, i, 0] = vx2
    cvec[1, i, 1] = vy2
    cvec[2, i, 0] = ix
    cvec[2, i, 1] = iy
    csc[0, i] = ww1
    csc[1, i] = ww2
    csc[2, i] = pt0 / pn0
    approaching[i] = appr
    singular[i] = sing
    if full:
        avec[0, i, 0] = r1x
        avec[0, i, 1] = r1y
        avec[1, i, 0] = r2x
        avec[1, i, 1] = r2y
        avec[2, i, 0] = ux
        avec[2, i, 1] = uy
        asc[0, i] = p_n
        asc[1, i] = p_t
        asc[2, i] = pn0
        asc[3, i] = pt0
        asc[4, i] = u_n
        asc[5, i] = u_t
        asc[6, i] = k_nn
        asc[7, i] = k_nt
        asc[8, i] = k_tt
        trig[i, 0] = -sn
        trig[i, 1] = cs
        trig[i, 2] = sn
    return (0 if (e >= 0.0) & (e <= 1.0) else 1), (0 if np.isfinite(b) else 1)


@_cached
@njit(parallel=True, error_model="numpy", fastmath=False)
def _solve_kernel_fast(m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, gamma, eps, beta, approach_tol,
                       singular_tol, full,
                  cvec, csc, approaching, singular, avec, asc, trig):  # pragma: no cover
    """Solve every case with the kernel's own sine and cosine (:func:`_sincos`).

    Writes ``cvec`` (3, N, 2) and ``csc`` (3, N) in the orders of :data:`CORE_VECTORS`,
    :data:`CORE_SCALARS`, and the flags; with ``full`` also ``avec`` (3, N, 2), ``asc``
    (9, N) (:data:`AUX_VECTORS`, :data:`AUX_SCALARS`) and ``trig`` (N, 3) =
    (-sin G, cos G, sin G). Returns the number of eps values outside [0, 1] (or NaN), of
    non-finite beta values, and of |Gamma| > TRIG_LIMIT (whose results are then not used).
    """
    n = gamma.shape[0]
    blocks = (n + BLOCK - 1) // BLOCK
    counts = np.zeros((blocks, 3), dtype=np.int64)
    for blk in prange(blocks):
        bad_eps = 0
        bad_beta = 0
        big = 0
        for i in range(blk * BLOCK, min(n, (blk + 1) * BLOCK)):
            g = gamma[i]
            sn, cs = _sincos(g)
            big += 0 if np.abs(g) <= TRIG_LIMIT else 1
            be, bb = _case(i, cs, sn, m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, eps, beta,
                           approach_tol, singular_tol, full, cvec, csc, approaching, singular,
                           avec, asc, trig)
            bad_eps += be
            bad_beta += bb
        counts[blk, 0] = bad_eps
        counts[blk, 1] = bad_beta
        counts[blk, 2] = big
    total = counts.sum(axis=0)
    return total[0], total[1], total[2]


@njit(error_model="numpy", fastmath=False)
def _solve_block(m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, gamma, eps, beta, approach_tol,
                 singular_tol, vel1, vel2, imp, yaw1, yaw2, mu0, code):  # pragma: no cover
    """Core outputs of one block of cases, in a loop LLVM vectorises (SIMD).

    Vectors are flat interleaved (x0, y0, x1, y1, ...) 1-D arrays and the two flags one
    byte ``code`` = approaching + 2 singular: with two separate flag arrays, 2-D indexing, an
    integer quadrant in the sine, or a loop that does not start at 0, LLVM keeps the loop
    scalar. Same operations as :func:`_case` with :func:`_sincos` (no fast-math, no
    contraction), hence bitwise its values. Returns the counts of bad eps, bad beta and
    |Gamma| > TRIG_LIMIT.
    """
    bad_eps = 0
    bad_beta = 0
    big = 0
    for i in range(gamma.shape[0]):
        g = gamma[i]
        sn, cs = _sincos(g)
        big += 0 if np.abs(g) <= TRIG_LIMIT else 1
        e = eps[i]
        b = beta[i]
        a1 = 1.0 / m1[i]
        b1 = 1.0 / i1[i]
        a2 = 1.0 / m2[i]
        b2 = 1.0 / i2[i]
        j = 2 * i
        r1x = pt[j] - cg1[j]
        r1y = pt[j + 1] - cg1[j + 1]
        r2x = pt[j] - cg2[j]
        r2y = pt[j + 1] - cg2[j + 1]
        v1x = v1[j]
        v1y = v1[j + 1]
        v2x = v2[j]
        v2y = v2[j + 1]
        om1 = w1[i]
        om2 = w2[i]
        (ux, uy, u_n, u_t, k_nn, k_nt, k_tt, pn0, pt0, appr, sing,
         p_n, p_t, ix, iy, vx1, vy1, vx2, vy2, ww1, ww2) = _impact(
            cs, sn, a1, b1, r1x, r1y, v1x, v1y, om1, a2, b2, r2x, r2y, v2x, v2y, om2, e, b,
            approach_tol, singular_tol)
        vel1[j] = vx1
        vel1[j + 1] = vy1
        vel2[j] = vx2
        vel2[j + 1] = vy2
        imp[j] = ix
        imp[j + 1] = iy
        yaw1[i] = ww1
        yaw2[i] = ww2
        mu0[i] = pt0 / pn0
        code[i] = np.uint8(appr) + np.uint8(2) * np.uint8(sing)
        bad_eps += 0 if (e >= 0.0) & (e <= 1.0) else 1
        bad_beta += 0 if np.isfinite(b) else 1
    return bad_eps, bad_beta, big


@_cached
@njit(parallel=True, error_model="numpy", fastmath=False)
def _solve_kernel_simd(m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, gamma, eps, beta,
                       approach_tol, singular_tol, vel1, vel2, imp, yaw1, yaw2, mu0,
                       code):  # pragma: no cover - compiled
    """Core outputs of every case with the kernel's own sine and cosine, vectorised.

    Vectors (inputs and outputs) are flat interleaved 1-D arrays of length 2N; ``code`` (N,)
    uint8 gets approaching + 2 singular. Each block of :data:`BLOCK` cases is handed, as
    slices starting at 0, to :func:`_solve_block`, which LLVM vectorises. Returns the counts
    of bad eps, bad beta and |Gamma| > TRIG_LIMIT (whose results are then not used).
    """
    n = gamma.shape[0]
    blocks = (n + BLOCK - 1) // BLOCK
    counts = np.zeros((blocks, 3), dtype=np.int64)
    for blk in prange(blocks):
        a = blk * BLOCK
        z = min(n, a + BLOCK)
        be, bb, bg = _solve_block(
            m1[a:z], i1[a:z], cg1[2 * a:2 * z], v1[2 * a:2 * z], w1[a:z], m2[a:z], i2[a:z],
            cg2[2 * a:2 * z], v2[2 * a:2 * z], w2[a:z], pt[2 * a:2 * z], gamma[a:z], eps[a:z],
            beta[a:z], approach_tol, singular_tol, vel1[2 * a:2 * z], vel2[2 * a:2 * z],
            imp[2 * a:2 * z], yaw1[a:z], yaw2[a:z], mu0[a:z], code[a:z])
        counts[blk, 0] = be
        counts[blk, 1] = bb
        counts[blk, 2] = bg
    total = counts.sum(axis=0)
    return total[0], total[1], total[2]


@_cached
@njit(parallel=True, error_model="numpy", fastmath=False)
def _solve_kernel_libm(m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, gamma, eps, beta, approach_tol,
                       singular_tol, full, cvec, csc, approaching, singular, avec, asc,
                       trig):  # pragma: no cover - compiled
    """Solve every case with the C library's sine and cosine: bitwise the numpy path's values.

    Same arguments as :func:`_solve_kernel_fast`."""
    n = gamma.shape[0]
    bad_eps = 0
    bad_beta = 0
    for i in prange(n):
        g = gamma[i]
        be, bb = _case(i, np.cos(g), np.sin(g), m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt,
                       eps, beta, approach_tol, singular_tol, full, cvec, csc, approaching,
                       singular, avec, asc, trig)
        bad_eps += be
        bad_beta += bb
    return bad_eps, bad_beta, 0


@_cached
@njit(parallel=True)
def _copy_kernel(m1, i1, cg1, v1, w1, m2, i2, cg2, v2, w2, pt, gamma, eps, beta, approach_tol,
                       singular_tol, full,
                 cvec, csc, approaching, singular, avec, asc, trig):  # pragma: no cover
    """The memory-traffic floor of :func:`_solve_kernel_libm`: same reads and writes, no arithmetic.

    Every input element is read once (summed) and every output element written once, in the
    same parallel loop over the same buffers as the solver.
    """
    n = gamma.shape[0]
    for i in prange(n):
        x = (m1[i] + i1[i] + w1[i] + m2[i] + i2[i] + w2[i] + gamma[i] + eps[i] + beta[i]
             + cg1[i, 0] + cg1[i, 1] + v1[i, 0] + v1[i, 1] + cg2[i, 0] + cg2[i, 1]
             + v2[i, 0] + v2[i, 1] + pt[i, 0] + pt[i, 1])
        for k in range(3):
            cvec[k, i, 0] = x
            cvec[k, i, 1] = x
            csc[k, i] = x
        approaching[i] = x < 0
        singular[i] = x > 0
        if full:
            for k in range(3):
                avec[k, i, 0] = x
                avec[k, i, 1] = x
                trig[i, k] = x
            for k in range(9):
                asc[k, i] = x
    return 0, 0, 0


def _any_layout_signature() -> tuple:
    """The argument types of the scalar-loop kernels (:func:`_solve_kernel_fast`,
    :func:`_solve_kernel_libm`): the inputs read-only of any layout, then the two tolerances,
    ``full`` and the C-contiguous output buffers of :func:`allocate`."""
    def array(ndim, layout="A", dtype=types.float64, readonly=False):
        return types.Array(dtype, ndim, layout, readonly=readonly)

    inputs = [array(2 if name in VECTOR_FIELDS else 1, readonly=True) for name in INPUTS]
    outputs = [array(3, "C"), array(2, "C"), array(1, "C", types.boolean),
               array(1, "C", types.boolean), array(3, "C"), array(2, "C"), array(2, "C")]
    return (*inputs, types.float64, types.float64, types.boolean, *outputs)


#: The one signature each scalar-loop kernel is compiled for (:func:`scalar_kernel`).
SCALAR_SIGNATURE = _any_layout_signature()


def scalar_kernel(dispatcher):
    """``dispatcher`` (:func:`_solve_kernel_fast` or :func:`_solve_kernel_libm`) compiled once,
    for :data:`SCALAR_SIGNATURE`, on first use (from numba's cache when it holds it).

    numba compiles a kernel anew for every tuple of argument types, and a scalar input
    broadcast to the batch is a stride-0 view (layout "A") where an array is contiguous
    ("C"): each mix of the two cost a compilation of 5-20 s. These kernels keep their loop
    scalar (library or branchy trig, the auxiliary fields), so reading every input through
    its strides costs nothing measurable (1e6 cases: 3.3-3.8 M cases/s either way, the
    values bitwise the same); the vectorised :func:`_solve_kernel_simd` keeps its
    contiguous specialisations (any-layout inputs run it at a third of the speed).
    """
    if SCALAR_SIGNATURE not in dispatcher.overloads:
        dispatcher.compile(SCALAR_SIGNATURE)
        dispatcher.disable_compile()   # later calls convert their arrays to these types
    return dispatcher


def _flat(value, shape: tuple, vector: bool) -> np.ndarray:
    """``value`` broadcast to ``shape`` (+ (2,) for vectors), flattened to (N,) or (N, 2).

    A view when possible (contiguous full arrays, and scalars via stride 0), else a copy.
    """
    full = shape + (2,) if vector else shape
    arr = np.broadcast_to(np.asarray(value, dtype=float), full)
    return arr.reshape((-1, 2) if vector else (-1,))


def broadcast_shape(inputs: dict) -> tuple:
    """Common shape of the named inputs (vectors without their trailing 2)."""
    return np.broadcast_shapes(*[np.shape(inputs[k])[:-1] if k in VECTOR_FIELDS
                                 else np.shape(inputs[k]) for k in INPUTS])


def flatten_inputs(inputs: dict, shape: tuple) -> list[np.ndarray]:
    """The kernel's input arguments from the named inputs (see :data:`INPUTS`)."""
    return [_flat(inputs[name], shape, name in VECTOR_FIELDS) for name in INPUTS]


def allocate(n: int, full: bool) -> list[np.ndarray]:
    """Output buffers for ``n`` cases (uninitialised: the kernel writes every element)."""
    m = n if full else 0
    return [np.empty((len(CORE_VECTORS), n, 2)), np.empty((len(CORE_SCALARS), n)),
            np.empty(n, dtype=bool), np.empty(n, dtype=bool),
            np.empty((len(AUX_VECTORS), m, 2)), np.empty((len(AUX_SCALARS), m)),
            np.empty((m, 3))]


def solve_arrays(inputs: dict, approach_tol: float, singular_tol: float, full: bool = False,
                 copy_only: bool = False, fast_trig: bool = False) -> dict:
    """Run the kernel on named inputs (SI; see :data:`INPUTS`) broadcast together.

    Parameters
    ----------
    inputs : dict
        The fields of :data:`INPUTS` by their dotted names (``vehicle1.mass`` [kg],
        ``vehicle1.yaw_inertia`` [kg m^2], ``vehicle1.cg`` [m] (..., 2), ``vehicle1.velocity``
        [m/s] (..., 2), ``vehicle1.yaw_rate`` [rad/s], the same for vehicle 2,
        ``impact.point`` [m] (..., 2), ``impact.normal_angle`` [rad], ``impact.restitution``
        and ``impact.beta`` [-]), in any shapes that broadcast.
    approach_tol, singular_tol : float
        Relative tolerances of the approach and singular-q tests [-]
        (:data:`pim.model.solver.APPROACH_TOLERANCE`, ``SINGULAR_TOLERANCE``): arguments of
        the compiled functions, so changing them needs no recompilation.
    full : bool
        Also return the auxiliary fields (:data:`AUX`), not just the core ones.
    copy_only : bool
        Run the memory-traffic floor instead: same reads and writes, no arithmetic.
    fast_trig : bool
        Use the kernel's own branch-free sine and cosine (:func:`_sincos`, within 1 ulp of
        the C library's) instead of the C library's, which numpy uses; the core outputs then
        come from the vectorised :func:`_solve_kernel_simd` (near the memory-copy bound), and
        results differ from the numpy path by round-off (module notes: :data:`ULP_BOUND`)
        instead of not at all.

    Returns
    -------
    dict
        The core fields of :class:`pim.Result` (``velocity1/2, impulse, yaw_rate1/2, mu0,
        approaching, q_singular``; with ``full`` also :data:`AUX`) at the broadcast shape,
        and ``bad_eps`` / ``bad_beta``: the number of eps outside [0, 1] (or NaN) and of
        non-finite beta.
    """
    shape = broadcast_shape(inputs)
    n = int(np.prod(shape, dtype=np.int64))
    args = flatten_inputs(inputs, shape)
    out = allocate(n, full)
    tols = float(approach_tol), float(singular_tol)
    big = 0
    if fast_trig and not full and not copy_only:
        cvec, csc = out[0], out[1]
        code = np.empty(n, dtype=np.uint8)
        bad_eps, bad_beta, big = _solve_kernel_simd(
            *[a.reshape(-1) for a in args], *tols, *[v.reshape(-1) for v in cvec], *csc, code)
        out[2] = (code & 1).view(bool)
        out[3] = (code >> 1).view(bool)
    else:
        kernel = _copy_kernel if copy_only else scalar_kernel(
            _solve_kernel_fast if fast_trig else _solve_kernel_libm)
        bad_eps, bad_beta, big = kernel(*args, *tols, bool(full), *out)
    if big:  # some |Gamma| beyond the range of the kernel's own sine and cosine: redo
        out = allocate(n, full)
        bad_eps, bad_beta, big = scalar_kernel(_solve_kernel_libm)(*args, *tols, bool(full),
                                                                   *out)
    cvec, csc, appr, sing, avec, asc, trig = out
    fields = {name: cvec[k].reshape(shape + (2,)) for k, name in enumerate(CORE_VECTORS)}
    fields.update({name: csc[k].reshape(shape) for k, name in enumerate(CORE_SCALARS)})
    fields["approaching"] = appr.reshape(shape)
    fields["q_singular"] = sing.reshape(shape)
    if full:
        fields.update({name: avec[k].reshape(shape + (2,)) for k, name in enumerate(AUX_VECTORS)})
        fields.update({name: asc[k].reshape(shape) for k, name in enumerate(AUX_SCALARS)})
        trig = trig.reshape(shape + (3,))
        trig.flags.writeable = False  # normal and tangent overlap in it
        fields["normal"] = trig[..., 1:]
        fields["tangent"] = trig[..., :2]
    fields["bad_eps"], fields["bad_beta"] = int(bad_eps), int(bad_beta)
    return fields


def stream_copy(inputs: dict, full: bool = False) -> dict:
    """The memory-copy bound: :func:`solve_arrays` with the arithmetic taken out."""
    return solve_arrays(inputs, 0.0, 0.0, full=full, copy_only=True)


def case_inputs(case, eps, beta) -> dict:
    """The kernel's named inputs of a :class:`pim.Case` with eps and beta [-]."""
    v1, v2, imp = case.vehicle1, case.vehicle2, case.impact
    return {"vehicle1.mass": v1.mass, "vehicle1.yaw_inertia": v1.yaw_inertia,
            "vehicle1.cg": v1.cg, "vehicle1.velocity": v1.velocity,
            "vehicle1.yaw_rate": v1.yaw_rate, "vehicle2.mass": v2.mass,
            "vehicle2.yaw_inertia": v2.yaw_inertia, "vehicle2.cg": v2.cg,
            "vehicle2.velocity": v2.velocity, "vehicle2.yaw_rate": v2.yaw_rate,
            "impact.point": imp.point, "impact.normal_angle": imp.normal_angle,
            "impact.restitution": eps, "impact.beta": beta}


def solve_case(case, eps, beta, approach_tol: float, singular_tol: float,
               fast_trig: bool = True) -> Result:
    """:func:`pim.solve` of ``case`` on the kernel.

    The core fields (post-impact velocities, yaw rates, impulse, mu0 and the flags) come from
    one pass; the auxiliary fields (:data:`AUX`: arms, approach velocity, K, n-t and critical
    impulse components, normal, tangent) from a second, full pass when the first of them is
    read. ``eps`` and ``beta`` are arrays [-]; raises ValueError (as :func:`pim.solve`) when
    eps is outside [0, 1] or beta is not finite. ``fast_trig``: see :func:`solve_arrays`.
    """
    inputs = case_inputs(case, eps, beta)
    out = solve_arrays(inputs, approach_tol, singular_tol, fast_trig=fast_trig)
    bad_eps, bad_beta = out.pop("bad_eps"), out.pop("bad_beta")
    if bad_eps:
        raise InputError(f"eps (coefficient of restitution) must be in [0, 1] "
                         f"({bad_eps} values are not)")
    if bad_beta:
        raise InputError(f"beta (fraction of mu0) must be a finite number, usually in [0, 1] "
                         f"({bad_beta} values are not)")

    def fill() -> dict:
        full = solve_arrays(inputs, approach_tol, singular_tol, full=True, fast_trig=fast_trig)
        return {name: full[name] for name in AUX}

    return Result(case, eps, beta, out, fill=fill,
                  backend="numba" if fast_trig else "numba-libm")
