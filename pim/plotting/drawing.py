"""The conventions figure: a case's geometry drawn with every sign the model uses.

``draw_case`` shows the outlines, CGs, the impact point C, the unit vectors n and t, the
contact-plane angle Gamma, the headings, the arms C - CG and the pre-impact velocities
(and, given a Result, the impulse on each vehicle). ``pim draw CASE --out FILE`` writes it.
matplotlib is imported only here, and only when drawing.
"""

from __future__ import annotations

import numpy as np

from ..model.case import Case, Vehicle
from ..model.geometry import outline_world

__all__ = ["outline", "draw_case"]


def outline(vehicle: Vehicle, default_length: float = 4.5, default_width: float = 1.8):
    """Corners [m] of a vehicle's length x width rectangle centred on its CG, shape (4, 2)."""
    return outline_world(vehicle.length or default_length, vehicle.width or default_width,
                         vehicle.cg, float(vehicle.heading))


_BOX = dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8)


def _arrow(ax, start, vec, color, label=None, offset=(4, 4), lw=1.8, fontsize=9):
    ax.annotate("", xy=start + vec, xytext=start,
                arrowprops=dict(arrowstyle="-|>", color=color, lw=lw, shrinkA=0, shrinkB=0,
                                mutation_scale=14), zorder=4)
    if label:
        ax.annotate(label, xy=start + vec, xytext=offset, textcoords="offset points",
                    color=color, fontsize=fontsize, bbox=_BOX, zorder=5)


def draw_case(case: Case, result=None, ax=None, velocity_scale: float | None = None):
    """Draw a scalar case's geometry and sign conventions on a matplotlib Axes.

    Parameters
    ----------
    case : Case
        A single (scalar) case.
    result : pim.Result, optional
        If given, the impulse on each vehicle is drawn at C.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure is made if None.
    velocity_scale : float, optional
        Arrow length per speed [m per m/s]; default: the fastest vehicle's arrow is 1.4 m.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Arc, Polygon

    if ax is None:
        fig = Figure(figsize=(9, 8), dpi=120)
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    c = np.asarray(case.impact.point, dtype=float)
    n = np.asarray(case.impact.normal, dtype=float)
    t = np.asarray(case.impact.tangent, dtype=float)
    speeds = [np.hypot(*v.velocity) for v in (case.vehicle1, case.vehicle2)]
    if velocity_scale is None:
        velocity_scale = 1.4 / max(max(speeds), 1e-9)
    colors = {1: "tab:blue", 2: "tab:red"}
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        color = colors[i]
        fixed = bool(v.fixed)
        corners = outline(v)
        ax.add_patch(Polygon(corners, closed=True, facecolor=color, alpha=0.10,
                             edgecolor=color, lw=1.5, hatch="///" if fixed else None, zorder=1))
        # The nose: a triangle on the front edge shows the heading.
        front = (corners[0] + corners[3]) / 2   # front-left and front-right corners
        heading = np.array([np.cos(float(v.heading)), np.sin(float(v.heading))])
        side = np.array([-heading[1], heading[0]])
        nose = np.array([front - 0.45 * heading + 0.3 * side, front, front - 0.45 * heading
                         - 0.3 * side])
        ax.add_patch(Polygon(nose, closed=True, color=color, alpha=0.6, zorder=2))
        g = np.asarray(v.cg, dtype=float)
        ax.plot(*g, marker="o", color=color, ms=7, zorder=3)
        name = f"CG{i}, vehicle {i}" + (" (fixed)" if fixed else "")
        away = g - c
        away = away / max(np.hypot(*away), 1e-9)
        ax.annotate(f"{name}\nheading {np.degrees(float(v.heading)):.0f}°", xy=g,
                    xytext=tuple(70 * away + (0, -12)), textcoords="offset points",
                    color=color, fontsize=9,
                    ha="center", bbox=_BOX, zorder=5)
        ax.plot(*np.c_[g, c], ls="--", color=color, lw=1.2, zorder=3)
        mid = g + 0.35 * (c - g)
        ax.annotate(f"r{i} = C - CG{i}", xy=mid, xytext=(-10, 8), textcoords="offset points",
                    color=color, fontsize=8, bbox=_BOX, zorder=5)
        if not fixed and speeds[i - 1] > 0:
            vel = np.asarray(v.velocity, dtype=float)
            _arrow(ax, g, velocity_scale * vel, color, f"v{i} = {np.hypot(*vel):.1f} m/s",
                   offset=(-30, 8))
        if not fixed and float(v.yaw_rate) != 0:
            ax.annotate(f"ω{i} = {float(v.yaw_rate):+.2f} rad/s (CCW +)", xy=g, xytext=(0, 14),
                        textcoords="offset points", color=color, fontsize=8, ha="center",
                        bbox=_BOX)
    # Contact plane, n, t and Gamma.
    ax.plot(*np.c_[c - 2.2 * t, c + 2.2 * t], color="0.3", lw=1.0, ls=":")
    ax.plot(*c, marker="X", color="k", ms=10)
    ax.annotate("C", xy=c, xytext=(-16, 6), textcoords="offset points", fontsize=12,
                weight="bold", bbox=_BOX, zorder=6)
    _arrow(ax, c, 0.9 * n, "k", "n: from 2 toward 1", offset=(-20, -22), lw=2.2)
    _arrow(ax, c, 0.9 * t, "0.35", "t: n turned +90°", offset=(6, 2), lw=2.2)
    ax.plot(*np.c_[c, c + np.array([1.0, 0.0])], color="0.5", lw=0.8)
    gamma = float(np.degrees(case.impact.normal_angle))
    lo, hi = sorted((0.0, gamma))
    ax.add_patch(Arc(c, 1.6, 1.6, theta1=lo, theta2=hi, color="k", lw=1.0))
    mid = np.radians(gamma / 2)
    ax.annotate(f"Γ = {gamma:.0f}°", xy=c + 0.9 * np.array([np.cos(mid), np.sin(mid)]),
                fontsize=10)
    if result is not None:
        p = np.asarray(result.impulse, dtype=float)
        if np.isfinite(p).all() and np.hypot(*p) > 0:
            unit = p / np.hypot(*p)
            _arrow(ax, c, 1.8 * unit, "darkblue", "impulse P on 1", lw=2.5)
            _arrow(ax, c, -1.8 * unit, "darkred", "-P on 2", lw=2.5, offset=(-40, -14))
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3, alpha=0.6)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title = case.name or "case"
    ax.set_title(f"{title}: global frame, angles CCW from +x")
    ax.autoscale_view()
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    ax.set_xlim(x0 - 0.8, x1 + 0.8)
    ax.set_ylim(y0 - 0.8, y1 + 0.8)
    return fig
