"""The conventions figure: a case's geometry drawn with every sign the model uses.

``draw_case`` shows the outlines, CGs, the impact point C, the unit vectors n and t, the
contact-plane angle Gamma, the headings, the arms C - CG and the pre-impact velocities
(and, given a Result, the impulse on each vehicle). ``pim draw CASE --out FILE`` writes it.
matplotlib is imported only here, and only when drawing.
"""

from __future__ import annotations

import numpy as np

from ..io.units import convert
from ..model.case import Case, Vehicle
from ..model.geometry import outline_world

__all__ = ["outline", "draw_case", "scene_limits", "ASPECT_RANGE"]


def outline(vehicle: Vehicle):
    """Corners [m] of a vehicle's length x width rectangle centred on its CG, shape (4, 2),
    front-left first and counter-clockwise (:func:`pim.model.geometry.outline_corners`), or
    None when the vehicle has no outline data."""
    if vehicle.length is None or vehicle.width is None:
        return None
    return outline_world(vehicle.length, vehicle.width, vehicle.cg, float(vehicle.heading),
                         vehicle.cg_to_front)


_BOX = dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8)

#: Distances [points] of a label's centre from its anchor tried in turn, nearest first, each
#: in 16 directions (the preferred one first): a label goes where it covers no other label,
#: arrow, marker or heading triangle, lies inside the axes and is nearest its anchor (an arm
#: or arc it covers counting LINE_COST farther).
_RINGS = (0, 9, 16, 24, 34, 46, 60, 78, 100, 126)
_DIRECTIONS = 16
#: How much farther [points] a label may sit to keep off an arm or Gamma's arc.
LINE_COST = 30.0


def _directions(preferred: float | None) -> list[float]:
    """The 16 directions [rad], nearest to ``preferred`` first (counter-clockwise first)."""
    base = 0.0 if preferred is None else preferred
    steps = sorted(range(_DIRECTIONS), key=lambda k: (min(k, _DIRECTIONS - k), -k))
    return [base + 2 * np.pi * k / _DIRECTIONS for k in steps]


def _overlapping(box: np.ndarray, others: np.ndarray) -> np.ndarray:
    """Which of ``others`` (k, 4: x0, y0, x1, y1) overlap ``box`` (4,) [px]."""
    return ((others[:, 0] < box[2]) & (others[:, 2] > box[0]) & (others[:, 1] < box[3])
            & (others[:, 3] > box[1]))


def _inside(box: np.ndarray, frame: np.ndarray) -> bool:
    return bool(box[0] >= frame[0] and box[1] >= frame[1] and box[2] <= frame[2]
                and box[3] <= frame[3])


