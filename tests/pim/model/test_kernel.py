"""The compiled kernel (pim/model/kernel.py) against the numpy reference path of pim.solve.

Both evaluate the one formula (pim/model/formula.py) with the same C library sine and cosine,
so they must agree bitwise (checked element by element); the fast-trig variant is held to 1e-12
normwise (max error over max magnitude), since a 1-ulp sine can be amplified by cancellation
in single elements. Scenes: random two-vehicle impacts, fixed obstacles, separating contacts
(no impact), singular q, and broadcast (scalar) inputs.
"""

import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pim
from pim.model import kernel
from pim.model.numba_cache import cache_stamp
from pim.model.solver import APPROACH_TOLERANCE, SINGULAR_TOLERANCE

# one xdist worker runs this file (--dist loadgroup): its kernels' specialisations are
# compiled once instead of once per worker on a fresh clone
pytestmark = pytest.mark.xdist_group("pim_kernel")

FIELDS = ["velocity1", "velocity2", "yaw_rate1", "yaw_rate2", "impulse", "impulse_n",
          "impulse_t", "critical_impulse_n", "critical_impulse_t", "normal", "tangent", "arm1",
          "arm2", "approach_velocity", "approach_n", "approach_t", "k_nn", "k_nt", "k_tt", "mu0"]
DERIVED = ["energy_loss", "delta_v1_magnitude", "pdof1", "pdof2", "separation_n",
           "crush_energy_tangential", "total_loss_brach"]


def random_case(n, seed, fixed=False):
    """n random scenes, every input varying; a third of them do not approach at C."""
    rng = np.random.default_rng(seed)

    def vehicle():
        m = rng.uniform(500, 3000, n)
        return pim.Vehicle(m, m * rng.uniform(0.8, 2.0, n) ** 2, rng.uniform(-3, 3, (n, 2)),
                           rng.uniform(-30, 30, (n, 2)), rng.uniform(-3, 3, n),
                           rng.uniform(-np.pi, np.pi, n))

    v1 = vehicle()
    if fixed:
        v2 = pim.Vehicle(np.full(n, np.inf), np.full(n, np.inf), rng.uniform(-3, 3, (n, 2)),
                         np.zeros((n, 2)), np.zeros(n), rng.uniform(-np.pi, np.pi, n))
    else:
        v2 = vehicle()
    impact = pim.Impact(rng.uniform(-2, 2, (n, 2)), rng.uniform(-20, 20, n))
    return pim.Case(v1, v2, impact), rng.uniform(0, 1, n), rng.uniform(-0.2, 1.2, n)


def assert_same(fast, ref, fields=FIELDS, rtol=0.0):
    """Equal to ``rtol`` relative per element (default 0: bitwise), NaN where NaN."""
    for name in fields:
        a = np.asarray(getattr(fast, name))
        b = np.broadcast_to(getattr(ref, name), a.shape)
        assert a.shape == b.shape, name
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=name)
        ok = ~np.isnan(b)
        err = np.abs(a[ok] - b[ok])
        assert np.all(err <= rtol * np.abs(b[ok])), (name, np.max(err / np.abs(b[ok])))
    np.testing.assert_array_equal(fast.approaching, np.broadcast_to(ref.approaching, a.shape[:1]))
    np.testing.assert_array_equal(fast.q_singular, np.broadcast_to(ref.q_singular, a.shape[:1]))


@pytest.mark.parametrize("fixed", [False, True])
def test_kernel_equals_numpy_on_random_scenes(fixed):
    case, eps, beta = random_case(20_000, seed=1 + fixed, fixed=fixed)
    ref = pim.solve(case, eps, beta, backend="numpy")
    fast = pim.solve(case, eps, beta, backend="numba", fast_trig=False)
    assert fast.backend == "numba-libm" and isinstance(fast, pim.Result)
    assert 0.2 < ref.approaching.mean() < 0.8  # both approaching and separating scenes
    assert not np.any(fast.impulse[~ref.approaching])  # no impact, no impulse
    assert_same(fast, ref, FIELDS + DERIVED)
    if fixed:  # the obstacle does not move
        assert np.all(fast.velocity2[~fast.q_singular] == 0)
        assert np.all(fast.yaw_rate2[~fast.q_singular] == 0)
    assert fast.problems() == ref.problems()


