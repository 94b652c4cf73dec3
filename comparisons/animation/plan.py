"""The plan view of a whole event: one picture of the motion from the approach to rest.

Each vehicle's outline every :func:`plan_interval` seconds with its time beside it (off the
outline, on a leader line; where two labels would overlap, as near an impact, the later one
is left out: :func:`thin_labels`), the CG paths, the tyre marks where a wheel slides, each
impact at its C with its contact plane and its number, the final (rest) outlines drawn solid and the
measured rest positions dotted where the case gives them; lengths in the user's unit, the
interval stated in the title. The compare, reconstruct and event reports show it
(matplotlib, written by :func:`pim.io.files.save_figure`).
"""

from __future__ import annotations

import math

import numpy as np

from comparisons.animation.render import COLORS, outline_of, pose_points, wheel_estimate
from pim.model.number_format import format_number
from pim.io.units import unit_scale
from pim.model.event import Event

__all__ = ["plan_view", "plan_interval", "thin_labels", "PLAN_OUTLINES",
           "IMPACT_OFFSETS"]

#: About how many outlines of each vehicle a plan view shows.
PLAN_OUTLINES = 10


def plan_interval(event: Event, outlines: int = PLAN_OUTLINES) -> float:
    """The time between drawn outlines [s]: the 1-2-2.5-5 step nearest to the event's
    duration over ``outlines``."""
    span = max(float(event.time[-1] - event.time[0]), 1e-3) / outlines
    steps = [m * 10.0 ** e for e in range(-2, 3) for m in (1, 2, 2.5, 5)]
    return min(steps, key=lambda s: abs(math.log(s / span)))


def _rgb(name: str) -> tuple:
    return tuple(c / 255 for c in COLORS[name])


def _snapshots(event: Event, interval: float) -> np.ndarray:
    """Indices of the samples nearest to every multiple of ``interval`` from the start,
    each impact's time and the end."""
    times = np.arange(math.ceil(event.time[0] / interval) * interval, event.time[-1],
                      interval)
    times = np.concatenate([times, [i.time for i in event.impacts], [event.time[-1]]])
    after = np.clip(np.searchsorted(event.time, times), 1, len(event) - 1)
    nearer = np.abs(event.time[after - 1] - times) <= np.abs(event.time[after] - times)
    return np.unique(np.where(nearer, after - 1, after))


def _moved(track, kept: list, k: int) -> bool:
    """Sample ``k`` is 10 cm or 1 degree away from the last kept outline (a vehicle at rest
    gets one outline, not one per interval)."""
    if not kept:
        return True
    j = kept[-1]
    return bool(np.hypot(*(track.position[k] - track.position[j])) > 0.1
                or abs(track.heading[k] - track.heading[j]) > math.radians(1.0))


def _track_layer(ax, event: Event, i: int, scale: float, interval: float) -> list:
    """Vehicle ``i``'s path, tyre marks, outlines with times and its final outline; returns
    the time labels as (time [s], text) in time order."""
    track = event.tracks[i]
    body = outline_of(track)
    edge, fill = _rgb(f"edge{i + 1}"), _rgb(f"fill{i + 1}")
    if track.fixed:
        if body is not None:
            pts = track.placed(body)[0] * scale
            ax.fill(pts[:, 0], pts[:, 1], color=_rgb("fixed"), ec=_rgb("fixed_edge"))
        return []
    ax.plot(*(track.position * scale).T, "-", color=edge, lw=1.2, label=f"vehicle {i + 1} CG")
    if track.sliding is not None and body is not None:
        wheels = track.placed(track.wheels if track.wheels is not None
                              else wheel_estimate(body)) * scale
        for j in range(4):
            xy = np.where(track.sliding[:, j, None], wheels[:, j], np.nan)
            ax.plot(*xy.T, "-", color=_rgb("marks"), lw=1.6, solid_capstyle="butt")
    if body is None:
        return []
    kept, last_index, labels = [], len(event) - 1, []
    for k in _snapshots(event, interval):
        moved = _moved(track, kept, k)
        if not moved and k != last_index:
            continue
        kept.append(k)
        pts = track.placed(body)[k] * scale
        last = k == last_index
        closed = np.vstack([pts, pts[:1]])
        ax.fill(*pts.T, color=fill, alpha=0.55 if last else 0.12, lw=0)
        ax.plot(*closed.T, "-", color=edge, lw=1.4 if last else 0.6)
        label = f"{format_number(float(event.time[k]), sig=3)} s"
        away = pts.mean(0) + _side(track, k, i) * float(np.ptp(body[:, 0])) * scale
        if moved:
            text = ax.annotate(label, pts.mean(0), xytext=away, fontsize=6.5, color=edge,
                               arrowprops=dict(arrowstyle="-", color=edge, lw=0.4,
                                               alpha=0.6))
            labels.append((float(event.time[k]), text))
    return labels


