"""Reconstruction chain (pim.analysis.reconstruction): evidence -> post-impact motion ->
speeds by linear momentum, on the bundled synthetic case whose rest states the forward
models generated from known speeds (31.09 ft/s each, pim/io/cases/synthetic-runout.toml)."""

import time
from dataclasses import replace
from importlib import resources

import numpy as np
import pytest

import pim
from pim.analysis.reconstruction import approach_direction, post_impact_motion, reconstruct
from pim.model.numbers import InputError
from pim.model.runout import runout

KNOWN = 31.09 * 0.3048  # [m/s], both vehicles


@pytest.mark.slow
def test_synthetic_case_gives_back_the_known_motion_and_speeds():
    case = pim.load_case("synthetic-runout")
    truth = pim.solve(pim.load_case("ricsac9"), eps=0.355, beta=1.0)
    post = post_impact_motion(case)
    assert post.messages == []
    np.testing.assert_allclose(post.case.measured.velocity1, truth.velocity1, atol=1e-6)
    np.testing.assert_allclose(post.case.measured.velocity2, truth.velocity2, atol=1e-6)
    assert post.case.measured.yaw_rate1 == pytest.approx(float(truth.yaw_rate1), abs=1e-6)
    assert post.case.measured.yaw_rate2 == pytest.approx(float(truth.yaw_rate2), abs=1e-6)
    # linear momentum (exact for PIM) gives the speeds back
    assert post.momentum.speed1 == pytest.approx(KNOWN, abs=1e-6)
    assert post.momentum.speed2 == pytest.approx(KNOWN, abs=1e-6)
    # and the propagated interval covers them with room (sigma from 0.1 m, 2 deg evidence)
    assert 0 < post.momentum.sigma1 < 1.0 and 0 < post.momentum.sigma2 < 1.0


