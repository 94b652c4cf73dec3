"""MP4 of a reconstructed crash from the impact to rest: both cars moving along their fitted
run-outs (:func:`pim.analysis.reconstruction.post_impact_motion`), the measured rest
positions drawn as outlines, a clock, axes in the case's length unit.

:func:`frame_states` computes what each frame shows (pure, tested: the first frame is the
impact pose, the last the fitted rest); :func:`write_reconstruction_mp4` draws the frames with
matplotlib (an Agg canvas on a :class:`matplotlib.figure.Figure`; the pyplot backend is never
touched) and writes them with imageio's ffmpeg writer, atomically.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.reconstruction import PostImpact
from ..io.files import atomic_path
from ..io.units import convert
from ..model.geometry import outline_world
from ..model.numbers import InputError
from .reconstruction_scene import COLOURS

__all__ = ["FrameStates", "frame_states", "write_reconstruction_mp4", "DEFAULT_FPS",
           "DEFAULT_HOLD"]

DEFAULT_FPS = 25
DEFAULT_HOLD = 1.0      # [s] the rest pose is held at the end


@dataclass(frozen=True)
class FrameStates:
    """Per frame: the time [s] after the impact and each car's (x, y, heading) [m, m, rad].

    ``states`` maps the vehicle number to an array (n_frames, 3).

    Attributes
    ----------
    times : ndarray (n_frames,)
        Time of each frame after the impact [s].
    states : dict of int to ndarray (n_frames, 3)
        Vehicle number (1, 2) -> its pose (x, y, heading) per frame [m, m, rad] (the rest
        pose once it has stopped; only the vehicles with a run-out).
    """

    times: np.ndarray
    states: dict


def frame_states(post: PostImpact, fps: int = DEFAULT_FPS,
                 hold: float = DEFAULT_HOLD) -> FrameStates:
    """Each car's pose at ``fps`` frames per second from the impact until the last car is at
    rest, then ``hold`` seconds of the rest poses; linear interpolation of the run-out's
    stored states (the heading is integrated continuously, so it interpolates without a
    jump at +-180 deg)."""
    if not (isinstance(fps, int | np.integer) and fps >= 1):
        raise InputError(f"fps must be a positive integer, got {fps!r}")
    if not (np.isfinite(hold) and hold >= 0):
        raise InputError(f"hold must be >= 0 [s], got {hold!r}")
    if not post.runouts:
        raise InputError("the reconstruction has no run-out to animate (no [evidence])")
    end = max(float(f.runout.time[-1]) for f in post.runouts.values())
    times = np.arange(int(np.ceil((end + hold) * fps)) + 1) / fps
    event = post.event(times)
    states = {i: np.column_stack([event.tracks[i - 1].position, event.tracks[i - 1].heading])
              for i in post.runouts}
    return FrameStates(times=times, states=states)


def _draw_scene(ax, post: PostImpact, frames, scale: float, unit: str) -> dict:
    """Draw the run-out paths, measured rest poses and C on ``ax`` (lengths times ``scale``,
    labelled in ``unit``); return {vehicle: (patch, length, width, cg_to_front)}, the
    patches each frame moves."""
    from matplotlib.patches import Polygon

    case = post.case
    patches, extent = {}, []
    for i, fit in post.runouts.items():
        vehicle = getattr(case, f"vehicle{i}")
        evidence = getattr(case.evidence, f"vehicle{i}")
        length = vehicle.length if vehicle.length is not None else 4.5
        width = vehicle.width if vehicle.width is not None else 1.8
        colour = COLOURS[i]
        path_xy = fit.runout.states[:, :2] * scale
        ax.plot(path_xy[:, 0], path_xy[:, 1], "-", color=colour, lw=0.8, alpha=0.5)
        rest = outline_world(length, width, evidence.rest_position, evidence.rest_heading,
                             vehicle.cg_to_front)
        closed = np.vstack([rest, rest[:1]]) * scale
        ax.plot(closed[:, 0], closed[:, 1], "--", color="k", lw=1.0)
        start = outline_world(length, width, frames.states[i][0, :2], frames.states[i][0, 2],
                              vehicle.cg_to_front)
        patch = Polygon(start * scale, closed=True, facecolor=colour, alpha=0.6,
                        edgecolor=colour, label=f"vehicle {i}")
        ax.add_patch(patch)
        patches[i] = (patch, length, width, vehicle.cg_to_front)
        extent += [path_xy, closed]
    ax.plot([], [], "--", color="k", label="measured rest")
    ax.plot(*(np.asarray(case.impact.point) * scale), "*", color="k", ms=10, label="C")
    pts = np.vstack(extent)
    margin = 0.15 * max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]), 1.0)
    ax.set_xlim(pts[:, 0].min() - margin, pts[:, 0].max() + margin)
    ax.set_ylim(pts[:, 1].min() - margin, pts[:, 1].max() + margin)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    return patches


def write_reconstruction_mp4(post: PostImpact, path, *, units: str = "si",
                             fps: int = DEFAULT_FPS, hold: float = DEFAULT_HOLD,
                             size=(8.0, 6.0), dpi: int = 100) -> Path:
    """Write the animation of ``post`` to ``path`` (MP4, H.264) atomically; return the path.

    Parameters
    ----------
    post : PostImpact
        The reconstruction's post-impact motion (with the fitted run-outs).
    path : path
        The MP4 file.
    units : str
        "si" or "us": the axes' length unit.
    fps : int
        Frames per second.
    hold : float
        [s] the rest poses are held this long at the end.
    size, dpi :
        Figure size [in] and resolution (the frame is size * dpi pixels, rounded to even).
    """
    import imageio.v2 as imageio
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    frames = frame_states(post, fps, hold)
    scale, unit = convert(1.0, "length", units)
    scale = float(scale)
    case = post.case
    fig = Figure(figsize=size, dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    patches = _draw_scene(ax, post, frames, scale, unit)
    clock = ax.set_title("")
    path = Path(path)
    with atomic_path(path) as tmp:
        writer = imageio.get_writer(tmp, format="FFMPEG", mode="I", fps=fps, codec="libx264",
                                    pixelformat="yuv420p", quality=7, macro_block_size=2,
                                    ffmpeg_log_level="error")
        try:
            for k, t in enumerate(frames.times):
                for i, (patch, length, width, front) in patches.items():
                    x, y, h = frames.states[i][k]
                    patch.set_xy(outline_world(length, width, (x, y), h, front) * scale)
                clock.set_text(f"{case.name}: t = {t:5.2f} s after the impact")
                canvas.draw()
                rgba = np.asarray(canvas.buffer_rgba())
                writer.append_data(rgba[: rgba.shape[0] // 2 * 2, : rgba.shape[1] // 2 * 2, :3])
        finally:
            writer.close()
    return path
