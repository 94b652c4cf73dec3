"""The analytic event (pim.event, pim.analysis.event): conservation through every impact, a
slide checked by hand, outlines that never pass through each other, RICSAC 9's secondary
contact, side slaps, the Monte Carlo's rest states against the single event."""

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pim
from pim.analysis.event import (
    WHEELBASE_PER_LENGTH,
    event_rest_many,
    event_vehicle,
    sliding_flags,
)
from pim.model.case import ImpactSpec
from pim.model.event_formula import CONTACT_TOLERANCE
from pim.model.geometry import outline_penetration
from pim.model.tyres import STANDARD_GRAVITY

L, W = 4.5, 1.8


def t_bone(v1_kmh=50.0, v2_kmh=10.0, along=-0.8, crush=0.3, eps=0.2, beta=1.0, impacts=()):
    """Vehicle 1 (heading +y) into the right side of vehicle 2 (heading +x, CG at the
    origin) at ``along`` [m] from its CG, outlines overlapping by ``crush`` [m]."""
    v1 = pim.Vehicle(1500.0, 2500.0, (along, -W / 2 - L / 2 + crush), (0.0, v1_kmh / 3.6), 0.0,
                     math.pi / 2, length=L, width=W)
    v2 = pim.Vehicle(1400.0, 2300.0, (0.0, 0.0), (v2_kmh / 3.6, 0.0), 0.0, 0.0, length=L,
                     width=W)
    return pim.Case(v1, v2, pim.Impact((along, -W / 2 + crush / 2), -math.pi / 2,
                                       restitution=eps, beta=beta), impacts=tuple(impacts))


def penetration_growth(ev) -> float:
    """The most the outlines' overlap depth grows [m] above its least value since the last
    impact, over every sample of the event (the outlines of a case may overlap at its
    impact configuration, by the crush; they may never run deeper into each other)."""
    outlines = [(t.position, t.heading, L, W, None) for t in ev.tracks]
    depth = np.maximum(outline_penetration(*outlines), 0.0)     # (< 0: a bound of the gap)
    starts = [int(np.searchsorted(ev.time, i.time, side="right")) for i in ev.impacts]
    worst = 0.0
    for a, b in zip(starts, starts[1:] + [len(depth)], strict=True):
        part = depth[a:b]
        if len(part):
            worst = max(worst, float(np.max(part - np.minimum.accumulate(part))))
    return worst


scenes = st.tuples(st.floats(20, 70), st.floats(0, 40), st.floats(-2.0, 2.0),
                   st.floats(0.05, 0.5), st.sampled_from([0.0, 0.7]))


@settings(max_examples=30, deadline=None)
@given(scenes)
def test_every_impact_conserves_momentum_and_loses_energy(scene):
    v1, v2, along, eps, mu = scene
    case = t_bone(v1, v2, along, eps=eps)
    ev = pim.event(case, tyre_friction=mu, approach=0.0)
    m = np.array([case.vehicle1.mass, case.vehicle2.mass])
    for imp in ev.impacts:
        dv = imp.delta_v
        scale = float(np.hypot(*imp.impulse)) + 1.0
        assert m[0] * dv[0] + m[1] * dv[1] == pytest.approx([0.0, 0.0], abs=1e-9 * scale)
        assert m[0] * dv[0] == pytest.approx(imp.impulse, abs=1e-9 * scale)
        assert imp.energy_loss >= -1e-9 * scale


@settings(max_examples=30, deadline=None)
@given(scenes)
def test_no_outlines_pass_through_each_other(scene):
    v1, v2, along, eps, mu = scene
    ev = pim.event(t_bone(v1, v2, along, eps=eps), tyre_friction=mu, approach=0.0)
    assert penetration_growth(ev) <= CONTACT_TOLERANCE + 2e-3


def test_single_impact_lets_the_outlines_pass_through():
    """The check above can fail: PIM's single impact, unwatched, runs vehicle 1 into
    vehicle 2 again (what the event's further impacts prevent)."""
    for along in (-0.8, 1.2):            # a re-contact after parting; one within the crush
        case = t_bone(along=along)
        assert penetration_growth(pim.event(case, single_impact=True)) > 0.3
        assert penetration_growth(pim.event(case)) <= CONTACT_TOLERANCE + 2e-3