@pytest.mark.slow
def test_field_tyre_case_evidence_is_the_numpy_forward_models_and_gives_back_the_speeds():
    """pim/io/cases/synthetic-runout-field.toml: its rest states are the numpy brush run-out
    (TimedRhs, LSODA) from the known post-impact motion, and the chain (run-out inverse on
    the compiled right-hand side, inverse PIM) gives the known speeds back."""
    case = pim.load_case("synthetic-runout-field")
    truth = pim.solve(pim.load_case("ricsac9"), eps=0.355, beta=1.0)
    for i in (1, 2):
        vehicle, ev = getattr(case, f"vehicle{i}"), getattr(case.evidence, f"vehicle{i}")
        car = ev.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia))
        assert car.tyre_model == "brush"
        run = runout(car, vehicle.cg, float(vehicle.heading), getattr(truth, f"velocity{i}"),
                     float(getattr(truth, f"yaw_rate{i}")), rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(run.rest_position, ev.rest_position, atol=1e-7)
        assert run.rest_heading == pytest.approx(ev.rest_heading, abs=1e-7)
    rec = reconstruct(case)
    assert rec.determined and rec.messages == []
    assert {i: f.tyre_model for i, f in rec.post.runouts.items()} == {1: "brush", 2: "brush"}
    assert rec.values["vehicle1.speed"] == pytest.approx(KNOWN, abs=1e-5)
    assert rec.values["vehicle2.speed"] == pytest.approx(KNOWN, abs=1e-5)
    assert rec.values["impact.restitution"] == pytest.approx(0.355, abs=1e-5)


def test_a_case_without_evidence_is_refused():
    with pytest.raises(ValueError, match=r"\[evidence\]"):
        post_impact_motion(pim.load_case("ricsac9"))


def test_approach_direction_is_velocity_or_heading():
    case = pim.load_case("ricsac9")
    np.testing.assert_allclose(approach_direction(case.vehicle1), [-1.0, 0.0], atol=1e-12)
    parked = replace(case.vehicle2, velocity=np.zeros(2), heading=np.pi / 2)
    np.testing.assert_allclose(approach_direction(parked), [0.0, 1.0], atol=1e-12)


@pytest.mark.slow
def test_synthetic_case_inverse_pim_recovers_the_speeds_to_1e_6():
    """The whole chain without noise: rest evidence -> run-out inverse -> inverse PIM gives
    back the speeds (and eps) the evidence was generated with."""
    rec = reconstruct(pim.load_case("synthetic-runout"))
    assert rec.determined and rec.messages == []
    assert rec.values["vehicle1.speed"] == pytest.approx(KNOWN, abs=1e-6)
    assert rec.values["vehicle2.speed"] == pytest.approx(KNOWN, abs=1e-6)
    assert rec.values["impact.restitution"] == pytest.approx(0.355, abs=1e-6)
    assert rec.momentum.speed1 == pytest.approx(KNOWN, abs=1e-6)


def test_a_case_with_neither_evidence_nor_measured_motion_is_refused():
    case = replace(pim.load_case("ricsac9"), measured=None,
                   unknown={"vehicle1.speed": (0.0, 30.0)})
    with pytest.raises(ValueError, match=r"neither \[evidence\] nor \[measured\]"):
        reconstruct(case)


def test_goodness_of_fit_is_reported_and_inconsistency_said():
    """issue 17 item 6: with sigmas the reconstruction reports chi-square, dof and p, and a
    measured motion PIM cannot produce at its sigmas is said to be inconsistent."""
    base = pim.load_case("ricsac9-reconstruct")
    truth = pim.solve(base, 0.3, 0.9)
    unknown = {"vehicle1.speed": (0.0, 35.0), "vehicle2.speed": (0.0, 35.0)}
    case = replace(base, impact=replace(base.impact, restitution=0.3, beta=0.9),
                   measured=pim.Measured(
                       np.asarray(truth.velocity1) + [0.05, -0.05], truth.velocity2,
                       float(truth.yaw_rate1), float(truth.yaw_rate2),
                       velocity1_sigma=[0.1, 0.1], velocity2_sigma=[0.1, 0.1],
                       yaw_rate1_sigma=0.05, yaw_rate2_sigma=0.05))
    rec = reconstruct(case, unknown=unknown, samples=0)
    g = rec.goodness
    assert g is not None and g.dof == 6 - 2 and g.consistent
    assert not any("inconsistent" in m for m in rec.messages)
    bad = replace(case, measured=replace(case.measured, velocity1=np.asarray(
        truth.velocity1) + [3.0, -3.0]))
    rec = reconstruct(bad, unknown=unknown, samples=0)
    assert rec.goodness.consistent is False
    assert any("inconsistent with PIM at the stated sigmas" in m for m in rec.messages)
@pytest.mark.parametrize("old, new, words", [
    ('rest_position = ["0.44940861599726445 m", "2.804097342912324 m"]',
     'rest_position = ["1000.0 m", "2.8 m"]', ["evidence.vehicle1.rest_position", "beyond any run-out"]),
    ('wheels = ["locked", "locked", 0.3, 0.3]', 'wheels = "free"',
     ["evidence.vehicle1.wheels", "free-rolling"]),
])
def test_unreachable_or_never_stopping_evidence_is_answered_at_once(tmp_path, old, new, words):
    """Issue 22: wheels = 'free' or a rest position 1 km away ran pim reconstruct for over
    120 s with no word; now one InputError before any run-out fit."""
    text = (resources.files("pim.io") / "cases" / "synthetic-runout.toml").read_text()
    assert old in text
    path = tmp_path / "case.toml"
    path.write_text(text.replace(old, new, 1))
    case = pim.load_case(path)
    start = time.perf_counter()
    with pytest.raises(InputError) as info:
        post_impact_motion(case)
    assert time.perf_counter() - start < 1.0
    assert all(w in str(info.value) for w in words), str(info.value)


def test_progress_names_each_stage_in_order():
    """Issue 22: pim reconstruct ran for minutes with no word; the stages are now reported
    (and the result does not depend on it)."""
    from concurrent.futures import ThreadPoolExecutor

    case = pim.load_case("ricsac9-reconstruct")
    seen = []
    with ThreadPoolExecutor(2) as pool:
        rec = reconstruct(case, samples=60, seed=3, executor=pool, blocks=2,
                          progress=seen.append)
    assert seen == ["inverse PIM", "Monte Carlo", "Monte Carlo block 1/2",
                    "Monte Carlo block 2/2"]
    with ThreadPoolExecutor(2) as pool:
        quiet = reconstruct(case, samples=60, seed=3, executor=pool, blocks=2)
    assert rec.values == quiet.values
    assert rec.samples.stats == quiet.samples.stats


def test_the_command_shows_its_stages_on_request(capsys):
    from pim_cli.main import main

    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "50", "--progress"]) == 0
    err = capsys.readouterr().err
    assert "pim reconstruct" in err and "Monte Carlo" in err


