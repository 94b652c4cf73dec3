"""What a regression baseline records of one case, section by section, with tolerances.

Each section runs one public function of the project on the case and returns its outputs
as :class:`Recorded` quantities, every value in SI with its unit and a tolerance taken from
the physics or numerics that produced it (docs/regression.md):

===============  ===========================  ==============================================
section          runs                         tolerance (``|now - baseline| <= max(abs,
                                              rel |baseline|)``)
===============  ===========================  ==============================================
solve            :func:`pim.solve`            round-off of the closed form: relative 1e-12,
                                              absolute 1e-12 x the largest value of the
                                              same unit in the section, or what moving the
                                              scene by round-off changes (a 1e-14 rad
                                              rotation, a 1e-13 m shift), if larger
fit              :func:`pim.fit`              the optimiser's: relative 1e-6, absolute 1e-6
                                              (eps, beta) or 1e-6 x the scale of the unit
crosscheck       :func:`sim.crosscheck`       the rigid scene's stated accuracy (docs/sim.md:
                                              every scene within 1e-6 at default settings):
                                              relative 1e-6, absolute 1e-6 x the unit scale
uncertainty      :func:`pim.uncertainty`      seeded Monte Carlo: bit for bit on the same
                                              versions; across versions 4 standard errors
                                              of each statistic (:func:`standard_error`)
reconstruct      :func:`pim.analysis.         values: the inverse fit's relative 1e-6;
                 reconstruction.reconstruct`  percentiles: as the Monte Carlo above
assumptions      :func:`comparisons.          the finite-duration pymunk scene's accuracy at
                 assumptions.run_assumptions` 20+ steps per contact (docs/contact-model.md:
                 (typical values, opt-in)     1e-3): absolute 1e-3 on the relative errors
===============  ===========================  ==============================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import pim
import sim
from comparisons.studies.assumptions import run_assumptions
from pim.analysis.reconstruction import reconstruct
from pim.analysis.residuals import has_measured_terms
from pim.io.units import SI_UNITS
from pim.model.numbers import InputError
from pim.model.quantities import OUTPUTS
from pim.model.result import output_values

__all__ = ["Recorded", "SECTIONS", "DEFAULT_SECTIONS", "DEFAULT_SETTINGS", "run_section",
           "standard_error", "ROUND_OFF_MOVES", "STATISTICAL_K", "CLOSED_FORM_REL", "FIT_REL",
           "SIM_REL", "COMPLIANT_ABS"]

#: Every section, in the order they run; the default ones leave out the slow assumptions.
SECTIONS = ("solve", "fit", "crosscheck", "uncertainty", "reconstruct", "assumptions")
DEFAULT_SECTIONS = SECTIONS[:-1]
#: Sample counts and seed of the Monte Carlo sections (stored in each baseline).
DEFAULT_SETTINGS = {"uncertainty_samples": 2000, "reconstruct_samples": 200, "seed": 0}

#: Round-off of the closed form [-] (a few thousand ulp: libm sine and cosine may differ by
#: an ulp across platforms, and a few subtractions amplify it).
CLOSED_FORM_REL = 1e-12
#: The fit's optimiser (L-BFGS-B from a coarse grid, gtol 1e-11 on the gradient: near a flat
#: minimum the parameters are determined only to about the square root of the cost's
#: round-off, and a scipy upgrade may stop at a neighbouring point) [-].
FIT_REL = 1e-6
#: The rigid pymunk scene against pim.solve: every scene within 1e-6 (docs/sim.md) [-].
SIM_REL = 1e-6
#: The finite-duration pymunk contact at >= 20 steps per contact: 1e-3 (docs/contact-model.md).
COMPLIANT_ABS = 1e-3
#: Standard errors a Monte Carlo statistic may move across versions.
STATISTICAL_K = 4.0


@dataclass
class Recorded:
    """One recorded output.

    Attributes
    ----------
    name : str
        ``section.quantity`` (e.g. ``solve.velocity1_x``).
    value : float
        The value [SI ``unit``] (NaN where undefined).
    kind : str
        Its unit kind (a key of :data:`pim.io.units.SI_UNITS`), for display.
    absolute, relative : float
        Tolerance across versions: ``|now - value| <= max(absolute, relative |value|)``.
    basis : str
        Where the tolerance comes from.
    exact_same_versions : bool
        Bit for bit when the dependency versions are the baseline's (seeded Monte Carlo).
    extra : dict
        Further plain data stored with the record (empty by default).
    """

    name: str
    value: float
    kind: str
    absolute: float
    relative: float
    basis: str
    exact_same_versions: bool = False
    extra: dict = field(default_factory=dict)

    @property
    def unit(self) -> str:
        return SI_UNITS[self.kind]


def _f(x) -> float:
    return float(np.asarray(x, dtype=float).reshape(()))


def _kind(kind: str | None) -> str:
    if kind in SI_UNITS:
        return kind
    return "dimensionless"   # None: a ratio


def _scaled(values: dict, kinds: dict, rel: float, floor: float, section: str,
            basis: str) -> list[Recorded]:
    """Quantities with relative tolerance ``rel`` and an absolute floor of ``floor`` times
    the largest finite magnitude of the same unit among ``values``."""
    scale: dict[str, float] = {}
    for key, v in values.items():
        if math.isfinite(v):
            scale[kinds[key]] = max(scale.get(kinds[key], 0.0), abs(v))
    return [Recorded(f"{section}.{key}", v, kinds[key], floor * max(scale.get(kinds[key], 0.0),
                                                                    1e-300), rel, basis)
            for key, v in values.items()]


def _outputs(result: pim.Result) -> dict:
    """Every scalar output of :data:`pim.model.quantities.OUTPUTS`
    (:func:`pim.model.result.output_values`) and the kinetic energy before [SI]."""
    out = {k: _f(v) for k, v in output_values(result).items()}
    out["kinetic_energy_before"] = _f(result.kinetic_energy_before)
    return out


#: Round-off-sized moves of the whole scene, (rotation [rad], translation [m]): what they
#: change in an output measures the case's conditioning (a near-singular q amplifies them).
ROUND_OFF_MOVES = ((1e-14, (0.0, 0.0)), (-1e-14, (0.0, 0.0)), (0.0, (1e-13, -1e-13)))


def _solve(case: pim.Case, settings: dict) -> list[Recorded]:
    if case.impact.restitution is None:
        raise LookupError("the case gives no impact.restitution")
    values = _outputs(pim.solve(case))          # the case's impact law
    kinds = {k: _kind(OUTPUTS[k].kind if k in OUTPUTS else "energy") for k in values}
    rows = _scaled(values, kinds, CLOSED_FORM_REL, CLOSED_FORM_REL, "solve",
                   "round-off of the closed form and the case's conditioning")
    moved = [_outputs(pim.solve(case.transformed(a, b))) for a, b in ROUND_OFF_MOVES]
    for r in rows:
        key = r.name[len("solve."):]
        spread = [abs(m[key] - r.value) for m in moved if math.isfinite(m[key] - r.value)]
        r.absolute = max([r.absolute, *spread])
    return rows


def _fit(case: pim.Case, settings: dict) -> list[Recorded]:
    if not has_measured_terms(case):
        raise LookupError("the case has no [measured] motion")
    fitted = pim.fit(case)                          # under the case's impact law
    if fitted.law == "kudlich-slibar":              # k, and mu_c (or its lower bound)
        values = {"k": fitted.eps, "mu_c": fitted.contact_friction, "rms": fitted.rms}
    else:
        values = {"eps": fitted.eps, "beta": fitted.beta, "rms": fitted.rms}
    kinds = dict.fromkeys(values, "dimensionless") | {"rms": "velocity"}
    for row in fitted.residual_table:
        values[f"{row['name']}"] = row["fitted"]
        kinds[row["name"]] = "velocity" if row["unit"] == "m/s" else "angular_velocity"
    rows = _scaled(values, kinds, FIT_REL, FIT_REL, "fit", "the fit's optimiser")
    for r in rows[:2]:
        r.absolute = FIT_REL          # eps and beta live in [0, 1]
    return rows


def _crosscheck(case: pim.Case, settings: dict) -> list[Recorded]:
    try:
        check = sim.crosscheck(case)
    except sim.SimulationError as exc:
        raise LookupError(f"the simulation failed ({exc})") from None
    units = {"m/s": "velocity", "rad/s": "angular_velocity", "N s": "impulse", "J": "energy"}
    values = {r.key: float(r.simulated) for r in check.rows}
    kinds = {r.key: units[r.unit] for r in check.rows}
    rows = _scaled(values, kinds, SIM_REL, SIM_REL, "crosscheck",
                   "the rigid scene's stated accuracy, docs/sim.md")
    rows.append(Recorded("crosscheck.error", check.error, "dimensionless", SIM_REL, 0.0,
                         "the rigid scene's stated accuracy, docs/sim.md"))
    return rows


def standard_error(samples, statistic: str) -> float:
    """Standard error of a Monte Carlo statistic from its samples (distribution-free).

    A percentile p (``"p5"``, ``"p50"``, ``"p95"``): half the distance between the sample
    quantiles at p -/+ sqrt(p (1 - p) / n) (the binomial spread of the order statistic);
    ``"mean"``: sd / sqrt(n); ``"sd"``: sd / sqrt(2 (n - 1)) [unit of the samples].
    """
    x = np.asarray(samples, float)
    x = x[np.isfinite(x)]
    n = x.size
    if n < 2:
        return math.nan
    sd = float(np.std(x, ddof=1))
    if statistic == "mean":
        return sd / math.sqrt(n)
    if statistic in ("sd", "std"):
        return sd / math.sqrt(2 * (n - 1))
    p = float(statistic[1:]) / 100
    d = math.sqrt(p * (1 - p) / n)
    lo, hi = np.quantile(x, [max(p - d, 0.0), min(p + d, 1.0)])
    return float(hi - lo) / 2


def _statistics(section: str, name: str, kind: str, stats, samples) -> list[Recorded]:
    rows = []
    for stat in ("p5", "p50", "p95", "mean", "sd" if hasattr(stats, "sd") else "std"):
        se = standard_error(samples, stat)
        rows.append(Recorded(f"{section}.{name}.{stat}", float(getattr(stats, stat)), kind,
                             STATISTICAL_K * se if math.isfinite(se) else 0.0, 0.0,
                             f"{STATISTICAL_K:g} standard errors of the seeded Monte Carlo",
                             exact_same_versions=True))
    return rows


def _uncertainty(case: pim.Case, settings: dict) -> list[Recorded]:
    if case.uncertainty is None:
        raise LookupError("the case has no [uncertainty] table")
    if case.impact.restitution is None:
        raise LookupError("the case gives no impact.restitution")
    mc = pim.uncertainty(case, n=int(settings["uncertainty_samples"]),
                         seed=int(settings["seed"]))
    rows = [Recorded("uncertainty.n_admissible", float(mc.n_admissible), "dimensionless",
                     0.0, 0.0, "the seeded sample", exact_same_versions=True)]
    rows[0].absolute = 4 * math.sqrt(max(mc.n - mc.n_admissible, 1))   # Poisson spread
    for name, st in mc.stats.items():
        rows += _statistics("uncertainty", name, _kind(OUTPUTS[name].kind), st,
                            mc.samples[name])
    return rows


def _unknown_kind(key: str) -> str:
    return "velocity" if key.endswith(".speed") else _kind(
        OUTPUTS.get(key, None).kind if key in OUTPUTS else None)


def _reconstruct(case: pim.Case, settings: dict) -> list[Recorded]:
    if not case.unknown:
        raise LookupError("the case has no [unknown] table")
    rec = reconstruct(case, samples=int(settings["reconstruct_samples"]),
                      seed=int(settings["seed"]))
    if not rec.determined:
        raise LookupError("the data do not determine the unknowns: " + "; ".join(rec.messages))
    values = {k: float(v) for k, v in rec.values.items()}
    kinds = {k: _unknown_kind(k) for k in values}
    rows = _scaled(values, kinds, FIT_REL, FIT_REL, "reconstruct", "the inverse fit's optimiser")
    if rec.samples is not None:
        for key, st in rec.samples.stats.items():
            rows += _statistics("reconstruct", key, _unknown_kind(key), st,
                                rec.samples.samples[key])
    return rows


def _assumptions(case: pim.Case, settings: dict) -> list[Recorded]:
    study = run_assumptions(case, sweeps=False, animation_after=None, executor="serial",
                            progress=False)
    basis = "the finite-duration pymunk contact's accuracy, docs/contact-model.md"
    rows = []
    for s in study.sweeps:
        o = s.typical
        if o.failure is not None:
            continue
        for key, err in o.errors.items():
            rows.append(Recorded(f"assumptions.{s.key}.{key}", float(err), "dimensionless",
                                 COMPLIANT_ABS, 0.0, basis))
        for key in ("eps_eff", "beta_eff", "fit_rms", "energy_loss", "pim_energy_loss",
                    "stick_fraction", "point_distance"):
            kind = {"fit_rms": "velocity", "point_distance": "length"}.get(key, "dimensionless")
            rows.append(Recorded(f"assumptions.{s.key}.{key}", float(getattr(o, key)), kind,
                                 COMPLIANT_ABS if kind == "dimensionless" else 1e-6,
                                 0.0 if kind == "dimensionless" else COMPLIANT_ABS, basis))
    return rows


#: Sections that run under the case's impact law (the others apply Brach's eps and beta).
LAW_SECTIONS = ("solve", "fit", "reconstruct")

_RUNNERS = {"solve": _solve, "fit": _fit, "crosscheck": _crosscheck,
            "uncertainty": _uncertainty, "reconstruct": _reconstruct,
            "assumptions": _assumptions}


def run_section(section: str, case: pim.Case, settings: dict) -> list[Recorded]:
    """The recorded outputs of one section for a case.

    Raises
    ------
    LookupError
        The case does not support the section (the message says why; a ValueError of the
        function it runs, e.g. no approach at C for a fit, counts as not supported).
    ValueError
        Unknown section name.
    """
    if section not in _RUNNERS:
        raise InputError(f"unknown section {section!r} (allowed: {', '.join(SECTIONS)})")
    law = case.impact.law or "brach"
    if section not in LAW_SECTIONS and law != "brach":
        raise LookupError(f"the {section} section applies Brach's (eps, beta); the case's "
                          f"impact law is {law!r}")
    try:
        return _RUNNERS[section](case, settings)
    except ValueError as exc:
        raise LookupError(str(exc)) from None