class _Labels:
    """Labels placed at what they name (along their arrow, on their arc, beside their
    marker), none covering another label, an arrow, an arm, an arc, a marker or a triangle,
    all inside the axes."""

    def __init__(self, ax):
        self.ax = ax
        self.labels = []       # (annotation, anchors [(xy, preferred direction)], rank)
        self.obstacles = []    # artists whose display extent a label must avoid
        self.segments = []     # (start, end) in data coordinates: arrows
        self.lines = []        # (start, end) in data coordinates: arms and arcs, which a
        #                        label may cover where nothing nearer has room
        self.points = []       # data points the view must show

    def arrow(self, start, vec, color, label=None, lw=1.8, fontsize=9, rank=1):
        """An arrow from ``start`` along ``vec`` [data], its label beside its shaft."""
        start = np.asarray(start, float)
        end = start + np.asarray(vec, float)
        self.ax.annotate("", xy=end, xytext=start,
                         arrowprops=dict(arrowstyle="-|>", color=color, lw=lw, shrinkA=0,
                                         shrinkB=0, mutation_scale=14), zorder=4)
        self.segments.append((start, end))
        self.points += [start, end]
        if label:
            self.along(label, start, end, color=color, fontsize=fontsize, rank=rank)

    def along(self, text, start, end, fractions=(0.6, 0.85, 0.4, 1.0, 0.2, 0.0), **kwargs):
        """A label beside the segment start-end, at the first fraction of it that has room
        (preferred side: left of the segment)."""
        start, end = np.asarray(start, float), np.asarray(end, float)
        d = end - start
        left = float(np.arctan2(d[0], -d[1])) if np.hypot(*d) > 0 else None
        return self.add(text, [(start + f * d, left) for f in fractions], **kwargs)

    def add(self, text, anchors, rank=1, **kwargs):
        """A label at the first of ``anchors`` ([(xy, preferred direction [rad] or None)]
        or one xy) that has room; labels of lower ``rank`` are placed first (nearest their
        anchors)."""
        if not isinstance(anchors, list):
            anchors = [(np.asarray(anchors, float), None)]
        kwargs.setdefault("bbox", _BOX)
        kwargs.setdefault("zorder", 5)
        ann = self.ax.annotate(text, xy=anchors[0][0], xytext=(0, 0),
                               textcoords="offset points", ha="center", va="center",
                               **kwargs)
        self.labels.append((ann, anchors, rank))
        return ann

    def _scene(self, fig) -> dict:
        """What a label must avoid, in pixels: the obstacles' boxes, the arrows and the lines
        sampled at 40 points each (with the segment each point belongs to), the axes'
        frame."""
        renderer = fig.canvas.get_renderer()
        to_px = self.ax.transData.transform
        f = np.linspace(0.0, 1.0, 40)[:, None]

        def sampled(segments):
            pts = [to_px(a) + f * (to_px(b) - to_px(a)) for a, b in segments]
            return (np.concatenate(pts) if pts else np.empty((0, 2)),
                    np.repeat(np.arange(len(pts)), 40))

        return {"obstacles": np.array([a.get_window_extent(renderer).extents
                                       for a in self.obstacles]).reshape(-1, 4),
                "arrows": sampled(self.segments), "lines": sampled(self.lines),
                "frame": self.ax.get_window_extent().padded(-2).extents}

    @staticmethod
    def _cost(box: np.ndarray, placed: np.ndarray, scene: dict) -> tuple[int, int]:
        """(what ``box`` [px] must not cover: labels, obstacles, arrows, and 100 when it
        leaves the axes; the arms and arc segments it covers), 2 px apart."""
        padded = box + np.array([-2.0, -2.0, 2.0, 2.0])

        def crossed(kind):
            pts, segment = scene[kind]
            inside = ((pts[:, 0] >= padded[0]) & (pts[:, 0] <= padded[2])
                      & (pts[:, 1] >= padded[1]) & (pts[:, 1] <= padded[3]))
            return len(np.unique(segment[inside]))

        hard = (int(_overlapping(padded, placed).sum())
                + int(_overlapping(padded, scene["obstacles"]).sum()) + crossed("arrows")
                + (0 if _inside(box, scene["frame"]) else 100))
        return hard, crossed("lines")

    def _candidates(self, anchors):
        """(anchor, offset [points]) nearest first: ring by ring, every anchor in turn."""
        for r in _RINGS:
            for xy, preferred in anchors:
                for a in _directions(preferred) if r else [0.0]:
                    yield xy, np.array([r * np.cos(a), r * np.sin(a)])

    def place(self, fig) -> None:
        """Move each label, lowest rank first, to its best candidate: covering nothing it
        must not (labels, arrows, markers, the axes' edge), then nearest, an arm or arc
        segment it covers counting as LINE_COST points farther. A label's box keeps its size
        as it moves: it is measured once and shifted."""
        renderer = fig.canvas.get_renderer()
        to_px = self.ax.transData.transform
        points_px = fig.dpi / 72.0
        scene = self._scene(fig)
        placed = np.empty((0, 4))
        for ann, anchors, _ in sorted(self.labels, key=lambda label: label[2]):
            ann.xy, ann.xyann = tuple(anchors[0][0]), (0.0, 0.0)
            base, origin = ann.get_window_extent(renderer).extents, to_px(anchors[0][0])
            best = None
            for xy, offset in self._candidates(anchors):
                distance = float(np.hypot(*offset))
                if best is not None and best[0][0] == 0 and distance > best[0][1]:
                    break                   # nothing farther can be better
                shift = to_px(xy) - origin + offset * points_px
                box = base + np.r_[shift, shift]
                hard, lines = self._cost(box, placed, scene)
                cost = (hard, distance + LINE_COST * lines)
                if best is None or cost < best[0]:
                    best = (cost, xy, offset, box)
            ann.xy, ann.xyann = tuple(best[1]), tuple(best[2])
            placed = np.vstack([placed, best[3]])

    def overlaps(self, fig) -> list[tuple[str, str]]:
        """Pairs (label, what it covers) that overlap; empty when the drawing is clean."""
        renderer = fig.canvas.get_renderer()
        scene = self._scene(fig)
        out = []
        boxes = [(ann.get_text(), ann.get_window_extent(renderer).extents)
                 for ann, *_ in self.labels]
        for i, (text, box) in enumerate(boxes):
            for other, obox in boxes[i + 1:]:
                if _overlapping(box, obox[None, :]).any():
                    out.append((text, other))
            if self._cost(box, np.empty((0, 4)), scene)[0] % 100:
                out.append((text, "an arrow, marker or triangle"))
            if not _inside(box, scene["frame"]):
                out.append((text, "the axes' edge"))
        return out


