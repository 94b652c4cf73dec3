"""Off-screen animation of a collision: the pymunk simulation solid, PIM's answer as a ghost.

Each frame shows both vehicles' outlines (filled: the simulation) with a heading mark, the
CGs, the impact point C, the contact plane (the tangent through C) and the normal n, the
velocity arrows, the impulse on vehicle 1 at C for a moment after the impact, and a clock.
The analytic post-impact motion (:func:`comparisons.animation.motion.analytic_motion`) is drawn over
the same frames as a dashed magenta outline with its own velocity arrows: when the
cross-check agrees it sits exactly on the simulated vehicle; any mismatch shows as a
visible offset.

Frames are drawn with Pillow's ImageDraw on a pre-rendered background (grid, scale bar,
C, n and the contact plane): several hundred frames per second
(``benchmarks/bench_animation.py`` prints the rate). The MP4 is written with imageio's
ffmpeg plugin (libx264, yuv420p, even frame size), the optional GIF with Pillow; both to
a temporary file in the output folder, then renamed.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

import pim
import sim
from comparisons.animation.motion import analytic_motion, simulated_motion
from pim.model.event import Event
from pim.io.files import atomic_paths
from pim.io.units import convert
from pim.model.geometry import outline_corners
from pim.model.numbers import InputError, checked_number

__all__ = ["AnimationInfo", "Renderer", "Framing", "build_renderer", "frame_times",
           "simulate_for_animation", "animation_settings",
           "write_animation", "animate_case", "DEFAULT_SIZE", "DEFAULT_FPS", "MAX_SHOWN"]

DEFAULT_SIZE = (960, 720)
DEFAULT_FPS = 30
#: Seconds shown after the impact by default (the issue asks for at least 2 s of motion).
DEFAULT_AFTER = 2.0
#: Longest time shown before or after the impact [s]: 10 minutes of scene, 18000 frames at
#: 30 fps (minutes of drawing); the bound is checked before any work.
MAX_SHOWN = 600.0
#: Default length and width [m] drawn for a vehicle without an outline.
DEFAULT_OUTLINE = (4.5, 1.8)
#: How long the impulse arrow stays on screen after the impact [s].
IMPULSE_SHOWN = 0.4

COLORS = {
    "background": (255, 255, 255), "grid": (232, 232, 232), "text": (20, 20, 20),
    "fill1": (120, 170, 230), "edge1": (20, 60, 140),
    "fill2": (245, 180, 110), "edge2": (150, 70, 10),
    "fixed": (170, 170, 170), "fixed_edge": (70, 70, 70),
    "ghost": (220, 0, 200), "impulse": (210, 20, 20), "contact": (0, 140, 70),
    "velocity": (10, 10, 10), "warning": (180, 0, 0),
}


def _font(size: int):
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow without FreeType sizing
        return ImageFont.load_default()


def frame_times(before: float, after: float, fps: int) -> np.ndarray:
    """Frame times [s] from -before to +after (0, the impact, is always a frame)."""
    if not (fps >= 1 and int(fps) == fps):
        raise InputError(f"fps must be a positive integer, got {fps!r}")
    if not (before >= 0 and after > 0 and math.isfinite(before + after)):
        raise InputError(f"before must be >= 0 and after > 0 [s], got {before!r}, {after!r}")
    n_before = int(round(before * fps))
    n_after = int(round(after * fps))
    return np.arange(-n_before, n_after + 1) / fps


def _auto_before(case: pim.Case) -> float:
    """Pre-impact time [s]: the faster vehicle covers about 1.2 of its length, 0.15-0.5 s."""
    best = 0.5
    for v in (case.vehicle1, case.vehicle2):
        if bool(v.fixed):
            continue
        speed = float(np.hypot(*np.asarray(v.velocity, float).reshape(2)))
        if speed > 0:
            best = min(best, 1.2 * (v.length or DEFAULT_OUTLINE[0]) / speed)
    return float(np.clip(best, 0.15, 0.5))


def simulate_for_animation(case: pim.Case, eps: float, beta: float, after: float,
                           tyre: float = 0.0, dt: float = 1e-3):
    """Run the simulator with a recorded trajectory reaching ``after`` seconds past impact."""
    return sim.simulate(case, eps, beta, animation_settings(after, tyre, dt))


def animation_settings(after: float, tyre: float = 0.0, dt: float = 1e-3) -> sim.Settings:
    """Simulator settings recording ``after`` seconds past the impact, tyre friction ``tyre``
    [-] after it (0: none)."""
    return sim.Settings(dt=dt, record=True, duration=after + 2 * dt,
                        tyre_friction=float(tyre) if tyre else False)


def _corners(vehicle: pim.Vehicle) -> np.ndarray | None:
    if vehicle.length is None or vehicle.width is None:
        if bool(vehicle.fixed):
            return None
        length, width = DEFAULT_OUTLINE
    else:
        length, width = vehicle.length, vehicle.width
    return outline_corners(length, width, vehicle.cg_to_front)


def _place(corners: np.ndarray, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Body-frame points (K, 2) at poses (F,) -> world points (F, K, 2)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x, y = corners[:, 0][None], corners[:, 1][None]
    return np.stack([c * x - s * y, s * x + c * y], -1) + position[:, None, :]


@dataclass(frozen=True)
class Framing:
    """Which stretch of a collision an animation shows, and its frames.

    Attributes
    ----------
    before : float or None
        Seconds shown before the impact (None: about 1.2 vehicle lengths of travel).
    after : float
        Seconds shown after the impact.
    fps : int
        Frames per second.
    size : (int, int)
        Frame width and height [px], both even.
    """

    before: float | None = None
    after: float = DEFAULT_AFTER
    fps: int = DEFAULT_FPS
    size: tuple = DEFAULT_SIZE


@dataclass(frozen=True)
class AnimationInfo:
    """What :func:`write_animation` wrote and how fast.

    Attributes
    ----------
    path : Path
        The MP4.
    gif : Path or None
        The GIF, if asked for.
    frames : int
        Frames written.
    fps : int
        Frames per second of the video.
    size : (int, int)
        Width and height [px].
    render_seconds : float
        Wall time spent drawing the frames [s].
    write_seconds : float
        Wall time spent encoding and writing [s].
    max_ghost_offset_px : float
        Largest distance [px] between a ghost corner and the matching simulated corner
        after the impact (0 when simulation and PIM agree).
    secondary_impact : sim.SecondaryImpact or None
        The outlines run into each other again after separation (a second impact PIM does
        not model); the frames from then on say so.
    """

    path: Path
    gif: Path | None
    frames: int
    fps: int
    size: tuple[int, int]
    render_seconds: float
    write_seconds: float
    max_ghost_offset_px: float
    secondary_impact: object = None

    @property
    def render_fps(self) -> float:
        """Frames drawn per second of wall time."""
        return self.frames / max(self.render_seconds, 1e-12)


class Renderer:
    """Draws the frames of one collision (Pillow), world y axis up.

    Parameters
    ----------
    case : pim.Case
        The single case.
    result : pim.Result
        PIM's answer (for the ghost's label values and the impulse arrow).
    simulated : pim.model.event.Event
        The simulated event at the frame times.
    ghost : pim.model.event.Event or None
        The analytic poses at the same times (None: no ghost).
    impulse : array_like (2,)
        Impulse on vehicle 1 to draw at C [N s] (the simulator's).
    size : (int, int)
        Frame size [px]; both even (libx264 with yuv420p needs it).
    title : str
        First line of the caption.
    secondary : sim.SecondaryImpact, optional
        A secondary impact after separation: frames from its time on carry a warning.
    """

    TOP, BOTTOM, MARGIN = 54, 46, 24

    def __init__(self, case: pim.Case, result: pim.Result, simulated: Event,
                 ghost: Event | None, impulse, *, size=DEFAULT_SIZE, title: str = "",
                 units: str = "si", secondary=None) -> None:
        width, height = (int(s) for s in size)
        if width % 2 or height % 2 or width < 160 or height < 160:
            raise InputError(f"size must be even and at least 160 px, got {size!r}")
        self.case, self.result, self.sim, self.ghost = case, result, simulated, ghost
        self.size = (width, height)
        self.title = title
        factor, unit = convert(1.0, "length", units)
        self.length_unit = (float(factor), unit)      # display units per metre, label
        factor, unit = convert(1.0, "impulse", units)
        self.impulse_unit = (float(factor), unit)     # display units per N s, label
        self.secondary = secondary
        self.times = simulated.time
        self.corners = (_corners(case.vehicle1), _corners(case.vehicle2))
        self.point = np.asarray(case.impact.point, float).reshape(2)
        gamma = float(case.impact.normal_angle)
        self.normal = np.array([math.cos(gamma), math.sin(gamma)])
        self.tangent = np.array([-self.normal[1], self.normal[0]])
        self.impulse = np.asarray(impulse, float).reshape(2)
        self._world = {}
        motions = [("sim", simulated)] + ([("ghost", ghost)] if ghost is not None else [])
        for tag, m in motions:
            for i, track in enumerate(m.tracks):
                if self.corners[i] is not None:
                    self._world[tag, i] = _place(self.corners[i], track.position,
                                                 track.heading)
        self._fit_view()
        self.font = _font(15)
        self.small = _font(12)
        self._background = self._draw_background()
        self._px = {key: self.to_px(val) for key, val in self._world.items()}
        self._cg = {(tag, i): self.to_px(m.tracks[i].position)
                    for tag, m in motions for i in range(2)}
        self._heading = {(tag, i): m.tracks[i].heading for tag, m in motions
                         for i in range(2)}
        self._vel = {(tag, i): m.tracks[i].velocity for tag, m in motions
                     for i in range(2)}

    # ---- geometry ------------------------------------------------------------------------
    def _fit_view(self) -> None:
        pts = [w.reshape(-1, 2) for w in self._world.values()]
        pts += [self.sim.vehicle1.position, self.sim.vehicle2.position, self.point[None]]
        pts = np.concatenate(pts)
        lo, hi = pts.min(0), pts.max(0)
        span = np.maximum(hi - lo, 1.0)
        width, height = self.size
        avail_w = width - 2 * self.MARGIN
        avail_h = height - self.TOP - self.BOTTOM - 2 * self.MARGIN
        self.scale = float(min(avail_w / span[0], avail_h / span[1]))   # px per m
        centre = (lo + hi) / 2
        self.origin = np.array([width / 2, self.TOP + self.MARGIN + avail_h / 2])
        self.centre = centre
        speeds = np.concatenate([self.sim.vehicle1.speed, self.sim.vehicle2.speed])
        vmax = max(float(speeds.max()), 1e-9)
        self.arrow_px_per_mps = 0.12 * min(width, height) / vmax
        p = float(np.hypot(*self.impulse))
        self.arrow_px_per_ns = 0.15 * min(width, height) / p if p > 0 else 0.0

    def to_px(self, world) -> np.ndarray:
        """World points [m] (..., 2) -> pixel coordinates (..., 2), y downwards."""
        w = np.asarray(world, float)
        x = (w[..., 0] - self.centre[0]) * self.scale + self.origin[0]
        y = self.origin[1] - (w[..., 1] - self.centre[1]) * self.scale
        return np.stack([x, y], -1)

    def outline_px(self, frame: int, vehicle: int, ghost: bool = False) -> np.ndarray | None:
        """Corners (4, 2) [px] of a vehicle's outline in a frame (None without an outline)."""
        key = ("ghost" if ghost else "sim", vehicle - 1)
        arr = self._px.get(key)
        return None if arr is None else arr[frame]

    def __len__(self) -> int:
        return len(self.times)

    # ---- drawing -------------------------------------------------------------------------
    def _arrow(self, draw, start, vec_px, color, width=3, dashed=False) -> None:
        start = np.asarray(start, float)
        end = start + vec_px
        length = float(np.hypot(*vec_px))
        if length < 2:
            return
        if dashed:
            self._dashed(draw, [start, end], color, width)
        else:
            draw.line([tuple(start), tuple(end)], fill=color, width=width)
        u = vec_px / length
        head = min(12.0, 0.4 * length)
        side = np.array([-u[1], u[0]])
        base = end - head * u
        draw.polygon([tuple(end), tuple(base + 0.45 * head * side),
                      tuple(base - 0.45 * head * side)], fill=color)

    @staticmethod
    def _dashed(draw, points, color, width, dash=9.0, gap=6.0) -> None:
        pts = np.asarray(points, float)
        for a, b in zip(pts[:-1], pts[1:], strict=True):
            d = b - a
            length = float(np.hypot(*d))
            if length == 0:
                continue
            u = d / length
            s = 0.0
            while s < length:
                e = min(s + dash, length)
                draw.line([tuple(a + s * u), tuple(a + e * u)], fill=color, width=width)
                s = e + gap

    def _draw_background(self) -> Image.Image:
        width, height = self.size
        img = Image.new("RGB", self.size, COLORS["background"])
        d = ImageDraw.Draw(img)
        # grid every 1, 2, 5 or 10 display units (m or ft): lines at least 40 px apart
        per_m, unit = self.length_unit
        shown = next(s for s in (0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000)
                     if s / per_m * self.scale >= 40)
        step = shown / per_m
        lo = self.centre - np.array([width, height]) / 2 / self.scale
        hi = self.centre + np.array([width, height]) / 2 / self.scale
        for x in np.arange(math.floor(lo[0] / step) * step, hi[0] + step, step):
            px = self.to_px([x, 0.0])[0]
            d.line([(px, self.TOP), (px, height - self.BOTTOM)], fill=COLORS["grid"])
        for y in np.arange(math.floor(lo[1] / step) * step, hi[1] + step, step):
            py = self.to_px([0.0, y])[1]
            if self.TOP <= py <= height - self.BOTTOM:
                d.line([(0, py), (width, py)], fill=COLORS["grid"])
        # contact plane through C, normal n, C itself
        c = self.to_px(self.point)
        half = 0.22 * min(width, height)
        t = self.tangent * np.array([1, -1])
        self._dashed(d, [c - half * t, c + half * t], COLORS["contact"], 2, dash=12, gap=6)
        d.text(tuple(c + half * t + np.array([4, -8])), "contact plane",
               fill=COLORS["contact"], font=self.small)
        # scale bar
        bar = step * self.scale
        y0 = height - 18
        d.line([(width - 30 - bar, y0), (width - 30, y0)], fill=COLORS["text"], width=3)
        d.text((width - 30 - bar, y0 - 18), f"{shown:g} {unit}", fill=COLORS["text"],
               font=self.small)
        # caption
        d.rectangle([0, 0, width, self.TOP - 4], fill=(248, 248, 248))
        d.text((10, 6), self.title, fill=COLORS["text"], font=self.font)
        legend = [("filled: pymunk simulation", COLORS["edge1"]),
                  ("dashed: PIM analytic (ghost)", COLORS["ghost"]) if self.ghost is not None
                  else ("", COLORS["text"]),
                  ("red: impulse on vehicle 1", COLORS["impulse"])]
        x = 10
        for text, color in legend:
            if text:
                d.text((x, 30), text, fill=color, font=self.small)
                x += int(d.textlength(text, font=self.small)) + 24
        return img

    def _vehicle(self, d, frame: int, i: int) -> None:
        vehicle = (self.case.vehicle1, self.case.vehicle2)[i]
        fixed = bool(vehicle.fixed)
        poly = self._px.get(("sim", i))
        if poly is None:         # a barrier without dimensions: its face along the plane
            c = self.to_px(self.point)
            t = self.tangent * np.array([1, -1])
            half = 0.45 * min(self.size)
            d.line([tuple(c - half * t), tuple(c + half * t)], fill=COLORS["fixed_edge"],
                   width=6)
            return
        fill = COLORS["fixed"] if fixed else COLORS[f"fill{i + 1}"]
        edge = COLORS["fixed_edge"] if fixed else COLORS[f"edge{i + 1}"]
        pts = [tuple(p) for p in poly[frame]]
        d.polygon(pts, fill=fill, outline=edge, width=2)
        if fixed:
            return
        cg = self._cg["sim", i][frame]
        front = (poly[frame][0] + poly[frame][3]) / 2
        d.line([tuple(cg), tuple(cg + 0.8 * (front - cg))], fill=edge, width=2)   # heading
        r = 5
        d.ellipse([cg[0] - r, cg[1] - r, cg[0] + r, cg[1] + r], fill=(255, 255, 255),
                  outline=COLORS["text"], width=2)
        d.line([(cg[0] - r, cg[1]), (cg[0] + r, cg[1])], fill=COLORS["text"], width=1)
        d.line([(cg[0], cg[1] - r), (cg[0], cg[1] + r)], fill=COLORS["text"], width=1)
        v = self._vel["sim", i][frame] * np.array([1, -1]) * self.arrow_px_per_mps
        self._arrow(d, cg, v, COLORS["velocity"], width=3)
        d.text(tuple(cg + np.array([8, 4])), str(i + 1), fill=COLORS["text"], font=self.font)

    def _ghost(self, d, frame: int, i: int) -> None:
        poly = self._px.get(("ghost", i))
        vehicle = (self.case.vehicle1, self.case.vehicle2)[i]
        if poly is None or bool(vehicle.fixed):
            return
        pts = poly[frame]
        self._dashed(d, [*pts, pts[0]], COLORS["ghost"], 2)
        cg = self._cg["ghost", i][frame]
        r = 4
        d.line([(cg[0] - r, cg[1] - r), (cg[0] + r, cg[1] + r)], fill=COLORS["ghost"], width=2)
        d.line([(cg[0] - r, cg[1] + r), (cg[0] + r, cg[1] - r)], fill=COLORS["ghost"], width=2)
        v = self._vel["ghost", i][frame] * np.array([1, -1]) * self.arrow_px_per_mps
        self._arrow(d, cg, v, COLORS["ghost"], width=1, dashed=True)

    def _contact(self, d) -> None:
        """C and the normal n, on top of the vehicles."""
        c = self.to_px(self.point)
        n = self.normal * np.array([1, -1])
        self._arrow(d, c, 60 * n, COLORS["contact"], width=2)
        d.text(tuple(c + 66 * n + np.array([-4, -8])), "n", fill=COLORS["contact"],
               font=self.font)
        r = 5
        d.ellipse([c[0] - r, c[1] - r, c[0] + r, c[1] + r], outline=COLORS["contact"], width=2)
        d.text((c[0] - 18, c[1] + 3), "C", fill=COLORS["contact"], font=self.font)

    def frame(self, index: int) -> Image.Image:
        """Frame ``index`` as an RGB Pillow image."""
        img = self._background.copy()
        d = ImageDraw.Draw(img)
        t = float(self.times[index])
        for i in (1, 0):
            self._vehicle(d, index, i)
        self._contact(d)
        if self.ghost is not None and t >= 0:
            for i in (0, 1):
                self._ghost(d, index, i)
        if 0 <= t <= IMPULSE_SHOWN and self.arrow_px_per_ns > 0:
            c = self.to_px(self.point)
            p = self.impulse * np.array([1, -1]) * self.arrow_px_per_ns
            self._arrow(d, c, p, COLORS["impulse"], width=5)
            d.text(tuple(c + p + np.array([6, -6])),
                   f"P = {np.hypot(*self.impulse) * self.impulse_unit[0]:.4g} "
                   f"{self.impulse_unit[1]}", fill=COLORS["impulse"],
                   font=self.font)
        phase = "before impact" if t < 0 else ("impact" if t == 0 else "after impact")
        self._clock(d, f"t = {t:+.3f} s   {phase}")
        if self.secondary is not None and t >= self.secondary.time:
            d.text((10, self.TOP + 2),            # above the scene: controls cover the bottom
                   f"SECONDARY IMPACT at t = {self.secondary.time:.3f} s: the outlines overlap "
                   f"again; PIM models one impact", fill=COLORS["warning"], font=self.font)
        return img

    def _clock(self, d, text: str) -> None:
        """The clock in the caption band at the top, right-aligned on the title's line (on
        the legend's when the title is long): a page's video controls cover the bottom."""
        x = self.size[0] - 10 - d.textlength(text, font=self.font)
        title_end = 10 + d.textlength(self.title, font=self.font)
        d.text((x, 6 if x > title_end + 20 else 28), text, fill=COLORS["text"],
               font=self.font)

    def array(self, index: int) -> np.ndarray:
        """Frame ``index`` as a (height, width, 3) uint8 array."""
        return _pixels(self.frame(index))

    def ghost_offset_px(self) -> float:
        """Largest distance [px] between ghost and simulated corners at t >= 0."""
        after = self.times >= 0
        worst = 0.0
        for i in (0, 1):
            a, b = self._px.get(("sim", i)), self._px.get(("ghost", i))
            if a is None or b is None:
                continue
            worst = max(worst, float(np.hypot(*(a[after] - b[after]).reshape(-1, 2).T).max()))
        return worst


def _pixels(img: Image.Image) -> np.ndarray:
    """RGB image -> (height, width, 3) uint8 array (tobytes: about twice np.asarray's speed)."""
    return np.frombuffer(img.tobytes(), np.uint8).reshape(img.height, img.width, 3)


def write_animation(renderer: Renderer, path, fps: int = DEFAULT_FPS, gif=None,
                    progress: bool | None = None) -> AnimationInfo:
    """Draw every frame and write the MP4 (and optionally a GIF at half size), atomically.

    Parameters
    ----------
    renderer : Renderer
        The prepared frames.
    path : path
        MP4 file to write.
    fps : int
        Frames per second of the video.
    gif : path, optional
        Also write an animated GIF (half size) there.
    progress : bool or None
        Show a tqdm bar on stderr (None: only on a terminal).
    """
    import imageio.v2 as imageio
    from tqdm import tqdm

    path = Path(path)
    render = 0.0
    start = _time.perf_counter()
    thumbs = []
    gif_path = None if gif is None else Path(gif)
    targets = (path,) if gif_path is None else (path, gif_path)
    with atomic_paths(*targets) as temps:
        writer = imageio.get_writer(temps[0], format="FFMPEG", mode="I", fps=fps,
                                    codec="libx264", pixelformat="yuv420p", quality=7,
                                    macro_block_size=2, ffmpeg_log_level="error")
        try:
            for i in tqdm(range(len(renderer)), desc="animation", unit="frame", leave=False,
                          disable=None if progress is None else not progress):
                t0 = _time.perf_counter()
                img = renderer.frame(i)
                render += _time.perf_counter() - t0
                writer.append_data(_pixels(img))
                if gif_path is not None:
                    thumbs.append(img.resize((img.width // 2, img.height // 2),
                                             Image.Resampling.BILINEAR))
        finally:
            writer.close()
        if gif_path is not None:
            thumbs[0].save(temps[1], format="GIF", save_all=True, append_images=thumbs[1:],
                           duration=round(1000 / fps), loop=0, optimize=False)
    total = _time.perf_counter() - start
    return AnimationInfo(path=path, gif=gif_path, frames=len(renderer), fps=int(fps),
                         size=renderer.size, render_seconds=render,
                         write_seconds=total - render,
                         max_ghost_offset_px=renderer.ghost_offset_px(),
                         secondary_impact=renderer.secondary)


def build_renderer(case: pim.Case, eps: float, beta: float, *,
                   framing: Framing | None = None, tyre: float = 0.0, ghost: bool = True,
                   result: pim.Result | None = None, simulated=None, units: str = "si",
                   title: str | None = None, **options) -> Renderer:
    """Simulate (unless ``simulated`` is given) and prepare the frames of one collision.

    Parameters
    ----------
    case : pim.Case
        The single case.
    eps, beta : float
        Restitution and fraction of mu0 [-].
    framing : Framing, optional
        The seconds shown before and after the impact, the frames per second and the frame
        size (default ``Framing()``).
    tyre : float
        Tyre/ground friction coefficient after the impact [-] (0: none, the default, so that
        simulation and ghost follow the same free motion); the ghost then decelerates with
        the same model.
    ghost : bool
        Draw PIM's answer as a ghost.
    result : pim.Result, optional
        ``pim.solve(case, eps, beta)`` if at hand.
    simulated : sim.SimResult or sim.CompliantResult, optional
        A simulation with a recorded trajectory reaching ``after``.
    units : {"si", "us"} or pim.io.units.DisplayUnits
        Units of the grid and scale bar (m or ft).
    title : str, optional
        Caption's first line (default: case, epsilon, beta, tyre friction).
    **options
        Any field of :class:`Framing` by name (``before``, ``after`` [s], ``fps``,
        ``size``), overriding ``framing``'s.

    A secondary impact after separation (:func:`sim.find_secondary_impact`) is marked in
    the frames and reported in the returned renderer's ``secondary``.
    """
    framing = _framing(framing, options)
    before, after, fps = framing.before, framing.after, framing.fps
    after = checked_number(after, "after", low=0.0, high=MAX_SHOWN, unit="s")
    if before is not None:
        before = checked_number(before, "before", low=0.0, high=MAX_SHOWN, unit="s")
    if result is None:
        result = pim.solve(case, eps, beta)
    if before is None:
        before = _auto_before(case)
    times = frame_times(before, after, fps)
    if simulated is None:
        simulated = simulate_for_animation(case, eps, beta, after, tyre)
    gravity = simulated.settings.gravity
    sim_motion = simulated_motion(case, simulated.trajectory, times)
    ghost_motion = analytic_motion(case, result, times, tyre, gravity) if ghost else None
    if title is None:
        title = (f"{case.name or 'case'}:  epsilon = {eps:.4g},  beta = {beta:.4g}"
                 + (f",  tyre friction {tyre:g}" if tyre else ",  no tyre friction after impact"))
    secondary = sim.find_secondary_impact(simulated.trajectory)
    return Renderer(case, result, sim_motion, ghost_motion, simulated.impulse,
                    size=framing.size, title=title, units=units, secondary=secondary)


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
