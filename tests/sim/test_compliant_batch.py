"""The compiled crush scene (engine="numba") against the pymunk scene and the reference.

Both engines run the functions of sim/compliant_formula.py and step them the same way
(Chipmunk's position update, the loads at the new positions, Chipmunk's velocity update,
same dt), from the same set-up (sim.compliant_setup.setup_arrays, whose cos and sin come
from the C library element by element, so a batch and each of its scenes alone get the same
bits): the same IEEE operations in the same order, sin, cos and sqrt from the same
library, no fast-math, no contraction. They agree to the last bit, and the tests say so: an
ulp of difference means an operation that differs between the engines (before sqrt replaced
hypot in the tally, numba's hypot and the C library's differed by an ulp in 5 of 140
scenes).
"""

import math
import time
from dataclasses import replace

import numpy as np
import pytest

import pim
import sim
from sim.batch import case_element
from sim.compliant_batch import STATUS_NAMES, CompliantBatch, contact_inputs
from sim.contact_law import stiffness_for_duration
from tests.scenes import random_cases

pytestmark = pytest.mark.xdist_group("compliant_kernel")
K = sim.DEFAULT_STIFFNESS
QUICK = sim.CompliantSettings(steps_per_contact=40, record=False)


def sample(n: int, seed: int, fixed: bool = False):
    """n random scenes and per-scene contact inputs (every input varies); with a fixed
    vehicle 2 the stiffness comes from a contact time and r is left at its default eps^2."""
    rng = np.random.default_rng(seed)
    case = random_cases(n, seed=seed, fixed=fixed)
    inputs = dict(
        eps=rng.uniform(0.0, 1.0, n),
        stiffness=10 ** rng.uniform(5, 6.7, n),
        friction=np.where(rng.random(n) < 0.25, 0.0, rng.uniform(0.0, 2.5, n)),
        tyre_friction=np.where(rng.random(n) < 0.3, 0.0, rng.uniform(0.1, 1.2, n)),
        tyre_mode=rng.choice(["rolling", "locked"], n),
        preload=np.where(rng.random(n) < 0.5, 0.0, rng.uniform(0.0, 5e4, n)),
        tangential_recovery=rng.uniform(0.0, 1.0, n))
    inputs["tangential_recovery"][rng.random(n) < 0.2] = 0.0
    if fixed:
        inputs["contact_time"] = rng.uniform(0.03, 0.2, n)
        del inputs["stiffness"], inputs["tangential_recovery"]
    return case, inputs


def pymunk_scene(case, inputs, i, settings=QUICK):
    """Scene i on the pymunk engine (its CompliantResult, or the failure's kind)."""
    one = {k: (v[i] if np.ndim(v) else v) for k, v in inputs.items()}
    try:
        return sim.simulate_compliant(case_element(case, i), one.pop("eps"),
                                      settings=settings, engine="pymunk", **one)
    except sim.SimulationError as err:
        return err.kind


def outputs(r) -> np.ndarray:
    return np.r_[r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2, r.contact_duration,
                 r.impulse, r.peak_force, r.peak_crush, r.permanent_crush, r.tyre_work,
                 r.stick_fraction, r.impact_point, r.impulse_normal, r.impact_point_body1,
                 r.impulse_normal_body2]


@pytest.mark.parametrize("fixed", [False, True])
def test_compiled_steps_as_pymunk_to_round_off_on_random_scenes(fixed):
    n = 200 if not fixed else 100
    case, inputs = sample(n, seed=11 if not fixed else 12, fixed=fixed)
    batch = sim.simulate_compliant(case, settings=QUICK, **inputs)
    assert isinstance(batch, CompliantBatch) and batch.shape == (n,)
    ran = 0
    for i in range(n):
        r = pymunk_scene(case, inputs, i)
        if isinstance(r, str):
            assert batch.status_name[i] == r, i
            assert np.isnan(batch.velocity1[i]).all()
            continue
        ran += 1
        assert batch.status[i] == 0, i
        got = outputs(batch.result(i))
        want = outputs(r)
        assert np.array_equal(got, want, equal_nan=True), (i, np.abs(got - want).max())
        assert batch.steps[i] == r.steps and batch.slip_reversed[i] == r.slip_reversed
        assert batch.energy_after[i] == r.energy_after
    assert ran >= n // 3      # the sample holds enough contacts (the rest do not approach)


