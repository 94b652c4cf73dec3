"""Input distributions for Monte Carlo: the ``[uncertainty]`` table of a case file, and sampling.

Each uncertain input of a case is named by its dotted path and given one distribution::

    [uncertainty]
    vehicle1.mass = {normal = "20 kg"}               # nominal +- sd 20 kg (normal)
    vehicle1.velocity_x = {normal = "1.5 ft/s"}
    vehicle2.yaw_rate = {normal = "5 deg/s", mean = "0 deg/s"}   # normal about another mean
    impact.normal_angle = {plusminus = "5 deg"}      # uniform on nominal +- 5 deg
    impact.point_x = {uniform = ["-0.2 m", "0.3 m"]} # uniform between absolute bounds
    impact.restitution = {uniform = [0.2, 0.5]}
    impact.beta = {fixed = 0.9}                      # a fixed value other than the nominal
    impact.restitution = {prior = "iihs-small-overlap-barrier"}   # a named empirical prior

Inputs (and their unit kind): ``vehicle1.`` / ``vehicle2.`` + ``mass``, ``yaw_inertia``,
``cg_x``, ``cg_y``, ``velocity_x``, ``velocity_y``, ``yaw_rate``, ``heading``; ``impact.`` +
``point_x``, ``point_y``, ``normal_angle``, ``restitution`` (eps), ``beta``. Values are unit
strings (bare numbers only for the dimensionless inputs and 0), parsed by
:mod:`pim.io.uncertainty_table`; unknown inputs, unknown distribution keys and bad bounds are
errors. Inputs not listed keep their nominal value.

Admissible ranges: eps in [0, 1], beta >= 0 (:data:`pim.model.case.BETA_RANGE_TEXT`), mass
and yaw inertia > 0. A normal distribution on such an input is *truncated* to the range
(sampled by inverse CDF between the CDF values of the bounds, so no sample piles up at a
bound and the shape inside the range is the normal's); uniform
bounds and fixed values must lie inside it (else ValueError). A fixed obstacle's mass, inertia,
velocity and yaw rate cannot be uncertain.

A ``prior`` is an empirical distribution: the sorted values of a coefficient found in published
tests (named priors are resolved by :mod:`pim.io.priors`), sampled by the inverse of their
empirical CDF, linearly interpolated between the plotting positions (i - 0.5)/n (Hazen), so
a sample never leaves [min, max] of the values.

Every sample is drawn by inverse CDF from one uniform variate per input (common random
numbers); :mod:`pim.analysis.montecarlo` reuses those uniform variates to bin the inputs for its
variance-based sensitivity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .numbers import InputError, did_you_mean
from .quantities import UNCERTAIN
from .solver import defaults

__all__ = ["Distribution", "UncertaintyTable", "nominal_values", "sample_inputs"]

#: Admissible (low, high) of inputs that have one; low is exclusive for mass and inertia.
_RANGE = {"impact.restitution": (0.0, 1.0), "impact.beta": (0.0, np.inf),
          **{f"vehicle{i}.{k}": (0.0, np.inf) for i in (1, 2) for k in ("mass", "yaw_inertia")},
          **{f"evidence.vehicle{i}.{k}": (0.0, np.inf) for i in (1, 2)
             for k in ("friction", "pre_impact.friction", "pre_impact.skid_length")}}
KINDS = ("normal", "uniform", "plusminus", "fixed", "prior")


@dataclass(frozen=True)
class Distribution:
    """One input's distribution, in SI.

    Parameters
    ----------
    kind : {"normal", "uniform", "plusminus", "fixed", "prior"}
        Normal (mean ``a`` or the nominal, sd ``b``), uniform on [a, b], uniform on
        nominal +- ``b``, the fixed value ``a``, or the empirical distribution of ``values``.
    a, b : float or None
        Parameters as above [SI unit of the input].
    values : tuple of float, optional
        For ``prior``: the observed values [SI unit of the input] (at least 2).
    label : str
        For ``prior``: its name, for reports.
    """

    kind: str
    a: float | None = None
    b: float | None = None
    values: tuple | None = None
    label: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError(f"distribution kind {self.kind!r} unknown "
                             f"(allowed: {', '.join(KINDS)})")
        if self.kind == "prior":
            v = np.asarray(self.values if self.values is not None else (), dtype=float)
            if v.ndim != 1 or v.size < 2 or not np.isfinite(v).all():
                raise InputError(f"prior {self.label!r} needs at least 2 finite values")
            object.__setattr__(self, "values", tuple(float(x) for x in np.sort(v)))

    def bounds(self, nominal: float) -> tuple[float, float]:
        """The (low, high) of a uniform distribution about ``nominal``."""
        if self.kind == "plusminus":
            return nominal - self.b, nominal + self.b
        return self.a, self.b

    def sd(self, nominal: float) -> float:
        """The standard deviation [SI unit of the input] of this distribution about
        ``nominal``: a normal's sd (before any truncation to the admissible range), a
        uniform's width / sqrt(12) (+- b: b / sqrt(3)), 0 for a fixed value, a prior's
        sample standard deviation (ddof 1)."""
        if self.kind == "fixed":
            return 0.0
        if self.kind == "prior":
            return float(np.std(self.values, ddof=1))
        if self.kind == "normal":
            return float(self.b)
        low, high = self.bounds(nominal)
        return float((high - low) / np.sqrt(12.0))

    def sample(self, nominal: float, u: np.ndarray, name: str) -> np.ndarray:
        """Values [SI] from uniform variates ``u`` in (0, 1) by inverse CDF.

        Normal distributions are truncated to the input's admissible range (module notes).
        """
        from scipy.special import ndtr, ndtri

        if self.kind == "fixed":
            return np.full(u.shape, self.a)
        if self.kind == "prior":
            v = np.asarray(self.values)
            return np.interp(u, (np.arange(v.size) + 0.5) / v.size, v)
        if self.kind in ("uniform", "plusminus"):
            low, high = self.bounds(nominal)
            return low + (high - low) * u
        mean = nominal if self.a is None else self.a
        sd = self.b
        if sd == 0:
            return np.full(u.shape, mean)
        low, high = _RANGE.get(name, (-np.inf, np.inf))
        c_low, c_high = ndtr((low - mean) / sd), ndtr((high - mean) / sd)
        if c_high - c_low < 1e-9:
            raise InputError(f"uncertainty.{name}: normal(mean {mean:g}, sd {sd:g}) has almost "
                             f"no probability inside the admissible range [{low:g}, {high:g}]")
        x = mean + sd * ndtri(c_low + (c_high - c_low) * u)
        return np.clip(x, low, high)  # guards round-off only

    def check(self, nominal: float, name: str) -> None:
        """ValueError if values of this distribution fall outside the input's range."""
        low, high = _RANGE.get(name, (-np.inf, np.inf))
        open_low = name.endswith(("mass", "yaw_inertia", "friction"))
        if self.kind == "normal":
            mean = nominal if self.a is None else self.a
            if not (low <= mean <= high) or (open_low and mean <= low):
                raise InputError(f"uncertainty.{name}: mean {mean:g} outside the admissible "
                                 f"range [{low:g}, {high:g}]")
            return
        if self.kind == "prior":
            values = (self.values[0], self.values[-1])
        else:
            values = (self.a,) if self.kind == "fixed" else self.bounds(nominal)
        for v in values:
            if not (low <= v <= high) or (open_low and v <= low):
                raise InputError(f"uncertainty.{name}: value {v:g} outside the admissible "
                                 f"range {'(' if open_low else '['}{low:g}, {high:g}]")

    @property
    def varies(self) -> bool:
        """False for fixed values and zero spreads."""
        if self.kind == "fixed":
            return False
        if self.kind == "prior":
            return self.values[0] != self.values[-1]
        if self.kind == "normal" or self.kind == "plusminus":
            return self.b != 0
        return self.a != self.b