#: Where an impact's label may stand off its C [points], tried in turn until it overlaps no
#: label already placed.
IMPACT_OFFSETS = ((6, 6), (6, -16), (-70, 6), (-70, -16), (6, 20), (6, -30), (-70, 20),
                  (-70, -30))


def thin_labels(fig, labels, offsets=None) -> list:
    """Leave out every label of ``labels`` (matplotlib texts, the most wanted first) whose
    text's box on the drawn figure overlaps one kept before it; a label in ``offsets`` (a
    dict: label -> its offsets from its point [points], an annotation's ``xyann``) is tried
    at each before it is left out. Returns the labels left out."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    canvas = FigureCanvasAgg(fig)
    canvas.draw()                      # the aspect and limits settle: the boxes are final
    renderer = canvas.get_renderer()
    kept, dropped = [], []
    for text in labels:
        for offset in (offsets or {}).get(text, (None,)):
            if offset is not None:
                text.xyann = offset
            box = Text.get_window_extent(text, renderer)    # the text, not its leader
            if not any(box.overlaps(other) for other in kept):
                kept.append(box)
                break
        else:
            text.remove()
            dropped.append(text)
    return dropped


def _side(track, k: int, i: int) -> np.ndarray:
    """Unit vector off the path at sample ``k``: vehicle 1's labels to the left of its
    motion, vehicle 2's to the right (the heading's where it does not move)."""
    v = track.velocity[k]
    if np.hypot(*v) < 1e-6:
        v = np.array([math.cos(track.heading[k]), math.sin(track.heading[k])])
    left = np.array([-v[1], v[0]]) / np.hypot(*v)
    return left if i == 0 else -left


def plan_view(event: Event, *, units="si", interval: float | None = None,
              measured_rest=(None, None), title: str = "", points=()):
    """A matplotlib Figure of ``event`` in plan view (module notes).

    Parameters
    ----------
    event : pim.model.event.Event
        The event (its samples; the outlines are taken at the nearest samples).
    units : {"si", "us"} or pim.io.units.DisplayUnits
        The length unit of the axes.
    interval : float, optional
        Time between drawn outlines [s] (default :func:`plan_interval`).
    measured_rest : tuple
        Per vehicle, the measured rest pose ``(position [m], heading [rad])`` or None.
    title : str
        First line of the title (the interval is stated after it).
    points : sequence of ndarray (k, 2)
        Measured points the CGs passed through [m] (a reconstruction's ``path_points``),
        drawn as black crosses.
    """
    from matplotlib.figure import Figure

    interval = plan_interval(event) if interval is None else float(interval)
    scale, unit = unit_scale("length", units)
    fig = Figure(figsize=(8, 6.5), dpi=120)
    ax = fig.add_subplot()
    labels = [_track_layer(ax, event, i, scale, interval) for i in (0, 1)]
    for i, rest in enumerate(measured_rest):
        body = outline_of(event.tracks[i])
        if rest is not None and body is not None:
            pts = pose_points(body, rest) * scale
            ax.plot(*np.vstack([pts, pts[:1]]).T, ":", color="k", lw=1.4,
                    label="measured rest" if i == 0 or measured_rest[0] is None else None)
    shown = [np.asarray(p, float).reshape(-1, 2) for p in points if len(p)]
    if shown:
        pts = np.concatenate(shown) * scale
        ax.plot(*pts.T, "+", color="k", ms=9, label="measured path points")
    impacts = _impacts(ax, event, scale)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_title(f"{title}\noutlines every {format_number(interval)} s (times beside them "
                 f"where there is room), CG paths, tyre marks (grey), impacts", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=7)
    # the impacts' labels first, then each vehicle's last (its rest), then the times in order
    finals = [group[-1][1] for group in labels if group]
    rest = sorted((pair for group in labels for pair in group[:-1]), key=lambda p: p[0])
    thin_labels(fig, impacts + finals + [text for _, text in rest],
                {text: IMPACT_OFFSETS for text in impacts})
    return fig


def _impacts(ax, event: Event, scale: float) -> list:
    """Each impact's C, its contact plane and its number with time; returns the labels."""
    size = max(float(np.ptp(np.concatenate([t.position for t in event.tracks]), axis=0).max()),
               4.0) * scale
    labels = []
    for k, impact in enumerate(event.impacts, start=1):
        c = np.asarray(impact.point, float) * scale
        g = float(impact.normal_angle)
        t = np.array([-math.sin(g), math.cos(g)]) * 0.06 * size
        ax.plot(*np.stack([c - t, c + t]).T, "--", color=_rgb("contact"), lw=1.2)
        ax.plot(*c, "*", color=_rgb("contact"), ms=10,
                label="impact C and contact plane" if k == 1 else None)
        labels.append(ax.annotate(f"impact {k}, {format_number(float(impact.time), sig=3)} s",
                                  c + t, xytext=IMPACT_OFFSETS[0],
                                  textcoords="offset points",
                                  fontsize=7, color=_rgb("contact")))
    return labels