def test_auto_backend_takes_the_kernel_for_large_batches_only():
    case, eps, beta = random_case(pim.model.solver.FAST_PATH_MIN_SIZE, seed=3)
    assert pim.solve(case, eps, beta).backend == "numba"
    small, eps, beta = random_case(100, seed=3)
    assert pim.solve(small, eps, beta).backend == "numpy"
    with pytest.raises(ValueError, match="backend"):
        pim.solve(small, eps, beta, backend="fortran")


def test_singular_q_is_flagged_and_nan_in_both_paths():
    """beta chosen so that K_nn Pn0 + beta K_nt Pt0 = 0: q = 1/(A - mu B) is singular."""
    case, eps, _ = random_case(5000, seed=4)
    ref1 = pim.solve(case, eps, 1.0, backend="numpy")
    beta = -(ref1.k_nn * ref1.critical_impulse_n) / (ref1.k_nt * ref1.critical_impulse_t)
    beta = np.where(np.isfinite(beta), beta, 0.5)
    ref = pim.solve(case, eps, beta, backend="numpy")
    fast = pim.solve(case, eps, beta, backend="numba", fast_trig=False)
    expected = ref1.approaching & np.isfinite(
        -(ref1.k_nn * ref1.critical_impulse_n) / (ref1.k_nt * ref1.critical_impulse_t))
    assert ref.q_singular.sum() > 1000
    np.testing.assert_array_equal(fast.q_singular, ref.q_singular)
    assert np.all(fast.q_singular <= expected)
    assert np.all(np.isnan(fast.velocity1[fast.q_singular]))
    assert_same(fast, ref)


def test_broadcast_inputs_and_shapes():
    """Scalar and (2,) inputs broadcast against a (40, 50) batch, as in the numpy path."""
    rng = np.random.default_rng(5)
    shape = (40, 50)
    v1 = pim.Vehicle(1500.0, 2500.0, (1.5, 0.2), rng.uniform(-20, 20, shape + (2,)),
                     rng.uniform(-1, 1, shape))
    v2 = pim.Vehicle.obstacle(cg=(-1.0, 0.0))
    case = pim.Case(v1, v2, pim.Impact((0.0, 0.0), rng.uniform(-1, 1, (50,))))
    eps = rng.uniform(0, 1, (40, 1))
    ref = pim.solve(case, eps, 0.7, backend="numpy")
    fast = pim.solve(case, eps, 0.7, backend="numba")
    assert fast.velocity1.shape == shape + (2,) and fast.mu0.shape == shape
    assert fast.normal.shape == shape + (2,)
    for name in FIELDS + DERIVED:
        a, b = np.broadcast_arrays(getattr(fast, name), getattr(ref, name))
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=0, err_msg=name)


def test_fast_trig_variant_agrees_normwise():
    case, eps, beta = random_case(20_000, seed=6)
    ref = pim.solve(case, eps, beta, backend="numpy")
    fast = kernel.solve_case(case, eps, beta, APPROACH_TOLERANCE, SINGULAR_TOLERANCE,
                             fast_trig=True)
    for name in FIELDS:
        a, b = np.asarray(getattr(fast, name)), getattr(ref, name)
        ok = np.isfinite(b)
        assert np.max(np.abs(a[ok] - b[ok])) <= 1e-12 * np.max(np.abs(b[ok])), name
    np.testing.assert_array_equal(fast.approaching, ref.approaching)


def test_solve_offers_the_fast_trig_kernel():
    case, eps, beta = random_case(20_000, seed=7)
    ref = pim.solve(case, eps, beta, backend="numpy", fast_trig=True)   # ignored by numpy
    fast = pim.solve(case, eps, beta)
    assert fast.backend == "numba"      # the fast kernel is the default
    # mu0 = Pt0 / Pn0 is ill-conditioned where Pn0 -> 0: its parts (in FIELDS) are compared.
    for name in [f for f in FIELDS if f != "mu0"]:
        a, b = np.asarray(getattr(fast, name)), getattr(ref, name)
        ok = np.isfinite(b)
        assert np.max(np.abs(a[ok] - b[ok])) <= 1e-12 * np.max(np.abs(b[ok])), name
    np.testing.assert_array_equal(fast.approaching, ref.approaching)


