"""The one list of a case's inputs and the one list of a result's outputs.

Every part of the project that names an input or an output reads these: the case file's
``[uncertainty]`` table and the Monte Carlo (:mod:`pim.model.distributions`), the batch
kernel's arguments (:mod:`pim.model.kernel`), the sensitivities (:mod:`pim.analysis`), the
derivatives, the command line's tables. An input is named by its dotted path in the case
file (``vehicle1.mass``, ``impact.normal_angle``); the x and y parts of a vector field are
``_x`` and ``_y`` inputs (``vehicle1.velocity_x``). An output is named by the
:class:`pim.Result` attribute it reads, with ``_x`` / ``_y`` for the parts of a vector.
Each has a unit kind (a key of :data:`pim.io.units.DIMENSIONS`, ``None`` when
dimensionless, ``"percent"``) and a label.
"""

from __future__ import annotations

from dataclasses import dataclass

from .numbers import InputError

__all__ = ["Quantity", "FIELDS", "INPUTS", "EVIDENCE_INPUTS", "MEASURED_INPUTS", "UNCERTAIN",
           "MEASURED", "OUTPUTS", "VECTOR_FIELDS", "UNKNOWNS", "field_of", "label_of"]


@dataclass(frozen=True)
class Quantity:
    """What a named input or output is: its unit kind and a label for tables and plots.

    Attributes
    ----------
    kind : str or None
        Unit kind: a key of :data:`pim.io.units.DIMENSIONS` (e.g. "velocity", "angle",
        "dimensionless"), "percent", or None for a dimensionless number [-].
    label : str
        Plain-language name for tables and plots (e.g. "mass of vehicle 1").
    """

    kind: str | None
    label: str


def _vehicle_fields(i: int) -> dict[str, Quantity]:
    v = f"vehicle {i}"
    return {
        f"vehicle{i}.mass": Quantity("mass", f"mass of {v}"),
        f"vehicle{i}.yaw_inertia": Quantity("inertia", f"yaw inertia of {v}"),
        f"vehicle{i}.cg": Quantity("length", f"CG of {v}"),
        f"vehicle{i}.velocity": Quantity("velocity", f"pre-impact velocity of {v}"),
        f"vehicle{i}.yaw_rate": Quantity("angular_velocity", f"pre-impact yaw rate of {v}"),
        f"vehicle{i}.heading": Quantity("angle", f"heading of {v}"),
    }


#: The fields of a case, in the batch kernel's argument order (the kernel takes all but the
#: headings, which only PDOF and drawings use). Vector fields have an x and a y part.
FIELDS: dict[str, Quantity] = {
    **_vehicle_fields(1), **_vehicle_fields(2),
    "impact.point": Quantity("length", "impact point C"),
    "impact.normal_angle": Quantity("angle", "contact-plane angle Gamma"),
    "impact.restitution": Quantity("dimensionless", "restitution epsilon"),
    "impact.beta": Quantity("dimensionless", "beta = mu / mu0"),
}
#: The vector fields among :data:`FIELDS`.
VECTOR_FIELDS = frozenset(("vehicle1.cg", "vehicle1.velocity", "vehicle2.cg", "vehicle2.velocity",
                           "impact.point"))


def _components() -> dict[str, Quantity]:
    out = {}
    for name, q in FIELDS.items():
        if name in VECTOR_FIELDS:
            for axis in "xy":
                out[f"{name}_{axis}"] = Quantity(q.kind, f"{q.label}, {axis}")
        else:
            out[name] = q
    return out


#: Every scalar input of a case: the fields, vectors split into their x and y parts.
INPUTS: dict[str, Quantity] = _components()

#: Inputs of a reconstruction's evidence that an ``[uncertainty]`` table may also vary (they
#: act on the run-out or on the crush energy, not on the impact).
EVIDENCE_INPUTS: dict[str, Quantity] = {
    **{f"evidence.vehicle{i}.friction": Quantity("dimensionless",
                                                f"tyre-road friction of vehicle {i}")
       for i in (1, 2)},
    **{f"evidence.vehicle{i}.crush.{key}": Quantity(kind, f"{label} of vehicle {i}")
       for i in (1, 2) for key, kind, label in (
           ("stiffness_a", "force_per_length", "crush stiffness A"),
           ("stiffness_b", "force_per_area", "crush stiffness B"),
           ("width", "length", "damage width"),
           ("depth_scale", "dimensionless", "factor on every crush depth"))},
    **{f"evidence.vehicle{i}.pre_impact.{key}": Quantity(kind, f"{label} of vehicle {i}")
       for i in (1, 2) for key, kind, label in (
           ("friction", "dimensionless", "tyre-road friction along the pre-impact marks"),
           ("skid_length", "length", "length of the pre-impact marks"))}}
#: Factors on measured evidence that an ``[uncertainty]`` table may vary: the event data
#: recorder's under-reporting, recorded delta-V = scale x true delta-V
#: (:data:`pim.model.evidence_terms.DELTA_V_SCALE`).
MEASURED_INPUTS: dict[str, Quantity] = {
    f"measured.vehicle{i}.delta_v_scale": Quantity(
        "dimensionless", f"recorded / true delta-V of vehicle {i}") for i in (1, 2)}
#: Every name an ``[uncertainty]`` table accepts.
UNCERTAIN: dict[str, Quantity] = {**INPUTS, **EVIDENCE_INPUTS, **MEASURED_INPUTS}


