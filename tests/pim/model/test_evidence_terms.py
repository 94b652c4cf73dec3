"""Evidence terms on the model's inputs and outputs (pim.model.evidence_terms): the vehicle
frame of a recorded delta-V, exact Jacobians against finite differences, and invariants of a
solved case (the terms of its own solution are zero residuals; the energy term is
Result.energy_loss)."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pim
from pim.analysis.free_fit import free_residuals
from pim.analysis.free_inputs import case_state
from pim.io.casefile import load_case
from pim.model.evidence_terms import (
    EvidenceTerm,
    as_residual_terms,
    delta_v_vehicle_frame,
    result_quantities,
)
from pim.model.motion import Term

TERMS = (EvidenceTerm("delta_v", 1, 0), EvidenceTerm("delta_v", 1, 1),
         EvidenceTerm("delta_v", 2, 0), EvidenceTerm("delta_v", 2, 1),
         EvidenceTerm("pre_crash_speed", 1), EvidenceTerm("pre_crash_speed", 2),
         EvidenceTerm("energy_loss"))


def scene(s1=9.5, s2=8.0, eps=0.2, beta=0.8):
    """RICSAC 9's scene (ricsac9-reconstruct) at known speeds along the headings."""
    case = load_case("ricsac9-reconstruct")
    return replace(case, vehicle1=replace(case.vehicle1, velocity=(-s1, 0.0)),
                   vehicle2=replace(case.vehicle2, velocity=(0.0, s2)),
                   impact=replace(case.impact, restitution=eps, beta=beta))


def test_vehicle_frame_convention():
    """x forward along the heading, y to the left: a car heading north (90 deg) that is
    slowed by 5 m/s and pushed 3 m/s west (to its left) records [-5, +3]."""
    long, lat = delta_v_vehicle_frame(0.0, 20.0, -3.0, 15.0, np.pi / 2)
    assert (long, lat) == pytest.approx((-5.0, 3.0), abs=1e-12)
    # heading east: pushed north is to the left too
    assert delta_v_vehicle_frame(10.0, 0.0, 8.0, 1.0, 0.0) == pytest.approx((-2.0, 1.0))


def test_delta_v_is_the_velocity_change_in_the_heading_frame():
    """Vehicle 1 heads 180 deg: its frame turns the global change around."""
    res = pim.solve(scene())
    q = result_quantities(res)
    dv = np.array([float(EvidenceTerm("delta_v", 1, a).value(q)) for a in (0, 1)])
    # independent: rotate V1' - V1 by -heading (180 deg) by hand
    d = np.asarray(res.velocity1) - np.array([-9.5, 0.0])
    assert dv == pytest.approx([-d[0], -d[1]], abs=1e-12)


KEYS = ("vehicle1.speed", "vehicle2.speed", "impact.restitution", "impact.beta",
        "vehicle1.heading", "impact.normal_angle")


def test_jacobians_match_finite_differences():
    case = scene()
    base = case_state(case)
    x = np.array([[9.5, 8.0, 0.2, 0.8, np.pi, 0.05]])
    k = len(TERMS)
    rows = np.zeros(0, dtype=int)
    r, jac = free_residuals(base, KEYS, x, rows, np.zeros(k), np.ones(k), evidence=TERMS)
    assert np.all(np.isfinite(jac))
    for j in range(len(KEYS)):
        h = 1e-6 * max(1.0, abs(x[0, j]))
        xp, xm = x.copy(), x.copy()
        xp[0, j] += h
        xm[0, j] -= h
        rp, _ = free_residuals(base, KEYS, xp, rows, np.zeros(k), np.ones(k), evidence=TERMS,
                               jacobian=False)
        rm, _ = free_residuals(base, KEYS, xm, rows, np.zeros(k), np.ones(k), evidence=TERMS,
                               jacobian=False)
        fd = (rp - rm)[0] / (2 * h)
        assert jac[0, :, j] == pytest.approx(fd, rel=1e-5, abs=1e-5 * (1 + np.abs(fd).max()))


@settings(max_examples=25, deadline=None)
@given(s1=st.floats(3.0, 30.0), s2=st.floats(3.0, 30.0), eps=st.floats(0.0, 1.0),
       beta=st.floats(0.2, 1.0))
def test_solved_case_terms_are_zero_and_energy_is_the_results(s1, s2, eps, beta):
    case = scene(s1, s2, eps, beta)
    res = pim.solve(case)
    q = result_quantities(res)
    energy = float(EvidenceTerm("energy_loss").value(q))
    assert energy == pytest.approx(float(res.energy_loss), rel=1e-9, abs=1e-6)
    # the state / output path of a fit gives the same values as the solved Result
    k = len(TERMS)
    truth = np.array([float(t.value(q)) for t in TERMS])
    r, _ = free_residuals(case_state(case), ("vehicle1.speed", "vehicle2.speed"),
                          np.array([[s1, s2]]), np.zeros(0, dtype=int), truth, np.ones(k),
                          evidence=TERMS, jacobian=False)
    assert np.abs(r).max() < 1e-9 * max(1.0, energy)
    assert float(EvidenceTerm("pre_crash_speed", 2).value(q)) == pytest.approx(s2)


