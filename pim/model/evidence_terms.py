"""Evidence beyond the post-impact motion: residual terms on the model's inputs and outputs.

A :class:`pim.model.motion.Term` reads one row of the post-impact motion. An
:class:`EvidenceTerm` is any scalar function of the model's *inputs* (the pre-impact state:
velocities, headings, C, CGs, masses) and *outputs* (post-impact motion, impulse), written
once here on plain arrays or on :class:`pim.model.dual.Dual` numbers alike, so that a fit
differentiates it exactly by the chain rule (d state / d p and d output / d p are carried by
the duals). The kinds:

``delta_v`` (vehicle i, axis 0 or 1) [m/s]
    The event data recorder's delta-V: the change of the CG velocity V'_i - V_i rotated into
    the vehicle frame at impact, x forward along the heading h_i, y to the left (CCW +90 deg):

        dV_long = dV_x cos h + dV_y sin h,     dV_lat = -dV_x sin h + dV_y cos h.

``pre_crash_speed`` (vehicle i) [m/s]
    The recorded pre-impact speed |V_i| (a measurement of a model input).
``energy_loss`` [J]
    The kinetic energy lost, T_L = -P.(u + U)/2 (:func:`impulse_work`, the formula of
    :attr:`pim.Result.energy_loss`): P the impulse on vehicle 1, u and U the relative
    velocity of the contact points before and after.

The residual of a term is (value - measured) / sigma; the measured values and sigmas are the
``[measured]`` table's (:class:`pim.Measured`).

:class:`CrushEnergyTerm` compares PIM's energy loss with both vehicles' crush energies from
their crush profiles (:mod:`pim.model.crush`), each times its force-balance factor, which
depends on the model's impulse direction (so it too is differentiated exactly).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from .crush import compared_energy, force_balance_factor
from .dual import Dual, cos_sin, hypot
from .motion import Term, as_terms
from .numbers import InputError

__all__ = ["EvidenceTerm", "EVIDENCE_KINDS", "DELTA_V_SCALE", "delta_v_vehicle_frame",
           "impulse_work", "hypot", "evidence_terms_of", "ModelQuantities", "EVIDENCE_TERMS",
           "result_quantities", "as_residual_terms", "split_terms", "CrushEnergyTerm",
           "energy_loss_of", "normal_crush_energy_of"]

#: Default range of the recorder's under-reporting, recorded delta-V = scale x true delta-V
#: (uniform [low, high], used by a reconstruction's Monte Carlo unless ``[uncertainty]``
#: names ``measured.vehicleN.delta_v_scale``). Niehoff, Gabler et al., "Evaluation of event
#: data recorders in full systems crash tests", 19th ESV Conference, 2005: with the full crash
#: pulse recorded, the average delta-V error in frontal tests was just under 6 %, the
#: recorder reading low; a range of 0 to 12 % under-reporting (mean 6 %) covers it
#: (docs/reconstruction.md).
DELTA_V_SCALE = (0.88, 1.0)

#: The kinds of evidence term, with their SI unit and unit kind (:mod:`pim.io.units`).
EVIDENCE_KINDS = {"delta_v": ("m/s", "velocity"), "pre_crash_speed": ("m/s", "velocity"),
                  "energy_loss": ("J", "energy")}


def delta_v_vehicle_frame(vx_before, vy_before, vx_after, vy_after, heading):
    """(longitudinal, lateral) velocity change [m/s] in the vehicle frame at impact.

    Parameters
    ----------
    vx_before, vy_before, vx_after, vy_after : array_like or Dual
        CG velocity before and after the impact, global frame [m/s].
    heading : array_like or Dual
        Heading h at impact [rad], CCW from +x.

    Returns
    -------
    (long, lat)
        dV . (cos h, sin h) and dV . (-sin h, cos h): x forward, y to the left.
    """
    c, s = cos_sin(heading)
    dx, dy = vx_after - vx_before, vy_after - vy_before
    return dx * c + dy * s, dy * c - dx * s


def impulse_work(px, py, u_x, u_y, big_u_x, big_u_y):
    """Kinetic energy lost in the impact, T_L = -P.(u + U)/2 [J] (Brach & Welsh, SAE
    2007-01-0737; :attr:`pim.Result.energy_loss` uses this formula).

    Parameters
    ----------
    px, py : array_like or Dual
        Impulse on vehicle 1 [N s].
    u_x, u_y, big_u_x, big_u_y : array_like or Dual
        Relative velocity of the contact points (vehicle 1 minus vehicle 2) before (u) and
        after (U) the impact [m/s].
    """
    return -0.5 * (px * (u_x + big_u_x) + py * (u_y + big_u_y))


def _contact(vx, vy, w, rx, ry):
    """Velocity (x, y) of the point at arm r from the CG: V + w k x r [m/s]."""
    return vx - w * ry, vy + w * rx


class ModelQuantities:
    """Named model inputs and outputs of a batch, as arrays or as :class:`Dual` numbers.

    ``q["vehicle1.velocity_x"]`` reads the state (:data:`pim.analysis.free_inputs.STATE`
    names), ``q["velocity1_x"]`` the outputs (:data:`pim.model.dual.MOTION_OUTPUTS`); with
    gradients given, each is a Dual carrying d / d parameters (built on first use).
    """

    def __init__(self, state_names, state, dstate, output_names, values, dvalues) -> None:
        self._cols = {n: (state, dstate, k) for k, n in enumerate(state_names)}
        self._cols.update({n: (values, dvalues, k) for k, n in enumerate(output_names)})
        self._cache: dict = {}

    def __getitem__(self, name: str):
        if name not in self._cache:
            x, dx, k = self._cols[name]
            self._cache[name] = x[..., k] if dx is None else Dual(x[..., k], dx[..., k, :])
        return self._cache[name]


@dataclass(frozen=True, order=True)
class EvidenceTerm:
    """One scalar of evidence on the model's inputs and outputs (module notes).

    Attributes
    ----------
    kind : {"delta_v", "pre_crash_speed", "energy_loss"}
    vehicle : int
        1 or 2 (0 for the energy loss, which belongs to the pair).
    axis : int
        0 longitudinal, 1 lateral for ``delta_v``; 0 otherwise.
    """

    kind: Literal["delta_v", "pre_crash_speed", "energy_loss"]
    vehicle: int = 0
    axis: int = 0

    def __post_init__(self) -> None:
        if self.kind not in EVIDENCE_KINDS:
            raise InputError(f"EvidenceTerm.kind must be one of {', '.join(EVIDENCE_KINDS)}, "
                             f"got {self.kind!r}")
        if (self.vehicle not in (1, 2)) != (self.kind == "energy_loss"):
            raise InputError(f"EvidenceTerm {self.kind}: vehicle must be "
                             f"{'0' if self.kind == 'energy_loss' else '1 or 2'}, "
                             f"got {self.vehicle!r}")
        if self.axis not in ((0, 1) if self.kind == "delta_v" else (0,)):
            raise InputError(f"EvidenceTerm {self.kind}: bad axis {self.axis!r}")

    @property
    def name(self) -> str:
        """Output name: ``delta_v1_long``, ``delta_v2_lat``, ``pre_crash_speed1``,
        ``energy_loss``."""
        if self.kind == "delta_v":
            return f"delta_v{self.vehicle}_{('long', 'lat')[self.axis]}"
        return self.kind + (str(self.vehicle) if self.vehicle else "")

    @property
    def group(self) -> str:
        """The piece of evidence it belongs to (a delta-V's two components are one)."""
        return {"delta_v": f"vehicle{self.vehicle} recorded delta-V",
                "pre_crash_speed": f"vehicle{self.vehicle} recorded pre-crash speed",
                "energy_loss": "energy loss"}[self.kind]

    @property
    def unit(self) -> str:
        """SI unit."""
        return EVIDENCE_KINDS[self.kind][0]

    @property
    def kind_of_unit(self) -> str:
        """Unit kind (:mod:`pim.io.units`)."""
        return EVIDENCE_KINDS[self.kind][1]

    @property
    def is_velocity(self) -> bool:
        """True for a speed-like term [m/s] (a delta-V component, a pre-crash speed)."""
        return self.kind != "energy_loss"

    def value(self, q: ModelQuantities):
        """The term's model value from the named inputs and outputs ``q`` (arrays or duals)."""
        if self.kind == "energy_loss":
            return self._energy(q)
        v = f"vehicle{self.vehicle}."
        if self.kind == "pre_crash_speed":
            return hypot(q[v + "velocity_x"], q[v + "velocity_y"])
        dv = delta_v_vehicle_frame(q[v + "velocity_x"], q[v + "velocity_y"],
                                   q[f"velocity{self.vehicle}_x"],
                                   q[f"velocity{self.vehicle}_y"], q[v + "heading"])
        return dv[self.axis]

    @staticmethod
    def _energy(q: ModelQuantities):
        return energy_loss_of(q)

    def take(self, rows) -> EvidenceTerm:
        """The term for a subset of a batch's rows (it holds no per-row data: itself)."""
        return self

    def target_of(self, measured) -> float | None:
        """The measured value in a :class:`pim.Measured` [SI], or None when not measured."""
        value = getattr(measured, self._field, None)
        if value is None:
            return None
        value = np.asarray(value, dtype=float)
        return float(value[self.axis] if self.kind == "delta_v" else value.reshape(()))

    def sigma_of(self, measured) -> float | None:
        """Its standard deviation in a :class:`pim.Measured` [SI], or None."""
        sigma = getattr(measured, self._field + "_sigma", None)
        if sigma is None:
            return None
        sigma = np.asarray(sigma, dtype=float)
        return float(sigma[self.axis] if self.kind == "delta_v" else sigma.reshape(()))

    @property
    def _field(self) -> str:
        return self.kind + (str(self.vehicle) if self.vehicle else "")

    def __str__(self) -> str:
        return self.name


def _relative_contact(q):
    """Relative velocity (x, y) of the contact points, vehicle 1 minus vehicle 2, before (u)
    and after (U) the impact [m/s]: ((u_x, u_y), (U_x, U_y))."""
    px_, py_ = q["impact.point_x"], q["impact.point_y"]
    r = [(px_ - q[f"vehicle{i}.cg_x"], py_ - q[f"vehicle{i}.cg_y"]) for i in (1, 2)]
    pre = [_contact(q[f"vehicle{i}.velocity_x"], q[f"vehicle{i}.velocity_y"],
                    q[f"vehicle{i}.yaw_rate"], *r[i - 1]) for i in (1, 2)]
    post = [_contact(q[f"velocity{i}_x"], q[f"velocity{i}_y"], q[f"yaw_rate{i}"],
                     *r[i - 1]) for i in (1, 2)]
    return ((pre[0][0] - pre[1][0], pre[0][1] - pre[1][1]),
            (post[0][0] - post[1][0], post[0][1] - post[1][1]))


def energy_loss_of(q):
    """T_L = -P.(u + U)/2 [J] of the named inputs and outputs ``q`` (:func:`impulse_work`)."""
    u, big_u = _relative_contact(q)
    return impulse_work(q["impulse_x"], q["impulse_y"], *u, *big_u)


def normal_crush_energy_of(q):
    """-P_n (u_n + U_n)/2 [J], the normal part of :func:`energy_loss_of` (Brach & Welsh,
    SAE 2007-01-0737; :attr:`pim.Result.crush_energy_normal`), n = (cos Gamma, sin Gamma)."""
    c, s = cos_sin(q["impact.normal_angle"])
    u, big_u = _relative_contact(q)
    p_n = q["impulse_x"] * c + q["impulse_y"] * s
    return -0.5 * p_n * ((u[0] + big_u[0]) * c + (u[1] + big_u[1]) * s)


@dataclass(frozen=True, eq=False)
class CrushEnergyTerm:
    """Crush-energy evidence: PIM's energy against both vehicles' measured crush energies.

    With the partition "total" (CRASH3) the value is

        T_L(model) - sum_i E_i (1 + tan^2 alpha_i)                              [J],

    alpha_i the angle between the impulse and vehicle i's damaged side's outward normal
    (the body-frame normal turned by the heading into the global frame;
    :func:`pim.model.crush.force_balance_factor`, capped); with "normal" (Brach & Welsh)
    it is -P_n (u_n + U_n)/2 - sum_i E_i. The measured value is 0 and the standard deviation
    that of sum_i E_i (:attr:`pim.model.crush.CrushProfile.energy_sigma` in quadrature; the
    factor, between 1 and its cap, is left out of the sigma).

    Attributes
    ----------
    energies : tuple of (float or ndarray (m,))
        E_1, E_2 [J] before the factor (0 without a profile); per row in a Monte Carlo.
    profiles : tuple of (CrushProfile or None)
        Each vehicle's crush profile (its damaged side), None without one.
    sigma : float
        [J], > 0.
    partition : str
        "total" or "normal" (:func:`pim.model.crush.compared_energy`).
    """

    energies: tuple
    profiles: tuple
    sigma: float
    partition: str = "total"

    kind = "crush_energy"
    vehicle = 0
    name = "crush_energy"
    group = "crush energy"
    unit = "J"
    kind_of_unit = "energy"
    is_velocity = False

    def __post_init__(self) -> None:
        compared_energy(self.partition)
        if not (np.isfinite(self.sigma) and self.sigma > 0):
            raise InputError(f"crush energy: its standard deviation must be > 0 [J], got "
                             f"{self.sigma!r} (give depth_sigma, stiffness sigmas or "
                             f"energy_sigma in [evidence.vehicleN.crush])")

    def value(self, q: ModelQuantities):
        """The model's energy minus the crush energies [J] (class notes)."""
        if not compared_energy(self.partition).force_balance:
            return normal_crush_energy_of(q) - (self.energies[0] + self.energies[1])
        out = energy_loss_of(q)
        for energy, factor in zip(self.energies, self.factors(q), strict=True):
            out = out - factor * energy
        return out

    def factors(self, q) -> tuple:
        """The force-balance factor of each vehicle at the model's impulse (1 without a
        profile or with the "normal" partition) [-]: its damaged side's normal in the global
        frame (:meth:`pim.model.crush.CrushProfile.normal`) against the impulse
        (:func:`pim.model.crush.force_balance_factor`)."""
        out = []
        for i, profile in enumerate(self.profiles, start=1):
            if profile is None or not compared_energy(self.partition).force_balance:
                out.append(1.0)
                continue
            out.append(force_balance_factor(q["impulse_x"], q["impulse_y"],
                                            *profile.normal(q[f"vehicle{i}.heading"])))
        return tuple(out)

    def target_of(self, measured) -> float:
        """The measured value: 0 (the energies are inside the term)."""
        return 0.0

    def sigma_of(self, measured) -> float:
        """Its standard deviation [J]."""
        return float(self.sigma)

    def take(self, rows) -> CrushEnergyTerm:
        """The term for the subset ``rows`` of a batch (per-row energies sliced)."""
        return replace(self, energies=tuple(e[rows] if np.ndim(e) else e
                                            for e in self.energies))

    def __str__(self) -> str:
        return self.name


#: Every evidence term, in output order.
EVIDENCE_TERMS = (tuple(EvidenceTerm("delta_v", i, a) for i in (1, 2) for a in (0, 1))
                  + tuple(EvidenceTerm("pre_crash_speed", i) for i in (1, 2))
                  + (EvidenceTerm("energy_loss"),))


def evidence_terms_of(measured) -> tuple[EvidenceTerm, ...]:
    """The evidence terms a :class:`pim.Measured` holds (none for None)."""
    if measured is None:
        return ()
    return tuple(t for t in EVIDENCE_TERMS if t.target_of(measured) is not None)


def result_quantities(result) -> dict:
    """The named inputs and outputs :meth:`EvidenceTerm.value` reads, from a solved
    :class:`pim.Result` (arrays of its shape)."""
    case = result.case
    q = {"impact.point_x": case.impact.point[..., 0], "impact.point_y": case.impact.point[..., 1],
         "impact.normal_angle": case.impact.normal_angle,
         "impulse_x": result.impulse[..., 0], "impulse_y": result.impulse[..., 1]}
    for i in (1, 2):
        v, g = getattr(case, f"vehicle{i}"), f"vehicle{i}."
        q.update({g + "velocity_x": v.velocity[..., 0], g + "velocity_y": v.velocity[..., 1],
                  g + "yaw_rate": v.yaw_rate, g + "heading": v.heading,
                  g + "cg_x": v.cg[..., 0], g + "cg_y": v.cg[..., 1],
                  f"velocity{i}_x": getattr(result, f"velocity{i}")[..., 0],
                  f"velocity{i}_y": getattr(result, f"velocity{i}")[..., 1],
                  f"yaw_rate{i}": getattr(result, f"yaw_rate{i}")})
    return {k: np.asarray(x, dtype=float) for k, x in q.items()}


_BY_NAME = {t.name: t for t in EVIDENCE_TERMS}


def as_residual_terms(terms) -> tuple:
    """Residual terms from :class:`pim.model.motion.Term` / :class:`EvidenceTerm` objects or
    their names, motion terms first (the order of every fit's residuals), each in the order
    given."""
    motion, evidence = [], []
    for t in terms:
        if isinstance(t, EvidenceTerm | CrushEnergyTerm):
            evidence.append(t)
        elif isinstance(t, str) and t in _BY_NAME:
            evidence.append(_BY_NAME[t])
        else:
            motion.extend(as_terms([t]))
    return tuple(motion) + tuple(evidence)


def split_terms(terms) -> tuple[tuple, tuple]:
    """(motion terms, evidence terms) of :func:`as_residual_terms`."""
    terms = as_residual_terms(terms)
    return (tuple(t for t in terms if isinstance(t, Term)),
            tuple(t for t in terms if not isinstance(t, Term)))