def with_outlines(case: pim.Case, fixed_outline: bool = True) -> pim.Case:
    """``case`` with a 4.5 m x 1.8 m outline on each moving vehicle (the CG 0.3 m ahead of
    the middle on vehicle 1), and on a fixed vehicle 2 only when ``fixed_outline``."""
    v1 = replace(case.vehicle1, length=4.5, width=1.8, cg_to_front=2.55)
    v2 = case.vehicle2
    if fixed_outline or not np.all(v2.fixed):
        v2 = replace(v2, length=4.5, width=1.8)
    return replace(case, vehicle1=v1, vehicle2=v2)


@pytest.mark.parametrize("fixed, bare", [(False, False), (True, True), (True, False)])
def test_outline_contact_compiled_as_pymunk(fixed, bare):
    # the distributed contact (outline overlap, its centroid and separating axis, the start
    # found back along the free paths; a bare barrier's block) steps alike on both engines
    n = 40
    case, inputs = sample(n, seed=21 + fixed + bare, fixed=fixed)
    case = with_outlines(case, fixed_outline=not bare)
    batch = sim.simulate_compliant(case, geometry="outline", settings=QUICK, **inputs)
    ran = 0
    for i in range(n):
        one = {k: v[i] for k, v in inputs.items()}
        try:
            r = sim.simulate_compliant(case_element(case, i), one.pop("eps"),
                                       geometry="outline", settings=QUICK, engine="pymunk",
                                       **one)
        except sim.SimulationError as err:
            assert batch.status_name[i] == err.kind, i
            continue
        ran += 1
        assert batch.status[i] == 0, i
        got, want = outputs(batch.result(i)), outputs(r)
        assert np.array_equal(got, want, equal_nan=True), (i, np.abs(got - want).max())
        assert batch.contact_start[i] == r.contact_start and batch.steps[i] == r.steps
    assert ran >= n // 4


def test_outlines_passing_through_each_other_are_tunnelled():
    case = pim.load_case("hard-high-speed")
    batch = sim.simulate_compliant(case, 0.3, K, geometry="outline")
    assert batch.status_name == "tunnelled"
    with pytest.raises(ValueError, match="needs vehicle1.length"):
        sim.simulate_compliant(random_cases(2, seed=1), 0.3, K, geometry="outline")
    with pytest.raises(ValueError, match="geometry must be one of"):
        sim.simulate_compliant(pim.load_case("ricsac9"), 0.3, K, geometry="polygon")


def test_the_sample_covers_tyre_modes_friction_and_plastic_recovery():
    case, inputs = sample(200, seed=11)
    batch = sim.simulate_compliant(case, settings=QUICK, **inputs)
    ok = batch.ok
    assert (ok & batch.locked & (batch.tyre_friction > 0)).sum() > 10
    assert (ok & ~batch.locked & (batch.tyre_friction > 0)).sum() > 10
    assert (ok & (batch.tangential_recovery == 0) & (batch.friction > 0)).sum() > 5
    assert (ok & (batch.stick_fraction > 0.5)).sum() > 5 and (ok & batch.slip_reversed).any()


