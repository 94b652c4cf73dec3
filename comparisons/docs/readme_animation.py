"""The README's picture of the main job: RICSAC 9's whole event (the pymunk event with the
analytic event as a ghost, from the approach to rest) as an animated GIF, and its plan view,
written by the same code as ``pim compare ricsac9`` and ``pim event ricsac9``:

    python -m comparisons.docs readme-animation
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pim
from comparisons.animation.collision import Framing, event_renderer, measured_rest
from comparisons.animation.plan import plan_view
from comparisons.animation.render import write_animation
from pim.io.files import save_figure
from pim.io.units import display_units

__all__ = ["regenerate", "GIF", "PLAN", "FPS", "SIZE"]

#: The files written, relative to docs/.
GIF, PLAN = "images/ricsac9-event.gif", "images/ricsac9-event-plan.png"
#: Frames per second of the README's GIF (a GIF counts its frame time in hundredths of a
#: second: 20 fps is exactly 5 of them; other rates keep real time by alternating durations,
#: :func:`comparisons.animation.render.gif_durations`, and 20 keeps the file small).
FPS = 20
#: Frame size of the README's GIF [px] (full size: the caption's text readable).
SIZE = (600, 600)


def regenerate(docs: Path) -> list[Path]:
    """Write :data:`GIF` and :data:`PLAN` under ``docs``; return their paths."""
    docs = Path(docs)
    (docs / "images").mkdir(parents=True, exist_ok=True)
    case = pim.load_case("ricsac9")
    units = display_units(case=case)
    renderer, analytic, _ = event_renderer(case, framing=Framing(fps=FPS, size=SIZE),
                                           units=units)
    with tempfile.TemporaryDirectory() as tmp:
        write_animation(renderer, Path(tmp) / "event.mp4", fps=FPS, gif=docs / GIF,
                        progress=False, gif_scale=1.0)
    save_figure(plan_view(analytic, units=units, measured_rest=measured_rest(case),
                          title="RICSAC 9: the analytic event"), docs / PLAN)
    return [docs / GIF, docs / PLAN]
