"""NHTSA's measured yaw inertias, and the yaw dynamic index per body class they give.

``pim/io/data/nhtsa_lvipd_yaw_dynamic_index.csv`` (its ``#`` lines give the source) holds
204 vehicles of NHTSA's Light Vehicle Inertial Parameter Database (Heydinger et al., SAE
1999-01-1336, as tabulated by K. Tse 2020): mass, measured yaw inertia and yaw dynamic index
D = I_z / (m a b). :func:`dynamic_indices` groups them by :data:`pim.model.inertia.BODIES`;
:func:`estimate_yaw_inertia` applies :func:`pim.model.inertia.yaw_inertia_estimate` to one
vehicle of a case file. ``python -m comparisons.docs inertia-estimate`` writes the table of
docs/inertia-estimate.md from them (a test keeps the two equal).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cache

import numpy as np

from ..model.inertia import (
    BODIES,
    DynamicIndex,
    InputEstimate,
    MassRegression,
    dynamic_index,
    mass_regression,
    yaw_inertia_estimate,
    yaw_inertia_from_length,
    yaw_inertia_from_mass,
)
from ..model.numbers import InputError, unit_text
from ..model.quantities import UNCERTAIN
from .axle_data import SOURCE as AXLE_SOURCE
from .axle_data import axle_fractions
from .datasets import bundled_rows
from .length_data import SOURCE as LENGTH_SOURCE
from .length_data import usable_lines
from .units import convert

__all__ = ["InertiaRecord", "DATA_FILE", "SOURCE", "load_inertia_records", "dynamic_indices",
           "estimate_yaw_inertia", "estimate_notes", "estimate_records", "held_out",
           "REGRESSION_GROUPS", "REGRESSION_SOURCE", "mass_regressions", "regression_group",
           "estimate_yaw_inertia_from_mass", "mass_held_out", "estimate_yaw_inertia_from_length"]

DATA_FILE = "nhtsa_lvipd_yaw_dynamic_index.csv"
#: Short citation of the data, for notes and reports.
SOURCE = "NHTSA's measured vehicles, Heydinger et al. 1999"
#: The groups of the mass-only line, as K. Tse (2020) published it: the cars, and the light
#: trucks (SUVs, pickups and vans) together; body class -> its group.
REGRESSION_GROUPS = {"car": ("car",), "truck": ("suv", "pickup", "van")}
#: Short citation of the mass-only line: the measurements and who published the line.
REGRESSION_SOURCE = ("NHTSA's measured vehicles, Heydinger et al. 1999; the line of I_z on "
                     "mass as K. Tse 2020 published it")
_COLUMNS = ("year", "make", "model", "body", "mass_kg", "yaw_inertia_kg_m2",
            "yaw_dynamic_index")


@dataclass(frozen=True)
class InertiaRecord:
    """One measured vehicle of the NHTSA database [SI].

    Attributes
    ----------
    year : int
        Model year.
    make, model : str
        As tabulated.
    body : str
        The database's type code (4S, 2S, 2C, 3H, 5H, SW, MP, PU, VN; see the CSV's notes).
    mass : float
        Mass [kg].
    yaw_inertia : float
        Measured yaw moment of inertia about the CG [kg m^2].
    dynamic_index : float
        Yaw dynamic index D = I_z / (m a b) [-].
    """

    year: int
    make: str
    model: str
    body: str
    mass: float
    yaw_inertia: float
    dynamic_index: float

    @property
    def axle_product(self) -> float:
        """a b = I_z / (m D) [m^2]: the product of the CG's distances to the two axles."""
        return self.yaw_inertia / (self.mass * self.dynamic_index)


def _record(row: dict, line: int) -> InertiaRecord:
    where = f"{DATA_FILE} line {line}"
    try:
        year, mass = int(row["year"]), float(row["mass_kg"])
        inertia, index = float(row["yaw_inertia_kg_m2"]), float(row["yaw_dynamic_index"])
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: not a number ({exc})") from None
    if not (mass > 0 and inertia > 0 and index > 0):
        raise InputError(f"{where}: mass, yaw inertia and dynamic index must be > 0")
    if not any(row["body"] in codes for codes in BODIES.values()):
        raise InputError(f"{where}: unknown body code {row['body']!r}")
    return InertiaRecord(year, row["make"], row["model"], row["body"], mass, inertia, index)


@cache
def load_inertia_records() -> tuple[InertiaRecord, ...]:
    """Every vehicle of the bundled file, in its order.

    Raises
    ------
    InputError
        A malformed row (naming the line) or missing columns.
    """
    return tuple(_record(row, line) for line, row in bundled_rows(DATA_FILE, _COLUMNS))


@cache
def dynamic_indices() -> dict[str, DynamicIndex]:
    """Body class (a key of :data:`pim.model.inertia.BODIES`) -> its yaw dynamic index."""
    records = load_inertia_records()
    return {body: dynamic_index([r.dynamic_index for r in records if r.body in codes], body,
                                SOURCE) for body, codes in BODIES.items()}


def regression_group(body: str) -> str:
    """The group of :data:`REGRESSION_GROUPS` a body class belongs to."""
    return next(group for group, bodies in REGRESSION_GROUPS.items() if body in bodies)