def test_both_engines_converge_to_the_solve_ivp_reference():
    # at the default 400 steps per contact both engines agree with the reference (DOP853,
    # rtol 1e-10) to 2e-4 m/s on RICSAC 9, as docs/contact-model.md's convergence table
    # has it for the pymunk scene (1e-5 or less)
    case = pim.load_case("ricsac9")
    settings = sim.CompliantSettings(record=False)
    for kw in (dict(friction=0.5), dict(friction=3.0, tangential_recovery=0.0),
               dict(tyre_friction=0.7, tyre_mode="locked")):
        mode = kw.pop("tyre_mode", None)
        rs = sim.CompliantSettings(record=False, rtol=1e-10, tyre_mode=mode or "rolling",
                                   tangential_recovery=kw.pop("tangential_recovery", None))
        ref = sim.reference_compliant(case, 0.355, K, settings=rs, **kw)
        batch = sim.simulate_compliant(case, 0.355, K, settings=settings, tyre_mode=mode,
                                       tangential_recovery=rs.tangential_recovery, **kw)
        stepped = sim.simulate_compliant(case, 0.355, K, settings=settings, engine="pymunk",
                                         tyre_mode=mode,
                                         tangential_recovery=rs.tangential_recovery, **kw)
        want = np.r_[ref.velocity1, ref.velocity2, ref.yaw_rate1, ref.yaw_rate2]
        for r in (batch, stepped):
            got = np.r_[r.velocity1, r.velocity2, r.yaw_rate1, r.yaw_rate2]
            assert np.abs(got - want).max() < 2e-4, kw


def test_inputs_broadcast_as_pim_solve_does():
    case = pim.load_case("ricsac9")
    eps = np.array([0.1, 0.355, 0.6])
    mu = np.array([[0.0], [0.5]])
    batch = sim.simulate_compliant(case, eps, K, friction=mu, settings=QUICK)
    assert batch.shape == (2, 3) and batch.velocity1.shape == (2, 3, 2)
    assert batch.yaw_rate2.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            one = sim.simulate_compliant(case, float(eps[j]), K, friction=float(mu[i, 0]),
                                         settings=QUICK)
            assert one.shape == ()
            assert np.array_equal(batch.velocity1[i, j], one.velocity1)
    # a batched case broadcast against per-scene eps
    cases = random_cases(4, seed=2)
    b = sim.simulate_compliant(cases, np.array([[0.2], [0.8]]), K, settings=QUICK)
    assert b.shape == (2, 4)
    assert np.array_equal(b.status[1], sim.simulate_compliant(cases, 0.8, K,
                                                              settings=QUICK).status)


def test_contact_time_sets_the_stiffness_per_scene():
    case = pim.load_case("ricsac9")
    batch = sim.simulate_compliant(case, 0.355, contact_time=np.array([0.05, 0.1, 0.2]),
                                   settings=QUICK)
    want = stiffness_for_duration(np.array([0.05, 0.1, 0.2]), batch.k_nn, 0.355)
    assert np.allclose(batch.stiffness, want, rtol=1e-15)
    # a point mass head on (K_nn constant): the contact lasts T
    head_on = sim.simulate_compliant(approaching_head_on(), 0.355,
                                     contact_time=np.array([0.05, 0.1, 0.2]))
    assert np.allclose(head_on.contact_duration, [0.05, 0.1, 0.2], rtol=1e-4)
    same = sim.simulate_compliant(case, 0.355, float(want[1]), settings=QUICK)
    assert np.array_equal(batch.velocity1[1], same.velocity1)
    pym = sim.simulate_compliant(case, 0.355, contact_time=0.1, settings=QUICK,
                                 engine="pymunk")
    assert np.array_equal(pym.velocity1, same.velocity1)


def approaching_head_on(speed=15.0):
    v1 = pim.Vehicle(1500.0, 2500.0, (-2.0, 0.0), (speed, 0.0))
    v2 = pim.Vehicle.obstacle()
    return pim.Case(v1, v2, pim.Impact(point=(0.0, 0.0), normal_angle=math.pi))


