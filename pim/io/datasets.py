"""Bundled published crash-test data: loaders into typed records (SI inside).

Three datasets ship in ``pim/io/data`` (each CSV opens with its source in ``#`` lines; the
papers are cited in docs/validation.md):

* ``iihs-barrier``: 41 IIHS small-overlap vehicle-to-barrier tests, Brach, Welsh & Brach,
  SAE 2014-01-0469, Appendix 2 part 1: the authors' PIM coefficients (e, mu as % of mu0,
  d1, phi, Gamma), impact speed, IIHS-measured delta-V components and yaw rate, and the
  group (NS non-sideswipe, SS sideswipe, OUTLIER excluded by the authors). The values follow
  the paper, not the widely copied workbook (see ``brach_matrix_vs_paper_discrepancies.csv``).
* ``iihs-car-to-car``: the 9 IIHS vehicle-to-vehicle tests (18 vehicles) of Appendix 2 part 2:
  e, mu, Phi, Gamma, speed, delta-V, yaw rate (no masses or arms: coefficient statistics only).
* ``ricsac``: RICSAC staged collisions 1, 3-12 (test 2 has no pre/post data): masses, yaw
  inertias (estimated by class in the source), measured pre/post velocities and post yaw
  rates, Gamma, theta, phi, published delta-V analyses.
* ``nhtsa-car-to-car``: four NHTSA vehicle-to-vehicle oblique frontal tests analysed by Rose,
  Fenton & Beauchamp (SAE 2006-01-0908): weights, yaw inertias, speeds, headings, impact
  centre and contact plane, their PIM inputs (cor, mu0, mu/mu0) and their PIM analysis's
  delta-V and yaw-rate change of each vehicle (not the tests' measured motion).

Every record carries ``origins``: each input or outcome field -> where its value comes from
(:data:`MEASURED`, :data:`PUBLISHED_GEOMETRY`, :data:`FITTED_BY_PIM`, :data:`VEHICLE_DATA`,
:data:`ESTIMATED`,
:data:`ANALYSIS_INPUT`, :data:`PIM_OUTPUT`), so that a study can tell a measured input from
one fitted with PIM to the same test's outcome (docs/validation.md, "Where each input comes
from").

A malformed or edited file raises ValueError naming the file, the row (line number) and
the column.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from ..model.numbers import InputError

__all__ = ["BarrierTest", "CarToCarVehicle", "RicsacTest", "NhtsaCarToCarTest", "DATASETS",
           "load_barrier", "load_car_to_car", "load_ricsac", "load_nhtsa_car_to_car",
           "load_dataset", "data_path", "bundled_rows", "body_class", "source_lines", "MEASURED",
           "PUBLISHED_GEOMETRY",
           "FITTED_BY_PIM", "VEHICLE_DATA", "ESTIMATED", "ANALYSIS_INPUT", "PIM_OUTPUT",
           "ORIGIN_KINDS",
           "BARRIER_ORIGINS", "CAR_TO_CAR_ORIGINS", "RICSAC_ORIGINS", "NHTSA_ORIGINS"]

FT = 0.3048                 # m per ft (exact)
DEG = math.pi / 180.0       # rad per deg

BARRIER_FILE = "brach2014_iihs_small_overlap_vehicle_to_barrier.csv"
CAR_TO_CAR_FILE = "brach2014_iihs_small_overlap_vehicle_to_vehicle.csv"
RICSAC_FILE = "ricsac_1-12_compiled.csv"
NHTSA_FILE = "rose2006_nhtsa_vehicle_to_vehicle.csv"
LB = 0.45359237             # kg per lb (exact)
SLUG_FT2 = 1.3558179483314004  # kg m^2 per lb ft s^2
MPH = 0.44704               # m/s per mph (exact)

#: Origin of a value: measured in the test.
MEASURED = "measured"
#: Geometry the source publishes (vehicle dimensions, impact point, contact plane), not
#: fitted to the test's motion.
PUBLISHED_GEOMETRY = "published geometry"
#: Fitted with PIM by the source's authors to this same test's measured motion: an input
#: taken from here carries the test's outcome.
FITTED_BY_PIM = "fitted by PIM on this test"
#: Vehicle data from a published table (weights, inertias), not weighed in the test.
VEHICLE_DATA = "published vehicle data"
#: Estimated by the source (e.g. mass x a class radius of gyration squared), not measured.
ESTIMATED = "published estimate"
#: An input of the source's own analysis (chosen by its authors, not measured).
ANALYSIS_INPUT = "analysis input"
#: The output of the source's PIM analysis, not a measurement.
PIM_OUTPUT = "PIM analysis output"
#: Every origin, with what it means.
ORIGIN_KINDS = {
    MEASURED: "measured in the test",
    PUBLISHED_GEOMETRY: "published geometry, not fitted to the test's motion",
    VEHICLE_DATA: "published vehicle data (weights, inertias), not weighed in the test",
    FITTED_BY_PIM: "fitted with PIM by the source's authors to this test's measured motion",
    ESTIMATED: "estimated by the source, not measured",
    ANALYSIS_INPUT: "an input chosen for the source's own analysis",
    PIM_OUTPUT: "the output of the source's PIM analysis, not a measurement",
}
#: Field -> origin of :class:`BarrierTest` (Brach et al. fitted e, mu and phi to the IIHS
#: video-derived motion at the published d1 and Gamma).
BARRIER_ORIGINS = {
    "restitution": FITTED_BY_PIM, "beta": FITTED_BY_PIM, "d": PUBLISHED_GEOMETRY,
    "phi": FITTED_BY_PIM, "normal_angle": PUBLISHED_GEOMETRY, "speed": MEASURED,
    "delta_v_x": MEASURED, "delta_v": MEASURED, "delta_v_y": MEASURED, "yaw_rate": MEASURED,
    "overlap_pct": MEASURED,
}
#: Field -> origin of :class:`CarToCarVehicle` (e, mu, Phi and Gamma fitted by the authors).
CAR_TO_CAR_ORIGINS = {
    "restitution": FITTED_BY_PIM, "beta": FITTED_BY_PIM, "phi": FITTED_BY_PIM,
    "normal_angle": FITTED_BY_PIM, "speed": MEASURED, "delta_v": MEASURED,
    "yaw_rate": MEASURED,
}
#: Field -> origin of :class:`RicsacTest` (the angles from Vossou & Koulocheris's Table 2,
#: whose paper does not say how they were chosen; the inertias mass x a class k^2).
RICSAC_ORIGINS = {
    "mass1": MEASURED, "mass2": MEASURED, "yaw_inertia1": ESTIMATED,
    "yaw_inertia2": ESTIMATED, "speed1_measured": MEASURED, "speed2_measured": MEASURED,
    "normal_angle": PUBLISHED_GEOMETRY, "theta1": PUBLISHED_GEOMETRY,
    "theta2": PUBLISHED_GEOMETRY, "phi1": PUBLISHED_GEOMETRY, "phi2": PUBLISHED_GEOMETRY,
    "velocity1_pre": MEASURED, "velocity2_pre": MEASURED, "velocity1_post": MEASURED,
    "velocity2_post": MEASURED, "yaw_rate1_post": MEASURED, "yaw_rate2_post": MEASURED,
    "published_delta_v": PIM_OUTPUT,
}
#: Field -> origin of :class:`NhtsaCarToCarTest` (the CSV's second source line).
NHTSA_ORIGINS = {
    "mass1": VEHICLE_DATA, "mass2": VEHICLE_DATA,
    "yaw_inertia1": VEHICLE_DATA, "yaw_inertia2": VEHICLE_DATA,
    "speed1": MEASURED, "speed2": MEASURED, "heading1": PUBLISHED_GEOMETRY,
    "heading2": PUBLISHED_GEOMETRY, "d1": PUBLISHED_GEOMETRY, "phi1": PUBLISHED_GEOMETRY,
    "d2": PUBLISHED_GEOMETRY, "phi2": PUBLISHED_GEOMETRY, "normal_angle": PUBLISHED_GEOMETRY,
    "restitution": ANALYSIS_INPUT, "mu0": ANALYSIS_INPUT, "beta": ANALYSIS_INPUT,
    "delta_v1": PIM_OUTPUT, "delta_v2": PIM_OUTPUT, "yaw_change1": PIM_OUTPUT,
    "yaw_change2": PIM_OUTPUT,
}


def _origins(table: dict):
    """A dataclass field holding a copy of ``table`` (field -> origin)."""
    return field(default_factory=lambda: dict(table), repr=False, compare=False)

#: Crash classes of the IIHS groups.
GROUPS = {"NS": "non-sideswipe", "SS": "sideswipe", "OUTLIER": "outlier (excluded by the authors)"}


@dataclass(frozen=True)
class BarrierTest:
    """One IIHS small-overlap barrier test and Brach et al.'s fitted PIM coefficients [SI].

    ``d`` [m] and ``phi`` [rad] place the impact point C from the CG (Brach's form, vehicle 1,
    theta = 0); ``normal_angle`` is Gamma [rad]; ``speed`` the impact speed [m/s];
    ``delta_v_x``/``delta_v_y`` the measured longitudinal/lateral delta-V magnitudes [m/s],
    ``delta_v`` the tabulated resultant [m/s], ``yaw_rate`` the measured yaw rate magnitude
    [rad/s]; ``beta`` = mu/mu0 [-].

    Attributes
    ----------
    test_id : str
        IIHS test number (e.g. "CEN1212").
    group : str
        Crash class, a key of :data:`GROUPS`: "NS" (non-sideswipe), "SS" (sideswipe) or
        "OUTLIER" (excluded by the authors).
    model_year : int
        The vehicle's model year.
    vehicle : str
        Make and model.
    vehicle_type : str
        Body type as tabulated (e.g. "Sedan").
    barrier : str
        Barrier as tabulated (e.g. "Flat 150 barrier").
    overlap_pct : float
        Overlap of the barrier with the vehicle's width [%].
    restitution : float
        Brach et al.'s fitted restitution e [-].
    beta : float
        Their fitted mu as a fraction of mu0 [-].
    d : float
        Distance of the impact point C from the CG [m].
    phi : float
        Brach's angle phi locating C from the CG [rad].
    normal_angle : float
        Gamma, the angle of the contact plane's normal [rad].
    speed : float
        Impact speed [m/s].
    delta_v_x : float
        Measured longitudinal delta-V magnitude [m/s].
    delta_v : float
        Tabulated resultant delta-V [m/s].
    delta_v_y : float
        Measured lateral delta-V magnitude [m/s].
    yaw_rate : float
        Measured yaw-rate magnitude [rad/s].
    line : int
        Line of the row in the CSV (for error messages).
    origins : dict of str to str
        Field -> origin of its value (:data:`BARRIER_ORIGINS`).
    """

    test_id: str
    group: str
    model_year: int
    vehicle: str
    vehicle_type: str
    barrier: str
    overlap_pct: float
    restitution: float
    beta: float
    d: float
    phi: float
    normal_angle: float
    speed: float
    delta_v_x: float
    delta_v: float
    delta_v_y: float
    yaw_rate: float
    line: int
    origins: dict = _origins(BARRIER_ORIGINS)


@dataclass(frozen=True)
class CarToCarVehicle:
    """One vehicle of an IIHS small-overlap car-to-car test (Brach et al., App. 2 part 2) [SI].

    Attributes
    ----------
    test_id : str
        IIHS test number with "a" or "b" for the vehicle (e.g. "CF09009a").
    group : str
        "NS" (non-sideswipe) or "SS" (sideswipe); the same for both vehicles.
    vehicle : str
        Model year, make and model.
    overlap : str
        Overlap as tabulated (e.g. "28%", "15 deg oblique").
    restitution : float
        Brach et al.'s fitted restitution e of the impact [-] (the same for both vehicles).
    beta : float
        Their fitted mu as a fraction of mu0 [-] (the same for both vehicles).
    phi : float
        The tabulated Phi of this vehicle [rad].
    normal_angle : float
        Gamma, the angle of the contact plane's normal [rad] (the same for both vehicles).
    speed : float
        Impact speed [m/s].
    delta_v : float
        Tabulated resultant delta-V [m/s].
    yaw_rate : float
        Measured yaw-rate magnitude [rad/s].
    line : int
        Line of the row in the CSV (for error messages).
    origins : dict of str to str
        Field -> origin of its value (:data:`CAR_TO_CAR_ORIGINS`).
    """

    test_id: str
    group: str
    vehicle: str
    overlap: str
    restitution: float
    beta: float
    phi: float
    normal_angle: float
    speed: float
    delta_v: float
    yaw_rate: float
    line: int
    origins: dict = _origins(CAR_TO_CAR_ORIGINS)


@dataclass(frozen=True)
class RicsacTest:
    """One RICSAC staged collision [SI]; motion fields are None where the sources give none.

    Velocities are (x, y) in the frame of Vossou & Koulocheris (2018, Table 1); angles from
    their Table 2 (Brach's theta, phi; Gamma). ``published_delta_v`` maps an analysis name
    (``raw_JB``, ``BrachSmith2002``, ``McHenry``, ``PIM1991``, ``PIM1998``, ``PIM2002``) to
    (dV1, dV2) [m/s].

    Attributes
    ----------
    number : int
        RICSAC test number.
    vehicle1, vehicle2 : str
        The vehicles' names, where a source states them ("" otherwise).
    mass1, mass2 : float
        Masses [kg].
    yaw_inertia1, yaw_inertia2 : float
        Yaw inertias [kg m^2] (mass x a class k^2 in the source, not measured).
    speed1_measured, speed2_measured : float
        Measured pre-impact speeds [m/s].
    normal_angle : float or None
        Gamma, the angle of the contact plane's normal [rad].
    theta1, theta2 : float or None
        Brach's vehicle angles theta [rad].
    phi1, phi2 : float or None
        Brach's angles phi locating C from each CG [rad].
    velocity1_pre, velocity2_pre : tuple of float (2,) or None
        Pre-impact velocities (x, y) [m/s].
    velocity1_post, velocity2_post : tuple of float (2,) or None
        Post-impact velocities (x, y) [m/s].
    yaw_rate1_post, yaw_rate2_post : float or None
        Post-impact yaw rates [rad/s].
    published_delta_v : dict of str to tuple
        Analysis name -> (dV1, dV2) [m/s] (an entry None where the source gives none).
    line : int
        Line of the row in the CSV (for error messages).
    origins : dict of str to str
        Field -> origin of its value (:data:`RICSAC_ORIGINS`).
    has_motion : bool
        True when measured pre- and post-impact motion is available (property).
    """

    number: int
    vehicle1: str
    vehicle2: str
    mass1: float
    yaw_inertia1: float
    mass2: float
    yaw_inertia2: float
    speed1_measured: float
    speed2_measured: float
    normal_angle: float | None
    theta1: float | None
    theta2: float | None
    phi1: float | None
    phi2: float | None
    velocity1_pre: tuple | None
    velocity2_pre: tuple | None
    velocity1_post: tuple | None
    velocity2_post: tuple | None
    yaw_rate1_post: float | None
    yaw_rate2_post: float | None
    published_delta_v: dict
    line: int
    origins: dict = _origins(RICSAC_ORIGINS)

    @property
    def has_motion(self) -> bool:
        """True when measured pre- and post-impact motion is available."""
        return self.velocity1_post is not None


@dataclass(frozen=True)
class NhtsaCarToCarTest:
    """One NHTSA vehicle-to-vehicle test as Rose, Fenton & Beauchamp analysed it (SAE
    2006-01-0908) [SI].

    Angles are counter-clockwise from +x as tabulated (vehicle 1 heads at 180 deg); the impact
    centre lies at distance ``d`` from each CG, at ``phi`` from the vehicle's heading. The
    delta-V and yaw-rate change are the authors' PIM analysis output, not the measured motion
    (:data:`NHTSA_ORIGINS`).

    Attributes
    ----------
    test : str
        NHTSA test number (e.g. "4363").
    vehicle1, vehicle2 : str
        Model year, make and model.
    mass1, mass2 : float
        Masses [kg] (vehicle data).
    yaw_inertia1, yaw_inertia2 : float
        Yaw inertias [kg m^2] (vehicle data).
    speed1, speed2 : float
        Impact speeds [m/s].
    heading1, heading2 : float
        Headings [rad].
    d1, d2 : float
        Distance from each CG to the impact centre [m].
    phi1, phi2 : float
        Polar angle of the impact centre from each vehicle's heading [rad].
    normal_angle : float
        Angle of the contact plane's normal [rad].
    restitution : float
        The authors' coefficient of restitution [-] (from their restitution model).
    mu0 : float
        The critical impulse ratio they tabulate [-].
    beta : float
        Their impulse ratio as a fraction of mu0 [-].
    delta_v1, delta_v2 : float
        Delta-V magnitude of each vehicle [m/s] (their PIM output).
    yaw_change1, yaw_change2 : float
        Magnitude of each vehicle's yaw-rate change [rad/s] (their PIM output).
    line : int
        Line of the row in the CSV (for error messages).
    origins : dict of str to str
        Field -> origin of its value (:data:`NHTSA_ORIGINS`).
    """

    test: str
    vehicle1: str
    vehicle2: str
    mass1: float
    yaw_inertia1: float
    mass2: float
    yaw_inertia2: float
    speed1: float
    speed2: float
    heading1: float
    heading2: float
    d1: float
    phi1: float
    d2: float
    phi2: float
    normal_angle: float
    restitution: float
    mu0: float
    beta: float
    delta_v1: float
    delta_v2: float
    yaw_change1: float
    yaw_change2: float
    line: int
    origins: dict = _origins(NHTSA_ORIGINS)


def data_path(name: str) -> Path:
    """Path of a bundled data file."""
    return Path(str(resources.files("pim.io") / "data" / name))


def bundled_rows(name: str, columns: tuple[str, ...]) -> list[tuple[int, dict]]:
    """The rows of the bundled CSV ``name`` (``pim/io/data``) after its ``#`` source lines,
    each with its line number in the file (for errors).

    Raises
    ------
    InputError
        The header is not ``columns``.
    """
    text = (resources.files("pim.io") / "data" / name).read_text(encoding="utf-8")
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    reader = csv.DictReader(lines[first:])
    if tuple(reader.fieldnames or ()) != tuple(columns):
        raise InputError(f"{name}: columns must be {', '.join(columns)}")
    return [(first + 2 + i, row) for i, row in enumerate(reader)]


def body_class(style: str, types: dict, where: str) -> str:
    """The body class (a key of ``types``: class -> the data's body styles in it) of a
    bundled row's body ``style``; an error naming the row (``where``) for an unknown one."""
    for body, styles in types.items():
        if style in styles:
            return body
    raise InputError(f"{where}: unknown body style {style!r}")


def source_lines(path) -> list[str]:
    """The leading ``#`` lines of a bundled CSV (its source), without the ``#``."""
    out = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("#"):
                break
            out.append(line[1:].strip())
    return out


class _Rows:
    """Reads a CSV after its ``#`` lines, checks the header, and converts cells with errors
    naming file, line and column."""

    def __init__(self, path, columns: list[str]):
        self.path = Path(path)
        self.name = self.path.name
        try:
            text = self.path.read_text(encoding="utf-8")
        except OSError as exc:
            raise InputError(f"{self.path}: cannot read ({exc.strerror})") from None
        except UnicodeDecodeError:
            raise InputError(f"{self.name}: not UTF-8 text") from None
        lines = text.splitlines()
        start = 0
        while start < len(lines) and lines[start].startswith("#"):
            start += 1
        if start >= len(lines):
            raise InputError(f"{self.name}: no header line")
        header = next(csv.reader([lines[start]]))
        if header != columns:
            missing = [c for c in columns if c not in header]
            extra = [c for c in header if c not in columns]
            detail = (f"missing {missing}" if missing else "") + \
                     (f" unexpected {extra}" if extra else "") or "columns out of order"
            raise InputError(f"{self.name} line {start + 1}: header does not match the expected "
                             f"columns ({detail.strip()}); expected {','.join(columns)}")
        self.columns = columns
        self.rows = []
        for offset, fields in enumerate(csv.reader(lines[start + 1:])):
            line = start + 2 + offset
            if not fields or all(not f.strip() for f in fields):
                continue
            if len(fields) != len(columns):
                raise InputError(f"{self.name} line {line}: {len(fields)} fields, "
                                 f"expected {len(columns)}")
            self.rows.append((line, dict(zip(columns, (f.strip() for f in fields), strict=False))))
        if not self.rows:
            raise InputError(f"{self.name}: no data rows")

    def number(self, line, row, column, low=-math.inf, high=math.inf, optional=False,
               low_open=False):
        text = row[column]
        where = f"{self.name} line {line} column {column!r}"
        if text == "":
            if optional:
                return None
            raise InputError(f"{where}: empty, a number is required")
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{where}: {text!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"{where}: {text!r} is not a finite number")
        if value < low or value > high or (low_open and value == low):
            raise InputError(f"{where}: {value:g} outside the allowed range "
                             f"{'(' if low_open else '['}{low:g}, {high:g}]")
        return value

    def reader(self, line, row):
        """``number`` bound to one row: ``f(column, low, high, low_open, optional=...)``."""
        def read(column, low=-math.inf, high=math.inf, low_open=False, optional=False):
            return self.number(line, row, column, low, high, optional=optional, low_open=low_open)
        return read

    def text(self, line, row, column, allowed=None, required=True):
        value = row[column]
        if required and not value:
            raise InputError(f"{self.name} line {line} column {column!r}: empty")
        if allowed is not None and value not in allowed:
            raise InputError(f"{self.name} line {line} column {column!r}: {value!r} is not one "
                             f"of {', '.join(allowed)}")
        return value

    def unique(self, records, key):
        seen = {}
        for r in records:
            k = getattr(r, key)
            if k in seen:
                raise InputError(f"{self.name} line {r.line}: duplicate {key} {k!r} "
                                 f"(first on line {seen[k]})")
            seen[k] = r.line
        return records


_BARRIER_COLUMNS = ["iihs_id", "group", "my", "vehicle", "vehicle_type", "barrier", "overlap_pct",
                    "e", "mu_pct_mu0", "d1_ft", "phi_deg", "Gamma_deg", "v0_fps", "dVx_fps",
                    "dV_fps", "dVy_fps", "Omega_dps"]


def load_barrier(path=None) -> list[BarrierTest]:
    """The IIHS small-overlap barrier tests (Brach et al. 2014, App. 2 part 1), in SI."""
    rows = _Rows(path or data_path(BARRIER_FILE), _BARRIER_COLUMNS)
    out = []
    for line, r in rows.rows:
        n = rows.reader(line, r)
        year = n("my", 1900, 2100)
        if year != int(year):
            raise InputError(f"{rows.name} line {line} column 'my': {year:g} is not a year")
        out.append(BarrierTest(
            test_id=rows.text(line, r, "iihs_id"), group=rows.text(line, r, "group", GROUPS),
            model_year=int(year), vehicle=rows.text(line, r, "vehicle"),
            vehicle_type=rows.text(line, r, "vehicle_type"),
            barrier=rows.text(line, r, "barrier"), overlap_pct=n("overlap_pct", 0, 100, True),
            restitution=n("e", 0, 1), beta=n("mu_pct_mu0", 0, 100) / 100.0,
            d=n("d1_ft", 0, 20, True) * FT, phi=n("phi_deg", -180, 180) * DEG,
            normal_angle=n("Gamma_deg", -180, 180) * DEG,
            speed=n("v0_fps", 0, 300, True) * FT, delta_v_x=n("dVx_fps", 0, 300) * FT,
            delta_v=n("dV_fps", 0, 300) * FT, delta_v_y=n("dVy_fps", 0, 300) * FT,
            yaw_rate=n("Omega_dps", 0, 3600) * DEG, line=line))
    return rows.unique(out, "test_id")


_CAR_TO_CAR_COLUMNS = ["iihs_id", "group", "vehicle", "overlap", "e", "mu_pct_mu0", "Phi_deg",
                       "Gamma_deg", "v0_fps", "dV_fps", "Omega_dps"]


def load_car_to_car(path=None) -> list[CarToCarVehicle]:
    """The IIHS car-to-car vehicles (Brach et al. 2014, App. 2 part 2), in SI."""
    rows = _Rows(path or data_path(CAR_TO_CAR_FILE), _CAR_TO_CAR_COLUMNS)
    out = []
    for line, r in rows.rows:
        n = rows.reader(line, r)
        test_id = rows.text(line, r, "iihs_id")
        if test_id[-1:] not in ("a", "b"):
            raise InputError(f"{rows.name} line {line} column 'iihs_id': {test_id!r} must end "
                             "in a or b (the two vehicles of one test)")
        out.append(CarToCarVehicle(
            test_id=test_id, group=rows.text(line, r, "group", ("NS", "SS")),
            vehicle=rows.text(line, r, "vehicle"), overlap=rows.text(line, r, "overlap"),
            restitution=n("e", 0, 1), beta=n("mu_pct_mu0", 0, 100) / 100.0,
            phi=n("Phi_deg", -180, 180) * DEG, normal_angle=n("Gamma_deg", -180, 180) * DEG,
            speed=n("v0_fps", 0, 300, True) * FT, delta_v=n("dV_fps", 0, 300) * FT,
            yaw_rate=n("Omega_dps", 0, 3600) * DEG, line=line))
    rows.unique(out, "test_id")
    by_test = {}
    for v in out:
        by_test.setdefault(v.test_id[:-1], []).append(v)
    for test, pair in by_test.items():
        if len(pair) != 2:
            raise InputError(f"{rows.name} line {pair[0].line}: test {test} has {len(pair)} "
                             "vehicle rows, expected 2 (a and b)")
        a, b = pair
        for attr in ("restitution", "beta", "normal_angle", "group"):
            if getattr(a, attr) != getattr(b, attr):
                raise InputError(f"{rows.name} line {b.line}: {attr} of {b.test_id} differs "
                                 f"from {a.test_id} (one impact has one value)")
    return out


_RICSAC_DV = ("raw_JB", "BrachSmith2002", "McHenry", "PIM1991", "PIM1998", "PIM2002")
_RICSAC_COLUMNS = (["ricsac", "veh1", "veh2", "m1_kg", "I1_kgm2", "m2_kg", "I2_kgm2",
                    "v1_pre_meas_mps", "v2_pre_meas_mps", "Gamma_deg", "theta1_deg", "theta2_deg",
                    "phi1_deg", "phi2_deg", "Vi1x", "Vi1y", "Vi2x", "Vi2y", "Vf1x", "Vf1y",
                    "Wf1_radps", "Vf2x", "Vf2y", "Wf2_radps"]
                   + [f"dV{i}_{a}" for a in _RICSAC_DV for i in (1, 2)]
                   + ["chk_dV1_from_Vossou", "chk_dV2_from_Vossou", "chk_momentum_residual_pct",
                      "chk_m1dV1_over_m2dV2_BrachSmith"])
_RICSAC_MOTION = ["Gamma_deg", "theta1_deg", "theta2_deg", "phi1_deg", "phi2_deg", "Vi1x", "Vi1y",
                  "Vi2x", "Vi2y", "Vf1x", "Vf1y", "Wf1_radps", "Vf2x", "Vf2y", "Wf2_radps"]


def load_ricsac(path=None) -> list[RicsacTest]:
    """The RICSAC staged collisions (compiled from Neades and Vossou & Koulocheris), in SI.

    A row's motion columns are all given or all empty (test 2); the ``chk_*`` columns are
    computed by the compiler, not source data, and are not read.
    """
    rows = _Rows(path or data_path(RICSAC_FILE), _RICSAC_COLUMNS)
    out = []
    for line, r in rows.rows:
        n = rows.reader(line, r)
        number = n("ricsac", 1, 99)
        if number != int(number):
            raise InputError(f"{rows.name} line {line} column 'ricsac': {number:g} is not a "
                             "test number")
        given = [c for c in _RICSAC_MOTION if r[c] != ""]
        if given and len(given) != len(_RICSAC_MOTION):
            empty = [c for c in _RICSAC_MOTION if r[c] == ""]
            raise InputError(f"{rows.name} line {line} column {empty[0]!r}: empty, but other "
                             "motion columns of the row are given (all or none)")
        m = {c: n(c, -100, 100, optional=True) for c in _RICSAC_MOTION if "deg" not in c}
        a = {c: n(c, -360, 360, optional=True) for c in _RICSAC_MOTION if "deg" in c}
        vec = lambda x, y, m=m: None if m[x] is None else (m[x], m[y])  # noqa: E731
        rad = lambda c, a=a: None if a[c] is None else a[c] * DEG  # noqa: E731
        out.append(RicsacTest(
            number=int(number), vehicle1=rows.text(line, r, "veh1", required=False),
            vehicle2=rows.text(line, r, "veh2", required=False),
            mass1=n("m1_kg", 0, 1e5, True), yaw_inertia1=n("I1_kgm2", 0, 1e6, True),
            mass2=n("m2_kg", 0, 1e5, True), yaw_inertia2=n("I2_kgm2", 0, 1e6, True),
            speed1_measured=n("v1_pre_meas_mps", 0, 100),
            speed2_measured=n("v2_pre_meas_mps", 0, 100),
            normal_angle=rad("Gamma_deg"), theta1=rad("theta1_deg"), theta2=rad("theta2_deg"),
            phi1=rad("phi1_deg"), phi2=rad("phi2_deg"),
            velocity1_pre=vec("Vi1x", "Vi1y"), velocity2_pre=vec("Vi2x", "Vi2y"),
            velocity1_post=vec("Vf1x", "Vf1y"), velocity2_post=vec("Vf2x", "Vf2y"),
            yaw_rate1_post=m["Wf1_radps"], yaw_rate2_post=m["Wf2_radps"],
            published_delta_v={k: tuple(n(f"dV{i}_{k}", 0, 100, optional=True) for i in (1, 2))
                               for k in _RICSAC_DV},
            line=line))
    return rows.unique(out, "number")


_NHTSA_COLUMNS = ["nhtsa_test", "vehicle1", "vehicle2", "weight1_lb", "izz1_lbfts2",
                  "weight2_lb", "izz2_lbfts2", "speed1_mph", "speed2_mph", "heading1_deg",
                  "heading2_deg", "d1_ft", "phi1_deg", "d2_ft", "phi2_deg", "normal_deg", "cor",
                  "critical_ir", "impulse_ratio", "dv1_mph", "dv2_mph", "domega1_dps",
                  "domega2_dps"]


def load_nhtsa_car_to_car(path=None) -> list[NhtsaCarToCarTest]:
    """The NHTSA car-to-car tests of Rose, Fenton & Beauchamp (SAE 2006-01-0908), in SI."""
    rows = _Rows(path or data_path(NHTSA_FILE), _NHTSA_COLUMNS)
    out = []
    for line, r in rows.rows:
        n = rows.reader(line, r)
        vehicles = {}
        for i in (1, 2):
            vehicles.update({
                f"mass{i}": n(f"weight{i}_lb", 0, 1e5, True) * LB,
                f"yaw_inertia{i}": n(f"izz{i}_lbfts2", 0, 1e6, True) * SLUG_FT2,
                f"speed{i}": n(f"speed{i}_mph", 0, 200) * MPH,
                f"heading{i}": n(f"heading{i}_deg", -360, 360) * DEG,
                f"d{i}": n(f"d{i}_ft", 0, 30) * FT, f"phi{i}": n(f"phi{i}_deg", -360, 360) * DEG,
                f"delta_v{i}": n(f"dv{i}_mph", 0, 200) * MPH,
                f"yaw_change{i}": n(f"domega{i}_dps", 0, 3600) * DEG})
        out.append(NhtsaCarToCarTest(
            test=rows.text(line, r, "nhtsa_test"), vehicle1=rows.text(line, r, "vehicle1"),
            vehicle2=rows.text(line, r, "vehicle2"),
            normal_angle=n("normal_deg", -360, 360) * DEG, restitution=n("cor", 0, 1),
            mu0=n("critical_ir", -10, 10), beta=n("impulse_ratio", 0, 1), line=line,
            **vehicles))
    return rows.unique(out, "test")


#: Dataset name -> loader.
DATASETS = {"iihs-barrier": load_barrier, "iihs-car-to-car": load_car_to_car,
            "ricsac": load_ricsac, "nhtsa-car-to-car": load_nhtsa_car_to_car}


def load_dataset(name: str, path=None):
    """Records of a bundled dataset by name (see :data:`DATASETS`)."""
    if name not in DATASETS:
        raise InputError(f"unknown dataset {name!r} (allowed: {', '.join(DATASETS)})")
    return DATASETS[name](path)
