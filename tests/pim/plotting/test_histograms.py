"""pim/plotting/histograms.py: Monte Carlo histograms as a Figure, without pyplot."""

import sys

import pim
from pim.plotting.histograms import plot_histograms, write_histograms
from tests.pim.analysis.test_montecarlo import collinear


def test_histograms_are_figures_written_atomically(tmp_path):
    case = collinear({"impact": {"restitution": {"uniform": [0.2, 0.5]}}})
    result = pim.uncertainty(case, n=2000)
    fig = plot_histograms(result, "us")
    visible = [ax for ax in fig.axes if ax.get_visible()]
    assert len(visible) == 9 and "[mph]" in visible[0].get_xlabel()
    path = write_histograms(result, tmp_path / "h.png")
    assert path.stat().st_size > 5000 and [p.name for p in tmp_path.iterdir()] == ["h.png"]
    assert "matplotlib.pyplot" not in sys.modules or not __import__(
        "matplotlib.pyplot").pyplot.get_fignums()   # nothing registered with pyplot
