"""Rendering speed of the collision animation (issue 5): frames/s of the Pillow renderer,
against a matplotlib Agg baseline with reused artists drawing the same outlines, measured in
the same run; and the MP4 encoding time.

    python benchmarks/bench_animation.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

import pim
from comparisons.animation.render import build_renderer, write_animation


def matplotlib_baseline(renderer, frames: int) -> float:
    """Frames/s of matplotlib Agg redrawing two polygons, two ghosts and a clock."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    w, h = renderer.size
    fig = Figure(figsize=(w / 100, h / 100), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.set_axis_off()
    ax.imshow(np.asarray(renderer._background), extent=(0, w, h, 0))   # same background
    polys = [ax.add_patch(Polygon(np.zeros((4, 2)), closed=True, fc=fc, ec="k"))
             for fc in ("tab:blue", "tab:orange")]
    ghosts = [ax.add_patch(Polygon(np.zeros((4, 2)), closed=True, fill=False, ec="m", ls="--"))
              for _ in range(2)]
    clock = ax.text(10, h - 20, "")
    start = time.perf_counter()
    for i in range(frames):
        k = i % len(renderer)
        for j in (0, 1):
            polys[j].set_xy(renderer.outline_px(k, j + 1))
            ghosts[j].set_xy(renderer.outline_px(k, j + 1, ghost=True))
        clock.set_text(f"t = {renderer.times[k]:+.3f} s")
        fig.canvas.draw()
        np.asarray(fig.canvas.buffer_rgba())
    return frames / (time.perf_counter() - start)


def main() -> None:
    case = pim.load_case("ricsac9")
    t0 = time.perf_counter()
    renderer = build_renderer(case, 0.355, 1.0)
    prepare = time.perf_counter() - t0
    n = len(renderer)
    renderer.frame(0)
    best = best_img = 0.0
    for _ in range(3):
        start = time.perf_counter()
        for i in range(n):
            renderer.frame(i)
        best_img = max(best_img, n / (time.perf_counter() - start))
        start = time.perf_counter()
        for i in range(n):
            renderer.array(i)
        best = max(best, n / (time.perf_counter() - start))
    base = matplotlib_baseline(renderer, n)
    with tempfile.TemporaryDirectory() as tmp:
        info = write_animation(renderer, Path(tmp) / "a.mp4", progress=False)
        t0 = time.perf_counter()
        write_animation(renderer, Path(tmp) / "a2.mp4", gif=Path(tmp) / "a.gif", progress=False)
        gif_total = time.perf_counter() - t0
    print(f"ricsac9 animation: {n} frames {renderer.size[0]}x{renderer.size[1]} at 30 fps")
    print(f"  simulate + prepare        : {prepare * 1e3:8.1f} ms")
    print(f"  Pillow renderer           : {best_img:8.0f} frames/s (full frames, PIL images)")
    print(f"  Pillow renderer + array   : {best:8.0f} frames/s (as arrays for the encoder)")
    print(f"  matplotlib Agg, reused    : {base:8.0f} frames/s (background + 4 outlines + clock)")
    print(f"  ratio Pillow / matplotlib : {best / base:8.1f} x")
    print(f"  MP4 (libx264) written in  : {info.write_seconds:8.2f} s "
          f"(render {info.render_seconds:.2f} s)")
    print(f"  MP4 + GIF written in      : {gif_total:8.2f} s")


if __name__ == "__main__":
    main()