def _group_rows(group: str) -> list[InertiaRecord]:
    codes = {c for body in REGRESSION_GROUPS[group] for c in BODIES[body]}
    return [r for r in load_inertia_records() if r.body in codes]


@cache
def mass_regressions() -> dict[str, MassRegression]:
    """Group (a key of :data:`REGRESSION_GROUPS`) -> its least-squares line of yaw inertia on
    mass over the bundled vehicles (:func:`pim.model.inertia.mass_regression`)."""
    return {group: mass_regression([r.mass for r in _group_rows(group)],
                                   [r.yaw_inertia for r in _group_rows(group)], group,
                                   REGRESSION_SOURCE) for group in REGRESSION_GROUPS}


def estimate_yaw_inertia_from_mass(mass: float, body: str, where: str) -> InputEstimate:
    """The yaw inertia of ``where`` (e.g. "vehicle1") estimated from its mass [kg] alone by
    the line of its body class's group (:func:`mass_regressions`), with its provenance:
    the estimate without a wheelbase."""
    _check_body(body, where)
    line = mass_regressions()[regression_group(body)]
    try:
        inertia, sd = yaw_inertia_from_mass(mass, line)
    except InputError as exc:
        raise InputError(f"{where}: no yaw_inertia (or radius_of_gyration) and no wheelbase "
                         f"given, and the {exc}; give {where}.yaw_inertia, "
                         f"{where}.wheelbase (the yaw dynamic index's estimate) or its body "
                         f"class ({where}.body: {', '.join(map(repr, BODIES))})") from None
    method = (f"I_z = {line.slope:.3f} m {'-' if line.intercept < 0 else '+'} "
              f"{abs(line.intercept):.0f} kg m^2 without a wheelbase, the least-squares line "
              f"of the {line.count} measured {line.group}s (R^2 = {line.r_squared:.3f})")
    return InputEstimate(f"{where}.yaw_inertia", float(inertia), float(sd), method,
                         REGRESSION_SOURCE, (("mass m", float(mass), "mass"),))


def estimate_yaw_inertia_from_length(mass: float, length: float, body: str,
                                     where: str) -> InputEstimate:
    """The yaw inertia of ``where`` (e.g. "vehicle1") estimated from its mass [kg] and
    overall length [m] without a wheelbase: the yaw dynamic index's estimate with the
    wheelbase from the length (:func:`pim.io.length_data.usable_lines`,
    :func:`pim.model.inertia.yaw_inertia_from_length`) and the class's CG position. A class
    without a usable line, or a length outside its line's, takes the mass-only line
    (:func:`estimate_yaw_inertia_from_mass`; its method says why the length was not used)."""
    _check_body(body, where)
    line = usable_lines().get(body)
    low, high = line.length_range if line is not None else (np.inf, -np.inf)
    if not low <= length <= high:
        estimate = estimate_yaw_inertia_from_mass(mass, body, where)
        why = (f"the overall length lies outside the lengths of the {line.count} {body}s of "
               f"the wheelbase line" if line is not None
               else f"no line of the wheelbase on the overall length for a {body}")
        return replace(estimate, method=f"{estimate.method}; {why}")
    index, f = dynamic_indices()[body], axle_fractions()[body]
    inertia, sd = yaw_inertia_from_length(mass, length, line, index, f)
    vehicles = f"{f.count} {body}s" if f.body == body else f"all {f.count} vehicles"
    assumed = (f"L = {line.slope:.3f} l {'-' if line.intercept < 0 else '+'} "
               f"{unit_text(abs(line.intercept), 'length', '.3g')} ± "
               f"{unit_text(line.sd, 'length', '.2g')} (1 sd, the line of the wheelbase L on "
               f"the length l of the {line.count} 1993 {body}s of {LENGTH_SOURCE})",
               f"a = {f.mean:.3f} L ± {f.predictive_sd:.3f} L (1 sd, the CG position of "
               f"{vehicles} in {AXLE_SOURCE})")
    method = (f"D m L^2 E[f (1 - f)], f = a / L, L from the overall length l, "
              f"D = {index.mean:.3f} the yaw dynamic index of a {body}")
    return InputEstimate(f"{where}.yaw_inertia", float(inertia), float(sd), method,
                         f"{SOURCE}; {AXLE_SOURCE}; {LENGTH_SOURCE}",
                         (("mass m", float(mass), "mass"), ("length l", float(length),
                                                            "length")), assumed)


def mass_held_out(group: str) -> tuple[int, int, float]:
    """How the mass-only line does on the group's measured vehicles it did not see: each
    left out in turn, the others' line estimates its yaw inertia from its mass. Returns
    (vehicles within 1.96 predictive sd of their measured value, vehicles, sd of the
    standardised errors (measured - estimate) / sd [-])."""
    rows = _group_rows(group)
    z = []
    for i, r in enumerate(rows):
        others = rows[:i] + rows[i + 1:]
        line = mass_regression([o.mass for o in others], [o.yaw_inertia for o in others],
                               group, REGRESSION_SOURCE)
        fit = line.slope * r.mass + line.intercept
        z.append((r.yaw_inertia - fit) / (float(line.predictive_sd(r.mass)) * fit))
    z = np.array(z)
    return int(np.sum(np.abs(z) <= 1.96)), len(rows), float(z.std(ddof=1))


