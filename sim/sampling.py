"""Random admissible impact scenes, for randomized cross-checks and benchmarks."""

from __future__ import annotations

import numpy as np

import pim

__all__ = ["random_scene", "random_scenes"]


def random_scene(rng: np.random.Generator, barrier_fraction: float = 0.2):
    """One random two-vehicle (or vehicle-barrier) scene and its (eps, beta).

    Masses 400-4000 kg, radii of gyration 0.6-2.2 m, C anywhere in a 20 m square, Gamma in
    [0, 2 pi), CG-to-C arms 0.3-4 m in any direction on the proper side of the contact
    plane, speeds up to 40 m/s, yaw rates up to 3 rad/s, eps in [0, 1], beta in [0, 1]
    (a quarter of the scenes at beta = 1 exactly, a tenth at eps = 0). Not filtered: use
    :func:`random_scenes` for admissible ones.

    Returns
    -------
    case : pim.Case
    eps, beta : float
    """
    gamma = rng.uniform(0, 2 * np.pi)
    point = rng.uniform(-10, 10, 2)

    def arm(side: float) -> np.ndarray:
        # C - CG: the CG of vehicle 1 lies on the +n side of the plane, vehicle 2's on -n
        angle = rng.uniform(-0.45 * np.pi, 0.45 * np.pi)
        direction = np.array([np.cos(gamma + angle), np.sin(gamma + angle)])
        return -side * rng.uniform(0.3, 4.0) * direction

    def vehicle(side: float) -> pim.Vehicle:
        mass = rng.uniform(400, 4000)
        k = rng.uniform(0.6, 2.2)
        length, width = rng.uniform(3.5, 6.0), rng.uniform(1.6, 2.1)
        return pim.Vehicle(mass=mass, yaw_inertia=mass * k * k, cg=point - arm(side),
                           velocity=rng.uniform(-25, 25, 2), yaw_rate=rng.uniform(-3, 3),
                           heading=rng.uniform(-np.pi, np.pi), length=length, width=width)

    v1 = vehicle(+1.0)
    if rng.uniform() < barrier_fraction:
        v2 = pim.Vehicle.obstacle(cg=point - arm(-1.0), heading=gamma)
    else:
        v2 = vehicle(-1.0)
    eps = 0.0 if rng.uniform() < 0.1 else float(rng.uniform(0, 1))
    beta = 1.0 if rng.uniform() < 0.25 else float(rng.uniform(0, 1))
    case = pim.Case(v1, v2, pim.Impact(point=point, normal_angle=gamma), name="random")
    return case, eps, beta


def random_scenes(count: int, seed: int = 0, barrier_fraction: float = 0.2):
    """``count`` random scenes that PIM finds admissible (approach, Pn > 0, no energy gain).

    Returns a list of (case, eps, beta); the same seed gives the same scenes.
    """
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        case, eps, beta = random_scene(rng, barrier_fraction)
        if bool(pim.solve(case, eps, beta).admissible):
            out.append((case, eps, beta))
    return out
