"""The configurations of ``pim assumptions``: which of PIM's assumptions each rung keeps.

A :class:`RungConfig` is the typed configuration of one simulated crush scene: which of
PIM's assumptions it keeps, at which parameter values, and where its impulse acts.
:func:`ladder_configs` builds the ladder at one contact time, each rung from its baseline
by changing exactly one assumption (:func:`changed_assumptions` says which; a test checks
every rung against its baseline):

============  =============================================  ================================
rung          assumption relaxed                             baseline (same contact time)
============  =============================================  ================================
law           Newton's restitution and mu = beta mu0         pim (``pim.solve``)
duration      instantaneous impulse                          law
outline       one contact point                              centroid
tyres         no external forces (wheels rolling)            outline (duration without one)
tyres_locked  no external forces (wheels locked)             outline (duration without one)
friction      PIM's tangential law                           tyres
============  =============================================  ================================

Where the impulse acts (``point``: the sheet's C and Gamma, or the line the illustrative
outlines' impulse acts on) is an *input* of PIM, not one of its assumptions: the
"centroid" configuration (the "duration" scene moved to where the outlines' impulse acts)
is the outline rung's baseline and, against the "duration" scene, the input-uncertainty
block "where C is" beside the ladder, never a rung (:data:`INPUT_FIELDS`).

The unmeasured parameters are ranges, not one chosen value: the contact time over
:data:`CONTACT_RANGE` (McHenry's 50-150 ms for the momentum exchange; Steffan and Moser,
SAE 960886: 45-60 ms to maximum engagement; docs/contact-model.md), the tangential
recovery r over [0, 1] (:func:`recoveries`), the wheels rolling and locked. The typical
values (:data:`TYPICAL`) are where the table and the regression baseline read the ladder.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

from sim.contact_law import tangential_recovery_default

__all__ = ["RungConfig", "Plan", "RUNGS", "ASSUMPTION_FIELDS", "INPUT_FIELDS", "TYPICAL",
           "CONTACT_RANGE", "RANGE_DURATIONS", "DURATIONS", "STIFF_LIMIT", "STICKING",
           "TYRE_FRICTIONS", "TYRE_MODES", "FRICTIONS", "HOLDS", "ROUGHLY",
           "changed_assumptions", "changed_inputs", "ladder_configs", "baseline_of",
           "recoveries", "plan"]

#: Marginal effect below which an assumption is negligible, and below which it is moderate.
HOLDS, ROUGHLY = 0.05, 0.15
#: Typical values of the physical parameters, written once: contact time [s], tyre friction
#: [-], friction between the vehicles [-] (the table's ladder and the regression baseline).
TYPICAL = {"duration": 0.1, "tyre_friction": 0.7, "friction": 0.5}
#: The contact times a car-to-car or car-to-barrier impact takes [s]: McHenry's 50-150 ms
#: (docs/contact-model.md, "Parameters from real crashes"). Verdicts are over this range.
CONTACT_RANGE = (0.05, 0.15)
#: Contact times of the verdicts [s]: the range in five steps (the typical one included).
RANGE_DURATIONS = (0.05, 0.075, 0.1, 0.125, 0.15)
#: Every contact time of the full study [s]: the range, and beyond it for the plots.
DURATIONS = (0.01, 0.025) + RANGE_DURATIONS + (0.2,)
#: The nearly instantaneous contact of the "law" rung [s].
STIFF_LIMIT = 0.002
#: PIM's sticking (beta = 1) as a contact law: a friction coefficient no impact exhausts,
#: a friction spring this many times stiffer than the crush, and no tangential rebound.
STICKING = {"friction": 10.0, "stiffness_ratio": 1000.0, "recovery": 0.0}
#: Tyre frictions [-] of the tyre-effect curves, the wheels' states, mu_c [-] of the map.
TYRE_FRICTIONS = (0.35, 0.7, 1.0)
TYRE_MODES = ("rolling", "locked")
FRICTIONS = (0.2, 0.5, 1.0)


@dataclass(frozen=True)
class RungConfig:
    """Which of PIM's assumptions a simulated scene keeps, and where its impulse acts.

    Attributes
    ----------
    law : {"pim", "crush"}
        Newton's restitution and mu = beta mu0 (PIM itself), or the crush hysteresis with
        the same epsilon and a tangential law (``friction``).
    duration : float or None
        Contact time [s]; None: instantaneous (PIM; the crush law at :data:`STIFF_LIMIT`).
    point : {"C", "centroid"}
        Input, not an assumption: the case's C and normal Gamma, or the impulse centroid
        and mean contact normal of the outlines (the line the outlines' impulse acts on,
        the bodies where the outlines first touch).
    distributed : bool
        The outlines crush into each other (the force acts where they overlap).
    tyre_friction : float
        Tyre/ground friction during the contact [-] (0: no external forces).
    tyre_mode : {"rolling", "locked"}
        The wheels' state when ``tyre_friction`` > 0: free-rolling (lateral force only) or
        locked (the whole slip).
    friction : {"pim", "coulomb"}
        PIM's tangential law (frictionless for beta 0, sticking for beta 1), or Coulomb
        friction ``mu_c`` with tangential recovery ``recovery``.
    mu_c : float
        Friction between the vehicles [-] (Coulomb only).
    recovery : float or None
        Tangential recovery r [-] (Coulomb only; None: eps^2).
    """

    law: str = "pim"
    duration: float | None = None
    point: str = "C"
    distributed: bool = False
    tyre_friction: float = 0.0
    tyre_mode: str = "rolling"
    friction: str = "pim"
    mu_c: float = 0.0
    recovery: float | None = None


#: Assumption -> the fields of :class:`RungConfig` that say whether a scene keeps it.
ASSUMPTION_FIELDS = {
    "law": ("law",),
    "duration": ("duration",),
    "outline": ("distributed",),
    "tyres": ("tyre_friction", "tyre_mode"),
    "friction": ("friction", "mu_c", "recovery"),
}
#: Fields of :class:`RungConfig` that are PIM's inputs, not its assumptions.
INPUT_FIELDS = ("point",)
assert ({f for v in ASSUMPTION_FIELDS.values() for f in v} | set(INPUT_FIELDS)
        == {f.name for f in fields(RungConfig)})


@dataclass(frozen=True)
class RungSpec:
    """What a rung relaxes.

    Attributes
    ----------
    assumption : str
        The key of :data:`ASSUMPTION_FIELDS` the rung changes against its baseline.
    title : str
        The assumption relaxed, in a user's words.
    baseline : str
        The configuration it is measured against (a key of :func:`ladder_configs`).
    """

    assumption: str
    title: str
    baseline: str


#: Rung key -> what it relaxes, bottom first (``pim`` itself is the ladder's foot).
RUNGS = {
    "law": RungSpec("law", "Newton's restitution and mu = beta mu0 (replaced by the crush "
                    "hysteresis)", "pim"),
    "duration": RungSpec("duration", "instantaneous impulse (finite contact time)", "law"),
    "outline": RungSpec("outline", "one contact point (the outlines crush: a distributed "
                        "contact)", "centroid"),
    "tyres": RungSpec("tyres", "no external forces (tyre friction, wheels rolling)",
                      "outline"),
    "tyres_locked": RungSpec("tyres", "no external forces (tyre friction, wheels locked)",
                             "outline"),
    "friction": RungSpec("friction", "PIM's tangential law (Coulomb friction between the "
                         "vehicles)", "tyres"),
}


def changed_assumptions(config: RungConfig, baseline: RungConfig) -> set[str]:
    """The assumptions (keys of :data:`ASSUMPTION_FIELDS`) ``config`` differs in."""
    return {name for name, names in ASSUMPTION_FIELDS.items()
            if any(getattr(config, f) != getattr(baseline, f) for f in names)}


def changed_inputs(config: RungConfig, baseline: RungConfig) -> set[str]:
    """The input fields (:data:`INPUT_FIELDS`) ``config`` differs in."""
    return {f for f in INPUT_FIELDS if getattr(config, f) != getattr(baseline, f)}


def baseline_of(key: str, has_outline: bool) -> str:
    """The configuration rung ``key`` is measured against."""
    base = RUNGS[key].baseline
    return "duration" if base == "outline" and not has_outline else base


def ladder_configs(duration: float, has_outline: bool, *, tyre_friction: float | None = None,
                   mu_c: float | None = None, recovery: float | None = None) -> dict:
    """Name -> :class:`RungConfig` of the ladder at contact time ``duration`` [s]: ``pim``,
    the rungs of :data:`RUNGS` and, with outlines, the ``centroid`` configuration (input,
    not a rung), each rung its baseline with one assumption changed."""
    tyre = TYPICAL["tyre_friction"] if tyre_friction is None else tyre_friction
    mu = TYPICAL["friction"] if mu_c is None else mu_c
    out = {"pim": RungConfig()}
    out["law"] = replace(out["pim"], law="crush")
    out["duration"] = replace(out["law"], duration=duration)
    below = out["duration"]
    if has_outline:
        out["centroid"] = replace(below, point="centroid")
        out["outline"] = replace(out["centroid"], distributed=True)
        below = out["outline"]
    out["tyres"] = replace(below, tyre_friction=tyre, tyre_mode="rolling")
    out["tyres_locked"] = replace(below, tyre_friction=tyre, tyre_mode="locked")
    out["friction"] = replace(out["tyres"], friction="coulomb", mu_c=mu, recovery=recovery)
    return out


def recoveries(eps: float) -> tuple:
    """The tangential recoveries r [-] the friction verdict spans: plastic (0), the default
    eps^2, half and elastic (1); r is not measured in crash tests."""
    return tuple(sorted({0.0, float(tangential_recovery_default(eps)), 0.5, 1.0}))


@dataclass(frozen=True)
class Plan:
    """What a study simulates.

    Attributes
    ----------
    durations : tuple of float
        Contact times of the ladders [s], shortest first.
    range_durations : tuple of float
        Those the verdicts span [s] (within :data:`CONTACT_RANGE`).
    tyre_frictions : tuple of float
        Tyre frictions of the tyre curves [-].
    frictions : tuple of float
        mu_c of the friction map [-] (at the typical contact time).
    recoveries : tuple of float
        Tangential recoveries r [-] of the friction rung.
    default_recovery : float
        The default r = eps^2 [-] (the ladder's friction rung, ``recovery=None``).
    """

    durations: tuple
    range_durations: tuple
    tyre_frictions: tuple
    frictions: tuple
    recoveries: tuple
    default_recovery: float

    def recovery(self, r: float) -> float | None:
        """``r`` as a configuration holds it: None for the default eps^2."""
        return None if r == self.default_recovery else r

    def configs(self, outline_at=()) -> list:
        """Every configuration simulated (unique, in order; ``pim`` left out), with the
        outline rung at the contact times in ``outline_at``."""
        out = []
        for d in self.durations:
            ladder = ladder_configs(d, d in outline_at)
            out += [c for k, c in ladder.items() if k != "pim"]
            out += [replace(ladder[k], tyre_friction=mu) for mu in self.tyre_frictions
                    for k in ("tyres", "tyres_locked")]
            mus = self.frictions if d == TYPICAL["duration"] else (
                (TYPICAL["friction"],) if d in self.range_durations else ())
            out += [replace(ladder["friction"], mu_c=mu, recovery=self.recovery(r))
                    for mu in mus for r in self.recoveries]
        return list(dict.fromkeys(out))


def plan(eps: float, sweeps: bool) -> Plan:
    """The full study (``sweeps``), or the verdicts only: the range's contact times at the
    typical tyre friction (the summary of ``pim compare``; the same verdicts and tables as
    the full study, which adds contact times and tyre frictions for the plots)."""
    rs, r0 = recoveries(eps), float(tangential_recovery_default(eps))
    if not sweeps:
        return Plan(RANGE_DURATIONS, RANGE_DURATIONS, (TYPICAL["tyre_friction"],),
                    FRICTIONS, rs, r0)
    return Plan(DURATIONS, RANGE_DURATIONS, TYRE_FRICTIONS, FRICTIONS, rs, r0)
