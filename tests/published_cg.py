"""Test oracle: the yaw-inertia estimate of tests/data/no-yaw-inertia.toml from the published
figures, independent of pim.io.axle_data and pim.io.inertia_data.

The CG position comes from the NCAP 2004 table's own front-weight column (``wd_front`` =
b / L, so a / L = 1 - wd_front), read here with the csv module; the yaw dynamic index is the
cars' mean K. Tse (2020) printed, 1.091 (Heydinger et al., SAE 1999-01-1336).
"""

import csv
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "pim" / "io" / "data" / \
    "nhtsa_ncap2004_cg_position.csv"
CAR_STYLES = ("Sedan", "Wagon", "Hatchback", "Convertible")
PUBLISHED_CAR_INDEX = 1.091


def rows() -> list[dict]:
    lines = [line for line in DATA.read_text().splitlines() if not line.startswith("#")]
    return list(csv.DictReader(lines))


def car_fraction() -> tuple[float, float]:
    """Mean and predictive sd of a / L over the table's cars, from its front-weight column."""
    f = np.array([1 - float(r["wd_front"]) for r in rows() if r["type"] in CAR_STYLES])
    return f.mean(), f.std(ddof=1) * np.sqrt(1 + 1 / f.size)


def car_estimate(mass: float = 1500.0, wheelbase: float = 2.7) -> float:
    """D m L^2 (mu (1 - mu) - s^2) [kg m^2] for a car of the given mass and wheelbase."""
    mu, s = car_fraction()
    return PUBLISHED_CAR_INDEX * mass * wheelbase**2 * (mu * (1 - mu) - s * s)
