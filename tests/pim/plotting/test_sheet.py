"""The design sheet's plots: data objects, files, atomic writes, `pim plot`."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import pim
from pim import fit
from pim.plotting.sheet import PLOTS, cost_map, save_figure, sweep_epsilon, write_plots
from pim_cli.main import main


@pytest.fixture(scope="module")
def ricsac9():
    return pim.load_case("ricsac9")


@pytest.fixture(scope="module")
def fitted(ricsac9):
    return fit(ricsac9)


def test_every_plot_file_is_written_and_non_empty(ricsac9, fitted, tmp_path):
    paths = write_plots(ricsac9, fitted, tmp_path / "out")
    assert [p.name for p in paths] == [f"{s}.{f}" for s in PLOTS for f in ("png", "svg")]
    for path in paths:
        data = path.read_bytes()
        assert len(data) > 5000, path
        if path.suffix == ".png":
            assert data[:8] == b"\x89PNG\r\n\x1a\n"
        else:
            assert b"<svg" in data[:2000] and data.rstrip().endswith(b"</svg>")
    # nothing else (no temp files) is left in the directory
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(p.name for p in paths)


def test_plots_without_measured_values(ricsac9, tmp_path):
    bare = replace(ricsac9, measured=None)
    paths = write_plots(bare, None, tmp_path, formats=("png",), units="us")
    assert {p.stem for p in paths} == set(PLOTS) - {"velocity_error", "cost_map"}
    assert all(p.stat().st_size > 5000 for p in paths)
    with pytest.raises(ValueError, match="pass its fit"):
        write_plots(ricsac9, None, tmp_path)
    with pytest.raises(ValueError, match="formats"):
        write_plots(bare, None, tmp_path, formats=("gif",))


def test_sweep_is_the_solver_over_epsilon(ricsac9, fitted):
    sweep = sweep_epsilon(ricsac9, fitted)
    assert sweep.beta[0] == fitted.beta and sweep.result.velocity1.shape == (3, 201, 2)
    k = 57
    direct = pim.solve(ricsac9, sweep.eps[k], sweep.beta[1])
    np.testing.assert_allclose(sweep.result.velocity2[1, k], direct.velocity2, rtol=1e-12)
    # the profile is the lowest cost over beta in [0, 1]: below every fixed-beta curve, and
    # at the fitted epsilon equal to the optimum (to the profile's beta resolution)
    assert np.all(sweep.profile_cost <= sweep.cost.min(axis=0) + 1e-12)
    j = np.argmin(np.abs(sweep.eps - fitted.eps))
    assert sweep.profile_cost.min() == pytest.approx(fitted.cost, rel=1e-3)
    assert sweep.profile_beta[j] == 1.0


def test_cost_map_marks_the_unconstrained_minimum(fitted):
    cmap = cost_map(fitted, n=81)
    assert cmap.cost.shape == (81, 81) and cmap.beta[-1] == pytest.approx(1.5)
    i, j = np.unravel_index(np.nanargmin(cmap.cost), cmap.cost.shape)
    assert cmap.beta[i] == pytest.approx(1.4, abs=0.05)  # ricsac9.md: beta ~ 1.4 without the bound


def test_save_figure_is_atomic(fitted, tmp_path):
    from pim.plotting.sheet import plot_impulse_ratio

    fig = plot_impulse_ratio(sweep_epsilon(fitted.case, fitted), fitted)
    target = tmp_path / "mu.png"
    target.write_bytes(b"old")

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    fig.savefig = broken
    with pytest.raises(RuntimeError):
        save_figure(fig, target)
    assert target.read_bytes() == b"old"           # the old file is untouched
    assert [p.name for p in tmp_path.iterdir()] == ["mu.png"]  # no temp file left
    with pytest.raises(ValueError, match="suffix"):
        save_figure(fig, tmp_path / "noext")


def test_cli_plot(tmp_path, capsys):
    assert main(["plot", "ricsac9", "--out", str(tmp_path), "--format", "png"]) == 0
    lines = capsys.readouterr().out.split()
    assert len(lines) == len(PLOTS) and all(line.endswith(".png") for line in lines)


def test_import_pim_does_not_load_matplotlib():
    code = ("import sys, pim; pim.load_case('ricsac9'); "
            "import pim.analysis.fitting, pim.analysis.sensitivity; "
            "print('matplotlib' in sys.modules, 'scipy.optimize' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_cost_map_with_sigmas_is_the_chi_square_in_every_unit_system(ricsac9):
    """issue 22: with [measured] sigmas the cost map is the fit's chi-square (it was the
    unweighted sum in (ft/s)^2 and changed with the units), labelled so, and the fitted
    optimum is its minimum within the bounds."""
    from pim.plotting.sheet import plot_cost_map, plot_velocity_error

    m = replace(ricsac9.measured, velocity1_sigma=[0.2, 0.2], velocity2_sigma=[0.6, 0.6])
    f = fit(replace(ricsac9, measured=m))
    cmap = cost_map(f, n=41, beta_margin=0.0)
    assert np.nanmin(cmap.cost) >= f.cost - 1e-9
    r = pim.solve(f.case, cmap.eps[None, :], cmap.beta[:, None])
    chi2 = (((r.velocity1 - m.velocity1) / 0.2) ** 2).sum(-1) \
        + (((r.velocity2 - m.velocity2) / 0.6) ** 2).sum(-1)
    np.testing.assert_allclose(cmap.cost, chi2, rtol=1e-12)
    labels = {}
    for units in ("si", "us"):
        fig = plot_cost_map(cmap, units)
        labels[units] = fig.axes[-1].get_ylabel()
        assert fig.axes[-1].get_ylim() == plot_cost_map(cmap, "si").axes[-1].get_ylim()
        sweep = sweep_epsilon(f.case, f)
        assert "chi-square" in plot_velocity_error(sweep, f, units).axes[0].get_ylabel()
    assert labels["si"] == labels["us"] and "chi-square" in labels["si"]
    assert "ft" not in labels["us"] and "m/s" not in labels["si"]


SIDESWIPE = Path(__file__).resolve().parents[2] / "data" / "sideswipe-opposite.toml"


def test_cost_map_near_a_singular_q_keeps_its_colour_scale():
    """issue 33, point 1: an opposite-direction sideswipe (restitution 0.05, beta 0.18, measured
    motion) whose cost map crosses A - mu B = 0 reaches 6e15 (km/h)^2; the lower colour limit
    was 1e-6 of that maximum, above the 99th percentile, and plot_cost_map raised "vmin must be
    less or equal to vmax". The scale now spans at most 6 decades below the 99th percentile."""
    from pim.plotting.sheet import colour_limits, plot_cost_map

    f = fit(pim.load_case(SIDESWIPE))
    cmap = cost_map(f)
    finite = cmap.cost[np.isfinite(cmap.cost)]
    assert finite.max() > 1e6 * np.percentile(finite, 99)     # the case is what it claims
    lo, hi = colour_limits(cmap.cost)
    hi_expected = np.percentile(finite, 99)
    assert hi == pytest.approx(hi_expected) and lo == pytest.approx(max(finite.min(), hi / 1e6))
    fig = plot_cost_map(cmap, "si")
    fig.canvas.draw()                                          # the colour bar is laid out
    bar = fig.axes[1]
    kmh2 = 3.6 ** 2                                            # the scale in (km/h)^2
    assert bar.get_ylim() == pytest.approx((lo * kmh2, hi * kmh2))


@pytest.mark.parametrize(("values", "expected"), [
    ([1e15] + [2.0] * 200, (2.0, 2.02)),              # one huge value: not the upper limit
    ([1e-20, 1.0, 1.0, 1.0], (1e-6, 1.0)),            # at most 6 decades below the upper limit
    ([5.0, 5.0, np.nan], (5.0, 5.05)),                # a flat map still has lower < upper
    ([0.0, np.nan, np.inf], (1.0, 10.0)),             # nothing positive: a neutral scale
])
def test_colour_limits(values, expected):
    from pim.plotting.sheet import colour_limits

    lo, hi = colour_limits(np.array(values))
    assert 0 < lo < hi
    assert (lo, hi) == pytest.approx(expected)