# --- evidence other than rest positions (issue 19): RICSAC 9's scene solved forward at
# known speeds; each kind of evidence alone and together gives the speeds back ----------

S1, S2 = 9.5, 8.0
SPEEDS = {"vehicle1.speed": (0.0, 35.0), "vehicle2.speed": (0.0, 35.0)}


def _truth():
    from pim.io.casefile import load_case
    from pim.model.evidence_terms import EvidenceTerm, result_quantities

    case = load_case("ricsac9-reconstruct")
    case = replace(case, uncertainty=None,
                   vehicle1=replace(case.vehicle1, velocity=(-S1, 0.0)),
                   vehicle2=replace(case.vehicle2, velocity=(0.0, S2)),
                   impact=replace(case.impact, restitution=0.2, beta=0.8))
    res = pim.solve(case)
    q = result_quantities(res)
    dv = {i: [float(EvidenceTerm("delta_v", i, a).value(q)) for a in (0, 1)] for i in (1, 2)}
    return case, res, dv


def _evidence(kind):
    case, res, dv = _truth()
    sig = {"velocity1_sigma": [0.2, 0.2], "velocity2_sigma": [0.2, 0.2]}
    data = {
        "delta_v + pre-crash speed": dict(delta_v1=dv[1], delta_v1_sigma=[0.3, 0.3],
                                          pre_crash_speed2=S2, pre_crash_speed2_sigma=0.3),
        "delta_v of both": dict(delta_v1=dv[1], delta_v1_sigma=[0.3, 0.3], delta_v2=dv[2],
                                delta_v2_sigma=[0.3, 0.3], pre_crash_speed1=S1,
                                pre_crash_speed1_sigma=0.3),
        "energy + velocity": dict(velocity1=res.velocity1, velocity2=res.velocity2, **sig,
                                  energy_loss=float(res.energy_loss), energy_loss_sigma=4e3),
        "all": dict(velocity1=res.velocity1, velocity2=res.velocity2, **sig,
                    energy_loss=float(res.energy_loss), energy_loss_sigma=4e3,
                    delta_v1=dv[1], delta_v1_sigma=[0.3, 0.3], pre_crash_speed2=S2,
                    pre_crash_speed2_sigma=0.3),
    }[kind]
    return replace(case, measured=pim.Measured(**data))


@pytest.mark.parametrize("kind, unknown", [
    ("delta_v + pre-crash speed", SPEEDS),
    ("delta_v of both", SPEEDS),
    ("energy + velocity", {**SPEEDS, "impact.restitution": (0.0, 1.0)}),
    ("all", {**SPEEDS, "impact.restitution": (0.0, 1.0)})])
def test_each_kind_of_evidence_gives_back_the_known_speeds(kind, unknown):
    rec = reconstruct(_evidence(kind), unknown=unknown, samples=0)
    assert rec.determined, rec.messages
    assert rec.values["vehicle1.speed"] == pytest.approx(S1, abs=1e-5)
    assert rec.values["vehicle2.speed"] == pytest.approx(S2, abs=1e-5)
    if "impact.restitution" in unknown:
        assert rec.values["impact.restitution"] == pytest.approx(0.2, abs=1e-5)
    shares = rec.fit.evidence_shares
    for key in SPEEDS:      # each speed's variance is split over the evidence, summing to 1
        assert sum(shares[key].values()) == pytest.approx(1.0, abs=1e-9)