def test_a_side_slap_is_a_second_impact():
    ev = pim.event(t_bone(along=-0.8))           # tyres: DEFAULT_TYRE_FRICTION
    assert len(ev.impacts) == 2
    first, second = ev.impacts
    assert (first.source, second.source) == ("case", "outlines")
    assert 0.3 < second.time < 0.9
    assert second.law == "brach-capped"
    assert second.coefficients["eps"] == pytest.approx(0.1)
    assert second.coefficients["mu_c"] == pytest.approx(0.5)
    assert list(ev.phase).count("impact 2") == 1
    assert all(ev.stopped) and ev.phase[-1] == "rest"
    assert np.isfinite(second.pdof).all()


def test_straight_slide_ends_at_v2_over_2_mu_g():
    """A car strikes a barrier square on, its CG on the line of C: PIM returns it straight
    back at eps v (Brach's law, beta 1, no yaw); on four locked wheels it slides
    (eps v)^2 / (2 mu g) = 5^2 / (2 0.7 9.80665) = 1.8209 m (by hand)."""
    car = pim.Vehicle(1500.0, 2500.0, (0.0, 0.0), (10.0, 0.0), 0.0, 0.0, length=L, width=W)
    wall = pim.Vehicle.obstacle(cg=(L / 2 + 0.5 - 0.05, 0.0), heading=0.0, length=1.0,
                                width=20.0)
    case = pim.Case(car, wall, pim.Impact((L / 2, 0.0), math.pi, restitution=0.5, beta=1.0))
    ev = pim.event(case, tyre_friction=0.7)
    assert len(ev.impacts) == 1
    slide = 25.0 / (2 * 0.7 * STANDARD_GRAVITY)
    assert slide == pytest.approx(1.8209, abs=1e-4)
    assert ev.rest_position[0] == pytest.approx([-slide, 0.0], abs=5e-3)
    assert ev.rest_position[1] == pytest.approx(wall.cg)
    assert ev.vehicle1.sliding[len(ev.time) // 2:].any()


def test_ricsac9_free_motion_second_impact_near_044_s():
    """RICSAC 9 (the design sheet's case) without tyres: vehicle 1's left side runs into
    vehicle 2's rear right at 0.44 s (pim compare's warning, the pymunk overlap-area watch);
    the event solves it as a second impact. With the default tyres (0.7) there is none."""
    case = pim.load_case("ricsac9")
    free = pim.event(case, tyre_friction=0.0)
    assert [i.source for i in free.impacts] == ["case", "outlines"]
    assert free.impacts[1].time == pytest.approx(0.44, abs=0.04)
    assert not any(free.stopped)
    assert penetration_growth_of(case, free) <= CONTACT_TOLERANCE + 2e-3
    tyres = pim.event(case)
    assert len(tyres.impacts) == 1 and all(tyres.stopped)


def penetration_growth_of(case, ev) -> float:
    outlines = [(t.position, t.heading, v.length, v.width, v.cg_to_front)
                for t, v in zip(ev.tracks, (case.vehicle1, case.vehicle2), strict=True)]
    depth = np.maximum(outline_penetration(*outlines), 0.0)
    after = ev.time >= ev.impacts[-1].time
    part = depth[after]
    return float(np.max(part - np.minimum.accumulate(part)))


def test_monte_carlo_rest_states_are_the_single_events():
    """The kernel's own further impacts (event_rest_many) and pim.solve's (pim.event) give
    the same rest states, for a side slap and for RICSAC 9 without tyres."""
    for case, mu in ((t_bone(along=-0.8), None), (pim.load_case("ricsac9"), 0.0)):
        ev = pim.event(case, tyre_friction=mu)
        res = pim.solve(case)
        vel = np.stack([res.velocity1, res.velocity2])[None].repeat(3, 0)
        w = np.array([[float(res.yaw_rate1), float(res.yaw_rate2)]] * 3)
        many = event_rest_many(case, vel, w, tyre_friction=mu)
        assert (many.impacts == len(ev.impacts) - 1).all() and many.ok.all()
        assert many.rest_position[0] == pytest.approx(ev.rest_position, abs=1e-6)
        assert many.first_time[0] == pytest.approx(ev.impacts[1].time, abs=1e-9)


LAWS = {"brach": ImpactSpec(law="brach", restitution=0.3, beta=0.6),
        "brach-capped": ImpactSpec(law="brach-capped", restitution=0.2, beta=1.0,
                                   contact_friction=0.3),
        "kudlich-slibar": ImpactSpec(law="kudlich-slibar", restitution=0.2,
                                     contact_friction=0.4)}


@pytest.mark.parametrize("law", sorted(LAWS))
def test_monte_carlo_and_single_event_agree_under_each_law(law):
    """event_rest_many (the Monte Carlo's kernel) and pim.event give the same further
    impacts under every law [[impacts]] may name, Kudlich-Slibar's included: their count,
    the first one's time and the rest states they lead to."""
    case = t_bone(along=-0.8, impacts=[LAWS[law]])
    ev = pim.event(case)
    assert len(ev.impacts) >= 2 and {i.law for i in ev.impacts[1:]} == {law}
    res = pim.solve(case)
    many = event_rest_many(case, np.stack([res.velocity1, res.velocity2])[None],
                           [[float(res.yaw_rate1), float(res.yaw_rate2)]])
    assert many.ok.all() and many.impacts[0] == len(ev.impacts) - 1
    assert many.first_time[0] == ev.impacts[1].time
    assert many.rest_position[0] == pytest.approx(ev.rest_position, abs=1e-9)
    assert many.rest_heading[0] == pytest.approx(ev.rest_heading, abs=1e-9)


@pytest.mark.parametrize("law", sorted(LAWS))
def test_each_further_impact_is_pim_solve_at_its_contact(law):
    """The records the kernel's rows give are pim.solve's answer (the library's law, its own
    arithmetic) for the case of both vehicles as the event has them just before the impact,
    at its C and Gamma; the first impact is pim.solve(case) itself."""
    case = t_bone(along=-0.8, impacts=[LAWS[law]])
    ev = pim.event(case)
    assert ev.impacts[0].impulse == pytest.approx(np.asarray(pim.solve(case).impulse))
    spec = LAWS[law]
    for imp in ev.impacts[1:]:
        k = int(np.flatnonzero(ev.time == imp.time)[0])      # the row just before it
        vehicles = [replace(v, cg=t.position[k], heading=float(t.heading[k]),
                            velocity=imp.velocity_before[i], yaw_rate=imp.yaw_rate_before[i])
                    for i, (v, t) in enumerate(zip((case.vehicle1, case.vehicle2), ev.tracks))]
        assert vehicles[0].velocity == pytest.approx(ev.vehicle1.velocity[k])
        impact = pim.Impact(imp.point, imp.normal_angle, restitution=spec.restitution,
                            beta=spec.beta, law=law, contact_friction=spec.contact_friction)
        ref = pim.solve(pim.Case(*vehicles, impact))
        if law != "kudlich-slibar" and float(ref.energy_loss) < 0:   # solved frictionless
            ref = pim.solve(pim.Case(*vehicles, replace(impact, beta=0.0)))
        scale = 1e-9 * (1 + float(np.hypot(*ref.impulse)))
        assert imp.impulse == pytest.approx(np.asarray(ref.impulse), abs=scale)
        assert imp.velocity_after == pytest.approx(
            np.stack([ref.velocity1, ref.velocity2]), abs=1e-9)
        assert imp.energy_loss == pytest.approx(float(ref.energy_loss), rel=1e-9, abs=1e-6)
        assert ev.vehicle1.velocity[k + 1] == pytest.approx(imp.velocity_after[0])


def test_one_kernel_call_and_one_solve_per_event(monkeypatch):
    """The whole run-out, every further impact included, is one call of the compiled
    kernel; pim.solve runs once (the first impact), never per further impact."""
    from pim.analysis import event as module
    from pim.model import event_kernel

    calls = {"kernel": 0, "solve": 0}

    def counted(name, function):
        def run(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)
        return run

    monkeypatch.setattr(event_kernel, "run_event", counted("kernel", event_kernel.run_event))
    monkeypatch.setattr(module, "solve", counted("solve", module.solve))
    ev = pim.event(t_bone(along=-0.8, impacts=[LAWS["kudlich-slibar"]]))
    assert len(ev.impacts) >= 2
    assert calls == {"kernel": 1, "solve": 1}


def test_a_record_too_short_is_run_again_longer(monkeypatch):
    """Steps shrunk near contact may fill the kernel's record: the event runs again with a
    longer one and is the same event."""
    from pim.model import event_kernel

    case = t_bone(along=-0.8)
    expected = pim.event(case)
    real, sizes = event_kernel.run_event, []

    def short_first(*args, **kwargs):
        sizes.append(kwargs["record"])
        if len(sizes) == 1:
            kwargs["record"] = 20
        return real(*args, **kwargs)

    monkeypatch.setattr(event_kernel, "run_event", short_first)
    ev = pim.event(case)
    assert len(sizes) == 2 and sizes[1] > sizes[0]
    assert np.array_equal(ev.time, expected.time)
    assert np.array_equal(ev.vehicle2.position, expected.vehicle2.position)
    assert [i.time for i in ev.impacts] == [i.time for i in expected.impacts]


def test_given_c_and_gamma_of_a_further_impact_are_used():
    spec = ImpactSpec(law="brach", restitution=0.2, beta=0.5, point=(-0.5, 1.0),
                      normal_angle=3.0)
    second = pim.event(t_bone(along=-0.8, impacts=[spec])).impacts[1]
    assert second.point == pytest.approx([-0.5, 1.0]) and second.normal_angle == 3.0
    assert second.coefficients == {"eps": 0.2, "beta": 0.5}


def test_a_contact_without_end_is_refused_by_both():
    """A generated side slap near the struck car's front corner, slow (6.1 m/s into
    6.3 m/s): the cars stay in contact, impact after impact; pim.event refuses it, naming
    why, and the Monte Carlo's kernel marks the same sample not ok after as many."""
    from sim.event_check import side_slap_case

    case = side_slap_case(2.07, speed1=6.07, speed2=6.25, eps=0.238, beta=0.391)
    with pytest.raises(pim.InputError, match="more than 12 impacts after the first"):
        pim.event(case)
    res = pim.solve(case)
    many = event_rest_many(case, np.stack([res.velocity1, res.velocity2])[None],
                           [[float(res.yaw_rate1), float(res.yaw_rate2)]])
    assert not many.ok[0] and many.impacts[0] == 12


def test_impacts_table_sets_the_further_impacts_law():
    spec = ImpactSpec(law="brach", restitution=0.5, beta=0.0)
    ev = pim.event(t_bone(along=-0.8, impacts=[spec]))
    second = ev.impacts[1]
    assert second.law == "brach"
    assert second.coefficients == {"eps": 0.5, "beta": 0.0}
    # beta 0: no tangential impulse, the impulse along the contact normal
    n = np.array([math.cos(second.normal_angle), math.sin(second.normal_angle)])
    assert abs(float(np.cross(n, second.impulse))) < 1e-9 * np.hypot(*second.impulse)


def test_approach_is_the_stated_motion_held_back():
    case = t_bone()
    ev = pim.event(case, approach=1.0)
    assert ev.approach_duration == pytest.approx(1.0)
    assert ev.phase[0] == "approach"
    start = ev.vehicle1.position[0]
    assert start == pytest.approx(np.asarray(case.vehicle1.cg) - np.asarray(
        case.vehicle1.velocity))


def test_default_wheelbase_from_the_outline():
    rv = event_vehicle(t_bone().vehicle1, None, None, "vehicle1")
    assert rv.wheelbase == pytest.approx(WHEELBASE_PER_LENGTH * L)
    assert rv.friction == pytest.approx(0.7)
    assert rv.cg_to_front_axle == pytest.approx(rv.wheelbase / 2)


def test_sliding_flags_follow_the_slip():
    rv = event_vehicle(t_bone().vehicle1, None, None, "vehicle1")
    states = np.array([[0, 0, 0, 5.0, 0, 0], [0, 0, 0, 0.01, 0, 0]])
    assert sliding_flags(states, rv).tolist() == [[True] * 4, [False] * 4]
    assert not sliding_flags(states, rv, friction=0.0).any()


@pytest.mark.parametrize("name", ["side-slap", "hard-barrier", "synthetic-runout"])
def test_an_events_sliding_flags_are_the_slip_formula_on_its_states(name):
    """pim.event's wheels' flags (compiled, from the run-out's first sample on) are
    sliding_flags' (numpy, the same formula) on the event's own states: none in the
    approach, none for a fixed obstacle, and on a side slap both some and not all."""
    from sim.event_check import side_slap_case

    case = side_slap_case(1.6) if name == "side-slap" else pim.load_case(name)
    ev = pim.event(case)
    start = int(np.searchsorted(ev.time, 0.0)) + 1    # the run-out's first row (after t=0's)
    ev_data = case.evidence
    for i, (vehicle, track) in enumerate(zip((case.vehicle1, case.vehicle2), ev.tracks)):
        assert not track.sliding[:start].any()
        if vehicle.fixed:
            assert not track.sliding.any()
            continue
        rv = event_vehicle(vehicle, None if ev_data is None else getattr(
            ev_data, f"vehicle{i + 1}"), None, f"vehicle{i + 1}")
        states = np.column_stack([track.position, track.heading, track.velocity,
                                  track.yaw_rate])[start:]
        assert np.array_equal(track.sliding[start:], sliding_flags(states, rv))
    if name == "side-slap":
        flags = ev.vehicle1.sliding[start:]
        assert flags.any() and not flags.all()


@pytest.mark.parametrize("kwargs, match", [({"approach": -1.0}, "approach"),
                                           ({"tyre_friction": -0.1}, "tyre_friction"),
                                           ({"max_time": 0.0}, "max_time"),
                                           ({"tyre_friction": "0.7"}, "tyre_friction"),
                                           ({"tyre_friction": [0.7]}, "tyre_friction"),
                                           ({"approach": "1 s"}, "approach"),
                                           ({"max_time": True}, "max_time")])
def test_bad_options_name_the_field(kwargs, match):
    with pytest.raises(pim.InputError, match=match):
        pim.event(t_bone(), **kwargs)


def test_an_outline_is_required():
    case = pim.load_case("ricsac9")
    bare = pim.Case(pim.Vehicle(1500.0, 2500.0, (0.0, 0.0), (10.0, 0.0)), case.vehicle2,
                    case.impact)
    with pytest.raises(pim.InputError, match="vehicle1.length and width"):
        pim.event(bare)


def test_a_reconstruction_through_the_event_recovers_the_speeds():
    """Rest positions generated by the event at known post-impact motion (a T-bone with a
    side slap at 0.59 s): the single-impact run-out fits miss that motion (up to 0.47 rad/s
    and 0.27 m/s), the fit through the event recovers it within 0.1; the report names the
    re-contact."""
    from dataclasses import replace

    from pim.model.evidence import Evidence, VehicleEvidence

    case = t_bone(along=-0.8)
    res = pim.solve(case)
    truth = np.array([*res.velocity1, float(res.yaw_rate1), *res.velocity2,
                      float(res.yaw_rate2)])
    ev = pim.event(case)
    assert len(ev.impacts) == 2
    evidence = []
    for i in (1, 2):
        rv = event_vehicle(getattr(case, f"vehicle{i}"), None, None, f"vehicle{i}")
        evidence.append(VehicleEvidence(ev.rest_position[i - 1], float(ev.rest_heading[i - 1]),
                                        rv.wheelbase, rv.track, rv.cg_to_front_axle,
                                        rv.friction, position_sigma=0.05,
                                        heading_sigma=math.radians(1.0)))
    case = replace(case, evidence=Evidence(*evidence))
    post = pim.post_impact_motion(case)            # post.runouts: the single-impact fits
    got_single = np.array([*post.runouts[1].velocity, post.runouts[1].yaw_rate,
                           *post.runouts[2].velocity, post.runouts[2].yaw_rate])
    fit = post.event_fit
    got = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    assert np.max(np.abs(got_single - truth)) > 0.25
    assert np.max(np.abs(got - truth)) < 0.1
    assert fit.cost < 1e-6 and fit.impacts >= 1
    assert post.single_event_impacts >= 1
    assert any("fitted through the event" in m for m in post.messages)
    assert post.case.measured.velocity1 == pytest.approx(fit.velocity[0])


def test_the_event_after_a_given_motion_is_the_events_run_out():
    """event_after (a reconstruction's fitted motion carried through the further impacts)
    given PIM's post-impact motion is pim.event from the impact on: the same samples, the
    same further impacts; without a first record its impacts are the further ones."""
    from pim.analysis.event import event_after

    case = pim.load_case("ricsac9")
    r = pim.solve(case)
    full = pim.event(case, tyre_friction=0.0, approach=0.0)
    after = event_after(case, [r.velocity1, r.velocity2], [r.yaw_rate1, r.yaw_rate2],
                        tyre_friction=0.0, first=full.impacts[0])
    assert len(after.impacts) == len(full.impacts) == 2
    assert after.impacts[1].time == full.impacts[1].time
    np.testing.assert_array_equal(after.time, full.time[1:])
    for a, b in zip(after.tracks, full.tracks, strict=True):
        np.testing.assert_array_equal(a.position, b.position[1:])
    assert list(after.phase) == list(full.phase[1:])
    bare = event_after(case, [r.velocity1, r.velocity2], [r.yaw_rate1, r.yaw_rate2],
                       tyre_friction=0.0)
    assert [i.time for i in bare.impacts] == [full.impacts[1].time]
    with pytest.raises(pim.InputError, match="velocity must be"):
        event_after(case, [1.0, 2.0], [0.0, 0.0])


def _same_bits(a, b) -> bool:
    """``a`` and ``b`` (arrays or numbers) bitwise equal: shape, dtype and bytes (NaN too)."""
    if not isinstance(a, np.ndarray):
        return type(a) is type(b) and np.asarray(a).tobytes() == np.asarray(b).tobytes()
    return (isinstance(b, np.ndarray) and a.shape == b.shape and a.dtype == b.dtype
            and a.flags.c_contiguous == b.flags.c_contiguous and a.tobytes() == b.tobytes())


@pytest.mark.parametrize("name", ["ricsac9", "side-slap", "hard-barrier", "hard-pole",
                                  "synthetic-runout"])
@pytest.mark.parametrize("mu", [None, 0.0, 0.55])
def test_single_event_scene_is_the_generic_scene_bit_for_bit(name, mu):
    """The one-sample scene of a single event (pim.event's, RhsData.one, no broadcasting)
    holds the same arrays as the n-sample path's (RhsData.of) for one sample: RICSAC 9,
    the side slap, fixed obstacles, run-out evidence."""
    from sim.event_check import side_slap_case

    from pim.analysis.event import single_scene

    case = side_slap_case(1.6) if name == "side-slap" else pim.load_case(name)
    fast, generic = single_scene(case, mu), single_scene(case, mu, generic=True)
    fast_arrays = (*fast.kernel.vehicles[0], *fast.kernel.vehicles[1], *fast.kernel.arrays,
                   *fast.wheels, *fast.positions)
    generic_arrays = (*generic.kernel.vehicles[0], *generic.kernel.vehicles[1],
                      *generic.kernel.arrays, *generic.wheels, *generic.positions)
    assert len(fast_arrays) == len(generic_arrays) > 30
    bad = [k for k, (a, b) in enumerate(zip(fast_arrays, generic_arrays))
           if not _same_bits(a, b)]
    assert not bad, f"{name}: arrays {bad} differ"
    assert (fast.tyred, repr(fast.specs), fast.fixed) == (generic.tyred, repr(generic.specs),
                                                          generic.fixed)


def test_a_new_case_object_gets_a_new_scene(monkeypatch):
    """The scene is kept per case object (a case is frozen), never looked up by content: an
    equal new case object's is built anew."""
    import pim.analysis.event as module

    built = []
    original = module.single_scene
    monkeypatch.setattr(module, "single_scene",
                        lambda *a, **k: built.append(a[0]) or original(*a, **k))
    case = replace(pim.load_case("ricsac9"), name="kept scene")
    other = replace(case)
    pim.event(case)
    pim.event(case)
    pim.event(other)
    assert [c is case for c in built] == [True, False] and built[1] is other
