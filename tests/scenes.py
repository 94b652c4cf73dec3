"""Random scenes for property tests: hypothesis strategies and a vectorised numpy sampler."""

import numpy as np
from hypothesis import strategies as st

import pim

finite = dict(allow_nan=False, allow_infinity=False)


@st.composite
def scenes(draw, fixed: bool = False):
    """A random planar two-body impact (any Gamma, spinning vehicles); not always approaching."""
    def f(lo, hi):
        return draw(st.floats(lo, hi, **finite))

    def pair(lo, hi):
        return np.array([f(lo, hi), f(lo, hi)])

    m1 = f(100.0, 40000.0)
    v1 = pim.Vehicle(mass=m1, yaw_inertia=m1 * f(0.3, 3.0) ** 2, cg=pair(-4, 4),
                     velocity=pair(-40, 40), yaw_rate=f(-6, 6), heading=f(-np.pi, np.pi))
    if fixed:
        v2 = pim.Vehicle.obstacle(cg=pair(-4, 4), heading=f(-np.pi, np.pi))
    else:
        m2 = f(100.0, 40000.0)
        v2 = pim.Vehicle(mass=m2, yaw_inertia=m2 * f(0.3, 3.0) ** 2, cg=pair(-4, 4),
                         velocity=pair(-40, 40), yaw_rate=f(-6, 6), heading=f(-np.pi, np.pi))
    impact = pim.Impact(point=pair(-3, 3), normal_angle=f(-np.pi, np.pi))
    return pim.Case(v1, v2, impact)


def random_cases(n: int, seed: int = 0, fixed: bool = False) -> pim.Case:
    """n random scenes in one vectorised Case (every input varies)."""
    rng = np.random.default_rng(seed)
    m1, m2 = rng.uniform(100, 40000, n), rng.uniform(100, 40000, n)
    v1 = pim.Vehicle(m1, m1 * rng.uniform(0.3, 3, n) ** 2, rng.uniform(-4, 4, (n, 2)),
                     rng.uniform(-40, 40, (n, 2)), rng.uniform(-6, 6, n),
                     rng.uniform(-np.pi, np.pi, n))
    if fixed:
        v2 = pim.Vehicle(np.full(n, np.inf), np.full(n, np.inf), rng.uniform(-4, 4, (n, 2)),
                         np.zeros((n, 2)), np.zeros(n), rng.uniform(-np.pi, np.pi, n))
    else:
        v2 = pim.Vehicle(m2, m2 * rng.uniform(0.3, 3, n) ** 2, rng.uniform(-4, 4, (n, 2)),
                         rng.uniform(-40, 40, (n, 2)), rng.uniform(-6, 6, n),
                         rng.uniform(-np.pi, np.pi, n))
    impact = pim.Impact(rng.uniform(-3, 3, (n, 2)), rng.uniform(-np.pi, np.pi, n))
    return pim.Case(v1, v2, impact)


#: Two cars at right angles as case-file tables (SI), for tests that write a case file with
#: an [impact] table of their own (the impact-law tests).
TWO_CARS_TOML = """
[vehicle1]
mass = "1500 kg"
yaw_inertia = "2500 kg*m**2"
cg = ["1.5 m", "0.4 m"]
heading = "180 deg"
velocity = ["-12 m/s", 0]
[vehicle2]
mass = "1200 kg"
yaw_inertia = "1800 kg*m**2"
cg = ["-0.5 m", "-1.6 m"]
heading = "90 deg"
velocity = [0, "8 m/s"]
"""
