"""The README shows the main job's whole event (issue 32): the GIF and plan view it embeds
exist, are what comparisons.docs.readme_animation writes, and are images of the event."""

from pathlib import Path

import pytest
from PIL import Image

from comparisons.docs import readme_animation
from comparisons.docs.__main__ import PARTS

ROOT = Path(__file__).resolve().parents[3]


def test_the_readme_embeds_the_whole_event_written_by_its_script():
    readme = (ROOT / "README.md").read_text()
    for name in (readme_animation.GIF, readme_animation.PLAN):
        assert f"](docs/{name})" in readme
        assert (ROOT / "docs" / name).is_file()
    assert PARTS["readme-animation"] == readme_animation.__name__
    with Image.open(ROOT / "docs" / readme_animation.GIF) as gif:
        assert gif.n_frames > readme_animation.FPS          # more than a second of motion
        assert gif.info["duration"] == round(1000 / readme_animation.FPS)


def test_the_gif_plays_the_event_in_real_time():
    """The GIF's frame times add up to the event's time shown (the approach to rest and
    the hold) within 1 %: a GIF counts hundredths of a second, and 30 fps stored as 3 of
    them played 10 % fast."""
    import pim
    from comparisons.animation.collision import Framing, event_renderer

    renderer = event_renderer(pim.load_case("ricsac9"), framing=Framing(
        fps=readme_animation.FPS, size=readme_animation.SIZE))[0]
    shown = len(renderer.times) / readme_animation.FPS          # each frame for 1 / fps
    assert shown == pytest.approx(renderer.times[-1] - renderer.times[0]
                                  + 1 / readme_animation.FPS)
    total = 0
    with Image.open(ROOT / "docs" / readme_animation.GIF) as gif:
        for k in range(gif.n_frames):
            gif.seek(k)
            total += gif.info["duration"]
    assert total / 1000 == pytest.approx(shown, rel=0.01)