def test_the_recorder_under_reporting_moves_the_monte_carlo_up():
    """The recorder sees scale x the true delta-V with the scale in [0.88, 1] by default:
    the nominal speed takes the recording at face value, the Monte Carlo's median of
    vehicle 1's speed (whose delta-V drives it) lies above it."""
    rec = reconstruct(_evidence("delta_v + pre-crash speed"), unknown=SPEEDS, samples=300)
    st = rec.samples.stats["vehicle1.speed"]
    assert "measured.vehicle1.delta_v_scale" in rec.samples.varying
    assert st.p50 > S1 + 0.1 and st.p5 > S1 - 1.0
    assert "measured.vehicle1.delta_v_scale" in [d for d, _ in st.drivers[:2]]


def test_the_driving_evidence_is_named():
    """vehicle 2's speed from its recorded pre-crash speed, vehicle 1's from its delta-V."""
    rec = reconstruct(_evidence("delta_v + pre-crash speed"), unknown=SPEEDS, samples=0)
    sh = rec.fit.evidence_shares
    assert max(sh["vehicle1.speed"], key=sh["vehicle1.speed"].get) == "vehicle1 recorded delta-V"
    assert max(sh["vehicle2.speed"], key=sh["vehicle2.speed"].get) == \
        "vehicle2 recorded pre-crash speed"


def test_conflicting_evidence_names_the_terms_in_conflict():
    case = _evidence("all")
    m = replace(case.measured, pre_crash_speed2=S2 + 3.0)     # 10 sigma off
    rec = reconstruct(replace(case, measured=m), unknown=SPEEDS, samples=0)
    g = rec.goodness
    assert g.consistent is False and g.largest[0][0] == "pre_crash_speed2"
    assert "pre_crash_speed2" in g.summary()


def test_one_delta_v_alone_names_the_evidence_that_would_decide():
    _, _, dv = _truth()
    case = replace(_truth()[0], measured=pim.Measured(delta_v1=dv[1], delta_v1_sigma=[.3, .3]))
    rec = reconstruct(case, unknown={**SPEEDS, "impact.restitution": (0.0, 1.0)}, samples=0)
    assert not rec.determined
    msg = " ".join(rec.messages)
    assert "evidence that would decide it" in msg and "an energy loss (crush)" in msg
    assert "vehicle1's recorded pre-crash speed" in msg


def test_a_delta_v_beyond_every_speed_bound_is_refused():
    case = _evidence("delta_v + pre-crash speed")
    m = replace(case.measured, delta_v1=np.array([-60.0, 0.0]))
    with pytest.raises(InputError, match=r"measured.vehicle1.delta_v: .*larger than every "
                                         r"speed bound"):
        reconstruct(replace(case, measured=m), unknown=SPEEDS, samples=0)


def test_crush_profiles_and_a_pre_crash_speed_give_back_the_speeds():
    """synthetic-crush: crush profiles made so that each vehicle's corrected crush energy is
    half the true energy loss; with vehicle 2's recorded speed the speeds come back, and the
    Monte Carlo varies the named stiffness B."""
    from pim.io.casefile import load_case

    case = load_case("synthetic-crush")
    assert case.evidence.vehicle1 is None and case.evidence.crush1.side == "front"
    rec = reconstruct(case, samples=200)
    assert rec.determined, rec.messages
    assert rec.values["vehicle1.speed"] == pytest.approx(S1, abs=2e-3)
    assert rec.values["vehicle2.speed"] == pytest.approx(S2, abs=2e-3)
    assert max(rec.fit.evidence_shares["vehicle1.speed"].items(),
               key=lambda kv: kv[1])[0] == "crush energy"
    assert "evidence.vehicle1.crush.stiffness_b" in rec.samples.varying
    st = rec.samples.stats["vehicle1.speed"]
    assert st.p5 < S1 < st.p95
    c1, c2 = rec.crush
    assert c1.factor == pytest.approx(1.1568, abs=1e-4) and c1.energy == pytest.approx(
        16956.5, rel=1e-4)
    assert c1.ees == pytest.approx(np.sqrt(2 * c1.energy * c1.factor
                                           / float(case.vehicle1.mass)), rel=1e-12)
    assert c1.delta_v_crush > 0 and c1.delta_v_model > 0


