"""Plan view of a reconstruction: impact positions, fitted run-out paths, measured and
fitted rest positions (with outlines at impact and at rest)."""

from __future__ import annotations

import numpy as np

from ..analysis.reconstruction import PostImpact
from ..io.units import convert
from ..model.geometry import outline_world

__all__ = ["reconstruction_figure"]

COLOURS = {1: "tab:blue", 2: "tab:red"}


def reconstruction_figure(post: PostImpact, units: str = "si"):
    """A matplotlib Figure of the reconstruction in plan view, lengths in ``units``' length
    unit.

    Parameters
    ----------
    post : PostImpact
        From :func:`pim.analysis.reconstruction.post_impact_motion`.
    units : str
        ``"si"`` or ``"us"``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    scale, unit = convert(1.0, "length", units)
    scale = float(scale)
    fig = Figure(figsize=(8, 7), dpi=120)
    ax = fig.add_subplot()
    case = post.case
    for i, fit in post.runouts.items():
        vehicle = getattr(case, f"vehicle{i}")
        evidence = getattr(case.evidence, f"vehicle{i}")
        colour = COLOURS[i]
        path = fit.runout.states[:, :2] * scale
        ax.plot(path[:, 0], path[:, 1], "-", color=colour, lw=1.5,
                label=f"vehicle {i}: fitted run-out")
        length = vehicle.length if vehicle.length is not None else 4.5
        width = vehicle.width if vehicle.width is not None else 1.8
        for cg, heading, style in ((vehicle.cg, float(vehicle.heading), "-"),
                                   (fit.rest_position, fit.rest_heading, "--")):
            corners = outline_world(length, width, cg, heading, vehicle.cg_to_front) * scale
            closed = np.vstack([corners, corners[:1]])
            ax.plot(closed[:, 0], closed[:, 1], style, color=colour, lw=1.0)
        ax.plot(*(np.asarray(vehicle.cg) * scale), "o", color=colour, ms=5)
        ax.plot(*(evidence.rest_position * scale), "x", color="k", ms=9, mew=2)
        if len(evidence.path_points):
            pts = evidence.path_points * scale
            ax.plot(pts[:, 0], pts[:, 1], "+", color="k", ms=9)
    ax.plot([], [], "x", color="k", label="measured rest position")
    ax.plot([], [], "--", color="grey", label="fitted rest (outline)")
    ax.plot(*(np.asarray(case.impact.point) * scale), "*", color="k", ms=10, label="C")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_title(f"{case.name}: impact positions, fitted run-outs, rest positions")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return fig