@dataclass(frozen=True)
class UncertaintyTable:
    """The distributions of a case's uncertain inputs (dotted name -> :class:`Distribution`).

    Attributes
    ----------
    inputs : dict of str to Distribution
        Dotted input name (a key of :data:`pim.model.quantities.UNCERTAIN`, e.g.
        "vehicle1.mass") -> its distribution, in the input's SI unit; an unknown name or a
        value that is not a :class:`Distribution` raises :class:`InputError`.
    """

    inputs: dict

    def __post_init__(self) -> None:
        for name, dist in self.inputs.items():
            if name not in UNCERTAIN:
                raise InputError(f"uncertainty: unknown input {name!r}"
                                 f"{did_you_mean(name, UNCERTAIN)} (allowed: "
                                 f"{', '.join(UNCERTAIN)})")
            if not isinstance(dist, Distribution):
                raise InputError(f"uncertainty.{name} must be a Distribution")


def nominal_values(case, eps=None, beta=None) -> dict:
    """The nominal value [SI] of every input of :data:`INPUTS` in a scalar ``case``."""
    out = {}
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        p = f"vehicle{i}."
        out.update({p + "mass": v.mass, p + "yaw_inertia": v.yaw_inertia,
                    p + "cg_x": v.cg[..., 0], p + "cg_y": v.cg[..., 1],
                    p + "velocity_x": v.velocity[..., 0], p + "velocity_y": v.velocity[..., 1],
                    p + "yaw_rate": v.yaw_rate, p + "heading": v.heading})
    imp = case.impact
    out.update({"impact.point_x": imp.point[..., 0], "impact.point_y": imp.point[..., 1],
                "impact.normal_angle": imp.normal_angle,
                "impact.restitution": imp.restitution if eps is None else eps,
                "impact.beta": defaults(case, 0.0, beta)[1]})
    for name, value in out.items():
        if value is None:
            raise InputError(f"{name} has no nominal value: give eps (impact.restitution)")
        if np.size(value) != 1:
            raise InputError("uncertainty needs a scalar case (one scene), "
                             f"but {name} has shape {np.shape(value)}")
        out[name] = float(np.asarray(value).reshape(()))
    return out


