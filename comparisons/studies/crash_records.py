"""The bundled crash tests as both models run them: records by crash class, the origin of
every input, and the input variants of the leave-one-out study.

Classes (:func:`crash_classes`):

* the IIHS small-overlap barrier tests, non-sideswipe (16) and sideswipe (24), Brach, Welsh &
  Brach, SAE 2014-01-0469 (:func:`pim.analysis.validation.barrier_case`);
* the RICSAC tests whose measured motion balances linear momentum (3, 6, 11:
  :func:`pim.analysis.consistency.check_ricsac`) on the crush-edge geometry of
  :func:`pim.analysis.validation.ricsac_case`, and RICSAC 9 as the design sheet gives it
  (``pim.load_case("ricsac9")``, a class of one);
* the four NHTSA car-to-car tests of Rose, Fenton & Beauchamp (SAE 2006-01-0908,
  :func:`pim.analysis.validation.nhtsa_case`), whose tabulated outcome is the authors' PIM
  output (delta-V and yaw-rate change magnitudes), not measured motion.

The IIHS car-to-car table gives no masses, inertias or impact geometry: neither model can run
on it (:data:`UNRUNNABLE`).

**Where the barrier inputs come from.** d1, Gamma and the impact speed are published
geometry and measurements; phi was fitted with PIM by Brach et al. to each test's own motion,
and the yaw inertia is not published (the harness fits a radius of gyration k per test with
the published coefficients, :func:`pim.analysis.validation.fit_radius_of_gyration`). A test's
own phi or k would carry its outcome into its own prediction, so the study runs *folds*: fold
f holds test f out, and every test of fold f takes

* phi: the median of the published phi over the class's other tests (:data:`LEAK_FREE`), or
  each test's published phi (:data:`PUBLISHED_PHI`, the leaking variant shown beside it);
* k: the median per vehicle type of the fitted k of the barrier tests other than f (over
  every type when f was the only one of its type).

Fold n (one past the last test) holds no test out: the class fit's inputs.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import pim
from pim.analysis.consistency import check_ricsac
from pim.analysis.validation import (
    SPEED_TOLERANCE,
    YAW_TOLERANCE,
    barrier_case,
    fit_radius_of_gyration,
    nhtsa_case,
    nhtsa_motion,
    ricsac_case,
)
from pim.io.datasets import (
    ESTIMATED,
    MEASURED,
    PIM_OUTPUT,
    PUBLISHED_GEOMETRY,
    load_barrier,
    load_nhtsa_car_to_car,
    load_ricsac,
)

__all__ = ["CrashRecord", "InputVariant", "crash_classes", "input_variants", "UNRUNNABLE",
           "VELOCITY", "MAGNITUDES", "LEAK_FREE", "PUBLISHED_PHI", "PUBLISHED_INPUTS",
           "NON_SIDESWIPE", "SIDESWIPE", "RICSAC", "RICSAC9", "CAR_TO_CAR", "CLASS_NAMES",
           "CLASS_KEYS", "USED_FIELDS",
           "fitted_radii"]

NON_SIDESWIPE = "IIHS barrier, non-sideswipe"
SIDESWIPE = "IIHS barrier, sideswipe"
RICSAC = "RICSAC, momentum-consistent"
RICSAC9 = "RICSAC 9, design sheet"
CAR_TO_CAR = "NHTSA car-to-car (Rose et al.)"
#: The classes in the order of the report.
CLASS_NAMES = (NON_SIDESWIPE, SIDESWIPE, RICSAC, RICSAC9, CAR_TO_CAR)
#: Short key of each class (command line, JSON) -> its name.
CLASS_KEYS = {"non-sideswipe": NON_SIDESWIPE, "sideswipe": SIDESWIPE, "ricsac": RICSAC,
              "ricsac9": RICSAC9, "car-to-car": CAR_TO_CAR}
#: Observables: post-impact (vx, vy, omega) of each moving vehicle ...
VELOCITY = "post-impact velocity and yaw rate"
#: ... or (|delta-V|, |yaw-rate change|) of each vehicle (the NHTSA table's quantities).
MAGNITUDES = "delta-V and yaw-rate change magnitudes"
#: Variant names.
LEAK_FREE = "leak-free"
PUBLISHED_PHI = "published PIM-fitted phi"
PUBLISHED_INPUTS = "published inputs"
#: Datasets with measured motion that neither model can run, and why.
UNRUNNABLE = {"iihs-car-to-car": "the table gives no masses, yaw inertias or impact geometry "
                                 "(coefficient statistics only)"}

_K_ORIGIN = ("median per vehicle type of the radius of gyration fitted with PIM (published "
             "coefficients) on the other barrier tests, the held-out test excluded")


@dataclass(frozen=True, eq=False)
class CrashRecord:
    """One crash test as both models see it.

    Attributes
    ----------
    crash_class : str
        The crash class it belongs to.
    name : str
        The test's name.
    case : pim.Case
        The test with its published inputs (barrier tests: the published phi and the class
        radius of gyration of every barrier test; a leave-one-out fold builds its own,
        :class:`InputVariant`).
    observed : ndarray (k,)
        What the models are fitted to and judged on [m/s, rad/s] (``observable``).
    scale : ndarray (k,)
        Residual scale of each observed value: 1 mph, 10 deg/s.
    observable : str
        :data:`VELOCITY` or :data:`MAGNITUDES`.
    outcome_origin : str
        Origin of ``observed`` (:mod:`pim.io.datasets` origins).
    origins : dict of str to str
        Input -> origin, as the record's dataset states it, for the fields the study takes
        (:data:`USED_FIELDS`).
    source : object
        The dataset record (:mod:`pim.io.datasets`), or None.
    """

    crash_class: str
    name: str
    case: pim.Case
    observed: np.ndarray
    scale: np.ndarray
    observable: str
    outcome_origin: str
    origins: dict = field(default_factory=dict)
    source: object = None

    __test__ = False      # not a pytest class

    @property
    def moving(self) -> tuple[int, ...]:
        """The vehicles that move (1, or 1 and 2)."""
        return (1,) if bool(np.all(self.case.vehicle2.fixed)) else (1, 2)

    def observe(self, case: pim.Case, v1, w1, v2, w2) -> np.ndarray:
        """The observables of a model's post-impact velocities [m/s] and yaw rates [rad/s]
        (arrays broadcast; the last axis holds the k values)."""
        if self.observable == MAGNITUDES:
            return nhtsa_motion(case, v1, w1, v2, w2)
        parts = [np.asarray(v1, float), np.asarray(w1, float)[..., None]]
        if 2 in self.moving:
            parts += [np.asarray(v2, float), np.asarray(w2, float)[..., None]]
        shape = np.broadcast_shapes(*(p.shape[:-1] for p in parts))
        return np.concatenate([np.broadcast_to(p, shape + p.shape[-1:]) for p in parts],
                              axis=-1)


#: The dataset fields the study takes (inputs and outcome), by record type: the records'
#: other fields (the authors' fitted e and mu, published delta-V analyses) never enter it.
USED_FIELDS = {
    "BarrierTest": ("speed", "d", "phi", "normal_angle", "delta_v_x", "delta_v_y",
                    "yaw_rate"),
    "RicsacTest": ("mass1", "mass2", "yaw_inertia1", "yaw_inertia2", "velocity1_pre",
                   "velocity2_pre", "normal_angle", "theta1", "theta2", "phi1", "phi2",
                   "velocity1_post", "velocity2_post", "yaw_rate1_post", "yaw_rate2_post"),
    "NhtsaCarToCarTest": ("mass1", "mass2", "yaw_inertia1", "yaw_inertia2", "speed1",
                          "speed2", "heading1", "heading2", "d1", "phi1", "d2", "phi2",
                          "normal_angle", "delta_v1", "delta_v2", "yaw_change1",
                          "yaw_change2"),
}


def _used(source) -> dict:
    """The origins of the fields of ``source`` the study takes (:data:`USED_FIELDS`)."""
    return {k: source.origins[k] for k in USED_FIELDS[type(source).__name__]}


def _velocity_record(crash_class, name, case, origins, source=None) -> CrashRecord:
    m = case.measured
    observed = [np.asarray(m.velocity1, float), [float(m.yaw_rate1)]]
    scale = [SPEED_TOLERANCE, SPEED_TOLERANCE, YAW_TOLERANCE]
    if not bool(np.all(case.vehicle2.fixed)):
        observed += [np.asarray(m.velocity2, float), [float(m.yaw_rate2)]]
        scale = scale * 2
    return CrashRecord(crash_class, name, case, np.concatenate(observed), np.array(scale),
                       VELOCITY, MEASURED, origins=dict(origins), source=source)


def _nhtsa_record(test) -> CrashRecord:
    observed = np.array([test.delta_v1, test.yaw_change1, test.delta_v2, test.yaw_change2])
    scale = np.array([SPEED_TOLERANCE, YAW_TOLERANCE] * 2)
    return CrashRecord(CAR_TO_CAR, f"nhtsa{test.test}", nhtsa_case(test), observed, scale,
                       MAGNITUDES, PIM_OUTPUT, origins=_used(test), source=test)


def fitted_radii() -> tuple[list, dict]:
    """The barrier tests the authors kept and the radius of gyration k [m] fitted to each
    (:func:`pim.analysis.validation.fit_radius_of_gyration`): (tests, test_id -> k)."""
    barrier = [t for t in load_barrier() if t.group != "OUTLIER"]
    return barrier, {t.test_id: fit_radius_of_gyration(t) for t in barrier}


def _fold_k(test, barrier, radii, held: str | None) -> float:
    """k of ``test`` in the fold that holds ``held`` out (module notes)."""
    same = [radii[t.test_id] for t in barrier
            if t.test_id != held and t.vehicle_type == test.vehicle_type]
    pool = same or [radii[t.test_id] for t in barrier if t.test_id != held]
    return float(np.median(pool))


def _barrier_records(group: str, label: str, barrier, radii) -> list[CrashRecord]:
    tests = [t for t in barrier if t.group == group]
    out = []
    for t in tests:
        case = barrier_case(t, _fold_k(t, barrier, radii, None))
        origins = dict(_used(t), radius_of_gyration=_K_ORIGIN)
        out.append(_velocity_record(label, t.test_id, case, origins, t))
    return out


def crash_classes(max_tests: int | None = None,
                  radii: tuple | None = None) -> dict[str, list[CrashRecord]]:
    """The bundled tests both models can run, by crash class (module notes);
    ``max_tests`` keeps the first few of each class (fast checks); ``radii``: the output
    of :func:`fitted_radii` (computed when None)."""
    barrier, radii = fitted_radii() if radii is None else radii
    out = {NON_SIDESWIPE: _barrier_records("NS", NON_SIDESWIPE, barrier, radii),
           SIDESWIPE: _barrier_records("SS", SIDESWIPE, barrier, radii)}
    ricsac = [t for t in load_ricsac() if t.has_motion and t.normal_angle is not None]
    flagged = {c.test.split()[1] for c in check_ricsac(ricsac) if c.flagged}
    crush_edge = {"impact point C": "on the undeformed outline (length sqrt(12) k, k from the "
                                    f"inertia, {ESTIMATED}) at the published phi"}
    out[RICSAC] = [_velocity_record(RICSAC, f"ricsac{t.number}", ricsac_case(t),
                                    dict(_used(t), **crush_edge), t)
                   for t in ricsac if str(t.number) not in flagged]
    sheet = {"masses, inertias, pre-impact motion": MEASURED,
             "impact point C, normal": PUBLISHED_GEOMETRY + " (the design sheet's)"}
    out[RICSAC9] = [_velocity_record(RICSAC9, "ricsac9", pim.load_case("ricsac9"), sheet)]
    out[CAR_TO_CAR] = [_nhtsa_record(t) for t in load_nhtsa_car_to_car()]
    if max_tests is not None:
        out = {k: v[:max_tests] for k, v in out.items()}
    return out


@dataclass(frozen=True, eq=False)
class InputVariant:
    """The inputs of a class's tests in every fold (module notes).

    Attributes
    ----------
    name : str
        :data:`LEAK_FREE`, :data:`PUBLISHED_PHI` or :data:`PUBLISHED_INPUTS`.
    description : str
        One sentence on what the variant takes.
    origins : dict of str to str
        Input -> origin as this variant uses it.
    phi, radius_of_gyration : ndarray (n, n + 1) or None
        Barrier tests: phi [rad] and k [m] of test t in fold f (f = n: no test held out);
        None for the other classes (their cases do not change with the fold).
    """

    name: str
    description: str
    origins: dict
    phi: np.ndarray | None = None
    radius_of_gyration: np.ndarray | None = None

    def case(self, index: int, record: CrashRecord, folds) -> pim.Case:
        """Record ``index``'s case in the folds ``folds`` (an integer array: a batch of
        cases of its shape)."""
        if self.phi is None:
            return record.case
        folds = np.asarray(folds, dtype=int)
        return barrier_case(record.source, self.radius_of_gyration[index][folds],
                            phi=self.phi[index][folds])


def _fold_table(records, value) -> np.ndarray:
    """(n, n + 1) array: ``value(test, held_test_id or None)`` for each test and fold."""
    held = [r.source.test_id for r in records] + [None]
    return np.array([[value(r.source, h) for h in held] for r in records])


def _median_phi(records, held: str | None) -> float:
    return float(np.median([r.source.phi for r in records if r.source.test_id != held]))


def input_variants(records: list[CrashRecord], radii: tuple | None = None) -> list[InputVariant]:
    """The input variants of a class (module notes): barrier classes :data:`LEAK_FREE` and
    :data:`PUBLISHED_PHI`; the others :data:`PUBLISHED_INPUTS`. ``radii``: the output of
    :func:`fitted_radii` (computed when None)."""
    if not records or records[0].source is None or not hasattr(records[0].source, "group"):
        origins = dict(records[0].origins) if records else {}
        return [InputVariant(PUBLISHED_INPUTS, "the inputs as published (none of them fitted "
                                               "to the test's own outcome by the harness)",
                             origins)]
    barrier, k = fitted_radii() if radii is None else radii
    ks = _fold_table(records, lambda t, h: _fold_k(t, barrier, k, h))
    median = _fold_table(records, lambda t, h: _median_phi(records, h))
    published = _fold_table(records, lambda t, h: t.phi)
    base = dict(records[0].origins, radius_of_gyration=_K_ORIGIN)
    return [
        InputVariant(LEAK_FREE, "phi: the median of the published phi of the class's other "
                                "tests; k: the other tests' fitted radii of gyration",
                     dict(base, phi="median of the other tests' published phi (each fitted "
                                    "by PIM on its own test, never on the held-out one)"),
                     median, ks),
        InputVariant(PUBLISHED_PHI, "each test's own published phi, which Brach et al. "
                                    "fitted with PIM to that test's motion (leaks the outcome)",
                     base, published, ks),
    ]