def test_crush_alone_is_under_determined_and_says_what_decides():
    from pim.io.casefile import load_case

    case = replace(load_case("synthetic-crush"), measured=None)
    rec = reconstruct(case, samples=0)
    assert not rec.determined
    msg = " ".join(rec.messages)
    assert "under-determined: 2 unknowns" in msg and "crush_energy" in msg
    assert "evidence that would decide it" in msg


def test_a_family_names_the_evidence_that_would_decide_it():
    """vehicle 1's delta-V and vehicle 2's speed fix the impulse and vehicle 2's speed, but
    vehicle 1's speed trades against the restitution: its rest position, its recorded speed
    or the energy loss would decide it; vehicle 2's evidence would not (the Jacobian rows of
    each candidate against the fit's null direction)."""
    case, _, dv = _truth()
    m = pim.Measured(delta_v1=dv[1], delta_v1_sigma=[.3, .3], pre_crash_speed2=S2,
                     pre_crash_speed2_sigma=0.3)
    rec = reconstruct(replace(case, measured=m),
                      unknown={**SPEEDS, "impact.restitution": (0.0, 1.0)}, samples=0)
    assert not rec.determined
    family = next(x for x in rec.messages if x.startswith("family"))
    assert "impact.restitution, vehicle1.speed trade against each other" in family
    assert ("vehicle1's rest position (its post-impact motion), vehicle1's recorded "
            "pre-crash speed or an energy loss (crush) would decide it") in family
    assert "vehicle2's rest position" not in family
    deciding = dict(rec.fit.identifiability.deciding)
    assert set(deciding) == {"vehicle1's rest position (its post-impact motion)",
                             "vehicle1's recorded pre-crash speed", "an energy loss (crush)"}


@pytest.mark.slow
def test_rest_positions_mixed_with_recorded_delta_v_and_energy():
    """synthetic-runout's rest evidence plus vehicle 1's recorded delta-V and the energy loss
    of its own forward solution: the run-outs' motion and the new terms fit together, and
    the speeds come back (21.2 mph each)."""
    from pim.model.evidence_terms import EvidenceTerm, result_quantities

    case = pim.load_case("synthetic-runout")
    res = pim.solve(case)
    q = result_quantities(res)
    dv = [float(EvidenceTerm("delta_v", 1, a).value(q)) for a in (0, 1)]
    mixed = replace(case, measured=pim.Measured(
        delta_v1=dv, delta_v1_sigma=[0.3, 0.3], energy_loss=float(res.energy_loss),
        energy_loss_sigma=5e3))
    rec = reconstruct(mixed, samples=0)
    assert rec.determined and rec.post is not None
    assert {"delta_v1_long", "energy_loss", "velocity2_x"} <= set(rec.fit.residual_names)
    for key in ("vehicle1.speed", "vehicle2.speed"):
        assert rec.values[key] == pytest.approx(21.2 * 0.44704, abs=0.01)


# ---- a case written the PC-Crash way: the Kudlich-Slibar law, unknown speeds, k, mu_c -------
def _pccrash_measured(speed1, speed2, k, mu_c):
    """ricsac9-pccrash-reconstruct with its measured motion replaced by the post-impact
    motion at known speeds (along the headings), k and mu_c, solved forward by the vector-form
    solver (pim.model.impact_laws.solve_kudlich_slibar, independent of the fit's formula)."""
    from pim.model.impact_laws import solve_kudlich_slibar

    case = pim.load_case("ricsac9-pccrash-reconstruct")
    moving = replace(case, vehicle1=replace(case.vehicle1, velocity=(-speed1, 0.0)),
                     vehicle2=replace(case.vehicle2, velocity=(0.0, speed2)))
    r = solve_kudlich_slibar(moving, k, mu_c)
    return replace(case, measured=pim.Measured(
        velocity1=r.velocity1, velocity2=r.velocity2, yaw_rate1=float(r.yaw_rate1),
        yaw_rate2=float(r.yaw_rate2)))


