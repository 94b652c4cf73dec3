"""Speeds before the impact from each vehicle's pre-impact evidence, for ``pim solve`` and
``pim reconstruct``.

For every vehicle with ``[evidence.vehicleN.pre_impact]`` marks (:mod:`pim.model.pre_impact`,
eq. (2)) or a ``[driver.vehicleN]`` table starting before the impact
(:func:`pim.model.pre_impact.driver_start_speed`), the impact speed (the case's, or the
reconstruction's) becomes the speed at the start of the marks or at the table's first time.

The reconstruction's 5/50/95 % (:func:`reconstruction_pre_impact`): per Monte Carlo sample
used by the reconstruction, that sample's impact speed (its unknowns put into the fitted
case by :func:`pim.analysis.free_inputs.free_inputs`) with the marks' friction and length
drawn from ``[uncertainty]`` (``evidence.vehicleN.pre_impact.friction`` and
``.skid_length``; independent of the impact's inputs, so drawn here with their own
generator seeded from the reconstruction's seed), through
:meth:`pim.model.pre_impact.PreImpactMarks.start_speed` on the arrays. The driver path's
start speed is an increasing function of the impact speed alone (friction, tyre and table
fixed), so its percentiles are those of the impact speed carried through the root find.
A vehicle whose speed is not an unknown keeps the case's impact speed in every sample.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model.distributions import UncertaintyTable, sample_inputs
from ..model.numbers import InputError
from ..model.pre_impact import PreImpactMarks, driver_start_speed
from .free_inputs import STATE, case_state, free_inputs
from .montecarlo import PERCENTILES, first_order_indices

__all__ = ["PreImpactSpeed", "case_pre_impact", "reconstruction_pre_impact",
           "impact_speed_samples", "draw_marks", "PRE_IMPACT_SEED_KEY"]

#: Spawn key of the generator that draws the marks' friction and length (from the
#: reconstruction's seed: a run repeats, and the impact's draws are not disturbed).
PRE_IMPACT_SEED_KEY = 19


@dataclass(frozen=True)
class PreImpactSpeed:
    """One vehicle's speed before the impact [SI].

    Attributes
    ----------
    vehicle : int (1 or 2)
    source : "marks" (tyre marks before the impact) or "driver" (a driver table)
    impact_speed : float [m/s] the speed at the impact it starts from
    start_speed : float [m/s] at the start of the marks, or at ``start_time``
    p5, p50, p95 : float [m/s] over the Monte Carlo (NaN without one)
    n_used : int, samples behind the percentiles
    marks : PreImpactMarks or None
    start_time : float [s] or None, the driver table's first time
    varied : tuple of str, the inputs drawn besides the impact speed
    drivers : tuple of (str, float), first-order variance indices of the start speed over
        the samples (the impact speed ranked as its empirical CDF, and the drawn marks),
        largest first (empty without a Monte Carlo of the marks)
    """

    vehicle: int
    source: str
    impact_speed: float
    start_speed: float
    p5: float = float("nan")
    p50: float = float("nan")
    p95: float = float("nan")
    n_used: int = 0
    marks: PreImpactMarks | None = None
    start_time: float | None = None
    varied: tuple = field(default=())
    drivers: tuple = field(default=())

    @property
    def name(self) -> str:
        """Dotted name in tables and JSON."""
        return (f"vehicle{self.vehicle}.speed_at_marks_start" if self.source == "marks"
                else f"vehicle{self.vehicle}.speed_at_driver_start")


def _sources(case):
    """(vehicle number, evidence, marks or None, driver start time or None) per vehicle with
    pre-impact evidence."""
    out = []
    evidence = case.evidence
    for i in (1, 2):
        if evidence is None:
            continue
        ev, marks = getattr(evidence, f"vehicle{i}"), evidence.pre_impact(i)
        start = None
        if ev is not None and ev.driver is not None and float(ev.driver.time[0]) < 0:
            start = float(ev.driver.time[0])
        if marks is not None or start is not None:
            out.append((i, ev, marks, start))
    return out


def _driver_start(case, i, ev, impact_speed, start_time) -> float:
    vehicle = getattr(case, f"vehicle{i}")
    runout_vehicle = ev.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia))
    return driver_start_speed(runout_vehicle, impact_speed, start_time,
                              where=f"driver.vehicle{i}")


def _speed(case, i) -> float:
    return float(np.hypot(*np.asarray(getattr(case, f"vehicle{i}").velocity, dtype=float)))


def case_pre_impact(case, impact_speeds: dict | None = None) -> list[PreImpactSpeed]:
    """The speed before the impact of each vehicle with pre-impact evidence (no intervals).

    Parameters
    ----------
    case : Case (single) with ``evidence``.
    impact_speeds : dict vehicle number -> impact speed [m/s], optional; default the
        magnitude of the case's pre-impact velocities.
    """
    speeds = impact_speeds or {}
    out = []
    for i, ev, marks, start in _sources(case):
        v = float(speeds.get(i, _speed(case, i)))
        if marks is not None:
            out.append(PreImpactSpeed(i, "marks", v, float(marks.start_speed(v)),
                                      marks=marks))
        if start is not None:
            out.append(PreImpactSpeed(i, "driver", v, _driver_start(case, i, ev, v, start),
                                      start_time=start))
    return out


def impact_speed_samples(rec) -> dict:
    """Each vehicle's impact speed [m/s] per used Monte Carlo sample of a reconstruction
    (its unknowns put into the fitted case); a vehicle whose velocity is not an unknown
    keeps the fitted case's speed."""
    keys = tuple(rec.fit.values)
    x = np.stack([np.asarray(rec.samples.samples[k], dtype=float) for k in keys], axis=-1)
    state, _ = free_inputs(case_state(rec.fit.case), keys, x)
    out = {}
    for i in (1, 2):
        vx = state[:, STATE.index(f"vehicle{i}.velocity_x")]
        vy = state[:, STATE.index(f"vehicle{i}.velocity_y")]
        out[i] = np.hypot(vx, vy)
    return out