def _away(frm, to) -> float:
    """The direction [rad] from ``to`` toward ``frm`` (a label's side away from C)."""
    d = np.asarray(frm, float) - np.asarray(to, float)
    return float(np.arctan2(d[1], d[0])) if np.hypot(*d) > 1e-9 else np.pi / 2


def _draw_outline(ax, labels, v: Vehicle, corners, color: str) -> None:
    """The outline (hatched when fixed) and the nose triangle on the front edge."""
    from matplotlib.patches import Polygon

    ax.add_patch(Polygon(corners, closed=True, facecolor=color, alpha=0.10, edgecolor=color,
                         lw=1.5, hatch="///" if bool(v.fixed) else None, zorder=1))
    front = (corners[0] + corners[3]) / 2   # front-left and front-right corners
    heading = np.array([np.cos(float(v.heading)), np.sin(float(v.heading))])
    side = np.array([-heading[1], heading[0]])
    nose = np.array([front - 0.45 * heading + 0.3 * side, front,
                     front - 0.45 * heading - 0.3 * side])
    labels.obstacles.append(ax.add_patch(Polygon(nose, closed=True, color=color, alpha=0.6,
                                                 zorder=2)))
    if not bool(v.fixed):
        labels.points += list(corners)


def _draw_vehicle(ax, labels, i: int, v: Vehicle, *, color: str, c, t, speed: float,
                  velocity_scale: float, units: str) -> None:
    """Draw vehicle ``i`` (outline, nose, CG, arm to C, velocity, yaw rate) for draw_case:
    in ``color``, C at ``c`` with the tangent ``t``, its velocity arrow ``velocity_scale``
    [m per m/s] long per speed, labels in ``units``."""
    fixed = bool(v.fixed)
    corners = outline(v)
    g = np.asarray(v.cg, dtype=float)
    if corners is not None:
        _draw_outline(ax, labels, v, corners, color)
    elif fixed:
        # No outline: the obstacle is drawn as what defines it, the contact plane.
        wall = np.c_[c - 2.5 * t, c + 2.5 * t]
        ax.plot(*wall, color=color, lw=4, alpha=0.5, solid_capstyle="butt", zorder=1)
        labels.along("fixed obstacle (contact plane)", c - 2.3 * t, c + 2.3 * t,
                     fractions=(0.15, 0.85, 0.3, 0.7), color=color, fontsize=9, rank=3)
        return
    labels.obstacles += ax.plot(*g, marker="o", color=color, ms=7, zorder=3)
    labels.points.append(g)
    name = f"CG{i}, vehicle {i}" + (" (fixed)" if fixed else "")
    labels.add(f"{name}\nheading {np.degrees(float(v.heading)):.0f}°", [(g, _away(g, c))],
               color=color, fontsize=9, rank=3)
    ax.plot(*np.c_[g, c], ls="--", color=color, lw=1.2, zorder=3)
    labels.lines.append((g, c))
    labels.along(f"r{i} = C - CG{i}", g, c, fractions=(0.5, 0.35, 0.65, 0.2, 0.8),
                 color=color, fontsize=8, rank=2)
    if not fixed and speed > 0:
        vel = np.asarray(v.velocity, dtype=float)
        shown, speed_unit = convert(np.hypot(*vel), "velocity", units)
        labels.arrow(g, velocity_scale * vel, color, f"v{i} = {float(shown):.1f} {speed_unit}",
                     rank=0)
    if not fixed and float(v.yaw_rate) != 0:
        w, w_unit = convert(float(v.yaw_rate), "angular_velocity", units)
        labels.add(f"ω{i} = {float(w):+.1f} {w_unit} (CCW +)", [(g, np.pi / 2)],
                   color=color, fontsize=8, rank=2)