def test_each_status_code_where_it_belongs():
    case = approaching_head_on()
    away = approaching_head_on(-15.0)
    ok = sim.simulate_compliant(case, 0.3, K)
    assert ok.status == 0 and ok.ok and ok.failures() == {}
    no_contact = sim.simulate_compliant(away, 0.3, K)
    assert no_contact.status_name == "no_contact" and np.isnan(no_contact.velocity1).all()
    with pytest.raises(sim.SimulationError) as err:
        no_contact.result()
    assert err.value.kind == "no_contact"
    # a contact cut short before it can separate
    never = sim.simulate_compliant(case, 0.3, K, settings=sim.CompliantSettings(
        max_contact_time=0.01))
    assert never.status_name == "never_separated"
    never = sim.simulate_compliant(case, 0.3, K, settings=sim.CompliantSettings(
        max_fixed_steps=50))
    assert never.status_name == "never_separated"
    tunnelled = sim.simulate_compliant(case, 0.3, K, settings=sim.CompliantSettings(dt=1e-2))
    assert tunnelled.status_name == "tunnelled"
    # the same on pymunk, as exceptions
    for batch, settings in ((never, sim.CompliantSettings(max_fixed_steps=50)),
                            (tunnelled, sim.CompliantSettings(dt=1e-2))):
        with pytest.raises(sim.SimulationError) as err:
            sim.simulate_compliant(case, 0.3, K, settings=settings, engine="pymunk")
        assert err.value.kind == batch.status_name
    mixed = sim.simulate_compliant(case, 0.3, np.array([K, K * 0.05]),
                                   settings=sim.CompliantSettings(dt=2e-2))
    assert list(mixed.status_name) == ["tunnelled", "ok"]
    assert mixed.failures() == {"tunnelled": 1}
    assert set(STATUS_NAMES) - {"ok"} <= set(sim.FAILURE_KINDS)


@pytest.mark.parametrize("field, value, message", [
    ("eps", np.array([0.3, 1.2]), "eps must be finite, >= 0 and <= 1 .* 1.2 at index \\(1,\\)"),
    ("eps", "0.3", "eps must be a number"),
    ("stiffness", np.array([K, -1.0]), "stiffness must be finite, > 0 .*-1.0"),
    ("stiffness", np.nan, "stiffness must be finite"),
    ("friction", -0.1, "friction must be finite, >= 0"),
    ("tyre_friction", np.inf, "tyre_friction must be finite"),
    ("tyre_mode", np.array(["rolling", "skid"]), "tyre_mode must be one of .*'skid'"),
    ("preload", -1.0, "preload must be finite, >= 0"),
    ("tangential_recovery", 1.5, "tangential_recovery must be finite, >= 0 and <= 1"),
    ("contact_time", 0.0, "contact_time must be finite, > 0"),
])
def test_bad_input_names_the_field(field, value, message):
    args = dict(eps=0.3, stiffness=K)
    if field == "contact_time":
        args["stiffness"] = None
    args[field] = value
    with pytest.raises(ValueError, match=message):
        sim.simulate_compliant(pim.load_case("ricsac9"), **args)


def test_bad_combinations_are_refused():
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match="either stiffness .* or contact_time"):
        sim.simulate_compliant(case, 0.3)
    with pytest.raises(ValueError, match="either stiffness .* or contact_time"):
        sim.simulate_compliant(case, 0.3, K, contact_time=0.1)
    with pytest.raises(ValueError, match="do not broadcast"):
        sim.simulate_compliant(case, np.zeros(3) + 0.3, np.full(2, K))
    with pytest.raises(ValueError, match="engine must be one of"):
        sim.simulate_compliant(case, 0.3, K, engine="chipmunk")
    with pytest.raises(ValueError, match="settings must be a sim.CompliantSettings"):
        sim.simulate_compliant(case, 0.3, K, settings="fast")


def test_scalar_and_zero_d_inputs_are_one_scene():
    case = pim.load_case("ricsac9")
    a = sim.simulate_compliant(case, 0.355, K)
    b = sim.simulate_compliant(case, np.float64(0.355), np.array(K), friction=np.array(0.0))
    assert a.shape == b.shape == () and np.array_equal(a.velocity1, b.velocity1)
    assert contact_inputs(np.array(0.3), np.array(K), 0.0, 0.0,
                          sim.CompliantSettings())["stiffness"] == K


