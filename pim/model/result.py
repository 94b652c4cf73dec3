"""The outcome of :func:`pim.solve`: the core outputs and everything derived from them.

:class:`Result` holds the core outputs of the one formula (:mod:`pim.model.formula`):
post-impact motion, impulse, critical impulse, approach velocity, K and the flags. The rest is
read from them on first access and cached, each group defined once in its own module:
Brach's sheet notation (:mod:`pim.model.sheet_notation`), energies
(:mod:`pim.model.energy`), direction of force (:mod:`pim.model.pdof`) and admissibility
(:mod:`pim.model.admissibility`); the motion (delta-V, speeds, separation velocity) is here.

A result is read-only. Its core fields may be given ready (arrays of the numpy path), as
plain floats (the scalar path: each becomes a 0-d or (2,) array when first read), or left to a
``fill`` function that computes the missing ones together (the batch kernel's auxiliary
fields).
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .admissibility import Admissibility
from .display import convert, display_units
from .energy import EnergyOutputs
from .geometry import contact_velocity, dot
from .notebook import Notebook, Table, short
from .pdof import DirectionOutputs
from .quantities import OUTPUTS
from .result_table import rows_to_json, summarize, table_title
from .sheet_notation import SheetNotation

__all__ = ["Result", "CORE_FIELDS", "VECTOR_FIELDS", "output_values"]

#: The core fields of a result, in the order of :class:`Result`'s documentation.
CORE_FIELDS = ("velocity1", "velocity2", "yaw_rate1", "yaw_rate2", "impulse", "impulse_n",
               "impulse_t", "critical_impulse_n", "critical_impulse_t", "normal", "tangent",
               "arm1", "arm2", "approach_velocity", "approach_n", "approach_t", "k_nn", "k_nt",
               "k_tt", "approaching", "q_singular")
#: Core fields that are vectors (trailing axis of 2).
VECTOR_FIELDS = frozenset(("velocity1", "velocity2", "impulse", "normal", "tangent", "arm1",
                           "arm2", "approach_velocity"))
_READY = frozenset(("case", "eps", "beta") + CORE_FIELDS)


#: The outputs a batch of results shows in a notebook (min, median and max of each).
BATCH_OUTPUTS = ("speed1", "speed2", "delta_v1_magnitude", "delta_v2_magnitude", "yaw_rate1",
                 "yaw_rate2", "pdof1", "pdof2", "energy_loss")


class Result(SheetNotation, EnergyOutputs, DirectionOutputs, Admissibility, Notebook):
    """The outcome of :func:`pim.solve`: post-impact motion and everything derived from it.

    Every array broadcasts over the inputs (vectors carry a trailing axis of 2). The core
    fields are computed by :func:`pim.solve`; the other properties are computed on first
    access and cached. Units: m/s, rad/s, N s, J, rad.

    In a notebook a result shows as a table in the case's units (speeds in km/h or mph as
    the case file's system; :meth:`display_table`, ``_repr_html_``); :meth:`to_dict` and
    ``to_frame()`` (pandas) give its numbers.

    Parameters
    ----------
    case : Case
        The inputs.
    eps, beta : array_like
        Coefficient of restitution and fraction of mu0 used [-].
    fields : dict, optional
        Core fields (see below) as arrays.
    raw : dict, optional
        Core fields as floats (scalars) or (x, y) pairs (vectors); made arrays when read.
    fill : callable, optional
        Called once, with no argument, when a core field missing from ``fields`` and ``raw``
        is first read; returns a dict of the missing fields.
    backend : str
        What evaluated the formula: "python" (one case in floats), "numpy", "numba" (the batch
        kernel with its own sine and cosine, the default) or "numba-libm" (the batch kernel
        with the C library's, ``fast_trig=False``).

    Attributes
    ----------
    velocity1, velocity2 : ndarray (..., 2)
        Post-impact CG velocities [m/s].
    yaw_rate1, yaw_rate2 : ndarray
        Post-impact yaw rates [rad/s].
    impulse : ndarray (..., 2)
        Impulse P on vehicle 1 [N s] (vehicle 2 receives -P).
    impulse_n, impulse_t : ndarray
        Its components Pn, Pt along n and t [N s].
    critical_impulse_n, critical_impulse_t : ndarray
        The impulse at mu = mu0 (beta = 1) [N s].
    normal, tangent : ndarray (..., 2)
        Unit vectors n (from vehicle 2 toward vehicle 1) and t = n turned +90 deg.
    arm1, arm2 : ndarray (..., 2)
        Arms C - G_i [m].
    approach_velocity : ndarray (..., 2)
        Relative velocity of C before impact, u = u_1 - u_2 [m/s].
    approach_n, approach_t : ndarray
        Its components u_n, u_t [m/s].
    k_nn, k_nt, k_tt : ndarray
        The effective inverse-mass matrix K in n-t components [1/kg].
    approaching : ndarray of bool
        u_n < 0 beyond round-off (by more than the approach tolerance of |u_n| + |u_t|):
        the vehicles approach at C. Where False no impulse is applied.
    q_singular : ndarray of bool
        A - mu B = 0: the impulse is unbounded; outputs there are NaN.
    """

    def __init__(self, case, eps, beta, fields=None, *, raw=None, fill=None,
                 backend: str = "numpy") -> None:
        d = self.__dict__
        d["backend"] = backend
        d["case"] = case
        d["eps"] = eps
        d["beta"] = beta
        if fields:
            d.update(fields)
        d["_raw"] = raw
        d["_fill"] = fill

    def __getattr__(self, name):
        # called only for names not found the normal way: a core field not yet made
        d = self.__dict__
        raw = d.get("_raw")
        if raw is not None and name in raw:
            value = np.asarray(raw[name], dtype=bool if name in ("approaching", "q_singular")
                               else float)
            d[name] = value
            return value
        fill = d.get("_fill")
        if fill is not None and name in _READY:
            d["_fill"] = None
            d.update(fill())
            return d[name]
        raise AttributeError(f"'Result' object has no attribute {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError(f"Result is read-only (cannot set {name!r})")

    def __getstate__(self) -> dict:
        # pickle every core field as an array (a fill function does not pickle)
        state = {name: getattr(self, name) for name in _READY}
        state.update({k: v for k, v in self.__dict__.items() if k not in ("_raw", "_fill")})
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state, _raw=None, _fill=None)

    def __repr__(self) -> str:
        shape = np.shape(self.yaw_rate1)
        name = self.case.name or "(unnamed)"
        if shape:
            return f"Result({name!r}, {int(np.prod(shape))} impacts, shape={shape})"
        dv, unit = convert([self.delta_v1_magnitude, self.delta_v2_magnitude], "speed",
                           display_units(case=self.case))
        return (f"Result({name!r}, eps={short(self.eps)}, beta={short(self.beta)}: "
                f"|delta-V| {short(dv[0], unit)} and {short(dv[1], unit)}, "
                f"{'admissible' if bool(self.admissible) else 'inadmissible'})")

    def display_table(self, units=None) -> Table:
        """What the result shows in a notebook, in ``units`` (a
        :class:`pim.model.display.DisplayUnits` or "si"/"us"; default the case's): one
        impact's quantities per vehicle (:func:`pim.model.result_table.summarize`), or for
        a batch the smallest, median and largest of its main outputs."""
        shown = display_units(units, case=self.case)
        notes = (f"{shown}; angles in deg, yaw rates in deg/s",)
        if np.shape(self.yaw_rate1):
            return Table(f"{self.case.name or 'case'}: {np.size(self.yaw_rate1)} impacts",
                         ("quantity", "min", "median", "max", "unit"),
                         tuple(self._spread(name, shown) for name in BATCH_OUTPUTS), notes)
        notes += tuple(f"inadmissible: {p}" for p in self.problems())
        rows = tuple((r.label, r.vehicle1, None if r.single else r.vehicle2, r.unit)
                     for r in summarize(self, shown))
        return Table(table_title(self.case.name or "case", self),
                     ("quantity", "vehicle 1", "vehicle 2", "unit"), rows, notes)

    def _spread(self, name: str, shown) -> tuple:
        """(label, min, median, max, unit) of output ``name`` over a batch (NaN ignored)."""
        values, unit = convert(getattr(self, name), OUTPUTS[name].kind, shown)
        finite = values[np.isfinite(values)]
        low, mid, high = (np.percentile(finite, (0, 50, 100)) if finite.size
                          else (np.nan,) * 3)
        return OUTPUTS[name].label, float(low), float(mid), float(high), unit

    def to_dict(self, units=None) -> dict:
        """The result's numbers in ``units`` (default the case's), JSON-ready: one impact's
        table as ``pim solve --json`` gives it (key -> vehicle1, vehicle2 or value, unit),
        or a batch's main outputs as lists."""
        shown = display_units(units, case=self.case)
        head = {"case": self.case.name, "units": {"system": shown.system,
                                                  "speed": shown.speed}}
        if np.shape(self.yaw_rate1):
            out = {}
            for name in BATCH_OUTPUTS:
                values, unit = convert(getattr(self, name), OUTPUTS[name].kind, shown)
                out[name] = {"values": values.tolist(), "unit": unit}
            return head | {"shape": list(np.shape(self.yaw_rate1)), "outputs": out}
        return head | {"eps": float(self.eps), "beta": float(self.beta),
                       "admissible": bool(self.admissible), "problems": self.problems(),
                       "outputs": rows_to_json(summarize(self, shown))}

    @cached_property
    def delta_v1(self) -> np.ndarray:
        """Change of vehicle 1's CG velocity [m/s], shape (..., 2)."""
        return self.velocity1 - self.case.vehicle1.velocity

    @cached_property
    def delta_v2(self) -> np.ndarray:
        """Change of vehicle 2's CG velocity [m/s], shape (..., 2)."""
        return self.velocity2 - self.case.vehicle2.velocity

    @cached_property
    def delta_v1_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 1 [m/s]."""
        return np.hypot(self.delta_v1[..., 0], self.delta_v1[..., 1])

    @cached_property
    def delta_v2_magnitude(self) -> np.ndarray:
        """|delta-V| of vehicle 2 [m/s]."""
        return np.hypot(self.delta_v2[..., 0], self.delta_v2[..., 1])

    @cached_property
    def speed1(self) -> np.ndarray:
        """Post-impact speed of vehicle 1 [m/s]."""
        return np.hypot(self.velocity1[..., 0], self.velocity1[..., 1])

    @cached_property
    def speed2(self) -> np.ndarray:
        """Post-impact speed of vehicle 2 [m/s]."""
        return np.hypot(self.velocity2[..., 0], self.velocity2[..., 1])

    @cached_property
    def separation_velocity(self) -> np.ndarray:
        """Relative velocity of C after impact, U = U_1 - U_2 [m/s], shape (..., 2)."""
        return (contact_velocity(self.velocity1, self.yaw_rate1, self.arm1)
                - contact_velocity(self.velocity2, self.yaw_rate2, self.arm2))

    @cached_property
    def separation_n(self) -> np.ndarray:
        """U_n, normal relative velocity at C after impact [m/s]."""
        return dot(self.separation_velocity, self.normal)

    @cached_property
    def separation_t(self) -> np.ndarray:
        """U_t, tangential relative velocity at C after impact [m/s]."""
        return dot(self.separation_velocity, self.tangent)

    @cached_property
    def restitution_check(self) -> np.ndarray:
        """-U_n / u_n [-]: equals eps by construction (the sheet's consistency check)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return -self.separation_n / self.approach_n


def output_values(result: Result) -> dict[str, np.ndarray]:
    """Every scalar output of a :class:`pim.Result` by its name in
    :data:`pim.model.quantities.OUTPUTS` (what tables, sensitivities and the test oracle of
    the derivatives read).

    Parameters
    ----------
    result : Result
        Output of :func:`pim.solve`.

    Returns
    -------
    dict
        Name (a key of :data:`pim.model.quantities.OUTPUTS`) -> value in SI units
        [m/s, rad/s, N s, rad, J, %].
        ``impulse_*`` is the impulse on vehicle 1 (vehicle 2 receives its negative).
    """
    r = result
    p = r.impulse
    return {
        "velocity1_x": r.velocity1[..., 0], "velocity1_y": r.velocity1[..., 1],
        "velocity2_x": r.velocity2[..., 0], "velocity2_y": r.velocity2[..., 1],
        "yaw_rate1": r.yaw_rate1, "yaw_rate2": r.yaw_rate2,
        "speed1": r.speed1, "speed2": r.speed2,
        "delta_v1_x": r.delta_v1[..., 0], "delta_v1_y": r.delta_v1[..., 1],
        "delta_v2_x": r.delta_v2[..., 0], "delta_v2_y": r.delta_v2[..., 1],
        "delta_v1_magnitude": r.delta_v1_magnitude, "delta_v2_magnitude": r.delta_v2_magnitude,
        "impulse_x": p[..., 0], "impulse_y": p[..., 1],
        "impulse_magnitude": np.hypot(p[..., 0], p[..., 1]),
        "impulse_n": r.impulse_n, "impulse_t": r.impulse_t,
        "impulse_angle": r.impulse_angle, "pdof1": r.pdof1, "pdof2": r.pdof2,
        "mu0": r.mu0, "mu": r.mu, "q": r.q,
        "separation_n": r.separation_n, "separation_t": r.separation_t,
        "restitution_check": r.restitution_check,
        "kinetic_energy_after": r.kinetic_energy_after, "energy_loss": r.energy_loss,
        "energy_loss_percent": r.energy_loss_percent, "total_loss_brach": r.total_loss_brach,
        "crush_energy_normal": r.crush_energy_normal,
        "crush_energy_tangential": r.crush_energy_tangential,
        "tangential_share": r.tangential_share,
    }
