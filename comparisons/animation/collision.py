"""The collision's animation: the case's impact in pymunk (solid) with PIM's analytic motion
as a ghost, both as events, from the approach to rest, drawn by the one renderer
(:mod:`comparisons.animation.render`).

By default the animation starts :data:`pim.model.event.DEFAULT_APPROACH` before the impact
and runs until both vehicles are at rest, with the case's tyre friction (its
``[evidence]``'s) or :data:`pim.model.event.DEFAULT_TYRE_FRICTION` where it gives none; the
caption states the value and its source. ``--tyre-friction 0`` gives free motion (which
never comes to rest: :data:`DEFAULT_AFTER` seconds are shown).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

import pim
import sim
from comparisons.animation.motion import analytic_motion, case_impact, simulated_motion
from comparisons.animation.render import (
    DEFAULT_FPS,
    AnimationInfo,
    Look,
    Renderer,
    write_animation,
)
from pim.model.number_format import format_number
from pim.model.event import DEFAULT_APPROACH, DEFAULT_TYRE_FRICTION, Event
from pim.model.numbers import InputError, checked_number
from pim.model.tyres import STANDARD_GRAVITY
from sim.event_scene import tyre_friction_source
from sim.scene import footprint_lever

__all__ = ["Framing", "TyreChoice", "tyre_choice", "frame_times", "build_renderer",
           "animate_case", "event_renderer", "animate_event", "measured_rest",
           "simulate_for_animation", "animation_settings", "animation_plan", "DEFAULT_AFTER",
           "MAX_SHOWN", "REST_HOLD"]

#: Seconds shown after the impact of a motion that never comes to rest (no tyre friction).
DEFAULT_AFTER = 2.0
#: Longest time shown before or after the impact [s]: 10 minutes of scene, 18000 frames at
#: 30 fps (minutes of drawing); the bound is checked before any work.
MAX_SHOWN = 600.0
#: Seconds the rest poses are held at the end of an animation to rest.
REST_HOLD = 0.5


def frame_times(before: float, after: float, fps: int) -> np.ndarray:
    """Frame times [s] from -before to +after (0, the impact, is always a frame)."""
    if not (fps >= 1 and int(fps) == fps):
        raise InputError(f"fps must be a positive integer, got {fps!r}")
    if not (before >= 0 and after > 0 and math.isfinite(before + after)):
        raise InputError(f"before must be >= 0 and after > 0 [s], got {before!r}, {after!r}")
    return np.arange(-int(round(before * fps)), int(round(after * fps)) + 1) / fps


@dataclass(frozen=True)
class Framing:
    """Which stretch of a collision an animation shows, and its frames.

    Attributes
    ----------
    before : float or None
        Seconds shown before the impact (None: :data:`pim.model.event.DEFAULT_APPROACH`).
    after : float or None
        Seconds shown after the impact (None: until both vehicles are at rest, plus
        :data:`REST_HOLD`; :data:`DEFAULT_AFTER` without tyre friction).
    fps : int
        Frames per second.
    size : (int, int) or None
        Frame width and height [px], both even (None: fitted to the motion).
    """

    before: float | None = None
    after: float | None = None
    fps: int = DEFAULT_FPS
    size: tuple | None = None


@dataclass(frozen=True)
class TyreChoice:
    """The tyre friction of an animation after the impact and where it comes from.

    Attributes
    ----------
    value : float
        Tyre-road friction coefficient [-] (0: free motion).
    source : str
        Where it comes from, in words (the caption says it).
    """

    value: float
    source: str

    def text(self) -> str:
        """The caption's words: "tyre friction 0.7 (default: dry asphalt, ...)"."""
        if self.value == 0:
            return f"no tyre friction after the impact ({self.source}): free motion"
        return f"tyre friction {format_number(self.value)} ({self.source})"


def tyre_choice(case: pim.Case, tyre: float | None) -> TyreChoice:
    """The tyre friction of an animation: ``tyre`` when given (--tyre-friction), else the
    case's ``[evidence]`` friction (the larger of the two vehicles'), else
    :data:`pim.model.event.DEFAULT_TYRE_FRICTION`."""
    if tyre is not None:
        value = checked_number(tyre, "tyre friction", low=0.0, high=5.0)
        return TyreChoice(value, "--tyre-friction")
    given = [e.friction for e in (case.evidence.vehicle1, case.evidence.vehicle2)
             if e is not None] if case.evidence is not None else []
    if given:
        return TyreChoice(float(max(given)), "the case's [evidence]")
    return TyreChoice(DEFAULT_TYRE_FRICTION,
                      "default: dry asphalt, Fricke 1990; --tyre-friction to change")


def simulate_for_animation(case: pim.Case, eps: float, beta: float, after: float,
                           tyre: float = 0.0, dt: float = 1e-3):
    """Run the simulator with a recorded trajectory reaching ``after`` seconds past impact."""
    return sim.simulate(case, eps, beta, animation_settings(after, tyre, dt))