def test_kudlich_slibar_case_reconstruct_recovers_known_speeds_k_and_mu_c():
    case = _pccrash_measured(9.0, 11.0, 0.3, 0.4)        # slides: mu0(0) = 0.634 > 0.4
    rec = reconstruct(case)
    assert rec.determined and rec.fit.law == "kudlich-slibar", rec.messages
    assert rec.values["vehicle1.speed"] == pytest.approx(9.0, abs=1e-6)
    assert rec.values["vehicle2.speed"] == pytest.approx(11.0, abs=1e-6)
    assert rec.values["impact.k"] == pytest.approx(0.3, abs=1e-6)
    assert rec.values["impact.mu_c"] == pytest.approx(0.4, abs=1e-6)
    assert rec.fit.lower_bounds == {}


def test_kudlich_slibar_reconstruct_of_a_sticking_contact_says_mu_c_is_a_lower_bound():
    case = _pccrash_measured(9.0, 11.0, 0.3, 1.2)
    rec = reconstruct(case, samples=40, seed=1)
    needed = float(pim.solve(replace(case, vehicle1=replace(
        case.vehicle1, velocity=(-9.0, 0.0)), vehicle2=replace(
        case.vehicle2, velocity=(0.0, 11.0))), 0.0, 1.0, law="brach").mu0)   # Brach's, eps = 0
    assert rec.determined, rec.messages
    assert rec.values["vehicle1.speed"] == pytest.approx(9.0, abs=1e-6)
    assert rec.values["vehicle2.speed"] == pytest.approx(11.0, abs=1e-6)
    assert rec.values["impact.mu_c"] == pytest.approx(needed, rel=1e-6)
    assert any(f"any mu_c >= {needed:.4g} gives the same answer" in m for m in rec.messages)
    # the Monte Carlo runs under the law; mu_c's percentiles are its lower bounds
    assert rec.samples.n_used > 30
    assert rec.samples.stats["vehicle1.speed"].p5 < 9.0 < rec.samples.stats["vehicle1.speed"].p95
    assert any("lower bound in" in m for m in rec.samples.messages)


def test_reconstruct_names_the_argument_given_a_string():
    """Issue 28: reconstruct('ricsac9-reconstruct') and executor='serial' failed deep inside
    with an AttributeError (the latter after the inverse PIM)."""
    with pytest.raises(TypeError, match=r"^case must be a pim.Case .*got "
                                        r"'ricsac9-reconstruct'$"):
        reconstruct("ricsac9-reconstruct")
    with pytest.raises(TypeError, match=r"^executor must be None \(this process\), a "
                                        r"concurrent.futures.Executor or a "
                                        r"dask.distributed.Client, got 'serial'$"):
        reconstruct(pim.load_case("ricsac9-reconstruct"), samples=20, executor="serial")


def test_progress_stages_count_each_call_of_progress():
    from pim.analysis.reconstruction import progress_stages, worker_blocks

    measured = pim.load_case("ricsac9-reconstruct")       # no [evidence]: no run-out stage
    calls = []
    reconstruct(measured, samples=20, progress=calls.append)
    assert progress_stages(measured, 20) == len(calls) == 2
    assert progress_stages(measured, 0) == 1
    assert progress_stages(pim.load_case("synthetic-runout"), 20, workers=3) == 1 + 1 + 1 + 6
    assert worker_blocks(3) == 6


def test_monte_carlo_budget():
    from pim.analysis.reconstruction import MonteCarloBudget

    limit = MonteCarloBudget(samples=1000, workers=4, max_minutes=1.0)
    seconds = limit.wall_seconds(480.0)                     # 8 min in one process
    assert seconds == 120.0 and limit.over(seconds) and limit.noted(seconds)
    assert limit.affordable(seconds) == 500                 # half the time: half the samples
    assert not limit.over(60.0) and not limit.noted(10.0)


def test_undetermined_reason_names_what_is_missing():
    import dataclasses

    from pim.analysis.reconstruction import Reconstruction

    rec = Reconstruction(case=pim.load_case("ricsac9"), unknown={}, post=None, fit=None,
                         values={}, momentum=None, determined=False,
                         messages=["beta sits on its upper bound",
                                   "under-determined: 3 unknowns, 2 measured quantities"])
    assert rec.undetermined_reason == "under-determined: 3 unknowns, 2 measured quantities"
    other = dataclasses.replace(rec, messages=["a", "b"])
    assert other.undetermined_reason == "a; b"
