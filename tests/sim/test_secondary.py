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