def test_fast_sine_cosine_within_one_ulp():
    x = np.concatenate([np.linspace(-10, 10, 200_001), np.pi / 4 * np.arange(-400, 400),
                        [0.0, -0.0, 1e-300, 3e-9, kernel.TRIG_LIMIT]])
    sin_x, cos_x = _sincos_array(x)
    np.testing.assert_array_max_ulp(sin_x, np.sin(x), maxulp=1)
    np.testing.assert_array_max_ulp(cos_x, np.cos(x), maxulp=1)


def _sincos_array(x):
    from numba import njit

    @njit
    def run(x, s, c):
        for i in range(x.size):
            s[i], c[i] = kernel._sincos(x[i])

    s, c = np.empty_like(x), np.empty_like(x)
    run(x, s, c)
    return s, c


def test_scalar_loop_kernels_compile_once_for_every_input_layout():
    """Arrays, scalars broadcast as stride-0 views, an obstacle (scalar mass and velocity):
    one compiled version each of the library-trig and full-pass kernels (a compilation costs
    5-20 s; numba used to compile one per mix of contiguous and stride-0 inputs)."""
    case, eps, beta = random_case(50, seed=30)
    obstacle = pim.Case(case.vehicle1, pim.Vehicle.obstacle(cg=(1.0, 0.0)), case.impact)
    for scene in (case, obstacle):
        for e, b in ((eps, beta), (0.3, 0.8)):
            inputs = kernel.case_inputs(scene, e, b)
            ref = pim.solve(scene, e, b, backend="numpy")
            for fast_trig in (False, True):
                out = kernel.solve_arrays(inputs, APPROACH_TOLERANCE, SINGULAR_TOLERANCE,
                                          full=True, fast_trig=fast_trig)
                np.testing.assert_allclose(out["k_nt"], ref.k_nt, rtol=1e-12, atol=0)
    for dispatcher in (kernel._solve_kernel_libm, kernel._solve_kernel_fast):
        assert len(dispatcher.signatures) == 1, dispatcher.signatures


def test_huge_angles_fall_back_to_library_trig():
    case, eps, beta = random_case(1000, seed=7)
    far = pim.Case(case.vehicle1, case.vehicle2,
                   pim.Impact(case.impact.point, case.impact.normal_angle + 2e7))
    ref = pim.solve(far, eps, beta, backend="numpy")
    fast = kernel.solve_case(far, eps, beta, APPROACH_TOLERANCE, SINGULAR_TOLERANCE,
                             fast_trig=True)
    np.testing.assert_array_equal(fast.velocity1, ref.velocity1)


def test_bad_eps_and_beta_raise_like_the_numpy_path():
    case, eps, beta = random_case(100, seed=8)
    bad = eps.copy()
    bad[7] = 1.5
    with pytest.raises(ValueError, match="eps"):
        pim.solve(case, bad, beta, backend="numba")
    bad[7] = np.nan
    with pytest.raises(ValueError, match="eps"):
        pim.solve(case, bad, beta, backend="numba")
    bad_beta = beta.copy()
    bad_beta[3] = np.inf
    with pytest.raises(ValueError, match="beta"):
        pim.solve(case, eps, bad_beta, backend="numba")


def test_auxiliary_fields_are_lazy_and_results_pickle():
    case, eps, beta = random_case(1000, seed=9)
    fast = pim.solve(case, eps, beta, backend="numba")
    assert "k_nn" not in fast.__dict__ and "mu0" in fast.__dict__
    _ = fast.delta_v1_magnitude, fast.kinetic_energy_after  # need only core fields
    assert "k_nn" not in fast.__dict__
    _ = fast.approach_n
    assert "k_nn" in fast.__dict__ and fast.normal.flags.writeable is False
    back = pickle.loads(pickle.dumps(fast))
    assert type(back) is pim.Result
    np.testing.assert_array_equal(back.velocity1, fast.velocity1)