#: Radius [m] of the arc that marks Gamma.
_ARC = 0.8


def _draw_gamma(ax, labels, case: Case, c) -> None:
    """The reference direction +x, the arc from it to n and Gamma's label on the arc."""
    from matplotlib.patches import Arc

    ax.plot(*np.c_[c, c + np.array([1.0, 0.0])], color="0.5", lw=0.8)
    gamma = float(np.degrees(case.impact.normal_angle))
    lo, hi = sorted((0.0, gamma))
    ax.add_patch(Arc(c, 2 * _ARC, 2 * _ARC, theta1=lo, theta2=hi, color="k", lw=1.0))
    angles = np.radians(lo + (hi - lo) * np.array([0.5, 0.3, 0.7, 0.15, 0.85]))
    on_arc = [c + _ARC * np.array([np.cos(a), np.sin(a)]) for a in angles]
    if hi - lo < 10:            # no arc to speak of: along the reference direction +x
        on_arc = [c + np.array([r, 0.0]) for r in (0.8, 0.6, 1.0, 0.4)]
        angles = np.radians(np.full(len(on_arc), 90.0 if gamma >= 0 else -90.0))
    arc = [c + _ARC * np.array([np.cos(a), np.sin(a)])
           for a in np.radians(np.linspace(lo, hi, 13))]
    labels.lines += list(zip(arc[:-1], arc[1:], strict=True))
    labels.points += [c + _ARC * np.array(p) for p in ((1, 1), (-1, -1))]
    labels.add(f"Γ = {gamma:.0f}°", [(p, float(a)) for p, a in zip(on_arc, angles,
                                                                    strict=True)],
               fontsize=10, rank=1)


def _draw_contact(ax, labels, case: Case, c, n, t, result) -> None:
    """Draw C, the contact plane, n, t, Gamma and (given a Result) the impulse."""
    ax.plot(*np.c_[c - 2.2 * t, c + 2.2 * t], color="0.3", lw=1.0, ls=":")
    labels.obstacles += ax.plot(*c, marker="X", color="k", ms=10)
    labels.points.append(c)
    labels.add("C", [(c, 3 * np.pi / 4)], fontsize=12, weight="bold", zorder=6, rank=0)
    _draw_gamma(ax, labels, case, c)      # its label first: it has the fewest places
    labels.arrow(c, 0.9 * n, "k", "n: from 2 toward 1", lw=2.2)
    labels.arrow(c, 0.9 * t, "0.35", "t: n turned +90°", lw=2.2)
    if result is not None:
        p = np.asarray(result.impulse, dtype=float)
        if np.isfinite(p).all() and np.hypot(*p) > 0:
            unit = p / np.hypot(*p)
            labels.arrow(c, 1.8 * unit, "darkblue", "impulse P on 1", lw=2.5)
            labels.arrow(c, -1.8 * unit, "darkred", "-P on 2", lw=2.5)


#: Limits of the drawing's height over its width: a scene taller or wider than this (a long
#: wall) gets room on its short side rather than a tall, narrow or flat figure.
ASPECT_RANGE = (0.6, 1.1)
#: Width of the drawing's axes [inches].
WIDTH = 7.5


def scene_limits(points, aspect_range=ASPECT_RANGE) -> tuple[tuple, tuple]:
    """x and y limits [m] that show ``points`` with a margin for the labels, their height over
    width within ``aspect_range`` (the short side widened about the centre).

    Parameters
    ----------
    points : array_like (k, 2)
        What the drawing must show [m]: the moving vehicles' outlines, the CGs, C, the arrows
        (a fixed barrier's outline runs out of the frame).
    aspect_range : (float, float)
        Least and largest height / width [-].
    """
    pts = np.asarray(points, float).reshape(-1, 2)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = max(1.2, 0.15 * float(np.max(hi - lo)))
    lo, hi = lo - pad, hi + pad
    width, height = hi - lo
    target = float(np.clip(height / width, *aspect_range))
    size = np.array([max(width, height / target), max(height, width * target)])
    mid = (lo + hi) / 2
    return tuple(mid[0] + size[0] * np.array([-0.5, 0.5])), tuple(
        mid[1] + size[1] * np.array([-0.5, 0.5]))


