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

A malformed or edited file raises ValueError naming the file, the row (line number) and
the column.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ..model.numbers import InputError

__all__ = ["BarrierTest", "CarToCarVehicle", "RicsacTest", "DATASETS", "load_barrier",
           "load_car_to_car", "load_ricsac", "load_dataset", "data_path", "source_lines"]

FT = 0.3048                 # m per ft (exact)
DEG = math.pi / 180.0       # rad per deg

BARRIER_FILE = "brach2014_iihs_small_overlap_vehicle_to_barrier.csv"
CAR_TO_CAR_FILE = "brach2014_iihs_small_overlap_vehicle_to_vehicle.csv"
RICSAC_FILE = "ricsac_1-12_compiled.csv"

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

    @property
    def has_motion(self) -> bool:
        """True when measured pre- and post-impact motion is available."""
        return self.velocity1_post is not None


def data_path(name: str) -> Path:
    """Path of a bundled data file."""
    return Path(str(resources.files("pim.io") / "data" / name))


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


#: Dataset name -> loader.
DATASETS = {"iihs-barrier": load_barrier, "iihs-car-to-car": load_car_to_car,
            "ricsac": load_ricsac}


def load_dataset(name: str, path=None):
    """Records of a bundled dataset by name (see :data:`DATASETS`)."""
    if name not in DATASETS:
        raise InputError(f"unknown dataset {name!r} (allowed: {', '.join(DATASETS)})")
    return DATASETS[name](path)