def test_stream_copy_writes_every_output():
    case, eps, beta = random_case(1000, seed=10)
    inputs = kernel.case_inputs(case, eps, beta)
    core = kernel.stream_copy(inputs)
    full = kernel.stream_copy(inputs, full=True)
    x = sum(np.asarray(v, float).reshape(1000, -1).sum(axis=1) for v in inputs.values())
    np.testing.assert_allclose(core["mu0"], x, rtol=1e-12)
    np.testing.assert_allclose(full["k_tt"], x, rtol=1e-12)


def test_numba_cache_key_covers_the_formula():
    """numba keys its cache on kernel.py alone; ours adds formula.py's hash (a stale kernel
    after an edit of the formula would silently disagree with the numpy path)."""
    import hashlib
    from pathlib import Path

    from pim.model import formula

    digest = hashlib.sha256(Path(formula.__file__).read_bytes()).hexdigest()
    for dispatcher in (kernel._solve_kernel_libm, kernel._solve_kernel_fast,
                       kernel._copy_kernel):
        stamp = cache_stamp(dispatcher)
        assert stamp[1] == digest
        assert stamp[0]  # numba's own stamp of kernel.py is still part of the key


_STALE_SCRIPT = """
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
import pim
assert pim.__file__.startswith(sys.argv[1]), pim.__file__
rng = np.random.default_rng(0)
n = 2000
def vehicle():
    return pim.Vehicle(rng.uniform(500, 3000, n), rng.uniform(800, 4000, n),
                       rng.uniform(-3, 3, (n, 2)), rng.uniform(-30, 30, (n, 2)),
                       rng.uniform(-3, 3, n))
case = pim.Case(vehicle(), vehicle(), pim.Impact(rng.uniform(-2, 2, (n, 2)),
                                                  rng.uniform(-3, 3, n)))
a = pim.solve(case, 0.3, 0.8, backend="numpy")
b = pim.solve(case, 0.3, 0.8, backend="numba")
print(np.array_equal(a.velocity1, b.velocity1, equal_nan=True), float(a.velocity1[0, 0]))
"""


@pytest.mark.slow
def test_editing_the_formula_recompiles_the_kernel(tmp_path):
    """End to end: a copy of pim, solved, then its formula edited and solved again in a new
    process: the kernel must follow the edit (it did not with numba's cache=True)."""
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    root = Path(pim.__file__).parent
    shutil.copytree(root, tmp_path / "pim", ignore=shutil.ignore_patterns("__pycache__"))
    script = tmp_path / "run.py"
    script.write_text(_STALE_SCRIPT)

    def run():
        out = subprocess.run([sys.executable, str(script), str(tmp_path)], check=True,
                             capture_output=True, text=True, timeout=600).stdout.split()
        return out[0] == "True", float(out[1])

    same, before = run()
    assert same
    path = tmp_path / "pim" / "model" / "formula.py"
    text = path.read_text()
    assert text.count("e1 = 1.0 + eps") == 1
    path.write_text(text.replace("e1 = 1.0 + eps", "e1 = 1.0 + 0.5 * eps"))
    same, after = run()
    assert same and after != before