def test_names_groups_and_order():
    assert [t.name for t in TERMS] == ["delta_v1_long", "delta_v1_lat", "delta_v2_long",
                                       "delta_v2_lat", "pre_crash_speed1",
                                       "pre_crash_speed2", "energy_loss"]
    mixed = as_residual_terms(["energy_loss", "velocity1_x", TERMS[0]])
    assert mixed == (Term(1, "vx"), TERMS[-1], TERMS[0])
    assert TERMS[0].group == TERMS[1].group == "vehicle1 recorded delta-V"


@pytest.mark.parametrize("args, words", [
    (("delta_v", 3, 0), "vehicle must be 1 or 2"), (("energy_loss", 1), "vehicle must be 0"),
    (("delta_v", 1, 2), "bad axis"), (("crush", 1), "kind must be one of")])
def test_bad_terms_are_refused(args, words):
    with pytest.raises(ValueError, match=words):
        EvidenceTerm(*args)


# --- crush energy ---------------------------------------------------------------------

FRONT, RIGHT = np.array([1.0, 0.0]), np.array([0.0, -1.0])


def profile(side):
    from pim.model.crush import CrushProfile

    return CrushProfile(side, 1.2, (0.2, 0.3), 3.5e4, 1.7e5)


def crush_term(e1=17e3, e2=15e3, partition="total"):
    from pim.model.evidence_terms import CrushEnergyTerm

    return CrushEnergyTerm((e1, e2), (profile("front"), profile("right")), 3e3, partition)


def test_crush_term_is_the_energy_loss_minus_the_corrected_crush_energies():
    """Independent check of the CRASH3 factor: 1 / cos^2 of the angle between the impulse
    and each damaged side's normal, turned into the global frame by the heading."""
    res = pim.solve(scene())
    q = result_quantities(res)
    p = np.asarray(res.impulse, dtype=float)
    f = []
    for normal, heading in ((FRONT, np.pi), (RIGHT, np.pi / 2)):
        n = np.array([np.cos(heading) * normal[0] - np.sin(heading) * normal[1],
                      np.sin(heading) * normal[0] + np.cos(heading) * normal[1]])
        cos2 = (p @ n) ** 2 / (p @ p)
        f.append(min(1.0 / cos2, 2.0))
    expected = float(res.energy_loss) - 17e3 * f[0] - 15e3 * f[1]
    assert float(crush_term().value(q)) == pytest.approx(expected, rel=1e-12)
    normal = crush_term(partition="normal")
    assert float(normal.value(q)) == pytest.approx(float(res.crush_energy_normal) - 32e3,
                                                   rel=1e-12)


@pytest.mark.parametrize("partition", ["total", "normal"])
def test_crush_jacobian_matches_finite_differences(partition):
    case = scene()
    base = case_state(case)
    term = (crush_term(partition=partition),)
    x = np.array([[9.5, 8.0, 0.2, 0.8, np.pi, 0.05]])
    rows = np.zeros(0, dtype=int)
    _, jac = free_residuals(base, KEYS, x, rows, np.zeros(1), np.ones(1), evidence=term)
    for j in range(len(KEYS)):
        h = 1e-6 * max(1.0, abs(x[0, j]))
        xp, xm = x.copy(), x.copy()
        xp[0, j] += h
        xm[0, j] -= h
        rp = free_residuals(base, KEYS, xp, rows, np.zeros(1), np.ones(1), evidence=term,
                            jacobian=False)[0]
        rm = free_residuals(base, KEYS, xm, rows, np.zeros(1), np.ones(1), evidence=term,
                            jacobian=False)[0]
        fd = float((rp - rm)[0, 0] / (2 * h))
        assert jac[0, 0, j] == pytest.approx(fd, rel=1e-5, abs=1e-3)


def test_crush_term_rows_are_taken_per_sample():
    t = crush_term(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))
    sub = t.take(np.array([2, 0]))
    assert list(sub.energies[0]) == [3.0, 1.0] and list(sub.energies[1]) == [6.0, 4.0]
    assert crush_term().take(np.array([0])).energies == (17e3, 15e3)


def test_crush_term_needs_a_sigma():
    from pim.model.evidence_terms import CrushEnergyTerm

    with pytest.raises(ValueError, match="standard deviation must be > 0"):
        CrushEnergyTerm((1.0, 0.0), (profile("front"), None), 0.0)
