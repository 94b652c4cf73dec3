"""The inputs a fit may free, by their dotted case-file keys, and how each moves the case.

Every scalar input of :data:`pim.model.quantities.INPUTS` (``impact.normal_angle``,
``impact.point_x``, ``vehicle1.yaw_rate``, ``vehicle2.mass`` ...) sets the field it names.
The derived keys of :data:`EXTRA_KEYS` move the case as follows (applied in this order,
after the plain inputs):

``impact.point_along`` [m]
    C slides along the case's contact-plane tangent t0 = (-sin Gamma0, cos Gamma0) by this
    distance from the case's C (the crush edge; Gamma0 is the case's normal angle, so the
    edge does not turn when Gamma is fitted too). Both CGs stay put.
``vehicle{1,2}.speed`` [m/s]
    The pre-impact velocity becomes speed * u, u the unit direction of the case's velocity
    (of its heading where the velocity is zero).
``vehicle{1,2}.radius_of_gyration`` [m]
    The yaw inertia becomes m k^2 (m the vehicle's mass, fitted or not).
``impact.k`` [-], ``impact.mu_c`` [-]
    The Kudlich-Slibar law's restitution k (the restitution column, as
    ``impact.restitution``) and contact friction mu_c (>= 0; also the cap of
    "brach-capped"): the unknowns a PC-Crash user states (docs/impact-laws.md).
``vehicle{1,2}.phi`` [rad], ``vehicle{1,2}.d`` [m]
    Brach's angle and length of the arm CG -> C (:mod:`pim.io.brach`: the arm points at
    heading + phi). The CG moves to C - d (cos(h + phi), sin(h + phi)) about the (possibly
    moved) C; the one not freed keeps the case's value.

:func:`free_inputs` evaluates this map for many parameter vectors at once and, with dual
numbers (:mod:`pim.model.dual`), its exact Jacobian, so that a fit differentiates the whole
chain free parameters -> model inputs -> post-impact motion exactly.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..model.case import Case
from ..model.dual import MOTION_INPUTS, Dual, cos_sin, motion_inputs
from ..model.evidence import UNKNOWN_KINDS
from ..model.geometry import radius_of_gyration
from ..model.impact_laws import LAW_CODES, LAW_INPUTS, law_of, motion_of_law, needed_friction
from ..model.numbers import InputError
from ..model.pdof import wrap_angle
from ..model.quantities import INPUTS

__all__ = ["FREE_KEYS", "EXTRA_KEYS", "free_kind", "free_label", "STATE", "check_free", "check_free_for_case",
           "fields_set_by",
           "case_state", "free_inputs", "set_inputs", "current_value",
           "approach_direction", "unit_or_heading", "law_values", "state_law", "state_motion",
           "friction_floor", "MU_C_BOUNDS"]

#: Keys accepted beyond :data:`INPUTS`, with their meaning (module notes).
EXTRA_KEYS = {
    "impact.point_along": "C moved along the case's contact-plane tangent [m]",
    **{f"vehicle{i}.speed": "pre-impact speed [m/s] along the case's velocity direction"
       for i in (1, 2)},
    **{f"vehicle{i}.radius_of_gyration": "radius of gyration k [m]; yaw inertia = m k^2"
       for i in (1, 2)},
    **{f"vehicle{i}.phi": "Brach's angle of the arm CG -> C from the heading [rad]"
       for i in (1, 2)},
    **{f"vehicle{i}.d": "Brach's length of the arm CG -> C [m]" for i in (1, 2)},
    "impact.k": "restitution k of the Kudlich-Slibar law [-] in [0, 1]",
    "impact.mu_c": "contact friction mu_c [-] >= 0 (Kudlich-Slibar; the cap of brach-capped)",
}
#: Default search range of ``impact.mu_c`` [-] when a fit frees it without bounds.
MU_C_BOUNDS = (0.0, 2.0)
#: Every key a fit accepts.
FREE_KEYS = tuple(INPUTS) + tuple(EXTRA_KEYS)
#: Columns of the state :func:`free_inputs` returns: the model's inputs, the headings, the
#: contact friction mu_c (inf where the law has none) and the impact law's code
#: (:data:`pim.model.impact_laws.LAW_CODES`).
STATE = MOTION_INPUTS + ("vehicle1.heading", "vehicle2.heading", "impact.contact_friction",
                         "impact.law")
#: Free keys that set a state column of another name.
_ALIAS = {"impact.k": "impact.restitution", "impact.mu_c": "impact.contact_friction"}
#: The laws each law-specific key needs.
_LAWS_OF = {"impact.k": ("kudlich-slibar",), "impact.mu_c": ("kudlich-slibar", "brach-capped"),
            "impact.beta": ("brach", "brach-capped")}

_COLUMN = {name: k for k, name in enumerate(STATE)}
_POSITIVE = ("mass", "yaw_inertia", "radius_of_gyration", "d")
#: Keys that cannot be freed together (they set the same field).
_CLASHES = tuple((f"vehicle{i}.{a}", f"vehicle{i}.{b}") for i in (1, 2) for a, b in (
    ("speed", "velocity_x"), ("speed", "velocity_y"),
    ("radius_of_gyration", "yaw_inertia"),
    ("phi", "cg_x"), ("phi", "cg_y"), ("d", "cg_x"), ("d", "cg_y"))) + (
    ("impact.k", "impact.restitution"),)


def free_label(key: str) -> str:
    """A free key in words for tables: the input's label (:data:`INPUTS`), else the meaning
    of :data:`EXTRA_KEYS` without its unit, with the vehicle it is of ("pre-impact speed of
    vehicle 1" for ``vehicle1.speed``)."""
    if key in INPUTS:
        return INPUTS[key].label
    text = EXTRA_KEYS[key].split(" [")[0]
    return text + (f" of vehicle {key[7]}" if key.startswith("vehicle") else "")


def free_kind(key: str) -> str:
    """The unit kind of a free key (:data:`FREE_KEYS`), for parsing its bounds and showing
    its value: the input's kind (:data:`pim.model.quantities.INPUTS`), else the ``[unknown]``
    table's (:data:`pim.model.evidence.UNKNOWN_KINDS`).

    Raises
    ------
    KeyError
        ``key`` is not a free key.
    """
    return INPUTS[key].kind if key in INPUTS else UNKNOWN_KINDS[key]


def check_free(free: dict) -> dict:
    """Validate ``free``: known keys, finite bounds with low < high, physical ranges.

    Returns the bounds as ``{key: (low, high)}`` floats [SI].
    """
    out = {}
    for key, b in (free or {}).items():
        if key not in FREE_KEYS:
            raise InputError(f"free parameter {key!r} is unknown (allowed: "
                             f"{', '.join(FREE_KEYS)})")
        try:
            lo, hi = (float(x) for x in b)
        except (TypeError, ValueError):
            raise InputError(f"free parameter {key}: bounds must be (low, high) numbers in "
                             f"SI, got {b!r}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise InputError(f"free parameter {key}: bounds must be finite with low < high, "
                             f"got ({lo}, {hi})")
        attr = key.split(".", 1)[1]
        if attr in _POSITIVE and lo <= 0:
            raise InputError(f"free parameter {key}: bounds must be > 0, got ({lo}, {hi})")
        if key in ("impact.restitution", "impact.k") and not (0.0 <= lo and hi <= 1.0):
            raise InputError(f"free parameter {key}: bounds must lie in [0, 1], got ({lo}, {hi})")
        if attr == "speed" and lo < 0:
            raise InputError(f"free parameter {key}: bounds must be >= 0 [m/s], got ({lo}, {hi})")
        if key in ("impact.mu_c", "impact.beta") and lo < 0:
            raise InputError(f"free parameter {key}: bounds must be >= 0, got ({lo}, {hi})")
        out[key] = (lo, hi)
    for a, b in _CLASHES:
        if a in out and b in out:
            raise InputError(f"free parameters {a} and {b} set the same field: free one of them")
    return out


def fields_set_by(key: str) -> tuple[str, ...]:
    """The inputs (:data:`STATE` names) that free key ``key`` overwrites."""
    if key in _COLUMN or key in _ALIAS:
        return (_ALIAS.get(key, key),)
    group, attr = key.split(".", 1)
    return {"point_along": ("impact.point_x", "impact.point_y"),
            "speed": (f"{group}.velocity_x", f"{group}.velocity_y"),
            "radius_of_gyration": (f"{group}.yaw_inertia",),
            "phi": (f"{group}.cg_x", f"{group}.cg_y"),
            "d": (f"{group}.cg_x", f"{group}.cg_y")}[attr]


def check_free_for_case(case: Case, keys, law: str | None = None) -> None:
    """Refuse keys that cannot move in ``case``: a fixed obstacle's motion or inertia, and
    a law's parameter under another law (``law``: default the case's)."""
    law = law_of(case, law)
    for key in keys:
        if law not in _LAWS_OF.get(key, (law,)):
            raise InputError(f"free parameter {key} does not apply to impact law {law!r} "
                             f"(it is a parameter of {' or '.join(_LAWS_OF[key])})")
        group, attr = key.split(".", 1)
        if group.startswith("vehicle") and attr not in ("heading",):
            vehicle = getattr(case, group)
            if bool(np.any(vehicle.fixed)) and attr not in ("cg_x", "cg_y", "phi", "d"):
                raise InputError(f"free parameter {key}: {group} is a fixed obstacle "
                                 f"(infinite mass, at rest); its {attr} cannot be fitted")


def approach_direction(vehicle) -> np.ndarray:
    """Unit pre-impact direction of travel of a (single) vehicle: its velocity, or its
    heading when the velocity is zero (the direction of ``vehicleN.speed``)."""
    v = np.asarray(vehicle.velocity, dtype=float)
    return np.array(unit_or_heading(v[..., 0], v[..., 1],
                                    np.asarray(vehicle.heading, dtype=float)))


def unit_or_heading(vx, vy, heading) -> tuple[np.ndarray, np.ndarray]:
    """Unit vector of (vx, vy), or (cos, sin) of ``heading`` [rad] where the vector is zero."""
    speed = np.hypot(vx, vy)
    moving = speed > 0
    safe = np.where(moving, speed, 1.0)
    return (np.where(moving, vx / safe, np.cos(heading)),
            np.where(moving, vy / safe, np.sin(heading)))


def case_state(case: Case, eps=None, beta=None, *, law: str | None = None,
               contact_friction=None) -> np.ndarray:
    """The state (:data:`STATE`) of ``case`` [SI], shape S + (23,), for any case shape.

    ``eps`` and ``beta`` default to the case's impact (0 and 1 where it has none); ``law``
    and ``contact_friction`` to the case's (mu_c inf where it has none).
    """
    imp = case.impact
    eps = imp.restitution if eps is None else eps
    beta = imp.beta if beta is None else beta
    x = motion_inputs(case, 0.0 if eps is None else eps, 1.0 if beta is None else beta)
    shape = x.shape[:-1]
    extra = [case.vehicle1.heading, case.vehicle2.heading]
    extra += list(law_values(law_of(case, law), imp.contact_friction if contact_friction
                             is None else contact_friction).values())
    extra = [np.broadcast_to(np.asarray(e, dtype=float), shape)[..., None] for e in extra]
    return np.concatenate([x, *extra], axis=-1)


def law_values(law: str, contact_friction=None) -> dict:
    """The state columns of an impact law: ``impact.contact_friction`` (inf when None) and
    ``impact.law`` (its code, :data:`pim.model.impact_laws.LAW_CODES`)."""
    return {"impact.contact_friction": np.inf if contact_friction is None
            else contact_friction, "impact.law": LAW_CODES[law]}


def state_law(state) -> str:
    """The impact law of state rows (one law for all rows)."""
    codes = np.unique(np.asarray(state, dtype=float)[..., _COLUMN["impact.law"]])
    names = [name for name, code in LAW_CODES.items() if code in codes]
    if len(names) != 1 or len(codes) != 1:
        raise InputError(f"state rows must share one impact law, got codes {codes.tolist()}")
    return names[0]


_LAW_COLUMNS = [_COLUMN[name] for name in LAW_INPUTS]


def state_motion(state, dstate=None, *, jacobian: bool = True):
    """Post-impact motion of state rows under their impact law, and d motion / d p.

    ``state`` (m, 23) as :func:`free_inputs` returns it, ``dstate`` (m, 23, n) its
    derivative with respect to n parameters; :func:`pim.model.impact_laws.motion_of_law`.
    """
    state = np.asarray(state, dtype=float)
    return motion_of_law(state[..., _LAW_COLUMNS], state_law(state), jacobian=jacobian,
                         tangent=None if dstate is None else dstate[..., _LAW_COLUMNS, :])


def friction_floor(state, keys, x) -> tuple[np.ndarray, np.ndarray]:
    """Fitted values with a contact friction that is not reached replaced by its floor.

    Where ``impact.mu_c`` is among ``keys`` and the contact does not reach it (the
    Kudlich-Slibar compression sticks, or the Brach cap is not met), any mu_c above the
    needed friction (:func:`pim.model.impact_laws.needed_friction`) gives the same answer:
    mu_c only has a lower bound, and that bound stands for it.

    Parameters
    ----------
    state : array_like (23,) or (m, 23)
        The base state (everything not fitted).
    keys : sequence of str
        The fitted keys, the columns of ``x``.
    x : array_like (m, n)
        Fitted values [SI].

    Returns
    -------
    x : ndarray (m, n)
        ``x`` with mu_c replaced by its lower bound where it only has one.
    floored : ndarray (m,) of bool
        Where mu_c only has a lower bound (all False without ``impact.mu_c``).
    """
    x = np.array(np.atleast_2d(x), dtype=float)
    keys = tuple(keys)
    if "impact.mu_c" not in keys:
        return x, np.zeros(len(x), bool)
    j = keys.index("impact.mu_c")
    full, _ = free_inputs(np.asarray(state, dtype=float), keys, x)
    need = needed_friction(full[:, _LAW_COLUMNS], state_law(full))
    floored = np.isfinite(need) & (x[:, j] >= need)
    x[:, j] = np.where(floored, need, x[:, j])
    return x, floored


def free_inputs(base, keys, x, *, jacobian: bool = False):
    """The state (:data:`STATE`) with the free ``keys`` set to ``x``.

    Parameters
    ----------
    base : Case or array_like (23,) or (m, 23)
        The values of everything not freed: a single case, or state rows
        (:func:`case_state`), one per parameter vector or one for all.
    keys : sequence of str
        Free keys (:data:`FREE_KEYS`), the columns of ``x``.
    x : array_like (m, n)
        Values of the free keys [SI], one row per parameter vector.
    jacobian : bool
        Also return d state / d x (exact: dual numbers through the map of the module notes).

    Returns
    -------
    state : ndarray (m, 23)
        Columns :data:`STATE` [SI].
    jac : ndarray (m, 23, n) or None
    """
    keys = tuple(keys)
    x = np.atleast_2d(np.asarray(x, dtype=float))
    m, n = x.shape
    if n != len(keys):
        raise ValueError(f"x has {n} columns but {len(keys)} keys were given")
    base = case_state(base) if isinstance(base, Case) else np.asarray(base, dtype=float)
    base = np.broadcast_to(base, (m, len(STATE)))
    cols: list = list(base.T)

    def value(j):
        if not jacobian:
            return x[:, j]
        grad = np.zeros((m, n))
        grad[:, j] = 1.0
        return Dual(x[:, j], grad)

    given = {k: value(j) for j, k in enumerate(keys)}
    for key, v in given.items():
        if _ALIAS.get(key, key) in _COLUMN:
            cols[_COLUMN[_ALIAS.get(key, key)]] = v
    cx, cy = _COLUMN["impact.point_x"], _COLUMN["impact.point_y"]
    if "impact.point_along" in given:
        g0 = base[:, _COLUMN["impact.normal_angle"]]
        s = given["impact.point_along"]
        cols[cx] = cols[cx] + s * (-np.sin(g0))
        cols[cy] = cols[cy] + s * np.cos(g0)
    for i in (1, 2):
        if f"vehicle{i}.speed" in given:
            ux, uy = _direction(base, i)
            s = given[f"vehicle{i}.speed"]
            cols[_COLUMN[f"vehicle{i}.velocity_x"]] = s * ux
            cols[_COLUMN[f"vehicle{i}.velocity_y"]] = s * uy
        if f"vehicle{i}.radius_of_gyration" in given:
            k = given[f"vehicle{i}.radius_of_gyration"]
            cols[_COLUMN[f"vehicle{i}.yaw_inertia"]] = cols[_COLUMN[f"vehicle{i}.mass"]] * k * k
        if f"vehicle{i}.phi" in given or f"vehicle{i}.d" in given:
            phi0, d0 = _arm(base, i)
            phi = given.get(f"vehicle{i}.phi", phi0)
            d = given.get(f"vehicle{i}.d", d0)
            c, s = cos_sin(cols[_COLUMN[f"vehicle{i}.heading"]] + phi)
            cols[_COLUMN[f"vehicle{i}.cg_x"]] = cols[cx] - d * c
            cols[_COLUMN[f"vehicle{i}.cg_y"]] = cols[cy] - d * s
    state = np.empty((m, len(STATE)))
    for k, c in enumerate(cols):
        state[:, k] = c.value if isinstance(c, Dual) else c
    if not jacobian:
        return state, None
    jac = np.zeros((m, len(STATE), n))
    for k, c in enumerate(cols):
        if isinstance(c, Dual):
            jac[:, k, :] = c.grad
    return state, jac


def _direction(state: np.ndarray, i: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit direction of vehicle i's velocity in state rows (its heading where it is 0)."""
    return unit_or_heading(state[..., _COLUMN[f"vehicle{i}.velocity_x"]],
                           state[..., _COLUMN[f"vehicle{i}.velocity_y"]],
                           state[..., _COLUMN[f"vehicle{i}.heading"]])


def _arm(state: np.ndarray, i: int) -> tuple[np.ndarray, np.ndarray]:
    """Brach's (phi [rad], d [m]) of vehicle i in state rows."""
    ax = state[..., _COLUMN["impact.point_x"]] - state[..., _COLUMN[f"vehicle{i}.cg_x"]]
    ay = state[..., _COLUMN["impact.point_y"]] - state[..., _COLUMN[f"vehicle{i}.cg_y"]]
    phi = wrap_angle(np.arctan2(ay, ax) - state[..., _COLUMN[f"vehicle{i}.heading"]])
    return phi, np.hypot(ax, ay)


def set_inputs(case: Case, values: dict) -> Case:
    """``case`` with the inputs named by dotted keys set to ``values`` [SI] (scalars).

    ``impact.restitution`` and ``impact.beta`` are stored on the impact; the vehicles and the
    impact that a key moves (module notes) get their fields from the new state.
    """
    keys = tuple(values)
    if not keys:
        return case
    if case.shape != ():
        raise InputError("set_inputs needs a single case, not a batch of cases")
    state, _ = free_inputs(case, keys, [[float(values[k]) for k in keys]])
    s = dict(zip(STATE, state[0], strict=True))
    moved = {g for g in ("vehicle1", "vehicle2", "impact")
             if any(k.startswith(g + ".") for k in keys)}
    moved |= {f"vehicle{i}" for i in (1, 2) if f"vehicle{i}.phi" in keys
              or f"vehicle{i}.d" in keys}
    changes = {}
    for i in (1, 2):
        g = f"vehicle{i}"
        if g in moved:
            changes[g] = replace(
                getattr(case, g), mass=s[f"{g}.mass"], yaw_inertia=s[f"{g}.yaw_inertia"],
                cg=(s[f"{g}.cg_x"], s[f"{g}.cg_y"]),
                velocity=(s[f"{g}.velocity_x"], s[f"{g}.velocity_y"]),
                yaw_rate=s[f"{g}.yaw_rate"], heading=s[f"{g}.heading"])
    if "impact" in moved:
        imp = {"point": (s["impact.point_x"], s["impact.point_y"]),
               "normal_angle": s["impact.normal_angle"]}
        if "impact.restitution" in keys or "impact.k" in keys:
            imp["restitution"] = s["impact.restitution"]
        if "impact.beta" in keys:
            imp["beta"] = s["impact.beta"]
        if "impact.mu_c" in keys:
            imp["contact_friction"] = s["impact.contact_friction"]
        changes["impact"] = replace(case.impact, **imp)
    return replace(case, **changes)


def current_value(case: Case, key: str) -> float:
    """The value [SI] of a free key in ``case`` (``impact.point_along`` is 0 by definition:
    it is measured from the case's C)."""
    if key not in FREE_KEYS:
        raise InputError(f"free parameter {key!r} is unknown (allowed: {', '.join(FREE_KEYS)})")
    if key == "impact.point_along":
        return 0.0
    group, attr = key.split(".", 1)
    if key in ("impact.restitution", "impact.beta", "impact.k", "impact.mu_c"):
        v = getattr(case.impact, {"k": "restitution", "mu_c": "contact_friction"}.get(attr,
                                                                                     attr))
        return float("nan") if v is None else float(v)
    state = case_state(case)
    if np.shape(state) != (len(STATE),):
        raise InputError("current_value needs a single case, not a batch of cases")
    if key in _COLUMN:
        return float(state[_COLUMN[key]])
    i = int(group[-1])
    vehicle = getattr(case, group)
    if attr == "speed":
        return float(np.hypot(*np.asarray(vehicle.velocity, dtype=float)))
    if attr == "radius_of_gyration":
        return float(radius_of_gyration(vehicle.mass, vehicle.yaw_inertia))
    phi, d = _arm(state, i)
    return float(phi if attr == "phi" else d)