@pytest.mark.parametrize("fixed", [False, True])
def test_vectorised_kernel_equals_the_scalar_kernel_bitwise(fixed):
    """fast_trig's core outputs come from the SIMD block kernel; the auxiliary fields from the
    scalar kernel (_case): the same formula and operations, so every field agrees bitwise,
    across block boundaries (n not a multiple of BLOCK), for separating scenes, obstacles and
    singular q."""
    n = 2 * kernel.BLOCK + 123
    case, eps, beta = random_case(n, seed=12 + fixed, fixed=fixed)
    ref1 = pim.solve(case, eps, 1.0, backend="numpy")
    singular_beta = -(ref1.k_nn * ref1.critical_impulse_n) / (ref1.k_nt * ref1.critical_impulse_t)
    beta = np.where(np.arange(n) % 5 == 0, np.nan_to_num(singular_beta, nan=0.5), beta)
    inputs = kernel.case_inputs(case, eps, beta)
    simd = kernel.solve_arrays(inputs, APPROACH_TOLERANCE, SINGULAR_TOLERANCE, fast_trig=True)
    args = kernel.flatten_inputs(inputs, (n,))
    out = kernel.allocate(n, False)
    kernel.scalar_kernel(kernel._solve_kernel_fast)(*args, APPROACH_TOLERANCE,
                                                    SINGULAR_TOLERANCE, False, *out)
    scalar = dict(zip(kernel.CORE_VECTORS, out[0], strict=True))
    scalar.update(zip(kernel.CORE_SCALARS, out[1], strict=True))
    scalar.update(approaching=out[2], q_singular=out[3])
    for name, value in scalar.items():
        np.testing.assert_array_equal(simd[name], value, err_msg=name)
    assert simd["q_singular"].sum() > 100 and 0.2 < simd["approaching"].mean() < 0.8
    assert simd["approaching"].dtype == bool and simd["q_singular"].dtype == bool
    fast = pim.solve(case, eps, beta, backend="numba", fast_trig=True)
    ref = pim.solve(case, eps, beta, backend="numpy")
    np.testing.assert_array_equal(fast.q_singular, ref.q_singular)
    np.testing.assert_array_equal(fast.approaching, ref.approaching)
    # core (SIMD pass) and auxiliary (scalar pass) fields describe the same impulse
    p = fast.impulse_n[..., None] * fast.normal + fast.impulse_t[..., None] * fast.tangent
    ok = ~fast.q_singular
    np.testing.assert_array_equal(p[ok], fast.impulse[ok])


def test_vectorised_kernel_with_broadcast_inputs():
    """Scalar and (2,) inputs (stride-0 views, flattened by copy) give the numpy path's values."""
    rng = np.random.default_rng(14)
    shape = (30, 700)
    v1 = pim.Vehicle(1500.0, 2500.0, (1.5, 0.2), rng.uniform(-20, 20, shape + (2,)),
                     rng.uniform(-1, 1, shape))
    v2 = pim.Vehicle(1200.0, 2100.0, (-1.0, 0.3), (3.0, -4.0), 0.2)
    case = pim.Case(v1, v2, pim.Impact((0.0, 0.1), rng.uniform(-1, 1, (700,))))
    eps = rng.uniform(0, 1, (30, 1))
    ref = pim.solve(case, eps, 0.7, backend="numpy")
    fast = pim.solve(case, eps, 0.7, fast_trig=True)
    assert fast.backend == "numba" and fast.velocity1.shape == shape + (2,)
    for name in ("velocity1", "velocity2", "impulse", "yaw_rate1", "yaw_rate2"):
        a, b = np.broadcast_arrays(getattr(fast, name), getattr(ref, name))
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b)), name
    np.testing.assert_array_equal(fast.approaching, np.broadcast_to(ref.approaching, shape))


#: Outputs grouped by the quantities whose largest magnitude is their scale.
SCALES = {"velocity1": "velocity", "velocity2": "velocity", "approach_n": "velocity",
          "approach_t": "velocity", "yaw_rate1": "yaw", "yaw_rate2": "yaw",
          "impulse": "impulse", "impulse_n": "impulse", "impulse_t": "impulse",
          "critical_impulse_n": "impulse", "critical_impulse_t": "impulse",
          "k_nn": "k", "k_nt": "k", "k_tt": "k"}


def _mag(x):
    """Length of (..., 2) vectors."""
    x = np.asarray(x, float)
    return np.hypot(x[..., 0], x[..., 1])