def test_a_warm_call_compiles_nothing_and_is_fast():
    from sim import compliant_kernel
    case = pim.load_case("ricsac9")
    sim.simulate_compliant(case, 0.355, K)                      # compiled or loaded
    sim.simulate_compliant(random_cases(40, seed=1), 0.3, K)     # the parallel kernel
    before = {k: len(d.overloads) for k, d in compliant_kernel.kernels().items()}
    start = time.perf_counter()
    for eps in np.linspace(0.1, 0.9, 20):
        sim.simulate_compliant(case, eps, K, friction=0.3, tyre_friction=0.5)
    per_call = (time.perf_counter() - start) / 20
    after = {k: len(d.overloads) for k, d in compliant_kernel.kernels().items()}
    assert after == before == {"serial": 1, "parallel": 1}
    assert per_call < 0.05        # milliseconds (a shared machine), never a compilation


def test_issue28_a_stiff_contact_with_a_long_free_motion_is_refused_up_front():
    # k = 1e15 N/m steps at 3.75e-9 s: 1 s of free motion would be 2.7e8 pymunk steps (the
    # old code ran past 60 s); the step count is now fixed before the run and refused
    case = pim.load_case("ricsac9")
    settings = sim.CompliantSettings(duration=1.0)
    start = time.perf_counter()
    with pytest.raises(ValueError, match="settings.duration = 1 s .* settings.max_fixed_steps"):
        sim.simulate_compliant(case, 0.3, stiffness=1e15, settings=settings, engine="pymunk")
    assert time.perf_counter() - start < 5.0
    # the compiled engine steps the contact only (no free motion): bounded, and it runs
    stiff = sim.simulate_compliant(case, 0.3, stiffness=1e15, settings=settings)
    assert stiff.ok and stiff.steps <= settings.max_fixed_steps


def test_issue28_zero_d_arrays_are_numbers():
    case = pim.load_case("ricsac9")
    plain = sim.simulate_compliant(case, 0.3, 7.5e5, engine="pymunk", settings=QUICK)
    arrays = sim.simulate_compliant(case, np.array(0.3), stiffness=np.array(7.5e5),
                                    friction=np.array(0.0), engine="pymunk", settings=QUICK)
    assert np.array_equal(plain.velocity1, arrays.velocity1)
    with pytest.raises(ValueError, match="stiffness must be a number"):
        sim.simulate_compliant(case, 0.3, np.array([7.5e5]), engine="pymunk")


def test_a_batch_is_set_up_as_each_of_its_scenes_alone():
    # the engines agree bitwise only if a scene's parameters do not depend on the batch it
    # is in: numpy's vectorised cos/sin and its power of a 0-d array (x ** 2 against x * x)
    # differed by an ulp between a long array and one element
    from sim.compliant_setup import setup_arrays
    from sim.contact_law import tangential_recovery_default
    rng = np.random.default_rng(5)
    case = random_cases(300, seed=5)
    arrays = setup_arrays(case, (300,), 9.80665)
    eps, time_ = rng.uniform(0, 1, 300), rng.uniform(0.01, 0.3, 300)
    k = stiffness_for_duration(time_, arrays["k_nn"], eps)
    r = tangential_recovery_default(eps)
    for i in range(300):
        one = setup_arrays(case_element(case, i), (), 9.80665)
        for name in ("k_nn", "state0", "arm1", "arm2", "normal2", "wheels1", "loads1"):
            assert np.array_equal(one[name][0], arrays[name][i]), (name, i)
        assert float(stiffness_for_duration(float(time_[i]), float(one["k_nn"][0]),
                                            float(eps[i]))) == k[i], i
        assert float(tangential_recovery_default(float(eps[i]))) == r[i], i
    # a contact time and eps whose rate pi (1 + eps) / (2 T) = 30.706568948001884 the C
    # library's pow squares an ulp away from rate * rate (found by the benchmark's scenes)
    time_, eps = 0.056076606678265195, 0.09620843897031164
    batch = stiffness_for_duration(np.array([time_, 0.1]), np.array([1e-3, 1e-3]),
                                   np.array([eps, 0.3]))
    assert float(stiffness_for_duration(time_, 1e-3, eps)) == batch[0]