def sample_inputs(uncertainty: UncertaintyTable, nominal: dict, n: int, rng) -> tuple[dict, dict]:
    """Draw n samples of every input.

    Returns
    -------
    values : dict
        Input name -> array (n,) for uncertain inputs, float for the others [SI].
    uniforms : dict
        Input name -> the uniform variates (n,) its samples came from (varying inputs only).
    """
    values, uniforms = dict(nominal), {}
    fixed_obstacle = np.isinf(nominal.get("vehicle2.mass", 1.0))
    for name, dist in uncertainty.inputs.items():
        if fixed_obstacle and name in ("vehicle2.mass", "vehicle2.yaw_inertia",
                                       "vehicle2.velocity_x", "vehicle2.velocity_y",
                                       "vehicle2.yaw_rate"):
            raise InputError(f"uncertainty.{name}: vehicle2 is a fixed obstacle; "
                             f"its {name.split('.')[1]} cannot be uncertain")
        if name not in nominal:
            raise InputError(f"uncertainty.{name}: the case has no nominal value for it "
                             f"(an evidence input needs that vehicle's [evidence] table)")
        dist.check(nominal[name], name)
        if not dist.varies:
            values[name] = dist.sample(nominal[name], np.zeros(1), name)[0]
            continue
        u = rng.random(n) + 2.0**-54  # in (0, 1): never exactly a bound
        values[name] = dist.sample(nominal[name], u, name)
        uniforms[name] = u
    return values, uniforms