def _check_body(body: str, where: str) -> None:
    if body not in BODIES:
        raise InputError(f"{where}.body must be one of {', '.join(map(repr, BODIES))} (the "
                         f"class whose yaw dynamic index estimates the yaw inertia), got "
                         f"{body!r}")


def estimate_yaw_inertia(mass: float, wheelbase: float, cg_to_front_axle: float | None,
                         body: str, where: str) -> InputEstimate:
    """The yaw inertia of ``where`` (e.g. "vehicle1") estimated from its mass [kg], wheelbase
    [m] and CG-to-front-axle distance [m] by its body class's yaw dynamic index, with its
    provenance. Without the axle distance (None), the class's CG position a / L measured by
    NHTSA (:func:`pim.io.axle_data.axle_fractions`) stands in, its scatter in the sd."""
    _check_body(body, where)
    index = dynamic_indices()[body]
    inputs = (("mass m", float(mass), "mass"), ("wheelbase L", float(wheelbase), "length"))
    method = f"D m a (L - a), D = {index.mean:.3f} the yaw dynamic index of a {body}"
    if cg_to_front_axle is not None:
        inertia, sd = yaw_inertia_estimate(mass, wheelbase, index, cg_to_front_axle)
        inputs += (("CG to front axle a", float(cg_to_front_axle), "length"),)
        return InputEstimate(f"{where}.yaw_inertia", float(inertia), float(sd), method,
                             SOURCE, inputs)
    f = axle_fractions()[body]
    inertia, sd = yaw_inertia_estimate(mass, wheelbase, index, fraction=f)
    vehicles = f"{f.count} {body}s" if f.body == body else f"all {f.count} vehicles"
    assumed = (f"a = {f.mean:.3f} L ± {f.predictive_sd:.3f} L (1 sd, the CG position of "
               f"{vehicles} in {AXLE_SOURCE})")
    method = (f"D m L^2 E[f (1 - f)], f = a / L, D = {index.mean:.3f} the yaw dynamic index "
              f"of a {body}")
    return InputEstimate(f"{where}.yaw_inertia", float(inertia), float(sd), method,
                         f"{SOURCE}; {AXLE_SOURCE}", inputs, (assumed,))


def _figure(value: float, kind: str, units: str) -> str:
    number, unit = convert(value, kind, units)
    return f"{float(number):.4g} {unit}"


def estimate_notes(case, units: str) -> list[str]:
    """One line per estimated input of ``case`` (:attr:`pim.Case.estimates`), its figures in
    ``units`` ("si" or "us"), for the note on stderr and the reports: "vehicle1.yaw_inertia
    not given: estimated 2981 kg m^2 ±7.0 % (1 sd) = D m a (L - a), ... (mass m 1500 kg,
    wheelbase L 2.7 m; a = L/2 assumed; Heydinger et al. 1999)"."""
    lines = []
    for e in getattr(case, "estimates", ()):
        figures = ", ".join(f"{label} {_figure(v, kind, units)}" for label, v, kind in e.inputs)
        assumed = "".join(f"; {a} assumed" for a in e.assumptions)
        value = _figure(e.value, UNCERTAIN[e.name].kind, units)
        lines.append(f"{e.name} not given: estimated {value} ±{100 * e.relative_sd:.1f} % "
                     f"(1 sd) = {e.method} ({figures}{assumed}; {e.source}, "
                     f"docs/inertia-estimate.md)")
    return lines


def estimate_records(case, units: str) -> list[dict]:
    """The estimated inputs of ``case`` for ``--json``: name, value and sd in ``units``
    ("si" or "us") with the unit, the method, the source and what was assumed."""
    out = []
    for e in getattr(case, "estimates", ()):
        (value, sd), unit = convert([e.value, e.sd], UNCERTAIN[e.name].kind, units)
        out.append({"input": e.name, "value": float(value), "sd": float(sd), "unit": unit,
                    "method": e.method, "source": e.source,
                    "assumed": list(e.assumptions)})
    return out


def held_out(body: str) -> tuple[int, int, float]:
    """How the estimate does on the class's measured vehicles it did not see: each left out
    in turn, the others' index estimates its yaw inertia from its mass and a b. Returns
    (vehicles within 1.96 predictive sd of their measured value, vehicles, sd of the
    standardised errors (measured - estimate) / sd [-])."""
    rows = [r for r in load_inertia_records() if r.body in BODIES[body]]
    z = []
    for i, r in enumerate(rows):
        index = dynamic_index([o.dynamic_index for o in rows[:i] + rows[i + 1:]], body, SOURCE)
        scale = r.mass * r.axle_product
        z.append((r.yaw_inertia - index.mean * scale) / (index.predictive_sd * scale))
    z = np.array(z)
    return int(np.sum(np.abs(z) <= 1.96)), len(rows), float(z.std(ddof=1))