def draw_marks(marks: PreImpactMarks, uncertainty, i: int, n: int, rng):
    """The marks' ``(length (n,), friction (n,), uniforms)`` drawn from the
    ``[uncertainty]`` entries ``evidence.vehicle<i>.pre_impact.skid_length`` and
    ``.friction`` (their nominal values where none is given)."""
    prefix = f"evidence.vehicle{i}.pre_impact."
    nominal = {prefix + "skid_length": marks.skid_length, prefix + "friction": marks.friction}
    table = UncertaintyTable({k: d for k, d in (uncertainty.inputs.items() if uncertainty
                                                else ()) if k in nominal})
    values, uniforms = sample_inputs(table, nominal, n, rng)
    each = [np.broadcast_to(np.asarray(values[prefix + k], dtype=float), (n,))
            for k in ("skid_length", "friction")]
    return each[0], each[1], uniforms


def _drivers(start, impact, uniforms, i) -> tuple:
    """First-order indices of the start speeds: the impact speed (ranked: its empirical CDF,
    a monotone map like the inverse-CDF draws) and the drawn marks."""
    if start.size < 10:
        return ()
    ranks = (np.argsort(np.argsort(impact, kind="stable"), kind="stable") + 0.5) / impact.size
    found = first_order_indices(start, {f"vehicle{i}.speed (impact)": ranks, **uniforms})
    return tuple((name, float(index)) for name, index in found)


def _check_uncertainty(case, sources) -> None:
    """InputError for pre-impact uncertainty entries of a vehicle without marks."""
    have = {i for i, _, marks, _ in sources if marks is not None}
    for name in (case.uncertainty.inputs if case.uncertainty else {}):
        if ".pre_impact." in name and int(name.split(".")[1][-1]) not in have:
            raise InputError(f"uncertainty.{name}: the case has no "
                             f"[{name.rsplit('.', 1)[0]}] marks to vary")


def reconstruction_pre_impact(rec, seed: int = 0) -> list[PreImpactSpeed]:
    """The speed before the impact of each vehicle with pre-impact evidence, from a
    :class:`pim.analysis.reconstruction.Reconstruction` (module notes), with 5/50/95 % when
    it has a Monte Carlo."""
    case = rec.case
    sources = _sources(case)
    _check_uncertainty(case, sources)
    if not sources or rec.fit is None:
        return []
    nominal = case_pre_impact(case, {i: _speed(rec.fit.case, i) for i in (1, 2)})
    if not rec.samples or not rec.samples.n_used:
        return nominal
    impact = impact_speed_samples(rec)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(PRE_IMPACT_SEED_KEY,)))
    out = []
    for row in nominal:
        v = impact[row.vehicle]
        if row.source == "marks":
            length, friction, uniforms = draw_marks(row.marks, case.uncertainty, row.vehicle,
                                                    v.size, rng)
            start = row.marks.start_speed(v, length=length, friction=friction)
            p = np.percentile(start, PERCENTILES)
            varied, drivers = tuple(uniforms), _drivers(start, v, uniforms, row.vehicle)
        else:
            ev = getattr(case.evidence, f"vehicle{row.vehicle}")
            p = [_driver_start(case, row.vehicle, ev, q, row.start_time)
                 for q in np.percentile(v, PERCENTILES)]
            varied, drivers = (), ()
        out.append(PreImpactSpeed(row.vehicle, row.source, row.impact_speed, row.start_speed,
                                  *(float(x) for x in p), n_used=int(v.size), marks=row.marks,
                                  start_time=row.start_time, varied=varied, drivers=drivers))
    return out