def _format_axes(ax, labels, case: Case, units: str) -> None:
    """Equal aspect, the scene's limits, labels and ticks in the display unit, the title."""
    from matplotlib.ticker import FuncFormatter, MaxNLocator

    per_m, length_unit = convert(1.0, "length", units)
    per_m = float(per_m)
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.set_xlabel(f"x [{length_unit}]")
    ax.set_ylabel(f"y [{length_unit}]")
    in_units = FuncFormatter(lambda x, _: f"{x * per_m:.4g}")
    ax.xaxis.set_major_formatter(in_units)
    ax.yaxis.set_major_formatter(in_units)
    title = case.name or "case"
    ax.set_title(f"{title}: global frame, angles CCW from +x")
    xlim, ylim = scene_limits(labels.points)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    # Ticks at round numbers of the display unit (m or ft).
    for axis, (lo_, hi_) in ((ax.xaxis, xlim), (ax.yaxis, ylim)):
        ticks = MaxNLocator(8).tick_values(lo_ * per_m, hi_ * per_m) / per_m
        axis.set_ticks(ticks[(ticks >= lo_) & (ticks <= hi_)])


def _fit_figure(fig, ax) -> None:
    """Size the figure to its axes' aspect (the scene's), WIDTH inches wide plus margins."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    height = WIDTH * (y1 - y0) / (x1 - x0)
    margin = (1.0, 0.6, 0.7, 0.5)            # left, right, bottom, top [inches]
    w, h = WIDTH + margin[0] + margin[1], height + margin[2] + margin[3]
    fig.set_size_inches(w, h)
    ax.set_position((margin[0] / w, margin[2] / h, WIDTH / w, height / h))


def draw_case(case: Case, result=None, ax=None, velocity_scale: float | None = None,
              units: str = "si"):
    """Draw a scalar case's geometry and sign conventions on a matplotlib Axes.

    Parameters
    ----------
    case : Case
        A single (scalar) case.
    result : pim.Result, optional
        If given, the impulse on each vehicle is drawn at C.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new Figure is made if None.
    velocity_scale : float, optional
        Arrow length per speed [m per m/s]; default: the fastest vehicle's arrow is 1.4 m.
    units : {"si", "us"} or pim.io.units.DisplayUnits
        Units of the axes and the speed labels.

    Returns
    -------
    matplotlib.figure.Figure
        With ``fig.pim_labels`` (the label placer, whose ``overlaps(fig)`` lists any label
        that still covers another label, an arrow, a marker or a heading triangle).

    Notes
    -----
    A vehicle without outline data (length, width) is drawn as its CG only; a fixed obstacle
    without one is drawn as the contact plane (a wall through C).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    own = ax is None
    if own:
        fig = Figure(figsize=(WIDTH + 1.5, WIDTH), dpi=120)
        ax = fig.add_axes((0.1, 0.08, WIDTH / (WIDTH + 1.5), 0.84))
    else:
        fig = ax.figure
    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)       # label placement measures text on a renderer
    labels = _Labels(ax)
    c = np.asarray(case.impact.point, dtype=float)
    n = np.asarray(case.impact.normal, dtype=float)
    t = np.asarray(case.impact.tangent, dtype=float)
    speeds = [np.hypot(*v.velocity) for v in (case.vehicle1, case.vehicle2)]
    if velocity_scale is None:
        velocity_scale = 1.4 / max(max(speeds), 1e-9)
    colors = {1: "tab:blue", 2: "tab:red"}
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        _draw_vehicle(ax, labels, i, v, color=colors[i], c=c, t=t, speed=speeds[i - 1],
                      velocity_scale=velocity_scale, units=units)
    _draw_contact(ax, labels, case, c, n, t, result)
    _format_axes(ax, labels, case, units)
    if own:
        _fit_figure(fig, ax)
    fig.canvas.draw()          # fixes the transforms and text sizes the placement measures
    labels.place(fig)
    fig.pim_labels = labels
    return fig
