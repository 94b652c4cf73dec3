"""Histograms of a Monte Carlo uncertainty study (:class:`pim.UncertaintyResult`).

matplotlib is imported inside the functions, so that ``import pim`` stays fast. Files are
written atomically by :func:`pim.io.files.save_figure`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis.montecarlo import OUTPUTS, UncertaintyResult
from ..io.files import save_figure
from ..io.units import convert
from ..model.quantities import OUTPUTS as QUANTITIES

__all__ = ["plot_histograms", "write_histograms"]


def plot_histograms(result: UncertaintyResult, units: str = "si", bins: int = 60):
    """One histogram per output, with the 5/50/95th percentiles and the nominal value.

    Returns the matplotlib Figure.
    """
    from matplotlib.figure import Figure

    names = list(OUTPUTS)
    cols = 3
    rows = -(-len(names) // cols)
    fig = Figure(figsize=(4.2 * cols, 3.0 * rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax, name in zip(axes.flat, names, strict=False):
        label, kind = QUANTITIES[name].label, QUANTITIES[name].kind
        y, unit = convert(result.samples[name], kind, units)
        stats = result.stats[name]
        if y.size:
            ax.hist(y, bins=bins, color="0.65", edgecolor="none")
            for value, style in ((stats.p5, ":"), (stats.p50, "-"), (stats.p95, ":")):
                ax.axvline(float(convert(value, kind, units)[0]), color="k", ls=style, lw=1)
        if np.isfinite(stats.nominal):
            ax.axvline(float(convert(stats.nominal, kind, units)[0]), color="C3", lw=1.2)
        ax.set_xlabel(f"{label} [{unit}]")
        ax.set_yticks([])
        top = result.sensitivity[name][:2]
        if top:
            ax.set_title(", ".join(f"{k} {s:.2f}" for k, s in top), fontsize=8)
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    fig.suptitle(f"{result.case_name}: {result.n_admissible:,} admissible of {result.n:,} samples"
                 " (black: 5/50/95 %, red: nominal; titles: top first-order indices)",
                 fontsize=9)
    fig.tight_layout()
    return fig


def write_histograms(result: UncertaintyResult, path, units: str = "si") -> Path:
    """Draw :func:`plot_histograms` and write it atomically to ``path`` (.png or .svg)."""
    return save_figure(plot_histograms(result, units), Path(path))
