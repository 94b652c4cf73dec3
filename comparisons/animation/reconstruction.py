"""The reconstruction's animation: the fitted run-outs from the impact to rest
(:meth:`pim.analysis.reconstruction.PostImpact.event`), the measured rest positions as dotted
outlines, the impact at its C, drawn by the one renderer (:mod:`comparisons.animation.render`)
like every other animation of the project.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from comparisons.animation.motion import case_impact
from comparisons.animation.plan import plan_view
from comparisons.animation.render import DEFAULT_FPS, AnimationInfo, Look, Renderer, \
    write_animation
from pim.model.number_format import format_number
from pim.analysis.reconstruction import PostImpact
from pim.model.event import Event
from pim.model.numbers import InputError

__all__ = ["reconstruction_event", "reconstruction_renderer", "write_reconstruction_video",
           "reconstruction_plan", "DEFAULT_HOLD"]

#: Seconds the rest poses are held at the end of the reconstruction's animation.
DEFAULT_HOLD = 1.0


def reconstruction_event(post: PostImpact, result, fps: int = DEFAULT_FPS,
                         hold: float = DEFAULT_HOLD) -> Event:
    """The fitted run-outs at ``fps`` frames per second from the impact (t = 0) until the
    later vehicle is at rest, then ``hold`` seconds of the rest poses; the impact's record
    from the reconstruction's answer ``result`` (a :class:`pim.Result`), each vehicle's
    wheels from its ``[evidence]`` axles and the tyre marks where they slide
    (:meth:`pim.analysis.reconstruction.PostImpact.event`). A motion fitted through the
    event is shown through its further impacts, each marked at its C."""
    if not (isinstance(fps, int | np.integer) and fps >= 1):
        raise InputError(f"fps must be a positive integer, got {fps!r}")
    if not (np.isfinite(hold) and hold >= 0):
        raise InputError(f"hold must be >= 0 [s], got {hold!r}")
    if not post.runouts:
        raise InputError("the reconstruction has no run-out to animate (no [evidence])")
    first = case_impact(post.case, result)
    if post.event_fit is not None:      # fitted through the event: its further impacts too
        full = post.event(first=first)
        return full.at(_frame_times(float(full.time[-1]), fps, hold))
    end = max(float(f.runout.time[-1]) for f in post.runouts.values())
    return replace(post.event(_frame_times(end, fps, hold)), impacts=(first,))


def _frame_times(end: float, fps: int, hold: float) -> np.ndarray:
    """Frame times [s] from the impact to ``end`` and ``hold`` seconds more."""
    return np.arange(int(np.ceil((end + hold) * fps)) + 1) / fps


def _measured_rest(post: PostImpact) -> tuple:
    """Each vehicle's measured rest pose (position, heading) or None."""
    out = []
    for i in (1, 2):
        ev = getattr(post.case.evidence, f"vehicle{i}")
        out.append(None if ev is None else (ev.rest_position, ev.rest_heading))
    return tuple(out)


def reconstruction_renderer(post: PostImpact, result, *, units="si", fps: int = DEFAULT_FPS,
                            hold: float = DEFAULT_HOLD, size=None) -> Renderer:
    """The frames of the reconstructed crash (see :func:`reconstruction_event`), with the
    measured rest positions and the run-outs' tyre friction in the caption."""
    event = reconstruction_event(post, result, fps, hold)
    friction = ", ".join(
        f"vehicle {i}: {format_number(getattr(post.case.evidence, f'vehicle{i}').friction)}"
        for i in post.runouts)
    look = Look(title=f"{post.case.name or 'case'}: reconstruction, the fitted run-outs "
                      f"from the impact to rest",
                note=f"tyre friction from the case's [evidence] ({friction})", units=units,
                labels=("fitted run-out", ""), size=size,
                measured_rest=_measured_rest(post))
    return Renderer(event, look=look)


def write_reconstruction_video(post: PostImpact, result, path, *, units="si",
                               fps: int = DEFAULT_FPS, progress: bool | None = None,
                               size=None) -> AnimationInfo:
    """Write the reconstruction's animation (MP4) to ``path``, atomically."""
    renderer = reconstruction_renderer(post, result, units=units, fps=fps, size=size)
    return write_animation(renderer, path, fps=fps, progress=progress)


def reconstruction_plan(post: PostImpact, result, units="si"):
    """The reconstruction in plan view (:func:`comparisons.animation.plan.plan_view` of
    :func:`reconstruction_event`): the fitted run-outs' outlines at a stated interval with
    their times, the CG paths, the impact, the measured rest positions and path points."""
    points = [getattr(post.case.evidence, f"vehicle{i}").path_points for i in post.runouts]
    return plan_view(reconstruction_event(post, result, hold=0.0), units=units,
                     measured_rest=_measured_rest(post), points=points,
                     title=f"{post.case.name or 'case'}: the reconstruction's fitted run-outs")