def animation_settings(after: float, tyre: float = 0.0, dt: float = 1e-3) -> sim.Settings:
    """Simulator settings recording ``after`` seconds past the impact, tyre friction ``tyre``
    [-] after it (0: none)."""
    return sim.Settings(dt=dt, record=True, duration=after + 2 * dt,
                        tyre_friction=float(tyre) if tyre else False)


def animation_plan(case: pim.Case, result: pim.Result, tyre: float | None = None,
                   after: float | None = None) -> sim.Settings:
    """The simulator's settings of an animation: the tyre friction of :func:`tyre_choice`
    and a recording long enough for ``after`` seconds (None: until both vehicles stop under
    that friction, :data:`DEFAULT_AFTER` without friction)."""
    value = tyre_choice(case, tyre).value
    if after is None:
        after = _stop_estimate(case, result, value) if value else DEFAULT_AFTER
    return animation_settings(after, value)


def _stop_estimate(case: pim.Case, result: pim.Result, tyre: float) -> float:
    """Time [s] both vehicles need to stop under the ghost's deceleration (speed falls by
    mu g per second, the yaw rate by mu g d / k^2), doubled and 0.5 s more: the simulated
    sliding footprint turns longer once it stops translating (the simulation stops at rest)."""
    worst = 0.0
    for vehicle, v, w in ((case.vehicle1, result.velocity1, result.yaw_rate1),
                          (case.vehicle2, result.velocity2, result.yaw_rate2)):
        if bool(vehicle.fixed):
            continue
        decel = tyre * STANDARD_GRAVITY
        k2 = float(vehicle.yaw_inertia / vehicle.mass)
        yaw_decel = decel * footprint_lever(vehicle) / k2
        worst = max(worst, float(np.hypot(*np.asarray(v, float).reshape(2))) / decel,
                    abs(float(np.asarray(w))) / yaw_decel)
    return min(2.0 * worst + 0.5, MAX_SHOWN)


def _checked_framing(framing: Framing) -> Framing:
    before, after = framing.before, framing.after
    if after is not None:
        after = checked_number(after, "after", low=0.0, high=MAX_SHOWN, unit="s")
    if before is not None:
        before = checked_number(before, "before", low=0.0, high=MAX_SHOWN, unit="s")
    return replace(framing, before=DEFAULT_APPROACH if before is None else before,
                   after=after)


def collision_events(case: pim.Case, result: pim.Result, simulated, framing: Framing,
                     tyre: float) -> tuple[Event, Event]:
    """The simulated event and PIM's analytic one at the frame times of ``framing`` (its
    ``after`` None: to the simulated rest plus :data:`REST_HOLD`)."""
    end = float(simulated.trajectory.time[-1])
    times = frame_times(framing.before, framing.after or end + REST_HOLD, framing.fps)
    impact = case_impact(case, result, simulated.impulse, source="simulation")
    event = simulated_motion(case, simulated.trajectory, times, tyre=tyre, impact=impact)
    if framing.after is None:       # to rest (the recording holds its last state) or its end
        rest = event.time[event.phase == "rest"]
        times = frame_times(framing.before, float(rest[0]) + REST_HOLD if len(rest) else end,
                            framing.fps)
        event = simulated_motion(case, simulated.trajectory, times, tyre=tyre, impact=impact)
    ghost = analytic_motion(case, result, times, tyre, simulated.settings.gravity)
    return event, ghost


def build_renderer(case: pim.Case, eps: float, beta: float, *,
                   framing: Framing | None = None, tyre: float | None = None,
                   ghost: bool = True, result: pim.Result | None = None, simulated=None,
                   units: str = "si", title: str | None = None, **options) -> Renderer:
    """Simulate (unless ``simulated`` is given) and prepare the frames of one collision.

    Parameters
    ----------
    case : pim.Case
        The single case.
    eps, beta : float
        Restitution and fraction of mu0 [-].
    framing : Framing, optional
        The seconds shown before and after the impact, the frames per second and the frame
        size (default ``Framing()``: the approach to rest, a size fitted to the motion).
    tyre : float or None
        Tyre/ground friction coefficient after the impact [-] (None: :func:`tyre_choice`'s,
        the case's or the default; 0: free motion); the ghost decelerates with the same
        model.
    ghost : bool
        Draw PIM's answer as a ghost.
    result : pim.Result, optional
        ``pim.solve(case, eps, beta)`` if at hand.
    simulated : sim.SimResult or sim.CompliantResult, optional
        A simulation with a recorded trajectory reaching ``after``.
    units : {"si", "us"} or pim.io.units.DisplayUnits
        Units of the grid, scale bar and speeds.
    title : str, optional
        Caption's first line (default: case, epsilon, beta).
    **options
        Any field of :class:`Framing` by name (``before``, ``after`` [s], ``fps``,
        ``size``), overriding ``framing``'s.

    A secondary impact after separation (:func:`sim.find_secondary_impact`) is marked in
    the frames and reported in the returned renderer's ``secondary``.
    """
    framing = _checked_framing(_framing(framing, options))
    choice = tyre_choice(case, tyre)
    if result is None:
        result = pim.solve(case, eps, beta)
    if simulated is None:
        simulated = sim.simulate(case, eps, beta,
                                 animation_plan(case, result, tyre, framing.after))
    event, analytic = collision_events(case, result, simulated, framing, choice.value)
    if title is None:
        title = (f"{case.name or 'case'}:  epsilon = {format_number(eps)},  "
                 f"beta = {format_number(beta)}")
    secondary = sim.find_secondary_impact(simulated.trajectory)
    warnings = () if secondary is None else (
        (secondary.time, f"SECONDARY IMPACT at t = {secondary.time:.3f} s: the outlines "
                         f"overlap again; this animation models one impact (pim event: all)"),)
    look = Look(title=title, note=choice.text(), units=units, size=framing.size,
                labels=("pymunk simulation", "PIM analytic (ghost)"), warnings=warnings)
    return Renderer(event, analytic if ghost else None, look=look, secondary=secondary)


