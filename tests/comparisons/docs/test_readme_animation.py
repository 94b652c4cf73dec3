"""The README shows the main job's whole event (issue 32): the GIF and plan view it embeds
exist, are what comparisons.docs.readme_animation writes, and are images of the event."""

from pathlib import Path

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
