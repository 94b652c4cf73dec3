"""The simulated event: pymunk from the approach through every impact to rest, returned as
the project's one timeline type (:class:`pim.model.event.Event`).

The analytic event (``pim.event``) is checked against it (:mod:`sim.event_check`).

Phases, as the pymunk run steps them (fixed step ``settings.dt``; t = 0 is the first impact):

* **approach**: both vehicles in free motion (constant velocity and yaw rate: the stated
  pre-impact motion held back ``approach`` seconds, rounded to whole steps), no tyre forces
  (the vehicles are driven), nothing collides;
* **first impact**: the rigid scene of :func:`sim.simulate` exactly (:func:`sim.scene.build_scene`,
  :func:`sim.run.run_impact`): one contact point at the case's C with normal Gamma, pinned,
  exact placement, under the case's law as Brach's equivalent (eps, beta) (``pim.solve``
  under the law gives them; Kudlich-Slibar and the capped law included);
* **free motion**: the point contact removed, every moving vehicle on its four tyres
  (:mod:`sim.event_scene`), the outlines colliding under the secondary-impact law
  (restitution eps_2 and a Coulomb cap mu_c on the friction between the vehicles: Chipmunk's
  own polygon contact, velocity-only: its position correction is off, so no contact moves a
  body or adds energy);
* **rest**: a vehicle whose ``|v| + |omega| r_max`` falls below
  :data:`pim.model.event.REST_SPEED` is stopped (its velocities zeroed, its tyres idle)
  until something hits it; the event ends when both rest, or at ``max_time``.

Which contacts count (the rule, and why): the analytic event's (:mod:`pim.model.event_formula`).
PIM's outlines may overlap at the first impact (its crush, or illustrative outlines at its
configuration), so the overlap an impact leaves is no new contact: the outline contact is
*armed* once the outlines' overlap depth (the separating-axis test,
:func:`pim.model.geometry.outline_penetration`) grows by ``tolerance``
(:data:`pim.model.event_formula.CONTACT_TOLERANCE`, 1 cm) above its least value since the
last impact. An armed contact is processed in a step while some of its points approach
(relative normal velocity below -1e-9 x the speed scale, the rigid scene's rule), under
impact k's law (:func:`sim.event_scene.secondary_law`). An impact is a run of consecutive
processed steps that starts closing faster than :data:`IMPACT_SPEED` (and than twice what
the tyres alone close in a step) and ends at the first step closing no faster than the
tyres alone (slower contact steps are the vehicles pressed together by their tyres:
processed, so the outlines do not pass through each other, but no impact), recorded as an :class:`pim.model.event.ImpactRecord`
(``source="simulation"``): its time (the first step's), the impulse summed over its steps,
the contact point (the impulse-weighted mean of the arbiter's points) and normal (the
impulse-weighted mean of the arbiter's, turned to point from vehicle 2 to vehicle 1, PIM's
n), the velocities just before and just after with the tyres' share over its steps taken
out (the contact's own delta-V: momentum is conserved through it to round-off), the energy
it took and the PDOFs. The contact is disarmed after each impact.

A run is refused (:class:`sim.SimulationError`, never returned): "energy_gained" when an
impact or a step gains kinetic energy beyond ``settings.energy_tolerance`` of the event's
initial energy, "never_separated" when a contact still pushes after
``settings.max_contact_time``; the first impact's own failures as :func:`sim.simulate`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pymunk

import pim
from pim.model.case import checked_case
from pim.analysis.event import FREE_MOTION_TIME, sliding_flags
from pim.model.event import (
    DEFAULT_APPROACH,
    REST_SPEED,
    Event,
    ImpactRecord,
    Track,
    phase_labels,
)
from pim.model.event_formula import CONTACT_TOLERANCE, TUNNEL_FRACTION
from pim.model.geometry import kinetic_energy
from pim.model.numbers import InputError, check_type
from pim.model.pdof import pdof
from pim.model.runout import MAX_TIME

from .contact_law import check_positive
from .event_contacts import OutlineContacts, attach_outline_contacts
from .event_scene import (
    SecondaryLaw,
    event_tyres,
    outline_shapes,
    secondary_law,
    tyre_friction_source,
)
from .failures import SimulationError
from .run import body_state, run_impact
from .scene import build_scene, outline_corners
from .settings import Settings

__all__ = ["simulate_event", "SECONDARY_ITERATIONS", "EventRun", "IMPACT_SPEED",
           "TYRE_CLOSING"]

#: Solver iterations per step of the outline contacts when ``settings.iterations`` is None
#: (docs: 30 sweeps reached round-off in the contact tests of /work/shared/spec).
SECONDARY_ITERATIONS = 30
#: A contact after the first impact is an impact when its points close faster than this
#: [m/s] (1.1 km/h) and than twice the pressing speed of a step (below); slower contact
#: steps are the vehicles pressed together by their tyres (processed, so the outlines never
#: pass through each other, but no impact). Lower, a pressing contact becomes a saw-tooth
#: of impacts 1 cm of overlap apart (the contact rule's re-arming) and the outlines creep
#: into each other (6 cm seen at 0.05 m/s).
IMPACT_SPEED = 0.3
#: The most the tyres can close a contact in a step, per (mu g dt) [-]: each vehicle's CG
#: decelerates at mu g and its yaw adds about as much at the outline (m r^2 / I ~ 1): an
#: impact ends at the first step closing slower than this times mu g dt (and than a tenth
#: of IMPACT_SPEED), the speed that pressing alone gives.
TYRE_CLOSING = 4.0


@dataclass(eq=False)
class EventRun:
    """The state of one simulated event while it steps (:func:`simulate_event`).

    Attributes
    ----------
    scene : sim.Scene
        The rigid scene of the first impact (its Space, bodies).
    case : pim.Case
    settings : Settings
    tyres : list
        Each vehicle's :class:`sim.event_scene.EventTyres` or None.
    contacts : OutlineContacts
        The outline contacts' monitor.
    rows : list
        Recorded states (:func:`sim.run.body_state` rows).
    impacts : list of ImpactRecord
    resting : list of bool
        Each vehicle at rest now.
    energy0 : float
        Kinetic energy at the start [J].
    secondary : SecondaryLaw or None
        The law of every contact after the first impact (None: impact k's from the case,
        :func:`sim.event_scene.secondary_law`).
    pressing : float
        Time the outlines spent in contact without an impact (pressed together) [s].
    law_name : str
        The name of the next impact's law (:func:`sim.event_scene.secondary_law`).
    press_speed : float
        The closing speed the tyres alone give a contact in a step [m/s]:
        max(IMPACT_SPEED / 10, TYRE_CLOSING mu g dt), mu the larger tyre friction.
    notes : list of str
        Remarks for the event's notes.
    """

    scene: object
    case: pim.Case
    settings: Settings
    tyres: list
    contacts: OutlineContacts
    rows: list
    impacts: list
    resting: list
    energy0: float
    secondary: SecondaryLaw | None
    pressing: float = 0.0
    law_name: str = "brach-capped"
    press_speed: float = 0.0
    notes: list = field(default_factory=list)

    @property
    def bodies(self) -> tuple[pymunk.Body, pymunk.Body]:
        """``(body1, body2)``."""
        return self.scene.body1, self.scene.body2

    def energy(self) -> float:
        """Kinetic energy of both bodies now [J]."""
        return sum(_energy(b) for b in self.bodies)


def _energy(body: pymunk.Body) -> float:
    if body.body_type != pymunk.Body.DYNAMIC:
        return 0.0
    return float(kinetic_energy(body.mass, body.moment, tuple(body.velocity),
                                body.angular_velocity))


def _first_law(case: pim.Case, eps, beta) -> tuple[float, float, str, dict]:
    """Brach's (eps, beta) of the first impact under the case's law, the law and its
    coefficients."""
    law = case.impact.law or "brach"
    result = pim.solve(case, eps, beta)
    e, b = float(np.asarray(result.eps).reshape(())), float(np.asarray(result.beta).reshape(()))
    if not (math.isfinite(e) and math.isfinite(b)):
        raise SimulationError("no_contact", "no impact at C: the vehicles do not approach "
                              "there, so the event has no first impact")
    coefficients = {"eps": e, "beta": b}
    if case.impact.contact_friction is not None:
        coefficients["mu_c"] = float(case.impact.contact_friction)
    if law == "kudlich-slibar":
        coefficients = {"k": float(case.impact.restitution if eps is None else eps),
                        "mu_c": float(case.impact.contact_friction), "eps": e, "beta": b}
    return min(max(e, 0.0), 1.0), min(max(b, 0.0), 1.0), law, coefficients


def _approach(run: EventRun, steps: int) -> None:
    """Free motion from ``-steps * dt`` to ``-dt`` (the rigid scene's start), recorded;
    the point contact is out of the Space meanwhile, and the bodies end exactly at the
    scene's start pose."""
    scene, dt = run.scene, run.settings.dt
    b1, b2 = run.bodies
    start = [(b.position, b.angle, b.velocity, b.angular_velocity) for b in (b1, b2)]
    if steps > 1:
        scene.space.remove(*scene.contact_shapes)
        back = (steps - 1) * dt
        for b in (b1, b2):
            if b.body_type == pymunk.Body.DYNAMIC:
                b.position = b.position - b.velocity * back
                b.angle = b.angle - b.angular_velocity * back
        for k in range(steps - 1):
            run.rows.append(body_state(-(steps - k) * dt, scene))
            scene.space.step(dt)
        scene.space.add(*scene.contact_shapes)
    for b, (p, a, v, w) in zip((b1, b2), start, strict=True):
        if b.body_type == pymunk.Body.DYNAMIC:
            b.position, b.angle, b.velocity, b.angular_velocity = p, a, v, w
    run.rows.append(body_state(-dt, scene))


def _first_impact(run: EventRun, case: pim.Case, law: str, coefficients: dict) -> None:
    """The rigid scene's impact at t = 0, recorded (a sample before and after) as impact 1;
    then the point contact leaves the Space."""
    scene = run.scene
    v1, v2 = case.vehicle1, case.vehicle2
    states = []
    out = run_impact(scene, replace(run.settings, record=False), states)
    after = states[-1]
    pre = [np.asarray(v.velocity, float).reshape(2) for v in (v1, v2)]
    pre_w = [float(v.yaw_rate) for v in (v1, v2)]
    before = after[:7] + (*pre[0], pre_w[0], *pre[1], pre_w[1])
    run.rows += [before, after]
    post = np.stack([out.velocity1, out.velocity2])
    post_w = np.array([out.yaw_rate1, out.yaw_rate2])
    impulse = np.asarray(out.impulse, float)
    headings = (float(v1.heading), float(v2.heading))
    run.impacts.append(ImpactRecord(
        time=0.0, point=np.asarray(case.impact.point, float).reshape(2),
        normal_angle=float(case.impact.normal_angle), law=law, coefficients=coefficients,
        impulse=impulse, velocity_before=np.stack(pre), velocity_after=post,
        yaw_rate_before=np.array(pre_w), yaw_rate_after=post_w,
        energy_loss=scene.energy_before - out.energy_after,
        pdof=_pdofs(impulse, headings, bool(v2.fixed)), source="case"))
    scene.space.remove(*scene.contact_shapes)


def _pdofs(impulse, headings, fixed2: bool) -> np.ndarray:
    """Each vehicle's PDOF [rad] of the impulse on vehicle 1 (NaN for a fixed obstacle)."""
    return np.array([float(pdof(np.asarray(impulse, float), headings[0])),
                     math.nan if fixed2 else float(pdof(-np.asarray(impulse, float),
                                                        headings[1]))])


def _tyre_forces(run: EventRun, t: float) -> np.ndarray:
    """Set each moving vehicle's tyre force and moment for the next step; return them as
    (2, 3) rows ``(fx, fy, moment)`` [N, N, N m] (zeros for a resting or fixed one)."""
    out = np.zeros((2, 3))
    for i, (body, tyres) in enumerate(zip(run.bodies, run.tyres, strict=True)):
        if tyres is None or run.resting[i]:
            continue
        (fx, fy), moment = tyres.force(t, body)
        body.force = (fx, fy)
        body.torque = moment
        out[i] = fx, fy, moment
    return out


def _rest_check(run: EventRun) -> None:
    """Stop each vehicle whose |v| + |omega| r_max is below REST_SPEED; wake one that was
    hit."""
    for i, (body, tyres) in enumerate(zip(run.bodies, run.tyres, strict=True)):
        if body.body_type != pymunk.Body.DYNAMIC:
            run.resting[i] = True
            continue
        reach = tyres.reach if tyres is not None else 0.0
        measure = body.velocity.length + abs(body.angular_velocity) * reach
        if tyres is not None and measure < REST_SPEED:
            body.velocity = (0.0, 0.0)
            body.angular_velocity = 0.0
            run.resting[i] = True
        else:
            run.resting[i] = measure == 0.0 and tyres is not None


def _step(run: EventRun, step: int) -> tuple[float, np.ndarray, tuple]:
    """One step of the free motion from ``step - 1`` to ``step``: tyre forces, the engine's
    step; returns the new time [s], the tyres' (2, 3) forces of the step and the state
    before it (velocities and yaw rates)."""
    dt = run.settings.dt
    b1, b2 = run.bodies
    before = (np.array(b1.velocity), b1.angular_velocity, np.array(b2.velocity),
              b2.angular_velocity)
    forces = _tyre_forces(run, (step - 1) * dt)
    run.contacts.accepted = False
    run.contacts.closing = 0.0
    run.scene.space.step(dt)
    return step * dt, forces, before


def _start_contact(run: EventRun, t: float, before: tuple) -> dict:
    """A contact began in the step that ended at ``t``: the sample before it (positions
    now, velocities before) and the bookkeeping of the impact."""
    row = body_state(t, run.scene)
    run.rows.append(row[:7] + (*before[0], before[1], *before[2], before[3]))
    return {"time": t, "before": before, "tyre": np.zeros((2, 3)),
            "headings": (row[3], row[6]), "energy": run.energy()}


def _end_contact(run: EventRun, open_contact: dict) -> None:
    """The contact ``open_contact`` ended: record it as an impact (module notes) and check
    that it took no energy."""
    mon, dt = run.contacts, run.settings.dt
    b = run.bodies
    tyre = open_contact["tyre"] * dt
    after_v, after_w = [], []
    for i, body in enumerate(b):
        if body.body_type != pymunk.Body.DYNAMIC:
            after_v.append(np.zeros(2))
            after_w.append(0.0)
            continue
        after_v.append(np.array(body.velocity) - tyre[i, :2] / body.mass)
        after_w.append(body.angular_velocity - tyre[i, 2] / body.moment)
    v0 = open_contact["before"]
    before_v, before_w = np.stack([v0[0], v0[2]]), np.array([v0[1], v0[3]])
    energies = [sum(float(kinetic_energy(body.mass, body.moment, v[i], w[i]))
                    for i, body in enumerate(b) if body.body_type == pymunk.Body.DYNAMIC)
                for v, w in ((before_v, before_w), (after_v, after_w))]
    _check_gain(run, energies[0], energies[1], f"the impact at t = {open_contact['time']:.4g} s")
    weight = max(mon.weight, 1e-300)
    normal = mon.normal / max(float(np.hypot(*mon.normal)), 1e-300)
    run.impacts.append(ImpactRecord(
        time=open_contact["time"], point=mon.point / weight,
        normal_angle=float(np.arctan2(normal[1], normal[0])), law=run.law_name,
        coefficients=mon.law.coefficients, impulse=mon.impulse.copy(),
        velocity_before=before_v, velocity_after=np.stack(after_v),
        yaw_rate_before=before_w, yaw_rate_after=np.array(after_w),
        energy_loss=energies[0] - energies[1],
        pdof=_pdofs(mon.impulse, open_contact["headings"], b[1].body_type != pymunk.Body.DYNAMIC),
        source="simulation"))
    mon.clear()
    mon.disarm()
    _next_law(run)


def _check_gain(run: EventRun, before: float, after: float, what: str) -> None:
    """Refuse a rise of kinetic energy beyond the tolerance (of the event's initial energy)."""
    limit = before + run.settings.energy_tolerance * run.energy0 + 1e-9
    if not (math.isfinite(after) and after <= limit):
        raise SimulationError(
            "energy_gained", f"kinetic energy rose from {before:.9g} J to {after:.9g} J in "
            f"{what} (+{after - before:.3g} J; the event started with {run.energy0:.6g} J)")


def _contact_step(run: EventRun, open_contact, t: float, forces, before, step: int):
    """Book the step that ended at ``t`` (:func:`_free_motion`): an impact starts at a
    contact step closing faster than :data:`IMPACT_SPEED` and twice the pressing speed
    (:attr:`EventRun.press_speed`), continues over the contact steps closing faster than
    the pressing speed, and ends at the first other step; the slower contact steps press
    (the tyres push the vehicles together) and are no impact. Returns the open impact's
    bookkeeping or None."""
    mon, settings = run.contacts, run.settings
    closing = mon.closing if mon.accepted else 0.0
    if open_contact is None and closing > max(IMPACT_SPEED, 2.0 * run.press_speed):
        open_contact = _start_contact(run, t, before)
    elif open_contact is not None and closing <= run.press_speed:
        open_contact["tyre"] += forces      # the velocities now include this step's tyres
        _end_contact(run, open_contact)
        return None
    elif mon.accepted and open_contact is None:
        run.pressing += settings.dt
    if open_contact is None:
        mon.clear()                         # a pressing step's impulse is no impact's
    else:
        open_contact["tyre"] += forces
        mon.steps += 1
        if mon.steps * settings.dt > settings.max_contact_time + 0.5 * settings.dt:
            raise SimulationError(
                "never_separated", f"the impact that began at t = {open_contact['time']:.4g}"
                f" s still pushed after {mon.steps} steps ({settings.max_contact_time:g} s)",
                step)
    return open_contact


def _check_steps(run: EventRun) -> None:
    """Refuse a run in which a recorded step gained kinetic energy beyond the tolerance (of
    the event's initial energy): the rows' energies at once."""
    rows = np.array(run.rows, dtype=float)
    energy = np.zeros(len(rows))
    for i, body in enumerate(run.bodies):
        if body.body_type == pymunk.Body.DYNAMIC:
            energy += kinetic_energy(body.mass, body.moment, rows[:, 7 + 3 * i:9 + 3 * i],
                                     rows[:, 9 + 3 * i])
    gain = np.diff(energy)
    bad = np.flatnonzero(~(gain <= run.settings.energy_tolerance * run.energy0 + 1e-9))
    if bad.size:
        k = int(bad[0])
        _check_gain(run, float(energy[k]), float(energy[k + 1]),
                    f"the step to t = {rows[k + 1, 0]:.4g} s")


def _free_motion(run: EventRun, max_time: float) -> float | None:
    """Step from the first impact to rest or ``max_time``, recording every step and each
    impact; return the time both vehicles came to rest (None: not by ``max_time``)."""
    limit = int(math.ceil(max_time / run.settings.dt - 1e-9))
    open_contact = None
    for step in range(1, limit + 1):
        t, forces, before = _step(run, step)
        open_contact = _contact_step(run, open_contact, t, forces, before, step)
        _rest_check(run)
        run.rows.append(body_state(t, run.scene))
        if all(run.resting) and open_contact is None:
            return t
    if open_contact is not None:
        _end_contact(run, open_contact)
    return None


def _next_law(run: EventRun) -> None:
    """Set the law of the next impact (number ``len(run.impacts) + 1``) on the contacts."""
    law, name, note = secondary_law(run.case, len(run.impacts) + 1, run.secondary)
    run.contacts.law, run.law_name = law, name
    if note and note not in run.notes:
        run.notes.append(note)


def _check_options(settings, approach, max_time, tyre_friction) -> tuple[Settings, float,
                                                                          float]:
    settings = check_type(settings, "settings", Settings, "a sim.Settings (e.g. "
                          "sim.Settings(dt=1e-3))", none=True) or Settings()
    approach = check_positive(approach, "approach", "s", allow_zero=True)
    if max_time is None:
        free = tyre_friction is not None and tyre_friction == 0
        max_time = FREE_MOTION_TIME if free else MAX_TIME
    max_time = check_positive(max_time, "max_time", "s")
    settings = replace(settings, contact="point", start="exact", duration=0.0, record=False,
                       tyre_friction=False)
    return settings, approach, max_time


def _check_tunnelling(case: pim.Case, scene, dt: float) -> None:
    """Refuse a step at which the outlines could pass through each other: twice the
    scene's largest speed times ``dt`` above :data:`pim.model.event_formula.TUNNEL_FRACTION`
    of the smallest outline dimension (the analytic event's bound)."""
    sizes = [float(x) for v in (case.vehicle1, case.vehicle2) if v.length is not None
             for x in (v.length, v.width)]
    travel = 2.0 * scene.speed_scale * dt
    if sizes and travel > TUNNEL_FRACTION * min(sizes):
        raise SimulationError(
            "tunnelled", f"settings.dt = {dt:g} s lets the outlines close {travel:.3g} m in "
            f"one step, more than {TUNNEL_FRACTION:g} of their smallest dimension "
            f"({min(sizes):.3g} m): a contact could be missed; use dt <= "
            f"{TUNNEL_FRACTION * min(sizes) / (2.0 * scene.speed_scale):.2g} s")


def _setup(case: pim.Case, settings: Settings, first: tuple, tyre_friction, options: tuple
           ) -> tuple[EventRun, str, dict, str]:
    """The rigid scene of the first impact (``first``: eps, beta), the tyres and the run's
    state (``options``: the secondary law or None, the contact tolerance [m]); the law, its
    coefficients and the tyre friction's source in words."""
    e, b, law, coefficients = _first_law(case, *first)
    if case.vehicle1.length is None or case.vehicle1.width is None or (
            not case.vehicle2.fixed and (case.vehicle2.length is None
                                         or case.vehicle2.width is None)):
        raise InputError("the event needs each vehicle's length and width (the outlines "
                         "that collide after the first impact)")
    scene = build_scene(case, e, b, settings, analytic=pim.solve(case, e, 1.0, law="brach"))
    _check_tunnelling(case, scene, settings.dt)
    mu, source = tyre_friction_source(case, tyre_friction)
    tyres = [event_tyres(case, i, mu) for i in (1, 2)]
    contacts = OutlineContacts((scene.body1, scene.body2),
                               (outline_corners(case.vehicle1), outline_corners(case.vehicle2)),
                               scene.speed_scale, options[1], SecondaryLaw())
    mu_max = max([float(np.max(t.vehicle.friction)) for t in tyres if t is not None],
                 default=0.0)
    run = EventRun(scene=scene, settings=settings, tyres=tyres, contacts=contacts, rows=[],
                   impacts=[], resting=[False, False], energy0=scene.energy_before,
                   secondary=options[0], case=case, press_speed=max(
                       0.1 * IMPACT_SPEED, TYRE_CLOSING * mu_max * settings.gravity
                       * settings.dt))
    return run, law, coefficients, source


def _add_outlines(run: EventRun) -> None:
    """The outlines join the Space after the first impact, the contact disarmed (the depth
    there is the least so far)."""
    space = run.scene.space
    _next_law(run)
    space.add(*outline_shapes(run.case, *run.bodies, run.contacts.law))
    space.iterations = (run.settings.iterations if run.settings.iterations is not None
                        else SECONDARY_ITERATIONS)
    space.collision_slop = 1e6      # no position correction: contacts act on velocities only
    run.contacts.disarm()
    attach_outline_contacts(space, run.contacts)


def _event_of(run: EventRun, rest_time, notes: list) -> Event:
    """The recorded rows as an :class:`pim.model.event.Event` (sliding flags as the analytic
    event's, :func:`pim.analysis.event.sliding_flags`; none in the approach)."""
    rows = np.array(run.rows, dtype=float)
    time = rows[:, 0]
    tracks = []
    for i, vehicle in enumerate((run.case.vehicle1, run.case.vehicle2)):
        states = rows[:, [1 + 3 * i, 2 + 3 * i, 3 + 3 * i, 7 + 3 * i, 8 + 3 * i, 9 + 3 * i]]
        tyres = run.tyres[i]
        sliding = sliding_flags(states, None if tyres is None else tyres.vehicle)
        sliding[time < 0] = False
        tracks.append(Track(states[:, :2], states[:, 2], states[:, 3:5], states[:, 5],
                            sliding, outline_corners(vehicle), bool(vehicle.fixed),
                            wheels=None if tyres is None else tyres.vehicle.positions))
    phase = phase_labels(time, [imp.time for imp in run.impacts], rest_time)
    return Event(time=time, vehicle1=tracks[0], vehicle2=tracks[1], phase=phase,
                 impacts=tuple(run.impacts), source="simulated",
                 stopped=(bool(run.resting[0]), bool(run.resting[1])), notes=tuple(notes))


def _notes(run: EventRun, steps: int, source: str, rest_time, max_time: float) -> list:
    notes = [f"approach {steps * run.settings.dt:.4g} s of the pre-impact motion held back "
             f"(constant velocity and yaw rate)", source,
             f"pymunk: dt = {run.settings.dt:g} s"]
    ev = run.case.evidence
    if ev is not None and any(getattr(getattr(ev, f"vehicle{i}"), "pre_impact", None)
                              is not None for i in (1, 2) if getattr(ev, f"vehicle{i}")):
        notes.append("the case's pre-impact tyre marks are not simulated: the approach is "
                     "free motion")
    notes += run.notes
    if run.pressing > 0:
        notes.append(f"the outlines pressed together without an impact (closing slower than "
                     f"{max(IMPACT_SPEED, 2 * run.press_speed):.3g} m/s) for "
                     f"{run.pressing:.3g} s")
    if rest_time is None:
        notes.append(f"not at rest {max_time:g} s after the first impact (the time limit)")
    return notes


def simulate_event(case: pim.Case, *, tyre_friction=None, approach=DEFAULT_APPROACH,
                   settings: Settings | None = None, eps=None, beta=None,
                   secondary: SecondaryLaw | None = None, max_time: float | None = None,
                   tolerance: float = CONTACT_TOLERANCE) -> Event:
    """The whole event in pymunk: approach, every impact, run-out to rest (module notes).

    Parameters
    ----------
    case : pim.Case
        A single case with both vehicles' length and width (a fixed obstacle may have none:
        a straight face through C); its ``impacts`` (``[[impacts]]``) set the further
        impacts' laws.
    tyre_friction : float, optional
        Tyre-road friction [-] >= 0 of both vehicles (0: no tyre forces, free motion to
        ``max_time``); default the case's evidence, else
        :data:`pim.model.event.DEFAULT_TYRE_FRICTION`.
    approach : float
        How long before the first impact the event starts [s] >= 0 (rounded to steps).
    settings : Settings, optional
        The step ``dt`` [s], solver ``iterations`` (None: the rigid scene's automatic count
        for the first impact, :data:`SECONDARY_ITERATIONS` for the outlines),
        ``max_contact_time`` [s], ``energy_tolerance`` [-], ``gravity``; the contact
        switches are the rigid scene's (point contact, exact start) and ignored here.
    eps, beta : float, optional
        The first impact's coefficients [-] (default: the case's, under its law).
    secondary : SecondaryLaw, optional
        One law for every contact after the first impact (default: the case's
        ``[[impacts]]``, else eps_2 = 0.1 and a cap mu_c = 0.5, as ``pim.event``).
    max_time : float, optional
        Longest time after the first impact [s] > 0; default 60 s with tyres, 3 s without
        (``pim.event``'s).
    tolerance : float
        Growth of the outlines' overlap depth [m] that makes a new contact (module notes).

    Returns
    -------
    pim.model.event.Event
        ``source = "simulated"``; every step's state, each impact's record.

    Raises
    ------
    pim.InputError
        Bad input (an array case, missing outlines, a negative friction ...).
    SimulationError
        The run broke physics (energy gained) or a contact never ended.
    """
    case = checked_case(case)
    settings, approach, max_time = _check_options(settings, approach, max_time, tyre_friction)
    secondary = check_type(secondary, "secondary", SecondaryLaw, "a sim.SecondaryLaw",
                           none=True)
    tolerance = check_positive(tolerance, "tolerance", "m", allow_zero=True)
    run, law, coefficients, source = _setup(case, settings, (eps, beta), tyre_friction,
                                           (secondary, tolerance))
    steps = max(1, int(round(approach / settings.dt)))
    _approach(run, steps)
    _first_impact(run, case, law, coefficients)
    _add_outlines(run)
    rest_time = _free_motion(run, max_time)
    _check_steps(run)
    return _event_of(run, rest_time, _notes(run, steps, source, rest_time, max_time))