def test_a_case_is_set_up_once_for_repeated_calls():
    """The last four set-ups are kept by the case's identity (a functools.lru_cache, no
    module-level dict: issue 27 point 7); a kept set-up gives the same numbers as a fresh
    one, and an equal but other Case object is set up anew."""
    from sim import compliant_batch

    case = pim.load_case("ricsac9")
    compliant_batch._kept_setup.cache_clear()
    first = sim.simulate_compliant(case, 0.3, 2e6)
    again = sim.simulate_compliant(case, 0.3, 2e6)
    info = compliant_batch._kept_setup.cache_info()
    assert (info.hits, info.misses) == (1, 1)
    assert np.array_equal(first.rows, again.rows, equal_nan=True)
    sim.simulate_compliant(replace(case), 0.3, 2e6)
    assert compliant_batch._kept_setup.cache_info().misses == 2


# ---- the frozen contact geometry (settings.geometry_change=False; issue 34) ---------------
def _frozen(steps=400):
    return sim.CompliantSettings(record=False, steps_per_contact=steps,
                                 geometry_change=False)


@pytest.mark.parametrize("name", ["ricsac9", "hard-barrier"])
def test_the_frozen_frictionless_contact_is_pims_frictionless_impact(name):
    """Frozen geometry, no friction, no tyres: the contact is one degree of freedom along a
    fixed normal, and the crush hysteresis returns eps of the normal relative velocity at C
    exactly (docs/contact-model.md), so the outcome is Newton's frictionless impact, PIM
    with beta = 0 (pim.solve, an independent computation), to the integrator's second-order
    error (2e-5 m/s at 400 steps per contact), at any contact time. With the geometry
    turning and moving (the physics) a 0.25 s contact is not that impact."""
    case = pim.load_case(name)
    rigid = pim.solve(case, 0.3, 0.0)
    b = sim.simulate_compliant(case, 0.3, contact_time=np.array([0.01, 0.25]),
                               settings=_frozen())
    assert np.all(b.ok)
    for got, want in ((b.velocity1, rigid.velocity1), (b.velocity2, rigid.velocity2)):
        np.testing.assert_allclose(got, np.broadcast_to(want, got.shape), atol=1e-4)
    np.testing.assert_allclose(b.yaw_rate1, float(rigid.yaw_rate1), atol=2e-5)
    moving = sim.simulate_compliant(case, 0.3, contact_time=0.25,
                                    settings=replace(_frozen(), geometry_change=True))
    assert np.max(np.abs(moving.velocity1 - rigid.velocity1)) > 1e-2


def test_without_tyres_the_frozen_contact_does_not_depend_on_its_duration():
    """Frozen geometry and no external force: time scales out of the contact (every force
    scales with the stiffness, the steps with the duration), so friction, recovery and
    restitution give one outcome at 2 ms and at 250 ms; tyres (a force that does not scale)
    make it depend on the duration again."""
    case = pim.load_case("ricsac9")
    times = np.array([0.002, 0.05, 0.25])
    b = sim.simulate_compliant(case, 0.2, friction=0.8, contact_time=times,
                               settings=_frozen(20))
    np.testing.assert_allclose(b.velocity1, np.broadcast_to(b.velocity1[0], (3, 2)),
                               atol=1e-9)
    np.testing.assert_allclose(b.yaw_rate2, b.yaw_rate2[0], atol=1e-9)
    tyres = sim.simulate_compliant(case, 0.2, friction=0.8, tyre_friction=0.8,
                                   contact_time=times, settings=_frozen(20))
    assert abs(tyres.velocity1[2, 0] - tyres.velocity1[0, 0]) > 0.1