#: The measured post-impact motion of a case file's ``[measured]`` table, as inputs of a fit.
MEASURED: dict[str, Quantity] = {
    **{f"measured.velocity{i}_{a}": Quantity(
        "velocity", f"measured post-impact velocity of vehicle {i}, {a}")
       for i in (1, 2) for a in "xy"},
    **{f"measured.yaw_rate{i}": Quantity(
        "angular_velocity", f"measured post-impact yaw rate of vehicle {i}") for i in (1, 2)},
    **{f"measured.delta_v{i}_{a}": Quantity(
        "velocity", f"recorded delta-V of vehicle {i}, {a}")
       for i in (1, 2) for a in ("long", "lat")},
    **{f"measured.pre_crash_speed{i}": Quantity(
        "velocity", f"recorded pre-crash speed of vehicle {i}") for i in (1, 2)},
    "measured.energy_loss": Quantity("energy", "measured energy loss"),
    "measured.crush_energy": Quantity("energy", "energy loss minus the crush energies"),
}


def _unknowns() -> dict[str, Quantity]:
    out: dict[str, Quantity] = {}
    for i in (1, 2):
        v, p = f"vehicle {i}", f"vehicle{i}."
        out.update({
            p + "speed": Quantity("velocity", f"impact speed of {v}"),
            **{p + k: INPUTS[p + k] for k in ("velocity_x", "velocity_y", "yaw_rate")},
            p + "phi": Quantity("angle", f"angle of the arm CG-C of {v} from its heading "
                                         "(Brach's phi)"),
            p + "d": Quantity("length", f"length of the arm CG-C of {v} (Brach's d)"),
            p + "radius_of_gyration": Quantity("length", f"radius of gyration of {v}"),
            p + "yaw_inertia": INPUTS[p + "yaw_inertia"],
        })
    out.update({k: INPUTS[k] for k in ("impact.restitution", "impact.beta",
                                       "impact.normal_angle", "impact.point_x",
                                       "impact.point_y")})
    out.update({
        "impact.point_along": Quantity("length", "impact point C along the crush edge"),
        "impact.k": Quantity("dimensionless", "restitution k (Kudlich-Slibar)"),
        "impact.mu_c": Quantity("dimensionless", "friction mu_c between the vehicles"),
    })
    return out


#: Dotted keys an ``[unknown]`` table may name (what a reconstruction solves for), with the
#: physical kind of their bounds and their label.
UNKNOWNS: dict[str, Quantity] = _unknowns()


def label_of(name: str) -> str:
    """The plain-language label of a named unknown, input, measured term or output
    (``"vehicle1.speed"`` -> "impact speed of vehicle 1"); the name itself when it has
    none."""
    for table in (UNKNOWNS, UNCERTAIN, MEASURED, OUTPUTS):
        if name in table:
            return table[name].label
    return name


def field_of(name: str) -> tuple[str, int | None]:
    """The field of an input and its vector axis: ``"impact.point_x"`` -> ("impact.point", 0),
    ``"vehicle1.mass"`` -> ("vehicle1.mass", None)."""
    for axis, suffix in enumerate(("_x", "_y")):
        if name.endswith(suffix) and name[:-2] in VECTOR_FIELDS:
            return name[:-2], axis
    if name in FIELDS:
        return name, None
    raise InputError(f"unknown input {name!r} (allowed: {', '.join(INPUTS)})")


def _outputs() -> dict[str, Quantity]:
    out: dict[str, Quantity] = {}
    for i in (1, 2):
        v = f"vehicle {i}"
        out.update({
            f"velocity{i}_x": Quantity("velocity", f"post-impact velocity of {v}, x"),
            f"velocity{i}_y": Quantity("velocity", f"post-impact velocity of {v}, y"),
            f"yaw_rate{i}": Quantity("angular_velocity", f"post-impact yaw rate of {v}"),
            f"speed{i}": Quantity("speed", f"post-impact speed of {v}"),
            f"delta_v{i}_x": Quantity("velocity", f"delta-V of {v}, x"),
            f"delta_v{i}_y": Quantity("velocity", f"delta-V of {v}, y"),
            f"delta_v{i}_magnitude": Quantity("speed", f"|delta-V| of {v}"),
            f"pdof{i}": Quantity("angle", f"PDOF of {v} (clockwise from its heading)"),
        })
    out.update({
        "impulse_x": Quantity("impulse", "impulse on vehicle 1, x"),
        "impulse_y": Quantity("impulse", "impulse on vehicle 1, y"),
        "impulse_magnitude": Quantity("impulse", "|impulse|"),
        "impulse_n": Quantity("impulse", "normal impulse Pn"),
        "impulse_t": Quantity("impulse", "tangential impulse Pt"),
        "impulse_angle": Quantity("angle", "impulse direction on vehicle 1 (from +x)"),
        "mu0": Quantity(None, "critical impulse ratio mu0"),
        "mu": Quantity(None, "impulse ratio mu"),
        "q": Quantity(None, "Brach's q"),
        "separation_n": Quantity("velocity", "normal separation velocity at C"),
        "separation_t": Quantity("velocity", "tangential separation velocity at C"),
        "restitution_check": Quantity(None, "restitution check -U_n / u_n"),
        "kinetic_energy_after": Quantity("energy", "kinetic energy after"),
        "energy_loss": Quantity("energy", "kinetic energy lost"),
        "energy_loss_percent": Quantity("percent", "kinetic energy lost"),
        "total_loss_brach": Quantity("energy", "Brach's T_L"),
        "crush_energy_normal": Quantity("energy", "normal crush energy"),
        "crush_energy_tangential": Quantity("energy", "tangential crush energy"),
        "tangential_share": Quantity(None, "tangential share of the loss"),
    })
    return out


#: Every scalar output of a :class:`pim.Result` that analyses name (derivatives,
#: sensitivities, Monte Carlo), in SI.
OUTPUTS: dict[str, Quantity] = _outputs()
