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

__all__ = ["outline", "draw_case"]


def outline(vehicle: Vehicle):
    """Corners [m] of a vehicle's length x width rectangle centred on its CG, shape (4, 2),
    front-left first and counter-clockwise (:func:`pim.model.geometry.outline_corners`), or
    None when the vehicle has no outline data."""
    if vehicle.length is None or vehicle.width is None:
        return None
    return outline_world(vehicle.length, vehicle.width, vehicle.cg, float(vehicle.heading),
                         vehicle.cg_to_front)


_BOX = dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8)

#: Candidate label offsets [points] tried in turn, after the preferred one, until a label
#: overlaps no other label, arrow, marker or heading triangle.
_OFFSETS = [(dx, dy) for r in (14, 26, 40, 56, 74) for dx, dy in
            ((r, r), (-r, r), (r, -r), (-r, -r), (0, r), (0, -r), (r, 0), (-r, 0),
             (2 * r, 0), (-2 * r, 0))]


class _Labels:
    """Labels placed so that none covers another label, an arrow, a marker or a triangle."""

    def __init__(self, ax):
        self.ax = ax
        self.labels = []       # (annotation, preferred offset)
        self.obstacles = []    # artists whose display extent a label must avoid
        self.segments = []     # (start, end) in data coordinates: arrows' shafts

    def arrow(self, start, vec, color, label=None, offset=(4, 4), lw=1.8, fontsize=9):
        start = np.asarray(start, float)
        self.ax.annotate("", xy=start + vec, xytext=start,
                         arrowprops=dict(arrowstyle="-|>", color=color, lw=lw, shrinkA=0,
                                         shrinkB=0, mutation_scale=14), zorder=4)
        self.segments.append((start, start + vec))
        if label:
            self.add(label, start + vec, offset, color=color, fontsize=fontsize)

    def add(self, text, xy, offset, **kwargs):
        kwargs.setdefault("bbox", _BOX)
        kwargs.setdefault("zorder", 5)
        ann = self.ax.annotate(text, xy=xy, xytext=offset, textcoords="offset points",
                               **kwargs)
        self.labels.append((ann, offset))
        return ann

    def _hits(self, box, placed, renderer) -> bool:
        box = box.padded(2)
        for other in placed:
            if box.overlaps(other):
                return True
        for artist in self.obstacles:
            if box.overlaps(artist.get_window_extent(renderer)):
                return True
        to_px = self.ax.transData.transform
        for a, b in self.segments:
            pa, pb = to_px(a), to_px(b)
            for f in np.linspace(0.0, 1.0, 25):
                x, y = pa + f * (pb - pa)
                if box.x0 <= x <= box.x1 and box.y0 <= y <= box.y1:
                    return True
        return False

    def place(self, fig) -> None:
        """Move each label to the first candidate offset where it hits nothing placed."""
        renderer = fig.canvas.get_renderer()
        placed = []
        for ann, preferred in self.labels:
            for offset in [preferred, *_OFFSETS]:
                ann.set_position(offset)
                box = ann.get_window_extent(renderer)
                if not self._hits(box, placed, renderer):
                    break
            else:
                ann.set_position(preferred)
                box = ann.get_window_extent(renderer)
            placed.append(box)

    def overlaps(self, fig) -> list[tuple[str, str]]:
        """Pairs (label, what it covers) that overlap; empty when the drawing is clean."""
        renderer = fig.canvas.get_renderer()
        out = []
        boxes = [(ann.get_text(), ann.get_window_extent(renderer)) for ann, _ in self.labels]
        for i, (text, box) in enumerate(boxes):
            for other, obox in boxes[i + 1:]:
                if box.overlaps(obox):
                    out.append((text, other))
            if self._hits(box, [], renderer):
                out.append((text, "an arrow, marker or triangle"))
        return out