def test_the_frozen_geometry_is_refused_where_it_is_not_built():
    case = pim.load_case("ricsac9")
    with pytest.raises(ValueError, match="geometry_change"):
        sim.simulate_compliant(case, 0.2, contact_time=0.1, settings=_frozen(),
                               engine="pymunk")
    with pytest.raises(ValueError, match="geometry_change"):
        sim.reference_compliant(case, 0.2, 7.5e5, settings=_frozen())
    with pytest.raises(ValueError, match="geometry_change must be True or False"):
        sim.CompliantSettings(geometry_change=0)
# ---- physics kept: no ok result gains energy or lasts without end (issue 33 point 11) ----

def test_an_absurdly_soft_contact_is_refused_before_any_step():
    """stiffness 1e-300 N/m returned ok with 2e294 J gained and a 1.2e149 s contact, 1e-6
    N/m ok with 123 s of contact (the fault harness): both are refused up front, by the
    estimated duration, on both engines, with the reason."""
    from sim.compliant_setup import ESTIMATE_MARGIN
    from sim.failures import SimulationError

    case = pim.load_case("ricsac9")
    for k in (1e-300, 1e-6):
        batch = sim.simulate_compliant(case, 0.3, stiffness=k)
        assert not batch.ok and batch.status_name == "never_separated"
        assert np.isnan(batch.contact_duration) and np.isnan(batch.velocity1).all()
        with pytest.raises(SimulationError, match="never_separated|still pushed|estimated"):
            batch.result()
        with pytest.raises(SimulationError) as info:
            sim.simulate_compliant(case, 0.3, stiffness=k, engine="pymunk")
        assert info.value.kind == "never_separated"
        assert f"beyond {ESTIMATE_MARGIN:g} x settings.max_contact_time" in str(info.value)
    # a soft contact whose estimate lies within the margin still runs, and ends in time
    soft = sim.simulate_compliant(case, 0.3, stiffness=1e3)
    assert soft.ok and soft.contact_duration < soft.settings.max_contact_time


def test_a_contact_that_gains_energy_is_refused_never_ok():
    """An elastic contact stepped at 10 steps per contact gains energy on the step's error
    (old code: ok): refused as "energy_gained", NaN outputs, on both engines; the default
    step keeps it (within ENERGY_TOLERANCE)."""
    from sim.compliant_setup import ENERGY_TOLERANCE, CompliantSettings
    from sim.failures import SimulationError

    case = pim.load_case("ricsac9-brach")
    coarse = CompliantSettings(steps_per_contact=10)
    batch = sim.simulate_compliant(case, 1.0, stiffness=7.5e5, settings=coarse)
    assert batch.status_name == "energy_gained" and np.isnan(batch.velocity1).all()
    assert batch.failures() == {"energy_gained": 1}
    with pytest.raises(SimulationError) as info:
        sim.simulate_compliant(case, 1.0, stiffness=7.5e5, settings=coarse, engine="pymunk")
    assert info.value.kind == "energy_gained" and "kinetic energy rose" in str(info.value)
    fine = sim.simulate_compliant(case, 1.0, stiffness=7.5e5)
    assert fine.ok
    assert fine.energy_after <= fine.energy_before * (1 + ENERGY_TOLERANCE)


def test_physics_status_refuses_gain_and_overlong_contacts():
    from sim.compliant_setup import CompliantSettings, physics_status

    s = CompliantSettings()
    got = physics_status([100.0, 100.0, 100.0, 100.0], [99.0, 100.05, 101.0, np.nan],
                         [0.1, 0.1, 0.1, 0.1], s)
    assert [STATUS_NAMES[c] for c in got] == ["ok", "ok", "energy_gained", "energy_gained"]
    got = physics_status(100.0, 90.0, [0.5, 1.5, np.inf], s)
    assert [STATUS_NAMES[c] for c in got] == ["ok", "never_separated", "never_separated"]