def event_renderer(case: pim.Case, *, framing: Framing | None = None, tyre=None,
                   units="si", ghost: bool = True, eps=None, beta=None, strict: bool = True):
    """The whole event's frames: the pymunk event (:func:`sim.simulate_event`) solid, the
    analytic event (:func:`pim.event`) as a ghost, from ``framing.before`` (the approach,
    default :data:`pim.model.event.DEFAULT_APPROACH`) to rest plus :data:`REST_HOLD` (or
    ``framing.after`` seconds after the first impact).

    With ``strict`` False an analytic event that :func:`pim.event` refuses (an impact that
    gains energy ...) is left out: the pymunk event is drawn alone, the frames say why.

    Returns
    -------
    (Renderer, Event or None, Event)
        The renderer, the analytic event (None: refused) and the simulated one (as stored).
    """
    framing = _checked_framing(framing or Framing())
    warnings = ()
    try:
        analytic = pim.event(case, tyre_friction=tyre, approach=framing.before, eps=eps,
                             beta=beta)
    except InputError as exc:
        if strict:
            raise
        analytic, warnings = None, ((-math.inf, f"no analytic event: {exc}"),)
    simulated = sim.simulate_event(case, tyre_friction=tyre, approach=framing.before,
                                   eps=eps, beta=beta)
    after = framing.after if framing.after is not None else \
        max(e.end_time for e in (analytic, simulated) if e is not None) + REST_HOLD
    times = frame_times(framing.before, after, framing.fps)
    look = Look(title=f"{case.name or 'case'}: the whole event, approach to rest",
                note=tyre_friction_source(case, tyre)[1], units=units, size=framing.size,
                labels=("pymunk event", "analytic event"),
                measured_rest=measured_rest(case), warnings=warnings)
    shown = analytic.at(times) if ghost and analytic is not None else None
    return Renderer(simulated.at(times), shown, look=look), analytic, simulated


def measured_rest(case: pim.Case) -> tuple:
    """Each vehicle's measured rest pose (position [m], heading [rad]) from the case's
    ``[evidence]``, or None."""
    ev = case.evidence
    return tuple(None if ev is None or getattr(ev, f"vehicle{i}") is None
                 else (getattr(ev, f"vehicle{i}").rest_position,
                       getattr(ev, f"vehicle{i}").rest_heading) for i in (1, 2))


def animate_event(case: pim.Case, out, *, gif=None, progress: bool | None = None,
                  **kwargs) -> AnimationInfo:
    """Write the whole event's animation (:func:`event_renderer`; ``kwargs``: its options
    and :class:`Framing`'s fields by name) to ``out`` (MP4)."""
    options = {k: kwargs.pop(k) for k in ("tyre", "units", "ghost", "eps", "beta")
               if k in kwargs}
    renderer = event_renderer(case, framing=_framing(None, kwargs), strict=False,
                              **options)[0]
    return write_animation(renderer, out, fps=kwargs.get("fps", DEFAULT_FPS), gif=gif,
                           progress=progress)


def _framing(framing: Framing | None, options: dict) -> Framing:
    """``framing`` (default ``Framing()``) with the fields named in ``options`` replaced."""
    names = [f.name for f in fields(Framing)]
    unknown = sorted(set(options) - set(names))
    if unknown:
        raise InputError(f"build_renderer got unknown option(s) {', '.join(unknown)}; "
                         f"allowed: framing, tyre, ghost, result, simulated, units, title, "
                         f"{', '.join(names)}")
    return replace(framing or Framing(), **options)


def animate_case(case: pim.Case, eps: float, beta: float, out, *, gif=None,
                 progress: bool | None = None, **kwargs) -> AnimationInfo:
    """Simulate ``case`` at (eps, beta) and write its animation to ``out`` (MP4)."""
    renderer = build_renderer(case, eps, beta, **kwargs)
    return write_animation(renderer, out, fps=kwargs.get("fps", DEFAULT_FPS), gif=gif,
                           progress=progress)
