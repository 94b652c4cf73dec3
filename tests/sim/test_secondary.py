"""Secondary impacts after separation: the outlines running into each other again."""

import numpy as np
import pytest

import pim
import sim


@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


def test_secondary_impact_of_ricsac9_rigid_simulation_is_found(ricsac9):
    # the rigid pymunk replay of RICSAC 9 draws the outlines through each other after the
    # impact (the observation): the detector must say so
    r = sim.simulate(ricsac9, 0.355, 1.0, sim.Settings(record=True, duration=2.0))
    found = sim.find_secondary_impact(r.trajectory)
    assert found is not None and 0 < found.time < 2.0
    assert "secondary impact" in found.message()


def test_secondary_impact_needs_the_overlap_to_grow_again():
    box = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])
    gap = np.r_[0.5, 1.0, 2.0, 1.0, 0.5, 0.0]            # centre distance minus 2 m
    n = len(gap)
    def traj(x2):
        return sim.Trajectory(time=np.arange(n) * 0.1, position1=np.zeros((n, 2)),
                              angle1=np.zeros(n), position2=np.c_[x2, np.zeros(n)],
                              angle2=np.zeros(n), velocity1=np.zeros((n, 2)),
                              velocity2=np.zeros((n, 2)), yaw_rate1=np.zeros(n),
                              yaw_rate2=np.zeros(n), impact_index=0, outline1=box,
                              outline2=box)
    found = sim.find_secondary_impact(traj(2.0 + gap - 0.6))   # overlap 0.1, apart, again
    assert found is not None and found.index == 4
    assert found.overlap == pytest.approx(0.1)
    assert sim.find_secondary_impact(traj(2.0 + np.linspace(-0.5, 3.0, n))) is None


def test_no_outlines_no_verdict():
    v1 = pim.Vehicle(1500.0, 2500.0, (-1.0, 0.0), (15.0, 0.0))
    case = pim.Case(v1, pim.Vehicle.obstacle((1.0, 0.0)), pim.Impact((0.0, 0.0), np.pi))
    r = sim.simulate_compliant(case, 0.3, sim.DEFAULT_STIFFNESS,
                               settings=sim.CompliantSettings(duration=0.5), engine="pymunk")
    assert r.secondary_impact is None


def test_bad_tolerance(ricsac9):
    r = sim.simulate(ricsac9, 0.355, 1.0, sim.Settings(record=True))
    with pytest.raises(ValueError, match="tolerance"):
        sim.find_secondary_impact(r.trajectory, tolerance=0.0)


def test_secondary_impact_says_where_and_which_parts():
    """Issue 28: the note gives the place. Two 2 x 1 m boxes along x, the second 1.9 m ahead:
    they overlap over x in [0.9, 1.0], |y| <= 0.5, centroid (0.95, 0): vehicle 1's front
    against vehicle 2's rear; in feet 3.117 ft."""
    box = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])
    x2 = np.r_[2.5, 3.0, 4.0, 3.0, 1.9]
    n = len(x2)
    traj = sim.Trajectory(time=np.arange(n) * 0.1, position1=np.zeros((n, 2)),
                          angle1=np.zeros(n), position2=np.c_[x2, np.zeros(n)],
                          angle2=np.zeros(n), velocity1=np.zeros((n, 2)),
                          velocity2=np.zeros((n, 2)), yaw_rate1=np.zeros(n),
                          yaw_rate2=np.zeros(n), impact_index=0, outline1=box, outline2=box)
    found = sim.find_secondary_impact(traj)
    np.testing.assert_allclose(found.point, [0.95, 0.0], atol=1e-12)
    assert found.parts == ("front", "rear")
    assert "at (x, y) = (3.117 ft, 0 ft), vehicle 1's front against vehicle 2's rear" in \
        found.message("us")
    assert found.to_json("si")["x"] == pytest.approx(0.95)


def test_part_of_names_sides_and_corners():
    box = np.array([[2.0, 0.9], [-2.0, 0.9], [-2.0, -0.9], [2.0, -0.9]])
    assert sim.secondary.part_of(box, (0, 0), 0.0, (2.0, 0.0)) == "front"
    assert sim.secondary.part_of(box, (0, 0), 0.0, (0.0, -0.9)) == "right side"
    assert sim.secondary.part_of(box, (0, 0), 0.0, (-1.95, 0.85)) == "rear left"
    # turned 90 deg: the nose points along +y, so +x is its right
    assert sim.secondary.part_of(box, (0, 0), np.pi / 2, (0.9, 0.0)) == "right side"


def test_run_out_contact_agrees_with_the_overlap_area_detector(ricsac9):
    """pim.model.plausibility.secondary_contact (overlap depth, for the reconstruction's
    run-outs) and sim.find_secondary_impact (overlap area, for the simulations) are
    independent; on the rigid replay of RICSAC 9 both find the second contact, within
    0.05 s, and neither finds one where the outlines only part."""
    from pim.model.plausibility import secondary_contact

    r = sim.simulate(ricsac9, 0.355, 1.0, sim.Settings(record=True, duration=2.0))
    tr, i = r.trajectory, r.trajectory.impact_index
    poses = [np.c_[tr.position1, tr.angle1][i:], np.c_[tr.position2, tr.angle2][i:]]
    time, point = secondary_contact(tr.time[i:], *poses, ricsac9.vehicle1, ricsac9.vehicle2)
    found = sim.find_secondary_impact(tr)
    assert abs(time - found.time) < 0.05
    assert np.hypot(*(point - found.point)) < 0.5
    apart = [np.c_[np.linspace(0, 0, 50), np.linspace(0, -5, 50), np.full(50, np.pi)],
             np.c_[np.linspace(0, 5, 50), np.zeros(50), np.zeros(50)]]
    v1, v2 = ricsac9.vehicle1, ricsac9.vehicle2
    assert secondary_contact(np.linspace(0, 1, 50), *apart, v1, v2) is None


def test_watch_after_check_follows_the_case_law(ricsac9):
    """Brach's law: the rigid scene at the check's (eps, beta), as watch_after_impact;
    Kudlich-Slibar: its own two-phase run played on (found, not raised)."""
    import dataclasses

    from sim.crosscheck import crosscheck_law
    from sim.secondary import watch_after_check, watch_after_impact

    found, why = watch_after_check(ricsac9, crosscheck_law(ricsac9, 0.355, 1.0))
    expected = watch_after_impact(ricsac9, 0.355, 1.0)
    assert why == "" and found is not None and found.time == expected.time
    ks = dataclasses.replace(ricsac9, impact=dataclasses.replace(
        ricsac9.impact, law="kudlich-slibar", restitution=0.355, beta=None,
        contact_friction=0.4))
    found, why = watch_after_check(ks, crosscheck_law(ks))
    assert why == "" and (found is None or 0 < found.time < sim.secondary.WATCH_AFTER)


def test_watch_after_check_says_why_when_the_run_on_fails(ricsac9, monkeypatch):
    from sim.crosscheck import crosscheck_law
    from sim.secondary import watch_after_check

    check = crosscheck_law(ricsac9, 0.355, 1.0)

    def fails(*args, **kwargs):
        raise sim.SimulationError("never_separated", "the contact still pushed")

    monkeypatch.setattr(sim.secondary, "watch_after_impact", fails)
    assert watch_after_check(ricsac9, check) == (
        None, "a secondary contact after the impact was not checked: the run on after the "
              "impact failed (never_separated)")