def ulps_of_scale(fast, ref, case):
    """max |fast - numpy| per output in ulp of its scale times the condition number of q
    (the quantities of kernel.ULP_BOUND's note)."""
    a = ref.k_nn * ref.critical_impulse_n
    b = np.asarray(ref.beta) * ref.k_nt * ref.critical_impulse_t
    kappa = np.broadcast_to((np.abs(a) + np.abs(b)) / np.abs(a + b), np.shape(ref.impulse_n))
    pm = _mag(ref.impulse)
    groups = {
        "velocity": [_mag(ref.velocity1), _mag(ref.velocity2), _mag(case.vehicle1.velocity),
                     _mag(case.vehicle2.velocity), _mag(ref.approach_velocity)],
        "yaw": [np.abs(ref.yaw_rate1), np.abs(ref.yaw_rate2), np.abs(case.vehicle1.yaw_rate),
                np.abs(case.vehicle2.yaw_rate), _mag(ref.arm1) * pm / case.vehicle1.yaw_inertia,
                np.nan_to_num(_mag(ref.arm2) * pm / case.vehicle2.yaw_inertia)],
        "impulse": [pm, np.abs(ref.critical_impulse_n), np.abs(ref.critical_impulse_t)],
        "k": [np.abs(ref.k_nn), np.abs(ref.k_tt), np.abs(ref.k_nt)]}
    vectors = ("velocity1", "velocity2", "impulse")
    scale = {g: np.max(np.broadcast_arrays(*v), axis=0) for g, v in groups.items()}
    out = {}
    for name, group in SCALES.items():
        d = np.abs(np.asarray(getattr(fast, name)) - np.asarray(getattr(ref, name)))
        d = d.max(axis=-1) if name in vectors else d
        ok = np.isfinite(d) & np.isfinite(kappa) & (scale[group] > 0)
        ratio = d[ok] / np.spacing(scale[group][ok]) / kappa[ok]
        out[name] = float(ratio.max()) if ratio.size else 0.0
    return out


@pytest.mark.parametrize("fixed", [False, True])
def test_default_kernel_within_the_stated_ulp_bound_of_numpy(fixed):
    """The default (fast-trig) kernel against the numpy path on random scenes, singular q
    and separating scenes included: the only difference is sine and cosine (1 ulp)."""
    case, eps, beta = random_case(100_000, seed=20 + fixed, fixed=fixed)
    ref = pim.solve(case, eps, beta, backend="numpy")
    fast = pim.solve(case, eps, beta)
    worst = ulps_of_scale(fast, ref, case)
    assert max(worst.values()) <= kernel.ULP_BOUND, worst
    assert 0 < max(worst.values())      # not bitwise: the bound is what is promised
    np.testing.assert_array_equal(fast.approaching, ref.approaching)
    np.testing.assert_array_equal(fast.q_singular, ref.q_singular)
    np.testing.assert_array_max_ulp(fast.normal, ref.normal, maxulp=1)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(1, 60), seed=st.integers(0, 2**32 - 1),
       mass_scale=st.floats(1e-2, 1e5), speed=st.floats(1e-3, 1e3),
       angle=st.floats(-1e4, 1e4), fixed=st.booleans())
def test_default_kernel_ulp_bound_over_hypothesis_inputs(n, seed, mass_scale, speed, angle,
                                                        fixed):
    rng = np.random.default_rng(seed)

    def vehicle():
        m = mass_scale * rng.uniform(0.2, 5, n)
        return pim.Vehicle(m, m * rng.uniform(0.5, 3, n) ** 2, rng.uniform(-3, 3, (n, 2)),
                           speed * rng.uniform(-1, 1, (n, 2)), speed * rng.uniform(-1, 1, n),
                           rng.uniform(-np.pi, np.pi, n))

    v2 = pim.Vehicle.obstacle(cg=rng.uniform(-3, 3, (n, 2))) if fixed else vehicle()
    case = pim.Case(vehicle(), v2, pim.Impact(rng.uniform(-2, 2, (n, 2)),
                                              angle + rng.uniform(-1, 1, n)))
    ref = pim.solve(case, 0.3, 0.8, backend="numpy")
    fast = pim.solve(case, 0.3, 0.8, backend="numba")
    worst = ulps_of_scale(fast, ref, case)
    assert max(worst.values()) <= kernel.ULP_BOUND, worst
    np.testing.assert_array_max_ulp(fast.normal, ref.normal, maxulp=1)
    np.testing.assert_array_equal(fast.q_singular, ref.q_singular)