def _draw_vehicle(ax, labels, i: int, v: Vehicle, *, color: str, c, t, speed: float,
                  velocity_scale: float, units: str) -> None:
    """Draw vehicle ``i`` (outline, nose, CG, arm to C, velocity, yaw rate) for draw_case:
    in ``color``, C at ``c`` with the tangent ``t``, its velocity arrow ``velocity_scale``
    [m per m/s] long per speed, labels in ``units``."""
    from matplotlib.patches import Polygon

    fixed = bool(v.fixed)
    corners = outline(v)
    g = np.asarray(v.cg, dtype=float)
    if corners is not None:
        ax.add_patch(Polygon(corners, closed=True, facecolor=color, alpha=0.10,
                             edgecolor=color, lw=1.5, hatch="///" if fixed else None,
                             zorder=1))
        # The nose: a triangle on the front edge shows the heading.
        front = (corners[0] + corners[3]) / 2   # front-left and front-right corners
        heading = np.array([np.cos(float(v.heading)), np.sin(float(v.heading))])
        side = np.array([-heading[1], heading[0]])
        nose = np.array([front - 0.45 * heading + 0.3 * side, front,
                         front - 0.45 * heading - 0.3 * side])
        labels.obstacles.append(ax.add_patch(Polygon(nose, closed=True, color=color,
                                                     alpha=0.6, zorder=2)))
    elif fixed:
        # No outline: the obstacle is drawn as what defines it, the contact plane.
        wall = np.c_[c - 2.5 * t, c + 2.5 * t]
        ax.plot(*wall, color=color, lw=4, alpha=0.5, solid_capstyle="butt", zorder=1)
        labels.add("fixed obstacle (contact plane)", c - 2.3 * t, (6, -14), color=color,
                   fontsize=9)
        return
    labels.obstacles += ax.plot(*g, marker="o", color=color, ms=7, zorder=3)
    name = f"CG{i}, vehicle {i}" + (" (fixed)" if fixed else "")
    away = g - c
    away = away / max(np.hypot(*away), 1e-9)
    labels.add(f"{name}\nheading {np.degrees(float(v.heading)):.0f}°", g,
               tuple(70 * away + (0, -12)), color=color, fontsize=9, ha="center")
    ax.plot(*np.c_[g, c], ls="--", color=color, lw=1.2, zorder=3)
    mid = g + 0.35 * (c - g)
    labels.add(f"r{i} = C - CG{i}", mid, (-10, 8), color=color, fontsize=8)
    if not fixed and speed > 0:
        vel = np.asarray(v.velocity, dtype=float)
        shown, speed_unit = convert(np.hypot(*vel), "velocity", units)
        labels.arrow(g, velocity_scale * vel, color,
                     f"v{i} = {float(shown):.1f} {speed_unit}", offset=(-30, 8))
    if not fixed and float(v.yaw_rate) != 0:
        w, w_unit = convert(float(v.yaw_rate), "angular_velocity", units)
        labels.add(f"ω{i} = {float(w):+.1f} {w_unit} (CCW +)", g, (0, 14), color=color,
                   fontsize=8, ha="center")


def _draw_contact(ax, labels, case: Case, c, n, t, result) -> None:
    """Draw C, the contact plane, n, t, Gamma and (given a Result) the impulse."""
    from matplotlib.patches import Arc

    ax.plot(*np.c_[c - 2.2 * t, c + 2.2 * t], color="0.3", lw=1.0, ls=":")
    labels.obstacles += ax.plot(*c, marker="X", color="k", ms=10)
    labels.add("C", c, (-16, 6), fontsize=12, weight="bold", zorder=6)
    labels.arrow(c, 0.9 * n, "k", "n: from 2 toward 1", offset=(-20, -22), lw=2.2)
    labels.arrow(c, 0.9 * t, "0.35", "t: n turned +90°", offset=(6, 2), lw=2.2)
    ax.plot(*np.c_[c, c + np.array([1.0, 0.0])], color="0.5", lw=0.8)
    gamma = float(np.degrees(case.impact.normal_angle))
    lo, hi = sorted((0.0, gamma))
    ax.add_patch(Arc(c, 1.6, 1.6, theta1=lo, theta2=hi, color="k", lw=1.0))
    mid = np.radians(gamma / 2)
    labels.add(f"Γ = {gamma:.0f}°", c + 0.9 * np.array([np.cos(mid), np.sin(mid)]), (0, 0),
               fontsize=10, bbox=None)
    if result is not None:
        p = np.asarray(result.impulse, dtype=float)
        if np.isfinite(p).all() and np.hypot(*p) > 0:
            unit = p / np.hypot(*p)
            labels.arrow(c, 1.8 * unit, "darkblue", "impulse P on 1", lw=2.5)
            labels.arrow(c, -1.8 * unit, "darkred", "-P on 2", lw=2.5, offset=(-40, -14))


def _format_axes(ax, case: Case, units: str) -> None:
    """Equal aspect, labels and ticks in the display unit, a margin, the title."""
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
    ax.autoscale_view()
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    ax.set_xlim(x0 - 0.8, x1 + 0.8)
    ax.set_ylim(y0 - 0.8, y1 + 0.8)
    # Ticks at round numbers of the display unit (m or ft).
    for axis, (lo_, hi_) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        ticks = MaxNLocator(8).tick_values(lo_ * per_m, hi_ * per_m) / per_m
        axis.set_ticks(ticks[(ticks >= lo_) & (ticks <= hi_)])


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

    if ax is None:
        fig = Figure(figsize=(9, 8), dpi=120)
        ax = fig.add_subplot()
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
    _format_axes(ax, case, units)
    fig.canvas.draw()          # fixes the transforms and text sizes the placement measures
    labels.place(fig)
    fig.pim_labels = labels
    return fig
