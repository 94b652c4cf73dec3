"""Frames per second of the one renderer (issue 32 item 4) against the renderers it replaced,
measured in the same run on the same machine.

The baselines are the code of commit 1a30c2c (before the one renderer), read from git:
the collision's Pillow renderer (comparisons/animation/render.py, RICSAC 9 at (0.355, 1),
2 s after the impact, drawn frame by frame) and the reconstruction's matplotlib renderer
(pim/plotting/reconstruction_animation.py, frames drawn and encoded into its MP4). The one
renderer draws the same collision, the whole pymunk event of RICSAC 9 (approach, impact,
run-out to rest) and the same reconstruction (drawn and encoded). Best of three passes,
interleaved.

    python benchmarks/bench_animation.py
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import pim
import sim
from comparisons.animation.collision import build_renderer
from comparisons.animation.reconstruction import write_reconstruction_video
from comparisons.animation.render import Look, Renderer
from pim.model.event import DEFAULT_APPROACH

ROOT = Path(__file__).resolve().parents[1]
#: The commit whose renderers are the baselines.
BASELINE = "1a30c2c"


def old_module(path: str, name: str, folder: Path):
    """The module at ``path`` as of :data:`BASELINE`, imported as ``name``."""
    text = subprocess.run(["git", "-C", str(ROOT), "show", f"{BASELINE}:{path}"],
                          capture_output=True, text=True, check=True).stdout
    file = folder / (name.rsplit(".", 1)[-1] + ".py")
    file.write_text(text)
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def frames_per_second(renderer, passes: int = 3) -> float:
    """Best of ``passes`` of drawing every frame (as the encoder's arrays)."""
    best = 0.0
    renderer.array(0)
    for _ in range(passes):
        start = time.perf_counter()
        for i in range(len(renderer)):
            renderer.array(i)
        best = max(best, len(renderer) / (time.perf_counter() - start))
    return best


def whole_event_renderer(case) -> Renderer:
    """The whole pymunk event of ``case`` at 30 frames per second."""
    event = sim.simulate_event(case)
    times = np.arange(-round(DEFAULT_APPROACH * 30), round(event.end_time * 30) + 1) / 30
    return Renderer(event.at(times), look=Look(title="whole event", units="us"))


def reconstruction_post():
    """synthetic-runout's reconstruction (no Monte Carlo)."""
    from pim.analysis.reconstruction import reconstruct

    rec = reconstruct(pim.load_case("synthetic-runout"), samples=0)
    return rec.post, rec.fit.result


def main() -> None:
    case = pim.load_case("ricsac9")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old_render = old_module("comparisons/animation/render.py", "old_render", tmp)
        old_module("pim/plotting/reconstruction_scene.py",        # its colours (removed)
                   "pim.plotting.reconstruction_scene", tmp)
        old_rec = old_module("pim/plotting/reconstruction_animation.py",
                             "pim.plotting.old_reconstruction_animation", tmp)
        old = old_render.build_renderer(case, 0.355, 1.0)
        new = build_renderer(case, 0.355, 1.0, tyre=0.0, after=2.0,
                             before=float(old.times[0] * -1), size=old.size)
        whole = whole_event_renderer(case)
        post, result = reconstruction_post()
        rates = {"old": [], "new": [], "whole": [], "rec_old": [], "rec_new": []}
        for _ in range(3):
            rates["old"].append(frames_per_second(old, 1))
            rates["new"].append(frames_per_second(new, 1))
            rates["whole"].append(frames_per_second(whole, 1))
            t0 = time.perf_counter()
            path = old_rec.write_reconstruction_mp4(post, tmp / "old.mp4", units="us",
                                                    fps=30)
            n_old = len(old_rec.frame_states(post, 30).times)
            rates["rec_old"].append(n_old / (time.perf_counter() - t0))
            t0 = time.perf_counter()
            info = write_reconstruction_video(post, result, tmp / "new.mp4", units="us",
                                              fps=30, progress=False)
            rates["rec_new"].append(info.frames / (time.perf_counter() - t0))
            assert path.is_file()
    best = {k: max(v) for k, v in rates.items()}
    print(f"renderer frames per second, best of 3 interleaved passes (baseline: {BASELINE})")
    print(f"  collision, RICSAC 9, {len(old)} frames {old.size[0]}x{old.size[1]}:")
    print(f"    previous Pillow renderer   : {best['old']:8.0f} frames/s")
    print(f"    one renderer (events)      : {best['new']:8.0f} frames/s   "
          f"ratio {best['new'] / best['old']:.2f}")
    print(f"  whole pymunk event, RICSAC 9, {len(whole)} frames "
          f"{whole.size[0]}x{whole.size[1]} (tyre marks on):")
    print(f"    one renderer               : {best['whole']:8.0f} frames/s")
    print("  reconstruction video, synthetic-runout, drawn and encoded (MP4):")
    print(f"    previous matplotlib        : {best['rec_old']:8.0f} frames/s")
    print(f"    one renderer               : {best['rec_new']:8.0f} frames/s   "
          f"ratio {best['rec_new'] / best['rec_old']:.2f}")


if __name__ == "__main__":
    main()
