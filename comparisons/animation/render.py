"""The one animation renderer: any :class:`pim.model.event.Event`, off screen, with Pillow.

Every animation of the project is drawn here from events (the collision's simulated event
with PIM's analytic one as a ghost, the whole event from the approach to rest, a
reconstruction's fitted run-outs); the renderer never asks where an event came from.

Each frame shows both vehicles' outlines (filled: the event; dashed magenta: the ghost
event) with a heading mark, the CGs and velocity arrows; the tyre marks laid so far where a
wheel slides (:attr:`pim.model.event.Track.sliding`, dark grey); every impact of the event
at its C with its contact plane, its normal and its number, and for a moment after it the
impulse on vehicle 1; the measured rest positions as dotted outlines where the case gives
them; the CG paths faintly. All the text stands in the panel above the scene, never on a
vehicle and never under a video player's controls (which cover the bottom of a frame): the
title and the tyre friction with its source, the legend, and the clock with the phase and
each vehicle's speed in the user's speed unit, numbers in the reports' format
(:mod:`pim.model.number_format`).

The view is fitted to the motion: the union of every outline drawn (event, ghost, measured
rest, each C) fills the scene area in its binding direction, and without a stated frame
size the frame takes the motion's aspect (:func:`fitted_size`), so the motion fills the
frame both ways instead of a strip of it.

Frames are drawn on a pre-rendered background (grid, scale bar, paths, impacts, measured
rest, legend) onto which the tyre marks are laid as the frames advance: several hundred
frames per second (``benchmarks/bench_animation.py`` prints the rate against the previous
renderers measured in the same run). The MP4 is written with imageio's ffmpeg plugin
(libx264, yuv420p, even frame size), the optional GIF with Pillow (its frame times in whole
hundredths of a second that keep real time: :func:`gif_durations`); both to temporary files
in the output folder, then renamed. A warning too long for the frame's width is wrapped
within it, the text panel growing to hold its lines.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from pim.model.number_format import format_number
from pim.io.files import atomic_paths
from pim.io.process import held_signals
from pim.io.units import DisplayUnits, unit_scale
from pim.model.event import Event, Track
from pim.model.geometry import outline_corners
from pim.model.numbers import InputError

__all__ = ["AnimationInfo", "Renderer", "Look", "write_animation", "fitted_size",
           "wheel_estimate", "outline_of", "pose_points", "GlyphText", "gif_durations",
           "COLORS", "DEFAULT_SIZE", "DEFAULT_FPS", "DEFAULT_OUTLINE", "IMPULSE_SHOWN"]

#: Largest frame by default [px]: the width, and the height a square-ish motion gets.
DEFAULT_SIZE = (960, 720)
DEFAULT_FPS = 30
#: Default length and width [m] drawn for a vehicle without an outline.
DEFAULT_OUTLINE = (4.5, 1.8)
#: How long the impulse arrow stays on screen after each impact [s].
IMPULSE_SHOWN = 0.4
#: Smallest width and height of a fitted frame [px] (room for the caption's lines).
MIN_SIDE = (720, 360)

COLORS = {
    "background": (255, 255, 255), "grid": (232, 232, 232), "text": (20, 20, 20),
    "panel": (246, 246, 246),
    "fill1": (120, 170, 230), "edge1": (20, 60, 140), "path1": (175, 200, 235),
    "fill2": (245, 180, 110), "edge2": (150, 70, 10), "path2": (240, 205, 170),
    "fixed": (170, 170, 170), "fixed_edge": (70, 70, 70),
    "ghost": (220, 0, 200), "impulse": (210, 20, 20), "contact": (0, 140, 70),
    "velocity": (10, 10, 10), "warning": (180, 0, 0), "marks": (60, 60, 60),
    "rest": (0, 0, 0),
}


def _font(size: int):
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow without FreeType sizing
        return ImageFont.load_default()


@dataclass(frozen=True)
class Look:
    """What an animation says besides the motion.

    Attributes
    ----------
    title : str
        The caption's first line (the case and the impact law's coefficients).
    note : str
        Its second line: the tyre friction with its source, the approach, ...
    units : DisplayUnits or str
        Units of the grid, scale bar, speeds and impulses (speeds in the user's unit).
    labels : (str, str)
        Legend of the filled event and of the ghost.
    size : (int, int) or None
        Frame width and height [px], both even; None: within :data:`DEFAULT_SIZE`, the
        motion's aspect (:func:`fitted_size`).
    measured_rest : tuple
        Per vehicle, the measured rest pose ``(position (2,) [m], heading [rad])`` or None:
        drawn as dotted outlines.
    warnings : tuple of (float, str)
        ``(time [s], text)``: from that time on the frames carry the warning (red).
    """

    title: str = ""
    note: str = ""
    units: DisplayUnits | str = "si"
    labels: tuple = ("simulated", "analytic (ghost)")
    size: tuple | None = None
    measured_rest: tuple = (None, None)
    warnings: tuple = ()


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
        Largest distance [px] between a ghost corner and the matching corner of the event
        after the first impact (0 when they agree).
    secondary_impact : object
        A contact of the outlines after the impact that the event leaves unsolved (the
        single-impact animation's :class:`sim.SecondaryImpact`), or None.
    event : Event or None
        The event drawn (at the frame times).
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
    event: Event | None = None

    @property
    def render_fps(self) -> float:
        """Frames drawn per second of wall time."""
        return self.frames / max(self.render_seconds, 1e-12)


def wheel_estimate(outline: np.ndarray) -> np.ndarray:
    """Wheel contact points [m] (4, 2) of a car whose axles are unknown, from its outline
    (4, 2) [m]: the axles 20 % of the length behind the front and ahead of the rear (a
    car's overhangs, about 0.9-1.0 m of 4.5 m), the tyres 85 % of the width apart
    (front-left, front-right, rear-left, rear-right: :func:`pim.model.tyres.wheel_positions`'
    order)."""
    outline = np.asarray(outline, float)
    front, rear = outline[:, 0].max(), outline[:, 0].min()
    half = 0.85 * (outline[:, 1].max() - outline[:, 1].min()) / 2
    inset = 0.2 * (front - rear)
    x = [front - inset, front - inset, rear + inset, rear + inset]
    return np.column_stack([x, [half, -half, half, -half]])


def outline_of(track: Track) -> np.ndarray | None:
    """The body-frame outline drawn for a track: its own, a car's default for a moving
    vehicle without one, None for a fixed obstacle without one (a wall)."""
    if track.outline is not None:
        return np.asarray(track.outline, float)
    return None if track.fixed else outline_corners(*DEFAULT_OUTLINE)


def _extent(events, measured_rest) -> tuple[np.ndarray, np.ndarray]:
    """Lower-left and upper-right corners [m] of everything drawn (outlines at every
    sample, measured rest outlines, each impact's C)."""
    pts = []
    for ev in events:
        for track in ev.tracks:
            body = outline_of(track)
            pts.append(track.position if body is None else track.placed(body).reshape(-1, 2))
        pts += [np.asarray(i.point, float).reshape(1, 2) for i in ev.impacts]
    for track, rest in zip(events[0].tracks, measured_rest, strict=True):
        body = outline_of(track)
        if rest is not None and body is not None:
            pts.append(pose_points(body, rest))
    pts = np.concatenate(pts)
    return pts.min(0), pts.max(0)


class GlyphText:
    """Text drawn from glyphs rendered once (a frame's clock line re-rendered by FreeType
    each frame took a third of the frame's time): each character's coverage mask is cached
    as an array, a line is their concatenation, pasted once in the colour asked for (no
    kerning: the clock's digits need none)."""

    def __init__(self, font) -> None:
        self.font = font
        self.height = int(sum(font.getmetrics())) + 2
        self._glyphs = {}

    def _glyph(self, ch: str) -> np.ndarray:
        glyph = self._glyphs.get(ch)
        if glyph is None:
            advance = max(int(math.ceil(self.font.getlength(ch))), 1)
            mask = Image.new("L", (advance, self.height), 0)
            ImageDraw.Draw(mask).text((0, 0), ch, fill=255, font=self.font)
            glyph = self._glyphs[ch] = np.asarray(mask)
        return glyph

    def width(self, text: str) -> int:
        """The width of ``text`` as :meth:`draw` writes it [px]."""
        return int(sum(self._glyph(ch).shape[1] for ch in text))

    def _fitting(self, text: str, width: float) -> int:
        """How many leading characters of ``text`` fit in ``width`` [px] (at least one)."""
        ends = np.cumsum([self._glyph(ch).shape[1] for ch in text])
        return max(int(np.searchsorted(ends, width, side="right")), 1)

    def wrap(self, text: str, first: float, width: float) -> list[str]:
        """``text`` broken at spaces into lines of at most ``first`` px (the first line,
        which may start after other text; empty when not even a word fits there) and
        ``width`` px (the others); a word longer than a line is broken at characters."""
        lines, line, limit = [], "", first
        for word in text.split():
            trial = f"{line} {word}" if line else word
            if self.width(trial) <= limit:
                line = trial
                continue
            if line or limit < width:
                lines.append(line)
                limit = width
            line = word
            while self.width(line) > limit:
                cut = self._fitting(line, limit)
                lines.append(line[:cut])
                line = line[cut:]
        lines.append(line)
        return lines

    def draw(self, img: Image.Image, xy, text: str, color) -> float:
        """Write ``text`` on ``img`` at ``xy`` [px]; return the x just after it."""
        if not text:
            return xy[0]
        line = np.concatenate([self._glyph(ch) for ch in text], axis=1)
        x, y = int(round(xy[0])), int(round(xy[1]))
        mask = Image.fromarray(line[:, : max(img.width - x, 1)], "L")
        img.paste(color, (x, y, x + mask.width, y + mask.height), mask)
        return x + line.shape[1]


def pose_points(body: np.ndarray, pose) -> np.ndarray:
    """Body-frame points (K, 2) at one pose ``(position, heading)`` -> world (K, 2) [m]."""
    position, heading = pose
    c, s = math.cos(float(heading)), math.sin(float(heading))
    return np.asarray(position, float).reshape(1, 2) + body @ np.array([[c, s], [-s, c]])


def fitted_size(events, measured_rest=(None, None), width: int = DEFAULT_SIZE[0],
                height: int = DEFAULT_SIZE[1]) -> tuple[int, int]:
    """The frame [px] (even, at most ``width`` x ``height``, at least :data:`MIN_SIDE`) whose scene area has the aspect of the extent of ``events``: a long run-out gets
    a wide, low frame, a tall motion a narrow one, so the motion fills the frame both ways
    instead of a strip of it."""
    lo, hi = _extent(list(events), measured_rest)
    span = np.maximum(hi - lo, 1.0)
    pad_w = 2 * Renderer.MARGIN
    pad_h = Renderer.TOP + Renderer.BOTTOM + 2 * Renderer.MARGIN
    scale = min((width - pad_w) / span[0], (height - pad_h) / span[1])
    w = np.clip(2 * math.ceil((span[0] * scale + pad_w) / 2), MIN_SIDE[0], width)
    h = np.clip(2 * math.ceil((span[1] * scale + pad_h) / 2), MIN_SIDE[1], height)
    return int(w), int(h)


class Renderer:
    """Draws the frames of one event (Pillow), world y axis up.

    Parameters
    ----------
    event : pim.model.event.Event
        The event at the frame times (filled outlines).
    ghost : pim.model.event.Event, optional
        Another event at the same times drawn dashed over it (the analytic event over the
        simulated one).
    look : Look
        Caption, units, legend, frame size, measured rest poses, warnings.
    secondary : object, optional
        Passed on to :class:`AnimationInfo` (an unsolved secondary contact).
    """

    TOP, BOTTOM, MARGIN = 96, 8, 12

    def __init__(self, event: Event, ghost: Event | None = None, *, look: Look = Look(),
                 secondary=None) -> None:
        if ghost is not None and not np.array_equal(ghost.time, event.time):
            raise InputError("the ghost event must be sampled at the event's frame times")
        self.sim, self.ghost, self.look, self.secondary = event, ghost, look, secondary
        shown = [event] + ([ghost] if ghost is not None else [])
        size = look.size or fitted_size(shown, look.measured_rest)
        width, height = (int(s) for s in size)
        if width % 2 or height % 2 or width < 160 or height < 160:
            raise InputError(f"size must be even and at least 160 px, got {size!r}")
        self.size = (width, height)
        self.units = look.units if isinstance(look.units, DisplayUnits) \
            else DisplayUnits(look.units)
        self.times = event.time
        self.bodies = tuple(outline_of(t) for t in event.tracks)
        self.font, self.small = _font(15), _font(12)
        self.glyphs, self.small_glyphs = GlyphText(self.font), GlyphText(self.small)
        self._wrapped = {}
        extra = self._warning_rows() * self.small_glyphs.height
        if extra:            # the panel grows to hold a long warning's lines
            extra += extra % 2
            self.TOP = type(self).TOP + extra
            if look.size is None:
                self.size = (width, height + extra)
        self._fit_view(shown)
        self._px, self._cg, self._vel, self._wheels = {}, {}, {}, {}
        for tag, ev in [("sim", event)] + ([("ghost", ghost)] if ghost is not None else []):
            for i, track in enumerate(ev.tracks):
                if self.bodies[i] is not None:
                    self._px[tag, i] = self.to_px(track.placed(self.bodies[i]))
                self._cg[tag, i] = self.to_px(track.position)
                self._vel[tag, i] = track.velocity * np.array([1, -1]) * self.arrow_scale
        for i, track in enumerate(event.tracks):
            if track.sliding is not None and self.bodies[i] is not None:
                wheels = track.wheels if track.wheels is not None \
                    else wheel_estimate(self.bodies[i])
                self._wheels[i] = self.to_px(track.placed(wheels))
        self._speed = [unit_scale("speed", self.units)[0] * t.speed for t in event.tracks]
        self._background = self._draw_background()
        self._marks, self._marks_upto = self._background.copy(), 0

    # ---- the warnings, wrapped within the frame --------------------------------------------
    def warning_lines(self, text: str, x: float) -> list[str]:
        """Warning ``text`` in the lines it is drawn in: the first from ``x`` [px] (after
        the impulse's label), the others from the left edge, none past the frame's right
        edge (less a 10 px margin)."""
        key = (text, int(x))
        lines = self._wrapped.get(key)
        if lines is None:
            width = self.size[0]
            lines = self._wrapped[key] = self.small_glyphs.wrap(text, width - 10 - x,
                                                                width - 20)
        return lines

    def _warning_x(self, impulse: str) -> float:
        """Where a warning starts on the panel's last row [px]: after the impulse's label."""
        return 10 + self.small_glyphs.width(impulse) + 18 if impulse else 10

    def _warning_rows(self) -> int:
        """The rows the longest wrapped warning needs beyond the panel's last one."""
        rows = 0
        for t in self.times if self.look.warnings else ():
            warned = [text for when, text in self.look.warnings if t >= when]
            if warned:
                x = self._warning_x(self.impulse_text(float(t)))
                rows = max(rows, len(self.warning_lines(warned[-1], x)) - 1)
        return rows

    # ---- geometry ------------------------------------------------------------------------
    def _fit_view(self, shown) -> None:
        lo, hi = _extent(shown, self.look.measured_rest)
        span = np.maximum(hi - lo, 1.0)
        width, height = self.size
        avail = np.array([width - 2 * self.MARGIN,
                          height - self.TOP - self.BOTTOM - 2 * self.MARGIN], float)
        self.scale = float(np.min(avail / span))       # px per m
        self.centre = (lo + hi) / 2
        self.origin = np.array([width / 2, self.TOP + self.MARGIN + avail[1] / 2])
        speeds = np.concatenate([t.speed for ev in shown for t in ev.tracks])
        self.arrow_scale = 0.1 * min(width, height) / max(float(speeds.max()), 1e-9)
        impulses = [float(np.hypot(*i.impulse)) for i in self.sim.impacts]
        self.impulse_scale = 0.12 * min(width, height) / max(impulses + [1e-300])

    def to_px(self, world) -> np.ndarray:
        """World points [m] (..., 2) -> pixel coordinates (..., 2), y downwards."""
        w = np.asarray(world, float)
        x = (w[..., 0] - self.centre[0]) * self.scale + self.origin[0]
        y = self.origin[1] - (w[..., 1] - self.centre[1]) * self.scale
        return np.stack([x, y], -1)

    def outline_px(self, frame: int, vehicle: int, ghost: bool = False) -> np.ndarray | None:
        """Corners (4, 2) [px] of a vehicle's outline in a frame (None without an outline)."""
        arr = self._px.get(("ghost" if ghost else "sim", vehicle - 1))
        return None if arr is None else arr[frame]

    def scene_box(self) -> tuple[float, float, float, float]:
        """The scene area (left, top, right, bottom) [px], below the text panel."""
        return (0.0, float(self.TOP), float(self.size[0]), float(self.size[1] - self.BOTTOM))

    def __len__(self) -> int:
        return len(self.times)

    # ---- drawing primitives --------------------------------------------------------------
    def _arrow(self, draw, start, vec_px, color, width=3, dashed=False) -> None:
        start = np.asarray(start, float)
        end = start + vec_px
        length = float(np.hypot(*vec_px))
        if length < 2:
            return
        if dashed:
            _dashed(draw, [start, end], color, width)
        else:
            draw.line([tuple(start), tuple(end)], fill=color, width=width)
        u = vec_px / length
        head = min(12.0, 0.4 * length)
        side = np.array([-u[1], u[0]])
        base = end - head * u
        draw.polygon([tuple(end), tuple(base + 0.45 * head * side),
                      tuple(base - 0.45 * head * side)], fill=color)

    def _text(self, d, xy, text: str, color, font=None) -> float:
        """Write ``text`` at ``xy``; return the x just after it [px]."""
        font = font or self.small
        d.text(tuple(xy), text, fill=color, font=font)
        return xy[0] + d.textlength(text, font=font)

    # ---- the background: grid, paths, impacts, measured rest, caption -------------------
    def _draw_background(self) -> Image.Image:
        img = Image.new("RGB", self.size, COLORS["background"])
        d = ImageDraw.Draw(img)
        step, shown, unit = self._grid(d)
        for i in (0, 1):
            if not self.sim.tracks[i].fixed:
                d.line([tuple(p) for p in self._cg["sim", i]], fill=COLORS[f"path{i + 1}"],
                       width=2)
        self._measured_rest(d)
        for k, impact in enumerate(self.sim.impacts, start=1):
            self._impact(d, impact, k)
        self._caption(d, step, shown, unit)
        return img

    def _grid(self, d):
        """Grid lines every 1, 2, 5 ... display units (m or ft), at least 40 px apart;
        returns the step [m], its value and unit."""
        width, height = self.size
        per_m, unit = unit_scale("length", self.units)
        shown = next(s for s in (0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)
                     if s / per_m * self.scale >= 40)
        step = shown / per_m
        lo = self.centre - np.array([width, height]) / 2 / self.scale
        hi = self.centre + np.array([width, height]) / 2 / self.scale
        for x in np.arange(math.floor(lo[0] / step) * step, hi[0] + step, step):
            px = self.to_px([x, 0.0])[0]
            d.line([(px, self.TOP), (px, height)], fill=COLORS["grid"])
        for y in np.arange(math.floor(lo[1] / step) * step, hi[1] + step, step):
            py = self.to_px([0.0, y])[1]
            if py >= self.TOP:
                d.line([(0, py), (width, py)], fill=COLORS["grid"])
        return step, shown, unit

    def _measured_rest(self, d) -> None:
        for i, rest in enumerate(self.look.measured_rest):
            if rest is None or self.bodies[i] is None:
                continue
            pts = self.to_px(pose_points(self.bodies[i], rest))
            _dashed(d, [*pts, pts[0]], COLORS["rest"], 2, dash=3.0, gap=4.0)

    def _impact(self, d, impact, k: int) -> None:
        """Impact ``k``'s contact plane through C, its normal n, C and its number."""
        c = self.to_px(impact.point)
        gamma = float(impact.normal_angle)
        n = np.array([math.cos(gamma), -math.sin(gamma)])      # pixel frame (y down)
        t = np.array([-n[1], n[0]])
        half = max(0.12 * min(self.size), 3.0 * self.scale)
        _dashed(d, [c - half * t, c + half * t], COLORS["contact"], 2, dash=10, gap=6)
        self._arrow(d, c, 40 * n, COLORS["contact"], width=2)
        r = 5
        d.ellipse([c[0] - r, c[1] - r, c[0] + r, c[1] + r], outline=COLORS["contact"], width=2)
        end = c + half * t
        self._text(d, end + np.array([3, -7]), f"C{k}", COLORS["contact"], self.font)

    def _caption(self, d, step: float, shown: float, unit: str) -> None:
        width = self.size[0]
        d.rectangle([0, 0, width, self.TOP - 2], fill=COLORS["panel"])
        self._text(d, (10, 4), self.look.title, COLORS["text"], self.font)
        self._text(d, (10, 23), self.look.note, COLORS["text"])
        x = 10
        legend = [(f"filled: {self.look.labels[0]}", COLORS["edge1"])]
        if self.ghost is not None:
            legend.append((f"dashed: {self.look.labels[1]}", COLORS["ghost"]))
        if any(t.sliding is not None for t in self.sim.tracks):
            legend.append(("grey: tyre marks", COLORS["marks"]))
        if self.sim.impacts:
            legend.append(("green: impacts' C, plane", COLORS["contact"]))
        if any(r is not None for r in self.look.measured_rest):
            legend.append(("dotted: measured rest", COLORS["rest"]))
        for text, color in legend:
            x = self._text(d, (x, 40), text, color) + 18
        bar = step * self.scale
        y0 = self.TOP + 14
        d.rectangle([width - 44 - bar, self.TOP + 2, width - 8, y0 + 6], fill=COLORS["panel"])
        d.line([(width - 30 - bar, y0), (width - 30, y0)], fill=COLORS["text"], width=3)
        self._text(d, (width - 30, y0 - 7), f" {format_number(shown)} {unit}", COLORS["text"])

    # ---- one frame -----------------------------------------------------------------------
    def _lay_marks(self, upto: int) -> None:
        """Tyre marks of the samples before ``upto`` onto the marks layer (kept between
        frames, so a video's frames lay each segment once)."""
        if upto < self._marks_upto:
            self._marks, self._marks_upto = self._background.copy(), 0
        d = ImageDraw.Draw(self._marks)
        width = max(2, int(round(0.2 * self.scale)))        # a 20 cm tyre, at least 2 px
        for i, px in self._wheels.items():
            sliding = self.sim.tracks[i].sliding
            for k in range(max(self._marks_upto, 1), upto + 1):
                for j in np.flatnonzero(sliding[k - 1]):
                    d.line([tuple(px[k - 1, j]), tuple(px[k, j])], fill=COLORS["marks"],
                           width=width)
        self._marks_upto = max(self._marks_upto, upto)

    def _vehicle(self, d, frame: int, i: int) -> None:
        track = self.sim.tracks[i]
        poly = self._px.get(("sim", i))
        if poly is None:         # a wall without dimensions: drawn along the contact plane
            if self.sim.impacts:
                impact = self.sim.impacts[0]
                c = self.to_px(impact.point)
                g = float(impact.normal_angle)
                t = np.array([math.sin(g), math.cos(g)]) * 0.45 * min(self.size)
                d.line([tuple(c - t), tuple(c + t)], fill=COLORS["fixed_edge"], width=6)
            return
        fill = COLORS["fixed"] if track.fixed else COLORS[f"fill{i + 1}"]
        edge = COLORS["fixed_edge"] if track.fixed else COLORS[f"edge{i + 1}"]
        d.polygon([tuple(p) for p in poly[frame]], fill=fill, outline=edge, width=2)
        if track.fixed:
            return
        cg = self._cg["sim", i][frame]
        front = (poly[frame][0] + poly[frame][3]) / 2
        d.line([tuple(cg), tuple(cg + 0.8 * (front - cg))], fill=edge, width=2)   # heading
        r = 4
        d.ellipse([cg[0] - r, cg[1] - r, cg[0] + r, cg[1] + r], fill=(255, 255, 255),
                  outline=COLORS["text"], width=2)
        self._arrow(d, cg, self._vel["sim", i][frame], COLORS["velocity"], width=3)

    def _ghost(self, d, frame: int, i: int) -> None:
        poly = self._px.get(("ghost", i))
        if poly is None or self.ghost.tracks[i].fixed:
            return
        pts = poly[frame]
        _dashed(d, [*pts, pts[0]], COLORS["ghost"], 2)
        cg = self._cg["ghost", i][frame]
        r = 4
        d.line([(cg[0] - r, cg[1] - r), (cg[0] + r, cg[1] + r)], fill=COLORS["ghost"], width=2)
        d.line([(cg[0] - r, cg[1] + r), (cg[0] + r, cg[1] - r)], fill=COLORS["ghost"], width=2)
        self._arrow(d, cg, self._vel["ghost", i][frame], COLORS["ghost"], width=1, dashed=True)

    def _shown_impacts(self, t: float):
        """(number, impact) of the impacts less than :data:`IMPULSE_SHOWN` before ``t``."""
        return [(k, i) for k, i in enumerate(self.sim.impacts, start=1)
                if 0 <= t - i.time <= IMPULSE_SHOWN]

    def impulse_text(self, t: float) -> str:
        """The panel's label of the impulses shown at time ``t`` [s] ("" when none), in the
        user's impulse unit and the reports' number format."""
        factor, unit = unit_scale("impulse", self.units)
        return "   ".join(f"red: impulse {k} on vehicle 1, "
                          f"{format_number(factor * np.hypot(*i.impulse))} {unit}"
                          for k, i in self._shown_impacts(t))

    def _impulses(self, d, t: float) -> str:
        """The impulse arrows of the impacts shown at ``t``, at their C; returns their
        label for the panel."""
        for _, impact in self._shown_impacts(t):
            p = np.asarray(impact.impulse, float) * np.array([1, -1]) * self.impulse_scale
            self._arrow(d, self.to_px(impact.point), p, COLORS["impulse"], width=5)
        return self.impulse_text(t)

    def status(self, index: int) -> str:
        """The clock line of frame ``index``: time, phase, each vehicle's speed."""
        t = float(self.times[index])
        unit = self.units.label("speed")
        speeds = "   ".join(f"vehicle {i + 1}: {format_number(float(s[index]), sig=3)} {unit}"
                            for i, s in enumerate(self._speed) if not self.sim.tracks[i].fixed)
        return f"t = {t:+.2f} s   {self.phase(index)}   {speeds}"

    def phase(self, index: int) -> str:
        """The phase of frame ``index`` in words."""
        t = float(self.times[index])
        label = str(self.sim.phase[index])
        if label == "rest":
            return "at rest"
        done = sum(i.time <= t for i in self.sim.impacts)
        if label == "approach" or (not done and t < 0):
            return "approach"
        if label.startswith("impact"):
            return label
        return f"after impact {done}" if done else "after the impact"

    def frame(self, index: int) -> Image.Image:
        """Frame ``index`` as an RGB Pillow image."""
        self._lay_marks(index)
        img = self._marks.copy()
        d = ImageDraw.Draw(img)
        t = float(self.times[index])
        for i in (1, 0):
            self._vehicle(d, index, i)
        if self.ghost is not None and (not self.sim.impacts or t >= self.sim.impacts[0].time):
            for i in (0, 1):
                self._ghost(d, index, i)
        impulse = self._impulses(d, t)
        self.glyphs.draw(img, (10, 56), self.status(index), COLORS["text"])
        self.small_glyphs.draw(img, (10, 76), impulse, COLORS["impulse"])
        warned = [text for when, text in self.look.warnings if t >= when]
        if warned:
            x = self._warning_x(impulse)
            for row, line in enumerate(self.warning_lines(warned[-1], x)):
                self.small_glyphs.draw(img, (x if row == 0 else 10,
                                             76 + row * self.small_glyphs.height), line,
                                       COLORS["warning"])
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
        """Largest distance [px] between ghost and event corners at t >= 0."""
        after = self.times >= 0
        worst = 0.0
        for i in (0, 1):
            a, b = self._px.get(("sim", i)), self._px.get(("ghost", i))
            if a is None or b is None or not after.any():
                continue
            worst = max(worst, float(np.hypot(*(a[after] - b[after]).reshape(-1, 2).T).max()))
        return worst


def _dashed(draw, points, color, width, dash=9.0, gap=6.0) -> None:
    """A dashed polyline through ``points`` [px]."""
    pts = np.asarray(points, float)
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        d = b - a
        length = float(np.hypot(*d))
        if length == 0:
            continue
        u = d / length
        starts = np.arange(0.0, length, dash + gap)
        ends = np.minimum(starts + dash, length)
        for s, e in zip(starts, ends, strict=True):
            draw.line([tuple(a + s * u), tuple(a + e * u)], fill=color, width=width)


def gif_durations(frames: int, fps: float) -> list[int]:
    """Each of ``frames`` frames' duration [ms] in a GIF at ``fps`` frames per second.

    A GIF counts a frame's time in whole hundredths of a second, so 30 fps (33.3 ms) would
    be stored as 3 of them and play 10 % fast; here frame k lasts from ``round(100 k /
    fps)`` to ``round(100 (k + 1) / fps)`` hundredths (30 fps: 30, 30, 40 ms ...), so the
    clock never drifts more than half a hundredth from real time.
    """
    edges = np.round(np.arange(frames + 1) * 100.0 / float(fps)).astype(int)
    return (10 * np.diff(edges)).tolist()


def _pixels(img: Image.Image) -> np.ndarray:
    """RGB image -> (height, width, 3) uint8 array (tobytes: about twice np.asarray's speed)."""
    return np.frombuffer(img.tobytes(), np.uint8).reshape(img.height, img.width, 3)


def write_animation(renderer: Renderer, path, fps: int = DEFAULT_FPS, gif=None,
                    progress: bool | None = None, gif_scale: float = 0.5) -> AnimationInfo:
    """Draw every frame and write the MP4 (and optionally a GIF, at ``gif_scale`` of the
    frame size), atomically.

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
    gif_scale : float
        Size of the GIF's frames relative to the video's (default half: a smaller file).
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
                with held_signals():        # ffmpeg never gets part of a frame
                    writer.append_data(_pixels(img))
                if gif_path is not None:
                    thumbs.append(img if gif_scale == 1 else img.resize(
                        (round(img.width * gif_scale), round(img.height * gif_scale)),
                        Image.Resampling.BILINEAR))
        finally:
            with held_signals():            # ffmpeg ends, and is waited for, at a frame
                writer.close()
        if gif_path is not None:
            thumbs[0].save(temps[1], format="GIF", save_all=True, append_images=thumbs[1:],
                           duration=gif_durations(len(thumbs), fps), loop=0, optimize=False)
    total = _time.perf_counter() - start
    return AnimationInfo(path=path, gif=gif_path, frames=len(renderer), fps=int(fps),
                         size=renderer.size, render_seconds=render,
                         write_seconds=total - render,
                         max_ghost_offset_px=renderer.ghost_offset_px(),
                         secondary_impact=renderer.secondary, event=renderer.sim)
